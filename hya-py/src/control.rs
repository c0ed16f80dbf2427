//! The computed-torque controller with disturbance compensation.

use hya_core::dispatch::ForJoints;
use hya_core::erased::SliceController;
use hya_core::{ComputedTorque as CoreComputedTorque, Gains, JointVector};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::model::Model;
use crate::value_error;

struct BuildController<'a> {
    model: &'a Model,
    kp: &'a [f64],
    kd: &'a [f64],
    limit: Option<&'a [f64]>,
    friction: Option<&'a hya_ident::JointFriction>,
}

impl ForJoints for BuildController<'_> {
    type Output = PyResult<Box<dyn SliceController>>;
    fn call<const N: usize>(self) -> Self::Output {
        let setup = |e: hya_core::Error| PyValueError::new_err(format!("ComputedTorque: {e}"));
        let array = |x: &[f64]| -> [f64; N] { core::array::from_fn(|i| x[i]) };
        let gains = Gains::diagonal(array(self.kp), array(self.kd)).map_err(setup)?;
        let mut controller = CoreComputedTorque::new(self.model.nominal_with::<N>(self.friction)?, gains);
        if let Some(limit) = self.limit {
            controller = controller.with_torque_limit(JointVector::from_column_slice(limit)).map_err(setup)?;
        }
        Ok(Box::new(controller))
    }
}

/// The computed-torque controller with disturbance compensation (the paper's section IV):
///
///     τ = M(q) q̈_des + C(q, q̇) + G(q) − K_D (q̇ − q̇_des) − K_P (q − q_des) − d̂
///
/// with diagonal gains kp (N·m/rad) and kd (N·m·s/rad), and per-joint torque limits (N·m) if
/// given. With `friction` (a `friction.toml` from `hya identify`), the model is
/// ID + τ_f(q̇) + I_a q̈: the friction a feed-forward at the measured velocity, as a scenario's
/// `controller.friction_toml` makes it.
#[pyclass(module = "hya")]
pub struct ComputedTorque {
    dof: usize,
    inner: Box<dyn SliceController>,
}

#[pymethods]
impl ComputedTorque {
    #[new]
    #[pyo3(signature = (model, kp, kd, torque_limit=None, friction=None))]
    fn new(
        model: &Model,
        kp: Vec<f64>,
        kd: Vec<f64>,
        torque_limit: Option<Vec<f64>>,
        friction: Option<std::path::PathBuf>,
    ) -> PyResult<Self> {
        let friction = model.friction_file(friction)?;
        let n = model.dof_count();
        for (name, list) in [("kp", Some(&kp)), ("kd", Some(&kd)), ("torque_limit", torque_limit.as_ref())] {
            if let Some(list) = list.filter(|l| l.len() != n) {
                return Err(PyValueError::new_err(format!("{name}: {} values, expected {n}", list.len())));
            }
        }
        let build =
            BuildController { model, kp: &kp, kd: &kd, limit: torque_limit.as_deref(), friction: friction.as_ref() };
        let inner = crate::model::for_joints(n, build)?;
        Ok(Self { dof: n, inner })
    }

    /// The commanded torque (N·m) at the measured (q, qd) for the reference (q_des, qd_des,
    /// qdd_des; the last two zero if omitted), minus d_hat if given.
    #[pyo3(signature = (q, qd, q_des, qd_des=None, qdd_des=None, d_hat=None))]
    #[allow(clippy::too_many_arguments)]
    fn command(
        &self,
        q: Vec<f64>,
        qd: Vec<f64>,
        q_des: Vec<f64>,
        qd_des: Option<Vec<f64>>,
        qdd_des: Option<Vec<f64>>,
        d_hat: Option<Vec<f64>>,
    ) -> PyResult<Vec<f64>> {
        let n = self.dof;
        let zeros = vec![0.0; n];
        let (qd_des, qdd_des) = (qd_des.unwrap_or_else(|| zeros.clone()), qdd_des.unwrap_or_else(|| zeros.clone()));
        let args = [("q", &q), ("qd", &qd), ("q_des", &q_des), ("qd_des", &qd_des), ("qdd_des", &qdd_des)];
        for (name, list) in args.into_iter().chain(d_hat.as_ref().map(|d| ("d_hat", d))) {
            if list.len() != n {
                return Err(PyValueError::new_err(format!("{name}: {} values, expected {n}", list.len())));
            }
        }
        let mut tau = vec![0.0; n];
        self.inner.command([&q, &qd], [&q_des, &qd_des, &qdd_des], d_hat.as_deref(), &mut tau).map_err(value_error)?;
        Ok(tau)
    }
}
