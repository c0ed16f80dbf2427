//! The joint count fixed once: a model of `N` joints behind an object-safe trait whose methods
//! take slices of the checked length, and the estimators, observers and controllers it makes
//! behind hya-core's own slice traits (`hya_core::erased`), so that per-call work is the
//! const-generic code of hya-core with no allocation and no further dispatch on `N`.

use std::sync::Arc;

use hya_core::control::PdPlacement;
use hya_core::dispatch::{with_joints, ForJoints};
use hya_core::erased::{Boxed, SliceCartesian, SliceController, SliceObserver};
use hya_core::model::TreeModel;
use hya_core::observers::{ExtendedStateObserver, MomentumObserver, NonlinearDisturbanceObserver};
use hya_core::{
    CartesianImpedance, ComputedTorque, DisturbanceEstimator, Dynamics, Error, FilterParams, FrameImpedance, Gains,
    Impedance, JointVector, OnSlicesN, SliceDynamics, TimedEstimator, TreeFrame,
};
use hya_ident::{JointFriction, WithFriction};
use hya_robots::{with_arm, Arm, ForArm};

use crate::status::Failure;

/// Dynamics shared by a model and the estimators, observers and controllers made from it.
type Shared<const N: usize> = Arc<dyn Dynamics<N> + Send + Sync>;

/// A model whose joint count is fixed. Every slice has the model's length (checked by the
/// caller), so the conversions below cannot fail.
pub(crate) trait ArmModel: Send {
    /// Joint count.
    fn dof(&self) -> usize;
    /// The model's dynamics on slices: one state (`*_into`) or rows of states (`*_rows`: a
    /// shipped arm's generated batches in SIMD lanes, a URDF's one call per state).
    fn slices(&self) -> &dyn SliceDynamics;
    /// The paper's estimator started at rest at `(q0, τ0)`: stepped at `params`' sample time, or,
    /// given a start time `t0`, over timestamped samples.
    fn estimator(
        &self,
        params: FilterParams,
        t0: Option<f64>,
        q0: &[f64],
        tau0: &[f64],
    ) -> Result<Box<dyn SliceObserver>, Error>;
    /// One of the observers the paper compares against.
    fn observer(&self, spec: ObserverSpec<'_>) -> Result<Box<dyn SliceObserver>, Error>;
    /// A computed-torque controller with diagonal gains.
    fn controller(&self, kp: &[f64], kd: &[f64], placement: PdPlacement) -> Result<Box<dyn SliceController>, Error>;
    /// The Cartesian impedance controller on `tree`'s frame `frame` (its last link when `None`).
    fn cartesian(
        &self,
        tree: &TreeModel,
        frame: Option<&str>,
        gains: CartesianGains<'_>,
    ) -> Result<Box<dyn SliceCartesian>, Failure>;
    /// This model with the identified joint law added (`hya_ident::WithFriction`), the friction
    /// checked for this model's joints by its reader.
    fn with_friction(&self, friction: JointFriction) -> Box<dyn ArmModel>;
}

/// The Cartesian impedance controller's settings as C gives them: the spring and damper at the
/// frame, the posture's rest, spring and damper (all or none), the projector's damping `μ`
/// (checked by `hya_core::Impedance::from_slices`) and the torque limits, if any.
pub(crate) struct CartesianGains<'a> {
    pub(crate) stiffness: &'a [f64],
    pub(crate) damping: &'a [f64],
    pub(crate) posture: [Option<&'a [f64]>; 3],
    pub(crate) regularisation: f64,
    pub(crate) torque_limit: Option<&'a [f64]>,
}

/// Which baseline observer to make, with its parameters (slices of the model's length).
pub(crate) enum ObserverSpec<'a> {
    /// Chen's nonlinear disturbance observer, `Y = y I`.
    Nonlinear { gain: f64, dt_s: f64, qd0: &'a [f64] },
    /// The generalised-momentum observer with per-joint gains.
    Momentum { gain: &'a [f64], dt_s: f64, q0: &'a [f64], qd0: &'a [f64], tau0: &'a [f64] },
    /// The extended-state observer of bandwidth `ω`.
    ExtendedState { bandwidth_rad_s: f64, dt_s: f64, q0: &'a [f64] },
}

fn v<const N: usize>(values: &[f64]) -> JointVector<N> {
    JointVector::from_column_slice(values)
}

/// A model of `N` joints: its dynamics (shared with the estimators, observers and controllers it
/// makes) seen on slices.
struct Fixed<const N: usize>(OnSlicesN<N, Shared<N>>);

impl<const N: usize> Fixed<N> {
    fn new(dynamics: Shared<N>) -> Self {
        Self(OnSlicesN(dynamics))
    }

    /// The dynamics, for what the model makes.
    fn dynamics(&self) -> Shared<N> {
        self.0 .0.clone()
    }
}

impl<const N: usize> ArmModel for Fixed<N> {
    fn dof(&self) -> usize {
        N
    }
    fn slices(&self) -> &dyn SliceDynamics {
        &self.0
    }
    fn estimator(
        &self,
        params: FilterParams,
        t0: Option<f64>,
        q0: &[f64],
        tau0: &[f64],
    ) -> Result<Box<dyn SliceObserver>, Error> {
        let dynamics = self.dynamics();
        Ok(match t0 {
            None => Box::new(DisturbanceEstimator::new(dynamics, params, v(q0), v(tau0))?),
            Some(t0) => Box::new(TimedEstimator::new(dynamics, params, t0, v(q0), v(tau0))?),
        })
    }
    fn observer(&self, spec: ObserverSpec<'_>) -> Result<Box<dyn SliceObserver>, Error> {
        let dynamics = self.dynamics();
        Ok(match spec {
            ObserverSpec::Nonlinear { gain, dt_s, qd0 } => {
                Box::new(Boxed(Box::new(NonlinearDisturbanceObserver::new(dynamics, gain, dt_s, v(qd0))?)))
            }
            ObserverSpec::Momentum { gain, dt_s, q0, qd0, tau0 } => {
                let observer = MomentumObserver::new(dynamics, v(gain), dt_s, v(q0), v(qd0), v(tau0))?;
                Box::new(Boxed(Box::new(observer)))
            }
            ObserverSpec::ExtendedState { bandwidth_rad_s, dt_s, q0 } => {
                Box::new(Boxed(Box::new(ExtendedStateObserver::new(dynamics, bandwidth_rad_s, dt_s, v(q0))?)))
            }
        })
    }
    fn controller(&self, kp: &[f64], kd: &[f64], placement: PdPlacement) -> Result<Box<dyn SliceController>, Error> {
        let mut gains = [[0.0; N]; 2];
        gains[0].copy_from_slice(kp);
        gains[1].copy_from_slice(kd);
        let gains = Gains::diagonal(gains[0], gains[1])?;
        Ok(Box::new(ComputedTorque::new(self.dynamics(), gains).with_placement(placement)))
    }
    fn cartesian(
        &self,
        tree: &TreeModel,
        frame: Option<&str>,
        gains: CartesianGains<'_>,
    ) -> Result<Box<dyn SliceCartesian>, Failure> {
        let impedance =
            Impedance::<N>::from_slices(gains.stiffness, gains.damping, gains.posture, gains.regularisation)?;
        let mut controller = CartesianImpedance::new(self.dynamics(), impedance);
        if let Some(limit) = gains.torque_limit {
            controller = controller.with_torque_limit(v(limit))?;
        }
        let frame = TreeFrame::<N>::new(tree.clone(), frame).map_err(Failure::Model)?;
        Ok(Box::new(FrameImpedance::new(controller, frame)))
    }
    fn with_friction(&self, friction: JointFriction) -> Box<dyn ArmModel> {
        Box::new(Fixed::<N>::new(Arc::new(WithFriction::new(self.dynamics(), friction))))
    }
}

/// The shipped arm called `name`: its generated code.
pub(crate) fn shipped(name: &str) -> Result<Box<dyn ArmModel>, Failure> {
    struct Generated;
    impl ForArm for Generated {
        type Output = Box<dyn ArmModel>;
        fn call<const N: usize>(self, arm: Arm<N>) -> Box<dyn ArmModel> {
            Box::new(Fixed::<N>::new(Arc::new(arm.nominal)))
        }
    }
    with_arm(name, Generated).ok_or_else(|| Failure::UnknownArm(name.to_owned()))
}

/// Any loaded model: the run-time kinematic tree.
pub(crate) fn tree(model: TreeModel) -> Result<Box<dyn ArmModel>, Failure> {
    struct Tree(TreeModel);
    impl ForJoints for Tree {
        type Output = Result<Box<dyn ArmModel>, Failure>;
        fn call<const N: usize>(self) -> Self::Output {
            let dynamics = self.0.into_dynamics::<N>().map_err(Failure::Model)?;
            Ok(Box::new(Fixed::<N>::new(Arc::new(dynamics))))
        }
    }
    let (name, dof) = (model.name().to_owned(), model.dof());
    with_joints(dof, Tree(model)).unwrap_or(Err(Failure::JointCount { model: name, dof }))
}
