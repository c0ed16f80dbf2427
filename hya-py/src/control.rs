//! The computed-torque controller and the Cartesian impedance controller, both with disturbance
//! compensation.

use std::sync::{Mutex, PoisonError};

use hya_core::dispatch::ForJoints;
use hya_core::erased::{SliceCartesian, SliceController};
use hya_core::{
    CartesianImpedance as CoreCartesianImpedance, ComputedTorque as CoreComputedTorque, FrameImpedance, Gains,
    Impedance, JointVector, TreeFrame,
};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::model::Model;
use crate::value_error;

/// `Err` naming the first of `lists` that does not hold `n` values.
fn lengths<'a>(n: usize, lists: impl IntoIterator<Item = (&'a str, &'a [f64])>) -> PyResult<()> {
    match lists.into_iter().find(|(_, list)| list.len() != n) {
        Some((name, list)) => Err(PyValueError::new_err(format!("{name}: {} values, expected {n}", list.len()))),
        None => Ok(()),
    }
}

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
        let limit = torque_limit.as_deref().map(|l| ("torque_limit", l));
        lengths(n, [("kp", kp.as_slice()), ("kd", kd.as_slice())].into_iter().chain(limit))?;
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
        let args = args.into_iter().map(|(name, list)| (name, list.as_slice()));
        lengths(n, args.chain(d_hat.as_deref().map(|d| ("d_hat", d))))?;
        let mut tau = vec![0.0; n];
        self.inner.command([&q, &qd], [&q_des, &qd_des, &qdd_des], d_hat.as_deref(), &mut tau).map_err(value_error)?;
        Ok(tau)
    }
}

struct BuildCartesian<'a> {
    model: &'a Model,
    frame: Option<&'a str>,
    gains: [&'a [f64]; 2],
    posture: [Option<&'a [f64]>; 3],
    regularisation: f64,
    limit: Option<&'a [f64]>,
}

impl ForJoints for BuildCartesian<'_> {
    type Output = PyResult<Box<dyn SliceCartesian>>;
    fn call<const N: usize>(self) -> Self::Output {
        let setup = |e: hya_core::Error| PyValueError::new_err(format!("CartesianImpedance: {e}"));
        let [stiffness, damping] = self.gains;
        let gains =
            Impedance::<N>::from_slices(stiffness, damping, self.posture, self.regularisation).map_err(setup)?;
        let mut controller = CoreCartesianImpedance::new(self.model.nominal::<N>()?, gains);
        if let Some(limit) = self.limit {
            controller = controller.with_torque_limit(JointVector::from_column_slice(limit)).map_err(setup)?;
        }
        let frame = TreeFrame::<N>::new(self.model.tree().clone(), self.frame)
            .map_err(|e| PyValueError::new_err(format!("CartesianImpedance: {e}")))?;
        Ok(Box::new(FrameImpedance::new(controller, frame)))
    }
}

/// Cartesian impedance control of one frame of the arm with the paper's compensation:
///
///     τ = Jᵀ (K_x e − D_x (J q̇ − ẋ_des)) + C(q, q̇) + G(q) − d̂ + P (−K_n (q − q_rest) − D_n q̇)
///     e = (p_des − p, log(R_des Rᵀ)),   P = I − Jᵀ (J Jᵀ + μ² I)⁻¹ J
///
/// stiffness K_x and damping D_x: 6 values each (N/m, N·s/m for x, y, z in the base; then
/// N·m/rad, N·m·s/rad), non-negative; frame: any link of the description (default: the last);
/// posture_rest with posture_stiffness and posture_damping (per joint) hold the joints near a pose
/// in the task's null space; mu (m) damps the projector near singular poses; torque_limit
/// (N·m per joint) saturates the command. Poses, twists and Jacobians are in the base's axes,
/// linear parts first (Pinocchio's LOCAL_WORLD_ALIGNED). The law and the frame's kinematics
/// behind a command do not allocate (the Python call around them does).
#[pyclass(module = "hya")]
pub struct CartesianImpedance {
    dof: usize,
    /// Its frame's kinematics are computed into buffers it holds: one call at a time.
    inner: Mutex<Box<dyn SliceCartesian>>,
}

#[pymethods]
impl CartesianImpedance {
    #[new]
    #[pyo3(signature = (model, stiffness, damping, frame=None, posture_rest=None, posture_stiffness=None,
        posture_damping=None, mu=1e-3, torque_limit=None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        model: &Model,
        stiffness: Vec<f64>,
        damping: Vec<f64>,
        frame: Option<String>,
        posture_rest: Option<Vec<f64>>,
        posture_stiffness: Option<Vec<f64>>,
        posture_damping: Option<Vec<f64>>,
        mu: f64,
        torque_limit: Option<Vec<f64>>,
    ) -> PyResult<Self> {
        let n = model.dof_count();
        lengths(n, torque_limit.as_deref().map(|l| ("torque_limit", l)))?;
        let posture = [posture_rest.as_deref(), posture_stiffness.as_deref(), posture_damping.as_deref()];
        let build = BuildCartesian {
            model,
            frame: frame.as_deref(),
            gains: [&stiffness, &damping],
            posture,
            regularisation: mu,
            limit: torque_limit.as_deref(),
        };
        let inner = crate::model::for_joints(n, build)?;
        Ok(Self { dof: n, inner: Mutex::new(inner) })
    }

    /// The controlled frame's name.
    #[getter]
    fn frame(&self) -> String {
        self.inner.lock().unwrap_or_else(PoisonError::into_inner).frame().to_owned()
    }

    /// The commanded torque (N·m) at the measured (q, qd) for the frame's desired position
    /// (3 values, m), orientation (3 × 3 rotation whose columns are the frame's desired axes in
    /// the base's) and twist (6 values, m/s then rad/s; at rest if omitted), minus d_hat if given.
    #[pyo3(signature = (q, qd, position_des, orientation_des, twist_des=None, d_hat=None))]
    fn command(
        &self,
        q: Vec<f64>,
        qd: Vec<f64>,
        position_des: Vec<f64>,
        orientation_des: Vec<Vec<f64>>,
        twist_des: Option<Vec<f64>>,
        d_hat: Option<Vec<f64>>,
    ) -> PyResult<Vec<f64>> {
        let n = self.dof;
        let state = [("q", q.as_slice()), ("qd", qd.as_slice())];
        lengths(n, state.into_iter().chain(d_hat.as_deref().map(|d| ("d_hat", d))))?;
        if orientation_des.len() != 3 || orientation_des.iter().any(|row| row.len() != 3) {
            return Err(PyValueError::new_err("orientation_des: a 3 × 3 rotation matrix, expected"));
        }
        let rows: Vec<f64> = orientation_des.concat();
        let twist_des = twist_des.unwrap_or_else(|| vec![0.0; 6]);
        let mut tau = vec![0.0; n];
        let mut inner = self.inner.lock().unwrap_or_else(PoisonError::into_inner);
        inner
            .command([&q, &qd], [&position_des, &rows, &twist_des], d_hat.as_deref(), &mut tau)
            .map_err(value_error)?;
        Ok(tau)
    }
}
