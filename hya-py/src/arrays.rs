//! NumPy arguments in, NumPy results out: one state as shape `(dof,)`, or `n` states as
//! `(n, dof)`; every value finite, or `ValueError` naming the argument.

use numpy::ndarray::{ArrayD, IxDyn};
use numpy::{AllowTypeChange, IntoPyArray, PyArrayDyn, PyArrayLikeDyn, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// Rows of one argument, row-major, each `width` long.
#[derive(Debug, Clone)]
pub struct Rows {
    /// The values, `count × width`.
    pub data: Vec<f64>,
    /// How many rows.
    pub count: usize,
    /// Whether the caller passed a batch (`(n, width)`) rather than one row (`(width,)`).
    pub batched: bool,
}

impl Rows {
    /// Row `k`.
    pub fn row(&self, k: usize, width: usize) -> &[f64] {
        &self.data[k * width..(k + 1) * width]
    }
}

/// Reads `value` (a NumPy array or anything array-like) as rows of `width` finite numbers.
///
/// A C-contiguous float64 array is copied as it is; anything else goes through NumPy's
/// conversion first.
pub fn rows(name: &str, value: &Bound<'_, PyAny>, width: usize) -> PyResult<Rows> {
    if let Ok(array) = value.downcast::<PyArrayDyn<f64>>() {
        let array = array.readonly();
        // `as_slice` also accepts Fortran order, whose memory holds the rows column by column.
        if let (true, Ok(data)) = (array.is_c_contiguous(), array.as_slice()) {
            return checked(name, data.to_vec(), array.shape(), width);
        }
    }
    let array: PyArrayLikeDyn<'_, f64, AllowTypeChange> =
        value.extract().map_err(|_| PyValueError::new_err(format!("{name}: expected an array of numbers")))?;
    let view = array.as_array();
    checked(name, view.iter().copied().collect(), view.shape(), width)
}

/// `data` of shape `shape` as rows of `width`, if the shape fits and every value is finite.
fn checked(name: &str, data: Vec<f64>, shape: &[usize], width: usize) -> PyResult<Rows> {
    let (count, batched) = match shape {
        [w] if *w == width => (1, false),
        [n, w] if *w == width => (*n, true),
        shape => {
            return Err(PyValueError::new_err(format!("{name}: shape {shape:?}, expected ({width},) or (n, {width})")))
        }
    };
    // One pass with no exit, which the compiler vectorises; the search only on failure.
    if !data.iter().fold(true, |finite, x| finite & x.is_finite()) {
        let at = data.iter().position(|x| !x.is_finite()).unwrap_or_default();
        let (row, column) = (at / width, at % width);
        let place = if batched { format!("[{row}, {column}]") } else { format!("[{column}]") };
        return Err(PyValueError::new_err(format!("{name}{place} = {}: not finite", data[at])));
    }
    Ok(Rows { data, count, batched })
}

/// Reads several arguments of the same width and checks they hold the same number of rows.
pub fn same_rows<const K: usize>(args: [(&str, &Bound<'_, PyAny>); K], width: usize) -> PyResult<[Rows; K]> {
    let mut out = Vec::with_capacity(K);
    for (name, value) in args {
        out.push(rows(name, value, width)?);
    }
    if let Some(first) = out.first() {
        for (rows, (name, _)) in out.iter().zip(args) {
            if rows.count != first.count || rows.batched != first.batched {
                return Err(PyValueError::new_err(format!(
                    "{name}: {} row(s), but {} has {}",
                    rows.count, args[0].0, first.count
                )));
            }
        }
    }
    out.try_into().map_err(|_| PyValueError::new_err("internal: argument count"))
}

/// `data` as an array of shape `(count, *item)` if `batched`, else `item`.
pub fn output<'py>(
    py: Python<'py>,
    data: Vec<f64>,
    count: usize,
    batched: bool,
    item: &[usize],
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let mut shape = if batched { vec![count] } else { Vec::new() };
    shape.extend_from_slice(item);
    let array = ArrayD::from_shape_vec(IxDyn(&shape), data).map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok(array.into_pyarray(py))
}
