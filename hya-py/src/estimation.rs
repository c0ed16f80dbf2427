//! The disturbance estimator of Lu, Sandy & Buchli and the observers it is compared with,
//! stepped one tick per call or run over a whole log.

use hya_core::erased::{self, SliceObserver};
use hya_core::{FilterParams, JointVector, Measurement, ObserverDesign};
use std::sync::{Mutex, PoisonError};

use hya_core::dispatch::ForJoints;
use numpy::PyArrayDyn;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::arrays::{checked, converted, output, row, rows, same_count, Rows};
use crate::model::Model;
use crate::value_error;

/// Builds an observer for `N` joints on the nominal model of `robot`.
struct Build<'a> {
    design: ObserverDesign,
    model: &'a Model,
    /// The identified joint law added to the model, if any.
    friction: Option<&'a hya_ident::JointFriction>,
    /// The first sample's time, for the paper's estimator over timestamped samples.
    t0: Option<f64>,
    q0: &'a [f64],
    qd0: &'a [f64],
    tau0: &'a [f64],
}

impl ForJoints for Build<'_> {
    type Output = PyResult<Box<dyn SliceObserver>>;
    fn call<const N: usize>(self) -> Self::Output {
        let nominal = self.model.nominal_with::<N>(self.friction)?;
        let first = Measurement {
            position: JointVector::from_column_slice(self.q0),
            velocity: Some(JointVector::from_column_slice(self.qd0)),
            torque: JointVector::from_column_slice(self.tau0),
        };
        erased::observer(&self.design, nominal, &first, self.t0)
            .map_err(|e| PyValueError::new_err(format!("the observer: {e}")))
    }
}

/// One sample: at its time `t` for an estimator built with `t0`, else at the fixed period.
fn step(
    observer: &mut dyn SliceObserver,
    t: Option<f64>,
    (q, qd, tau): (&[f64], Option<&[f64]>, &[f64]),
    d_hat: &mut [f64],
) -> Result<(), String> {
    match (t, observer.is_timed()) {
        (None, false) => observer.update(q, qd, tau, d_hat).map_err(|e| e.to_string()),
        (Some(t), true) => observer.update_at(t, q, tau, d_hat).map(drop).map_err(|e| e.to_string()),
        (Some(_), false) => {
            Err("t: this estimator was built without t0; pass t0 to the constructor to give samples times".into())
        }
        (None, true) => Err("t: this estimator was built with t0, so every sample needs its time t".into()),
    }
}

/// Steps `observer` over every row of a log (rows of `n`), without the GIL; `d̂` for every row.
fn run_log(
    py: Python<'_>,
    observer: &mut dyn SliceObserver,
    n: usize,
    (q, qd, tau): (&[f64], Option<&[f64]>, &[f64]),
    t: Option<&[f64]>,
) -> PyResult<Vec<f64>> {
    py.allow_threads(|| {
        let mut out = vec![0.0; q.len()];
        for (k, d_hat) in out.chunks_mut(n.max(1)).enumerate() {
            let (q, tau) = (row(q, k, n), row(tau, k, n));
            step(observer, t.map(|t| t[k]), (q, qd.map(|v| row(v, k, n)), tau), d_hat)
                .map_err(|e| PyValueError::new_err(format!("row {k}: {e}")))?;
        }
        Ok(out)
    })
}

/// The shared body of every observer class: the model's joint count and the observer (which
/// itself refuses an update without the velocity it needs).
struct ObserverCore {
    dof: usize,
    /// Behind a mutex only to be `Sync`, as Python classes must be: every use holds `&mut`.
    inner: Mutex<Box<dyn SliceObserver>>,
}

impl ObserverCore {
    #[allow(clippy::too_many_arguments)]
    fn new(
        model: &Model,
        design: ObserverDesign,
        friction: Option<hya_ident::JointFriction>,
        t0: Option<f64>,
        q0: Option<&Bound<'_, PyAny>>,
        qd0: Option<&Bound<'_, PyAny>>,
        tau0: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let n = model.dof_count();
        let vector = |name: &'static str, value: Option<&Bound<'_, PyAny>>| -> PyResult<Option<Vec<f64>>> {
            value.map(|v| rows(name, v, n)?.one_row().map(<[f64]>::to_vec)).transpose()
        };
        let q0 = vector("q0", q0)?.unwrap_or_else(|| vec![0.0; n]);
        let qd0 = vector("qd0", qd0)?.unwrap_or_else(|| vec![0.0; n]);
        let tau0 = match vector("tau0", tau0)? {
            Some(tau0) => tau0,
            None => model.gravity_of(&q0),
        };
        let build = Build { design, model, friction: friction.as_ref(), t0, q0: &q0, qd0: &qd0, tau0: &tau0 };
        let inner = crate::model::for_joints(n, build)?;
        Ok(Self { dof: n, inner: Mutex::new(inner) })
    }

    fn observer(&mut self) -> &mut dyn SliceObserver {
        self.inner.get_mut().unwrap_or_else(PoisonError::into_inner).as_mut()
    }

    fn disturbance(&self) -> Vec<f64> {
        let mut d_hat = vec![0.0; self.dof];
        // The slice has the observer's joint count: nothing to refuse.
        let _ = self.inner.lock().unwrap_or_else(PoisonError::into_inner).disturbance(&mut d_hat);
        d_hat
    }

    fn update<'py>(
        &mut self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        tau: &Bound<'py, PyAny>,
        qd: Option<&Bound<'py, PyAny>>,
        t: Option<f64>,
    ) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let n = self.dof;
        let (q, tau, qd) = measurements(["q", "tau", "qd"], (q, tau, qd), n)?;
        let (q, tau, qd) = (q.one_row()?, tau.one_row()?, qd.as_ref().map(Rows::one_row).transpose()?);
        let mut d_hat = vec![0.0; n];
        step(self.observer(), t, (q, qd, tau), &mut d_hat).map_err(PyValueError::new_err)?;
        output(py, d_hat, 1, false, &[n])
    }

    fn run<'py>(
        &mut self,
        py: Python<'py>,
        q_log: &Bound<'py, PyAny>,
        tau_log: &Bound<'py, PyAny>,
        qd_log: Option<&Bound<'py, PyAny>>,
        t: Option<Vec<f64>>,
    ) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let n = self.dof;
        let (q, tau, qd) = measurements(["q_log", "tau_log", "qd_log"], (q_log, tau_log, qd_log), n)?;
        same_count([Some(&q), Some(&tau), qd.as_ref()].into_iter().flatten())?;
        if let Some(t) = t.as_ref().filter(|t| t.len() != q.count) {
            return Err(PyValueError::new_err(format!("t: {} times, but q_log has {} rows", t.len(), q.count)));
        }
        // Copies of arrays read in place, as the GIL is released.
        let (q_log, tau_log) = (q.detached()?, tau.detached()?);
        let qd_log = qd.as_ref().map(Rows::detached).transpose()?;
        let out = run_log(py, self.observer(), n, (&q_log, qd_log.as_deref(), &tau_log), t.as_deref())?;
        output(py, out, q.count, true, &[n])
    }
}

/// The measured joint angles, torques and (optional) velocities of an observer's `update` or
/// `run`, under the caller's argument names: every argument converted before any is checked, as
/// a conversion can run Python code that writes into an array already read in place.
fn measurements<'py>(
    names: [&'static str; 3],
    (q, tau, qd): (&Bound<'py, PyAny>, &Bound<'py, PyAny>, Option<&Bound<'py, PyAny>>),
    width: usize,
) -> PyResult<(Rows<'py>, Rows<'py>, Option<Rows<'py>>)> {
    let (q, tau) = (converted(names[0], q, width)?, converted(names[1], tau, width)?);
    let qd = qd.map(|v| converted(names[2], v, width)).transpose()?;
    checked([Some(&q), Some(&tau), qd.as_ref()].into_iter().flatten())?;
    Ok((q, tau, qd))
}

/// The disturbance estimator of Lu, Sandy & Buchli, "Nonlinear disturbance attenuation control
/// of hydraulic robotics" (the paper's section III):
///
///     d̂ = ID(q̂, q̂̇, q̂̈) − τ̂,   ID(q, q̇, q̈) = M(q) q̈ + C(q, q̇) + G(q)
///
/// where (q̂, q̂̇, q̂̈) are the states of the third-order filter
///
///     H(s) = ω1 ω2² / ((s + ω1)(s² + 2 ζ ω2 s + ω2²))
///
/// driven by the measured joint angles q (rad), and τ̂ the output of an identical filter driven
/// by the measured joint torques τ (N·m): no numerical differentiation. d̂ (N·m) estimates
/// d = M q̈ + C + G − τ, everything acting on the joints besides the actuators (friction, loads,
/// model error), seen through the filter; the controller subtracts it (`ComputedTorque`).
///
/// Args:
///     model: a hya.Model; the estimator runs on it as loaded (a shipped arm's generated code,
///         or the URDF's run-time model).
///     zeta, omega1, omega2: the filter's damping ratio and corner frequencies, rad/s
///         (the paper's 0.8, 50, 50 by default).
///     dt: the control period, s (0.001).
///     q0, tau0: the state the estimator starts at rest in (zeros, and G(q0)).
///     t0: the time of that first sample, s, for a log with timestamps: then every `update`
///         and `run` takes its samples' times `t` (strictly increasing), and each step is
///         filtered exactly over its own length (first-order hold); a step longer than
///         100 / max(omega1, omega2) s (2 s by default) restarts the estimator at rest, any
///         shorter gap is bridged exactly (the samples either side joined by a straight line).
///     friction: a `friction.toml` from `hya identify` (or `hya.identify`'s friction written
///         out): d̂ is then what neither the rigid body nor that joint law explains,
///         d̂ + τ_f(q̂̇) + I_a q̂̈, as `hya estimate --friction` gives it.
#[pyclass(module = "hya")]
pub struct DisturbanceEstimator {
    core: ObserverCore,
}

#[pymethods]
impl DisturbanceEstimator {
    #[new]
    #[pyo3(signature = (model, zeta=0.8, omega1=50.0, omega2=50.0, dt=0.001, q0=None, tau0=None, t0=None, friction=None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        model: &Model,
        zeta: f64,
        omega1: f64,
        omega2: f64,
        dt: f64,
        q0: Option<&Bound<'_, PyAny>>,
        tau0: Option<&Bound<'_, PyAny>>,
        t0: Option<f64>,
        friction: Option<std::path::PathBuf>,
    ) -> PyResult<Self> {
        let params = FilterParams::new(zeta, omega1, omega2, dt).map_err(value_error)?;
        let friction = model.friction_file(friction)?;
        let core = ObserverCore::new(model, ObserverDesign::Paper(params), friction, t0, q0, None, tau0)?;
        Ok(Self { core })
    }

    /// One control tick: filters the measured angles q (rad) and torques tau (N·m) and
    /// returns the new d̂ (N·m). A non-finite input raises ValueError and changes nothing.
    /// With t0 given at construction, t (s) is the sample's time, after the previous one's.
    #[pyo3(signature = (q, tau, t=None))]
    fn update<'py>(
        &mut self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        tau: &Bound<'py, PyAny>,
        t: Option<f64>,
    ) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        self.core.update(py, q, tau, None, t)
    }

    /// Steps every row of a log (shape (T, dof) each, one row per control tick, or one row
    /// per time of t, shape (T,), with t0 given at construction) from the current state, as
    /// `update` row by row would, and returns d̂ for every row, (T, dof).
    #[pyo3(signature = (q_log, tau_log, t=None))]
    fn run<'py>(
        &mut self,
        py: Python<'py>,
        q_log: &Bound<'py, PyAny>,
        tau_log: &Bound<'py, PyAny>,
        t: Option<Vec<f64>>,
    ) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        self.core.run(py, q_log, tau_log, None, t)
    }

    /// The latest d̂, N·m.
    #[getter]
    fn disturbance(&self) -> Vec<f64> {
        self.core.disturbance()
    }
}

/// Declares an observer class: its paper, its constructor's extra parameter, and whether it
/// reads velocities.
macro_rules! observer_class {
    ($(#[$doc:meta])* $name:ident, $design:expr) => {
        $(#[$doc])*
        #[pyclass(module = "hya")]
        pub struct $name {
            core: ObserverCore,
        }

        #[pymethods]
        impl $name {
            #[new]
            #[pyo3(signature = (model, bandwidth=50.0, dt=0.001, q0=None, qd0=None, tau0=None))]
            fn new(
                model: &Model,
                bandwidth: f64,
                dt: f64,
                q0: Option<&Bound<'_, PyAny>>,
                qd0: Option<&Bound<'_, PyAny>>,
                tau0: Option<&Bound<'_, PyAny>>,
            ) -> PyResult<Self> {
                let design: fn(f64, f64) -> ObserverDesign = $design;
                let core = ObserverCore::new(model, design(bandwidth, dt), None, None, q0, qd0, tau0)?;
                Ok(Self { core })
            }

            /// One control tick from the measured angles q (rad), torques tau (N·m) and, where
            /// the observer needs them, velocities qd (rad/s); returns the new d̂ (N·m).
            #[pyo3(signature = (q, tau, qd=None))]
            fn update<'py>(
                &mut self,
                py: Python<'py>,
                q: &Bound<'py, PyAny>,
                tau: &Bound<'py, PyAny>,
                qd: Option<&Bound<'py, PyAny>>,
            ) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
                self.core.update(py, q, tau, qd, None)
            }

            /// Steps every row of a log ((T, dof) each) and returns d̂ for every row.
            #[pyo3(signature = (q_log, tau_log, qd_log=None))]
            fn run<'py>(
                &mut self,
                py: Python<'py>,
                q_log: &Bound<'py, PyAny>,
                tau_log: &Bound<'py, PyAny>,
                qd_log: Option<&Bound<'py, PyAny>>,
            ) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
                self.core.run(py, q_log, tau_log, qd_log, None)
            }

            /// The latest d̂, N·m.
            #[getter]
            fn disturbance(&self) -> Vec<f64> {
                self.core.disturbance()
            }
        }
    };
}

observer_class!(
    /// The generalized-momentum observer (De Luca & Mattone, ICRA 2003; Haddadin et al.,
    /// T-RO 2017), per-joint gain K_O = bandwidth (1/s):
    ///
    ///     p = M(q) q̇,   r = K_O (p − ∫(τ + Cᵀq̇ − G + r) dt − p0),   d̂ = r = K_O / (s + K_O) d
    ///
    /// It reads measured velocities (qd).
    MomentumObserver,
    |bandwidth_rad_s, dt_s| ObserverDesign::Momentum { bandwidth_rad_s, dt_s }
);

observer_class!(
    /// The nonlinear disturbance observer of Chen et al. (IEEE TIE 47(4), 2000) in the general
    /// form of Mohammadi et al. (2013), with hya's gain Y = β M(q0), β = bandwidth (1/s)
    /// (Mohammadi's own design is a scalar Y = y I):
    ///
    ///     p = Y q̇,   L = Y M⁻¹(q),   ż = −L z + L (C + G − τ − p),   d̂ = z + p
    ///
    /// so d̂ converges to d at rate β near q0 (equal bandwidth with the other observers). It
    /// reads measured velocities (qd).
    NonlinearDisturbanceObserver,
    |bandwidth_rad_s, dt_s| ObserverDesign::Nonlinear { bandwidth_rad_s, dt_s, gain: Default::default() }
);

observer_class!(
    /// The model-assisted extended-state observer (Han; Gao's bandwidth parameterisation), per
    /// joint, all three poles at −ω, ω = bandwidth (rad/s):
    ///
    ///     ż1 = z2 + 3ω (q − z1),   ż2 = z3 + [M⁻¹(τ − C − G)]_i + 3ω² (q − z1),
    ///     ż3 = ω³ (q − z1),   d̂ = M(q) z3
    ///
    /// Like the paper's method it needs only the angles q, not velocities.
    ExtendedStateObserver,
    |bandwidth_rad_s, dt_s| ObserverDesign::ExtendedState { bandwidth_rad_s, dt_s }
);
