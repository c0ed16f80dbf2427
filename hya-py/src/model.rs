//! `hya.Model`: rigid-body dynamics of a shipped arm (generated code) or of any URDF (the
//! run-time model), on NumPy arrays, one state or a batch per call.

use std::borrow::Cow;
use std::sync::Arc;

use hya_core::model::TreeModel;
use hya_core::{Dynamics, SliceDynamics};
use hya_ident::{JointFriction, WithFriction};
use hya_robots::RobotInfo;
use numpy::PyArrayDyn;
use pyo3::exceptions::{PyKeyError, PyValueError};
use pyo3::prelude::*;

use crate::arrays::{finite_results, output, row, rows, same_rows, Rows};
use crate::UrdfError;

/// The longest a batch may hold the GIL, reading NumPy's arrays in place: a fifth of Python's
/// default switch interval (`sys.getswitchinterval()`, 5 ms), the time a thread running
/// bytecode may itself keep the GIL from others. A batch that would take longer releases it.
const GIL_HOLD_NS: usize = 1_000_000;

/// A NumPy array of float64 handed to Python.
type Array<'py> = Bound<'py, PyArrayDyn<f64>>;

/// Calls `f` with `N` joints for `dof` from 1 to [`hya_core::dispatch::MAX_JOINTS`]; a
/// `ValueError` otherwise.
pub fn for_joints<T, F: hya_core::dispatch::ForJoints<Output = PyResult<T>>>(dof: usize, f: F) -> PyResult<T> {
    hya_core::dispatch::with_joints(dof, f).unwrap_or_else(|| {
        let most = hya_core::dispatch::MAX_JOINTS;
        Err(PyValueError::new_err(format!("the model has {dof} joints: hya's estimators run arms of 1 to {most}")))
    })
}

/// A robot's rigid-body dynamics.
///
/// Angles in rad, velocities in rad/s, accelerations in rad/s², torques in N·m, lengths in m.
/// Joints are in the model's order (`joint_names`). Every method takes one state as arrays of
/// shape `(dof,)`, or `n` states as `(n, dof)`, computed in one call. A batch reads float64
/// C-order arrays in place, holding the GIL, unless it would take more than about a millisecond:
/// then it releases the GIL and computes on copies. Arrays of the wrong shape, or holding NaN or
/// infinity, raise `ValueError` naming the argument.
///
/// Build one with `Model.builtin(name)` (a shipped arm: generated, unrolled code) or
/// `Model.from_urdf(path)` (any URDF: the run-time kinematic-tree model).
#[pyclass(module = "hya", frozen)]
pub struct Model {
    /// The shipped robot's name, or the URDF's path.
    source: String,
    /// The description's text, as loaded.
    urdf: String,
    model: TreeModel,
    generated: Option<&'static RobotInfo>,
}

impl Model {
    /// This model's dynamics as a fixed-size [`Dynamics`] for the estimators and the controller:
    /// the shipped arm's generated code, or the run-time model this object loaded (never
    /// reloaded from its path).
    pub fn nominal<const N: usize>(&self) -> PyResult<Arc<dyn Dynamics<N> + Send + Sync>> {
        let value_error = |e: String| PyValueError::new_err(format!("{}: {e}", self.source));
        match self.generated {
            Some(robot) => match hya_robots::nominal::<N>(robot.name) {
                Some(generated) => Ok(Arc::new(generated)),
                None => Err(value_error(format!("no generated dynamics of {N} joints (a registry bug)"))),
            },
            None => self
                .model
                .clone()
                .into_dynamics::<N>()
                .map(|d| Arc::new(d) as _)
                .map_err(|e| value_error(e.to_string())),
        }
    }

    /// [`Self::nominal`] with the identified joint law `friction` added where given
    /// (`ID + τ_f(q̇) + I_a q̈`, as `hya estimate --friction` and a scenario's
    /// `controller.friction_toml` add it).
    pub fn nominal_with<const N: usize>(
        &self,
        friction: Option<&JointFriction>,
    ) -> PyResult<Arc<dyn Dynamics<N> + Send + Sync>> {
        let rigid = self.nominal::<N>()?;
        Ok(match friction {
            None => rigid,
            Some(friction) => Arc::new(WithFriction::new(rigid, friction.clone())),
        })
    }

    /// The friction file at `path` (from `hya identify`), checked for this model's joints.
    pub fn friction_file(&self, path: Option<std::path::PathBuf>) -> PyResult<Option<JointFriction>> {
        path.map(|path| {
            JointFriction::from_file(&path, self.dof_count())
                .map_err(|e| PyValueError::new_err(format!("friction: {e}")))
        })
        .transpose()
    }

    /// The shipped robot's name, or the URDF's path.
    pub fn source(&self) -> &str {
        &self.source
    }

    /// Whether this is a shipped arm (`Model.builtin`), its dynamics generated code.
    pub fn is_shipped(&self) -> bool {
        self.generated.is_some()
    }

    /// The description's text.
    pub fn urdf(&self) -> &str {
        &self.urdf
    }

    /// The run-time model.
    pub fn tree(&self) -> &TreeModel {
        &self.model
    }

    /// Degrees of freedom.
    pub fn dof_count(&self) -> usize {
        self.model.bodies().len()
    }

    /// `G(q)` of one state of the right length.
    pub fn gravity_of(&self, q: &[f64]) -> Vec<f64> {
        let mut g = vec![0.0; q.len()];
        self.dynamics().gravity_into(q, &mut g);
        g
    }

    fn dynamics(&self) -> &(dyn SliceDynamics + Sync) {
        match self.generated {
            Some(robot) => robot.generated,
            None => &self.model,
        }
    }

    /// An upper bound of one state's cost in the costliest batch method, ns: forward dynamics
    /// of a shipped 6- or 7-joint arm took 66 to 167 ns per state in a generated batch, and
    /// 1.6 to 2.6 µs on the generic tree model the run-time model runs (BENCHMARKS.md, FD
    /// batch and FD generic, every round of the run of 2026-11-26 at `40ce7c5`).
    fn state_cost_ns(&self) -> usize {
        match self.generated {
            Some(_) => 250,
            None => 2_500,
        }
    }

    /// All states' outputs, `width` numbers per state: `batch(dynamics, values, out)` once over
    /// them (the batch entry points, on lanes of the vector unit for a shipped arm); for one
    /// state, or if `batch` fails, `each(dynamics, values, row, out)` row by row, which names
    /// the row at fault.
    ///
    /// A batch that fits in [`GIL_HOLD_NS`] reads the arrays in place with the GIL held. A
    /// larger one releases the GIL and runs on copies ([`Rows::detached`]), as Python threads
    /// may then write the arrays.
    fn compute<const K: usize>(
        &self,
        py: Python<'_>,
        inputs: [&Rows; K],
        (quantity, width): (&'static str, usize),
        batch: impl Fn(&(dyn SliceDynamics + Sync), [&[f64]; K], &mut [f64]) -> Result<(), hya_core::Error> + Send + Sync,
        each: impl Fn(&(dyn SliceDynamics + Sync), [&[f64]; K], usize, &mut [f64]) -> Result<(), String> + Send + Sync,
    ) -> PyResult<Vec<f64>> {
        let count = inputs.first().map_or(0, |rows| rows.count);
        let batched = inputs.first().is_some_and(|rows| rows.batched);
        let dynamics = self.dynamics();
        let run = |values: [&[f64]; K]| -> PyResult<Vec<f64>> {
            let mut out = vec![0.0; count * width];
            if !(count > 1 && batch(dynamics, values, &mut out).is_ok()) {
                for (k, chunk) in out.chunks_mut(width.max(1)).enumerate() {
                    each(dynamics, values, k, chunk).map_err(PyValueError::new_err)?;
                }
            }
            finite_results(quantity, &out, width, batched)?;
            Ok(out)
        };
        if count.saturating_mul(self.state_cost_ns()) <= GIL_HOLD_NS {
            let mut values = [&[][..]; K];
            for (value, rows) in values.iter_mut().zip(inputs) {
                *value = rows.values()?;
            }
            return run(values);
        }
        let mut copies: [Cow<'_, [f64]>; K] = std::array::from_fn(|_| Cow::Borrowed(&[][..]));
        for (copy, rows) in copies.iter_mut().zip(inputs) {
            *copy = rows.detached()?;
        }
        py.allow_threads(|| run(copies.each_ref().map(|copy| &copy[..])))
    }
}

#[pymethods]
impl Model {
    /// The model of a URDF file. Raises `hya.UrdfError` (a `ValueError`) naming the file and
    /// the link or joint at fault.
    #[staticmethod]
    fn from_urdf(path: std::path::PathBuf) -> PyResult<Self> {
        let source = path.display().to_string();
        let urdf = hya_urdf::read_file(&path).map_err(|e| UrdfError::new_err(e.to_string()))?;
        let loaded = hya_urdf::load_str(&urdf, &source).map_err(|e| UrdfError::new_err(e.to_string()))?;
        Ok(Self { source, urdf, model: loaded.model, generated: None })
    }

    /// A shipped arm by name (`Model.builtin_names()`): generated code behind every method.
    #[staticmethod]
    fn builtin(name: &str) -> PyResult<Self> {
        let robot = hya_robots::find(name).ok_or_else(|| {
            let known: Vec<&str> = hya_robots::ROBOTS.iter().map(|r| r.name).collect();
            PyKeyError::new_err(format!("no shipped robot `{name}`; shipped: {}", known.join(", ")))
        })?;
        let loaded = hya_urdf::load_str(robot.urdf, robot.name).map_err(|e| UrdfError::new_err(e.to_string()))?;
        Ok(Self { source: name.to_owned(), urdf: robot.urdf.to_owned(), model: loaded.model, generated: Some(robot) })
    }

    /// The names of the shipped arms.
    #[staticmethod]
    fn builtin_names() -> Vec<&'static str> {
        hya_robots::ROBOTS.iter().map(|r| r.name).collect()
    }

    /// Degrees of freedom.
    #[getter]
    fn dof(&self) -> usize {
        self.dof_count()
    }

    /// The joints' names, in the order of every array's columns.
    #[getter]
    fn joint_names(&self) -> Vec<String> {
        self.model.bodies().iter().map(|b| b.joint.clone()).collect()
    }

    /// The names of the frames `frame_pose` accepts (every link of the URDF).
    #[getter]
    fn frame_names(&self) -> Vec<String> {
        self.model.frames().iter().map(|f| f.name.clone()).collect()
    }

    /// Whether the methods run generated code (a shipped arm) or the run-time model.
    #[getter]
    fn generated(&self) -> bool {
        self.generated.is_some()
    }

    fn __repr__(&self) -> String {
        let path = if self.generated.is_some() { "generated" } else { "run-time model" };
        format!("hya.Model({:?}, dof={}, {path})", self.source, self.dof())
    }

    /// `τ = M(q) q̈ + C(q, q̇) + G(q)`, N·m: the joint torques that produce `q̈` at `(q, q̇)`
    /// (gravity included, along the URDF's −z at 9.81 m/s²).
    fn inverse_dynamics<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        qd: &Bound<'py, PyAny>,
        qdd: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let n = self.dof();
        let [q, qd, qdd] = same_rows([("q", q), ("qd", qd), ("qdd", qdd)], n)?;
        let out = self.compute(
            py,
            [&q, &qd, &qdd],
            ("tau", n),
            |d, [q, qd, qdd], tau| d.inverse_dynamics_rows(q, qd, qdd, tau),
            |d, [q, qd, qdd], k, tau| {
                d.inverse_dynamics_into(row(q, k, n), row(qd, k, n), row(qdd, k, n), tau);
                Ok(())
            },
        )?;
        output(py, out, q.count, q.batched, &[n])
    }

    /// `M(q)`, kg·m²: the joint-space mass matrix, symmetric positive definite, shape
    /// `(dof, dof)` (or `(n, dof, dof)`).
    fn mass_matrix<'py>(&self, py: Python<'py>, q: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let n = self.dof();
        let q = rows("q", q, n)?;
        let out = self.compute(
            py,
            [&q],
            ("mass", n * n),
            |d, [q], m| d.mass_matrix_rows(q, m),
            |d, [q], k, m| {
                d.mass_matrix_into(row(q, k, n), m);
                Ok(())
            },
        )?;
        output(py, out, q.count, q.batched, &[n, n])
    }

    /// `G(q)`, N·m: the torques that hold the arm still at `q`.
    fn gravity<'py>(&self, py: Python<'py>, q: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let n = self.dof();
        let q = rows("q", q, n)?;
        let out = self.compute(
            py,
            [&q],
            ("tau", n),
            |d, [q], g| d.gravity_rows(q, g),
            |d, [q], k, g| {
                d.gravity_into(row(q, k, n), g);
                Ok(())
            },
        )?;
        output(py, out, q.count, q.batched, &[n])
    }

    /// `q̈ = M(q)⁻¹ (τ − C(q, q̇) − G(q))`, rad/s², by the articulated-body algorithm.
    fn forward_dynamics<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        qd: &Bound<'py, PyAny>,
        tau: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let n = self.dof();
        let [q, qd, tau] = same_rows([("q", q), ("qd", qd), ("tau", tau)], n)?;
        let out = self.compute(
            py,
            [&q, &qd, &tau],
            ("qdd", n),
            |d, [q, qd, tau], qdd| d.forward_dynamics_rows(q, qd, tau, qdd),
            |d, [q, qd, tau], k, qdd| {
                d.forward_dynamics_into(row(q, k, n), row(qd, k, n), row(tau, k, n), qdd)
                    .map_err(|e| format!("row {k}: {e}"))
            },
        )?;
        output(py, out, q.count, q.batched, &[n])
    }

    /// ns per state of `calls` calls of the Rust batch behind `method` (`"inverse_dynamics"` or
    /// `"forward_dynamics"`) on the states `(a, b, c)`, copied once, timed in Rust without
    /// Python: the reference a benchmark compares the Python call with in the same process
    /// (`tools/python_bench.py`).
    fn _rust_batch_ns(
        &self,
        method: &str,
        a: &Bound<'_, PyAny>,
        b: &Bound<'_, PyAny>,
        c: &Bound<'_, PyAny>,
        calls: usize,
    ) -> PyResult<f64> {
        let n = self.dof();
        let [a, b, c] = same_rows([("a", a), ("b", b), ("c", c)], n)?;
        let [a, b, c] = [a.detached()?, b.detached()?, c.detached()?];
        let (dynamics, mut out) = (self.dynamics(), vec![0.0; a.len()]);
        let batch = match method {
            "inverse_dynamics" => <dyn SliceDynamics>::inverse_dynamics_rows,
            "forward_dynamics" => <dyn SliceDynamics>::forward_dynamics_rows,
            other => return Err(PyValueError::new_err(format!("method: `{other}` has no batch here"))),
        };
        let start = std::time::Instant::now();
        for _ in 0..calls {
            batch(dynamics, &a, &b, &c, &mut out).map_err(|e| PyValueError::new_err(e.to_string()))?;
        }
        let states = calls as f64 * (a.len() / n.max(1)) as f64;
        Ok(start.elapsed().as_secs_f64() * 1e9 / states.max(1.0))
    }

    /// The pose of frame `name` (a link) in the base frame at `q`: a 4×4 homogeneous matrix
    /// `[[R, p], [0, 1]]` with `p_base = R p_frame + p` (shape `(n, 4, 4)` for a batch).
    /// Computed by the run-time model for every robot.
    fn frame_pose<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        name: &str,
    ) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let q = rows("q", q, self.dof())?;
        self.per_frame_row(py, [&q], name, &[4, 4], |model, [q], out| {
            let pose = model.frame_pose(name, q)?;
            // hya's transform maps base coordinates into the frame's (`E`); its transpose
            // holds the frame's axes in base coordinates.
            let (rotation, origin) = (pose.rotation.transpose(), pose.translation);
            for row in 0..3 {
                out[4 * row..4 * row + 4].copy_from_slice(&[
                    rotation[(row, 0)],
                    rotation[(row, 1)],
                    rotation[(row, 2)],
                    origin[row],
                ]);
            }
            out[12..].copy_from_slice(&[0.0, 0.0, 0.0, 1.0]);
            Ok(())
        })
    }

    /// The geometric Jacobian of frame `name` (a link) at `q`, shape `(6, dof)` (`(n, 6, dof)`
    /// for a batch): rows 0–2 map `q̇` to the linear velocity of the frame's origin, rows 3–5 to
    /// its angular velocity, both in the base's axes (Pinocchio's `LOCAL_WORLD_ALIGNED`), or in
    /// the frame's own axes with `local=True` (`LOCAL`). The run-time model, for every robot.
    #[pyo3(signature = (q, name, local=false))]
    fn frame_jacobian<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        name: &str,
        local: bool,
    ) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let n = self.dof();
        let q = rows("q", q, n)?;
        self.per_frame_row(py, [&q], name, &[6, n], |model, [q], out| {
            let jacobian = if local { model.frame_jacobian_local(name, q)? } else { model.frame_jacobian(name, q)? };
            // Row-major: the transpose's column-major storage.
            out.copy_from_slice(jacobian.transpose().as_slice());
            Ok(())
        })
    }

    /// `J̇(q, q̇) q̇` of frame `name`, shape `(6,)` (`(n, 6)` for a batch): the classical
    /// acceleration of the frame's origin (m/s²) and its angular acceleration (rad/s²) at
    /// `q̈ = 0`, in the base's axes, so that the frame accelerates at `J q̈ + J̇ q̇`.
    fn frame_acceleration_bias<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        qd: &Bound<'py, PyAny>,
        name: &str,
    ) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let [q, qd] = same_rows([("q", q), ("qd", qd)], self.dof())?;
        self.per_frame_row(py, [&q, &qd], name, &[6], |model, [q, qd], out| {
            out.copy_from_slice(&model.frame_acceleration_bias(name, q, qd)?);
            Ok(())
        })
    }

    /// `(∂q̈/∂q, ∂q̈/∂q̇, M⁻¹)` of forward dynamics at `(q, q̇, τ)`, each `(dof, dof)` (`(n, dof,
    /// dof)` for a batch), row `i` being `∂q̈_i`: `−M⁻¹ ∂ID/∂q` and `−M⁻¹ ∂ID/∂q̇` at
    /// `q̈ = FD(q, q̇, τ)`, and `M⁻¹ = ∂q̈/∂τ`.
    fn forward_dynamics_derivatives<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        qd: &Bound<'py, PyAny>,
        tau: &Bound<'py, PyAny>,
    ) -> PyResult<[Array<'py>; 3]> {
        let n = self.dof();
        let [q, qd, tau] = same_rows([("q", q), ("qd", qd), ("tau", tau)], n)?;
        let one = |d: &(dyn SliceDynamics + Sync), [q, qd, tau]: [&[f64]; 3], k: usize, out: &mut [f64]| {
            let (by_q, rest) = out.split_at_mut(n * n);
            let (by_qd, inverse) = rest.split_at_mut(n * n);
            d.forward_dynamics_derivatives_into(row(q, k, n), row(qd, k, n), row(tau, k, n), [by_q, by_qd, inverse])
                .map_err(|e| format!("row {k}: {e}"))
        };
        let batch = |d: &(dyn SliceDynamics + Sync), [q, qd, tau]: [&[f64]; 3], out: &mut [f64]| {
            d.forward_dynamics_derivatives_rows(q, qd, tau, out)
        };
        let out = self.compute(py, [&q, &qd, &tau], ("forward_dynamics_derivatives", 3 * n * n), batch, one)?;
        let part = |p: usize| -> Vec<f64> {
            out.chunks(3 * n * n).flat_map(|state| state[p * n * n..(p + 1) * n * n].iter().copied()).collect()
        };
        Ok([
            output(py, part(0), q.count, q.batched, &[n, n])?,
            output(py, part(1), q.count, q.batched, &[n, n])?,
            output(py, part(2), q.count, q.batched, &[n, n])?,
        ])
    }
}

impl Model {
    /// For every row of `inputs`, `f(model, row's values, out)` writing `shape`'s numbers, on
    /// copies without the GIL; frame `name` checked first by the model (a `KeyError` listing
    /// the frames).
    fn per_frame_row<'py, const K: usize>(
        &self,
        py: Python<'py>,
        inputs: [&Rows<'py>; K],
        name: &str,
        shape: &[usize],
        f: impl Fn(&TreeModel, [&[f64]; K], &mut [f64]) -> Result<(), hya_core::model::ModelError> + Send + Sync,
    ) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        self.model.frame(name).map_err(|e| PyKeyError::new_err(e.to_string()))?;
        let (n, width) = (self.dof(), shape.iter().product::<usize>());
        let (count, batched) = (inputs[0].count, inputs[0].batched);
        let mut copies: [Cow<'_, [f64]>; K] = std::array::from_fn(|_| Cow::Borrowed(&[][..]));
        for (copy, rows) in copies.iter_mut().zip(inputs) {
            *copy = rows.detached()?;
        }
        let model = &self.model;
        let out = py.allow_threads(|| -> PyResult<Vec<f64>> {
            let mut out = vec![0.0; count * width];
            for (k, chunk) in out.chunks_mut(width.max(1)).enumerate() {
                let values = copies.each_ref().map(|copy| row(copy, k, n));
                f(model, values, chunk).map_err(|e| PyValueError::new_err(format!("row {k}: {e}")))?;
            }
            Ok(out)
        })?;
        finite_results("frame", &out, width, batched)?;
        output(py, out, count, batched, shape)
    }
}
