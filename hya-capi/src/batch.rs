//! Many states in one call: `count` rows of `n` = dof values one after another (row-major
//! `count × n`), each output row-major `count × width`. A shipped arm runs them in its generated
//! batches, several states per SIMD register (`hya_core::SliceDynamics`' rows); a URDF model
//! one state at a time. The checks are the single calls', with the row named: `n` must be the
//! model's dof, every input finite ("row 3: non-finite q[1] = NaN"), every result finite, an
//! output apart from every input; outputs whose width is not `n` come with their length `len`,
//! checked as the single calls check theirs. Neither the work nor a refusal allocates.
//!
//! A state the batch refuses (a mass matrix not positive definite) sends the call to the states
//! one at a time, as Python's batches do: the first that fails alone is reported with its row,
//! the rows before it written; if none fails alone, every row is written and the call succeeds.

use crate::model::{on_model, HyaModel};
use crate::slices::{input_rows, output, output_rows, rows_length};
use crate::status::{Failure, HyaStatus};

/// Three arguments of `count × n` doubles each ([`input_rows`]).
///
/// # Safety
/// Each pointer is null or valid for reading `count × n` doubles.
unsafe fn inputs<'a>(
    arguments: [(&'static str, *const f64); 3],
    rows: (usize, usize),
    dof: usize,
) -> Result<[&'a [f64]; 3], Failure> {
    let [a, b, c] = arguments;
    // SAFETY: the caller's contract.
    unsafe {
        Ok([input_rows(a.0, a.1, rows, dof)?, input_rows(b.0, b.1, rows, dof)?, input_rows(c.0, c.1, rows, dof)?])
    }
}

/// `Err` naming the row of the first non-finite result in `values`, rows of `parts.len()` parts
/// of `part` values each, the part by its name (`dqdd_dq[4]` rather than `out[4]`):
/// [`hya_core::finite_result`] of each part.
fn finite_rows(values: &[f64], parts: &[&'static str], part: usize) -> Result<(), Failure> {
    for (row, values) in values.chunks(parts.len() * part).enumerate() {
        for (quantity, values) in parts.iter().zip(values.chunks(part)) {
            hya_core::finite_result(quantity, values).map_err(|error| Failure::CoreInRow { row, error })?;
        }
    }
    Ok(())
}

/// After the batch refused a state: `single(k)` for `k = 0, 1, …, count − 1` (each writing its
/// own row), stopping at the first that fails, which is returned with its row.
fn one_by_one(count: usize, mut single: impl FnMut(usize) -> Result<(), hya_core::Error>) -> Result<(), Failure> {
    (0..count).try_for_each(|row| single(row).map_err(|error| Failure::CoreInRow { row, error }))
}

/// Row `k` of `values`, rows `width` long.
fn row(values: &[f64], k: usize, width: usize) -> &[f64] {
    &values[k * width..(k + 1) * width]
}

/// Row `k` of `values` to write, rows `width` long.
fn row_mut(values: &mut [f64], k: usize, width: usize) -> &mut [f64] {
    &mut values[k * width..(k + 1) * width]
}

/// `τ = M(q) q̈ + C(q, q̇) + G(q)` (N·m) at `count` states: `q` (rad), `qd` (rad/s), `qdd`
/// (rad/s²) and `tau` hold `count × n` doubles, row-major, `n` = dof. As
/// `hya_model_inverse_dynamics`, state by state.
///
/// # Safety
/// `model` is null or a live handle; each non-null array holds `count × n` doubles.
#[no_mangle]
pub unsafe extern "C" fn hya_model_inverse_dynamics_batch(
    model: *mut HyaModel,
    q: *const f64,
    qd: *const f64,
    qdd: *const f64,
    count: usize,
    n: usize,
    tau: *mut f64,
) -> HyaStatus {
    // SAFETY: the caller's contract; lengths checked against the model.
    unsafe {
        on_model(model, |arm, dof| {
            let [q, qd, qdd] = inputs([("q", q), ("qd", qd), ("qdd", qdd)], (count, n), dof)?;
            let tau = output_rows("tau", tau, (count, dof), &[q, qd, qdd])?;
            arm.slices().inverse_dynamics_rows(q, qd, qdd, tau).map_err(Failure::Core)?;
            finite_rows(tau, &["tau"], dof)
        })
    }
}

/// `G(q)` (N·m) at `count` states: `q` (rad) and `tau` hold `count × n` doubles, `n` = dof. As
/// `hya_model_gravity`, state by state.
///
/// # Safety
/// `model` is null or a live handle; each non-null array holds `count × n` doubles.
#[no_mangle]
pub unsafe extern "C" fn hya_model_gravity_batch(
    model: *mut HyaModel,
    q: *const f64,
    count: usize,
    n: usize,
    tau: *mut f64,
) -> HyaStatus {
    // SAFETY: the caller's contract; lengths checked against the model.
    unsafe {
        on_model(model, |arm, dof| {
            let q = input_rows("q", q, (count, n), dof)?;
            let tau = output_rows("tau", tau, (count, dof), &[q])?;
            arm.slices().gravity_rows(q, tau).map_err(Failure::Core)?;
            finite_rows(tau, &["tau"], dof)
        })
    }
}

/// `M(q)` (kg·m²) at `count` states: `q` holds `count × n` doubles (`n` = dof), `mass` `len` =
/// `count × n²`, one symmetric matrix after another. As `hya_model_mass_matrix`, state by state.
///
/// # Safety
/// `model` is null or a live handle; `q` holds `count × n` doubles and `mass` `len`.
#[no_mangle]
pub unsafe extern "C" fn hya_model_mass_matrix_batch(
    model: *mut HyaModel,
    q: *const f64,
    count: usize,
    n: usize,
    mass: *mut f64,
    len: usize,
) -> HyaStatus {
    // SAFETY: the caller's contract; lengths checked against the model.
    unsafe {
        on_model(model, |arm, dof| {
            let q = input_rows("q", q, (count, n), dof)?;
            let mass = output("mass", mass, len, rows_length("mass", count, dof * dof)?, &[q])?;
            arm.slices().mass_matrix_rows(q, mass).map_err(Failure::Core)?;
            finite_rows(mass, &["mass"], dof * dof)
        })
    }
}

/// `q̈ = M(q)⁻¹ (τ − C(q, q̇) − G(q))` (rad/s²) at `count` states: `q`, `qd`, `tau` (N·m) and
/// `qdd` hold `count × n` doubles, `n` = dof. As `hya_model_forward_dynamics`, state by state;
/// `HYA_ERR_NUMERIC` at the first state whose mass matrix is not positive definite, named by
/// its row (the rows before it written).
///
/// # Safety
/// `model` is null or a live handle; each non-null array holds `count × n` doubles.
#[no_mangle]
pub unsafe extern "C" fn hya_model_forward_dynamics_batch(
    model: *mut HyaModel,
    q: *const f64,
    qd: *const f64,
    tau: *const f64,
    count: usize,
    n: usize,
    qdd: *mut f64,
) -> HyaStatus {
    // SAFETY: the caller's contract; lengths checked against the model.
    unsafe {
        on_model(model, |arm, dof| {
            let [q, qd, tau] = inputs([("q", q), ("qd", qd), ("tau", tau)], (count, n), dof)?;
            let qdd = output_rows("qdd", qdd, (count, dof), &[q, qd, tau])?;
            let model = arm.slices();
            if model.forward_dynamics_rows(q, qd, tau, qdd).is_err() {
                one_by_one(count, |k| {
                    let [q, qd, tau] = [q, qd, tau].map(|x| row(x, k, dof));
                    model.forward_dynamics_into(q, qd, tau, row_mut(qdd, k, dof))
                })?;
            }
            finite_rows(qdd, &["qdd"], dof)
        })
    }
}

/// `(∂q̈/∂q, ∂q̈/∂q̇, M⁻¹)` of forward dynamics at `count` states: `q`, `qd`, `tau` hold
/// `count × n` doubles (`n` = dof); `out` holds `len` = `count × 3n²`: per state `∂q̈/∂q`
/// (1/s²), `∂q̈/∂q̇` (1/s), `M⁻¹ = ∂q̈/∂τ` (1/(kg·m²)), each `n × n` row-major (row `i` is
/// `∂q̈_i`), one after another. As `hya_model_forward_dynamics_derivatives`, state by state;
/// `HYA_ERR_NUMERIC` at the first state whose mass matrix is not positive definite, named by
/// its row (the rows before it written).
///
/// # Safety
/// `model` is null or a live handle; `q`, `qd`, `tau` hold `count × n` doubles and `out` `len`.
#[no_mangle]
pub unsafe extern "C" fn hya_model_forward_dynamics_derivatives_batch(
    model: *mut HyaModel,
    q: *const f64,
    qd: *const f64,
    tau: *const f64,
    count: usize,
    n: usize,
    out: *mut f64,
    len: usize,
) -> HyaStatus {
    // SAFETY: the caller's contract; lengths checked against the model.
    unsafe {
        on_model(model, |arm, dof| {
            let [q, qd, tau] = inputs([("q", q), ("qd", qd), ("tau", tau)], (count, n), dof)?;
            let part = dof * dof;
            let out = output("out", out, len, rows_length("out", count, 3 * part)?, &[q, qd, tau])?;
            let model = arm.slices();
            if model.forward_dynamics_derivatives_rows(q, qd, tau, out).is_err() {
                one_by_one(count, |k| {
                    let [q, qd, tau] = [q, qd, tau].map(|x| row(x, k, dof));
                    let (by_q, rest) = row_mut(out, k, 3 * part).split_at_mut(part);
                    let (by_qd, inverse) = rest.split_at_mut(part);
                    model.forward_dynamics_derivatives_into(q, qd, tau, [by_q, by_qd, inverse])
                })?;
            }
            finite_rows(out, &["dqdd_dq", "dqdd_dqd", "mass_inverse"], part)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The loader refuses every description whose mass matrix is singular where it checks, so
    /// the search for a failing row is tested on a closure.
    #[test]
    fn the_states_one_by_one_stop_at_the_first_that_fails_and_name_its_row() {
        let singular = || hya_core::Error::SingularMassMatrix;
        let mut written = Vec::new();
        let failure = one_by_one(5, |k| {
            written.push(k);
            if k >= 3 {
                Err(singular())
            } else {
                Ok(())
            }
        })
        .unwrap_err();
        assert_eq!(written, [0, 1, 2, 3], "the rows before the failing one, and no row after it");
        assert!(matches!(failure, Failure::CoreInRow { row: 3, error: hya_core::Error::SingularMassMatrix }));
        assert!(failure.to_string().starts_with("row 3: "), "{failure}");
        assert_eq!(failure.status(), HyaStatus::HyaErrNumeric);
        assert!(one_by_one(5, |_| Ok(())).is_ok(), "no row failing alone: every row written, no error");
    }

    #[test]
    fn a_non_finite_result_is_named_by_its_row_its_part_and_its_entry() {
        // Rows of two parts of two values: row 1's second part, entry 1.
        let values = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, f64::INFINITY];
        let failure = finite_rows(&values, &["by_q", "inverse"], 2).unwrap_err();
        let hya_core::Error::NonFiniteResult { quantity, index, .. } = (match failure {
            Failure::CoreInRow { row: 1, error } => error,
            other => panic!("{other}"),
        }) else {
            panic!("not a non-finite result")
        };
        assert_eq!((quantity, index), ("inverse", 1));
        assert_eq!(failure.status(), HyaStatus::HyaErrNumeric);
        assert!(failure.to_string().starts_with("row 1: "), "{failure}");
        assert!(finite_rows(&[0.0; 8], &["by_q", "inverse"], 2).is_ok());
    }
}
