//! The joint count fixed once: a model of `N` joints behind object-safe traits whose methods
//! take slices of the checked length, so that per-call work is the const-generic code of
//! hya-core with no allocation and no further dispatch on `N`.

use std::sync::Arc;

use hya_core::control::PdPlacement;
use hya_core::dispatch::{with_joints, ForJoints};
use hya_core::model::TreeModel;
use hya_core::observers::{
    DisturbanceObserver, ExtendedStateObserver, Measurement, MomentumObserver, NonlinearDisturbanceObserver,
};
use hya_core::{
    ComputedTorque, DisturbanceEstimator, Dynamics, Error, FilterParams, Gains, JointVector, Reference, TimedEstimator,
};
use hya_robots::{with_arm, Arm, ForArm};

use crate::status::Failure;

/// Dynamics shared by a model and the estimators, observers and controllers made from it.
type Shared<const N: usize> = Arc<dyn Dynamics<N> + Send + Sync>;

/// A model whose joint count is fixed. Every slice has the model's length (checked by the
/// caller), so the conversions below cannot fail.
pub(crate) trait ArmModel: Send {
    /// Joint count.
    fn dof(&self) -> usize;
    /// `τ = M(q) q̈ + C(q, q̇) + G(q)`.
    fn inverse_dynamics(&self, q: &[f64], qd: &[f64], qdd: &[f64], tau: &mut [f64]);
    /// `M(q)`, `n × n`, symmetric.
    fn mass_matrix(&self, q: &[f64], mass: &mut [f64]);
    /// `G(q)`.
    fn gravity(&self, q: &[f64], tau: &mut [f64]);
    /// `q̈ = M(q)⁻¹ (τ − C(q, q̇) − G(q))`.
    fn forward_dynamics(&self, q: &[f64], qd: &[f64], tau: &[f64], qdd: &mut [f64]) -> Result<(), Error>;
    /// The paper's estimator started at rest at `(q0, τ0)`: stepped at `params`' sample time, or,
    /// given a start time `t0`, over timestamped samples.
    fn estimator(
        &self,
        params: FilterParams,
        t0: Option<f64>,
        q0: &[f64],
        tau0: &[f64],
    ) -> Result<Box<dyn Estimate>, Error>;
    /// One of the observers the paper compares against.
    fn observer(&self, spec: ObserverSpec<'_>) -> Result<Box<dyn Observe>, Error>;
    /// A computed-torque controller with diagonal gains.
    fn controller(&self, kp: &[f64], kd: &[f64], placement: PdPlacement) -> Result<Box<dyn Control>, Error>;
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

/// The paper's estimator on slices, stepped at its fixed sample time or by timestamps.
pub(crate) trait Estimate: Send {
    /// One step of the fixed sample time with measured `q`, `τ`; writes the new `d̂`.
    fn update(&mut self, q: &[f64], tau: &[f64], d_hat: &mut [f64]) -> Result<(), Failure>;
    /// The sample at time `t` with measured `q`, `τ`; writes the new `d̂` and says whether the
    /// step was a gap too long to bridge (the estimator restarted at rest).
    fn update_at(&mut self, t: f64, q: &[f64], tau: &[f64], d_hat: &mut [f64]) -> Result<bool, Failure>;
    /// The latest `d̂`.
    fn disturbance(&self, d_hat: &mut [f64]);
    /// Restarts at rest at `(q0, τ0)` (a timed estimator: at the latest sample's time).
    fn reset(&mut self, q0: &[f64], tau0: &[f64]) -> Result<(), Failure>;
}

/// A baseline observer on slices.
pub(crate) trait Observe: Send {
    /// One tick with measured `q`, optionally `q̇`, and `τ`; writes the new `d̂`.
    fn update(&mut self, q: &[f64], qd: Option<&[f64]>, tau: &[f64], d_hat: &mut [f64]) -> Result<(), Error>;
}

/// The computed-torque law on slices.
pub(crate) trait Control: Send {
    /// The commanded torque for the state, the reference and, if given, `d̂`.
    fn command(
        &self,
        state: [&[f64]; 2],
        reference: [&[f64]; 3],
        d_hat: Option<&[f64]>,
        tau: &mut [f64],
    ) -> Result<(), Error>;
}

fn v<const N: usize>(values: &[f64]) -> JointVector<N> {
    JointVector::from_column_slice(values)
}

/// A model of `N` joints.
struct Fixed<const N: usize> {
    dynamics: Shared<N>,
}

impl<const N: usize> ArmModel for Fixed<N> {
    fn dof(&self) -> usize {
        N
    }
    fn inverse_dynamics(&self, q: &[f64], qd: &[f64], qdd: &[f64], tau: &mut [f64]) {
        tau.copy_from_slice(self.dynamics.inverse_dynamics(&v(q), &v(qd), &v(qdd)).as_slice());
    }
    fn mass_matrix(&self, q: &[f64], mass: &mut [f64]) {
        mass.copy_from_slice(self.dynamics.mass_matrix(&v(q)).as_slice());
    }
    fn gravity(&self, q: &[f64], tau: &mut [f64]) {
        tau.copy_from_slice(self.dynamics.gravity(&v(q)).as_slice());
    }
    fn forward_dynamics(&self, q: &[f64], qd: &[f64], tau: &[f64], qdd: &mut [f64]) -> Result<(), Error> {
        qdd.copy_from_slice(self.dynamics.forward_dynamics(&v(q), &v(qd), &v(tau))?.as_slice());
        Ok(())
    }
    fn estimator(
        &self,
        params: FilterParams,
        t0: Option<f64>,
        q0: &[f64],
        tau0: &[f64],
    ) -> Result<Box<dyn Estimate>, Error> {
        let dynamics = self.dynamics.clone();
        Ok(match t0 {
            None => Box::new(DisturbanceEstimator::new(dynamics, params, v(q0), v(tau0))?),
            Some(t0) => Box::new(TimedEstimator::new(dynamics, params, t0, v(q0), v(tau0))?),
        })
    }
    fn observer(&self, spec: ObserverSpec<'_>) -> Result<Box<dyn Observe>, Error> {
        let dynamics = self.dynamics.clone();
        Ok(match spec {
            ObserverSpec::Nonlinear { gain, dt_s, qd0 } => {
                Box::new(Baseline(Box::new(NonlinearDisturbanceObserver::new(dynamics, gain, dt_s, v(qd0))?)))
            }
            ObserverSpec::Momentum { gain, dt_s, q0, qd0, tau0 } => {
                let observer = MomentumObserver::new(dynamics, v(gain), dt_s, v(q0), v(qd0), v(tau0))?;
                Box::new(Baseline(Box::new(observer)))
            }
            ObserverSpec::ExtendedState { bandwidth_rad_s, dt_s, q0 } => {
                Box::new(Baseline(Box::new(ExtendedStateObserver::new(dynamics, bandwidth_rad_s, dt_s, v(q0))?)))
            }
        })
    }
    fn controller(&self, kp: &[f64], kd: &[f64], placement: PdPlacement) -> Result<Box<dyn Control>, Error> {
        let mut gains = [[0.0; N]; 2];
        gains[0].copy_from_slice(kp);
        gains[1].copy_from_slice(kd);
        let gains = Gains::diagonal(gains[0], gains[1])?;
        Ok(Box::new(ComputedTorque::new(self.dynamics.clone(), gains).with_placement(placement)))
    }
}

impl<const N: usize, D: Dynamics<N> + Send> Estimate for DisturbanceEstimator<N, D> {
    fn update(&mut self, q: &[f64], tau: &[f64], d_hat: &mut [f64]) -> Result<(), Failure> {
        d_hat.copy_from_slice(DisturbanceEstimator::update(self, &v(q), &v(tau))?.as_slice());
        Ok(())
    }
    fn update_at(&mut self, _: f64, _: &[f64], _: &[f64], _: &mut [f64]) -> Result<bool, Failure> {
        Err(Failure::Stepping {
            called: "hya_estimator_update_at",
            needs: "hya_estimator_new_timed",
            made_by: "hya_estimator_new",
            use_instead: "hya_estimator_update",
        })
    }
    fn disturbance(&self, d_hat: &mut [f64]) {
        d_hat.copy_from_slice(DisturbanceEstimator::disturbance(self).as_slice());
    }
    fn reset(&mut self, q0: &[f64], tau0: &[f64]) -> Result<(), Failure> {
        Ok(DisturbanceEstimator::reset(self, v(q0), v(tau0))?)
    }
}

impl<const N: usize, D: Dynamics<N> + Clone + Send> Estimate for TimedEstimator<N, D> {
    fn update(&mut self, _: &[f64], _: &[f64], _: &mut [f64]) -> Result<(), Failure> {
        Err(Failure::Stepping {
            called: "hya_estimator_update",
            needs: "hya_estimator_new",
            made_by: "hya_estimator_new_timed",
            use_instead: "hya_estimator_update_at",
        })
    }
    fn update_at(&mut self, t: f64, q: &[f64], tau: &[f64], d_hat: &mut [f64]) -> Result<bool, Failure> {
        let step = TimedEstimator::update(self, t, &v(q), &v(tau))?;
        d_hat.copy_from_slice(step.disturbance.as_slice());
        Ok(step.restarted)
    }
    fn disturbance(&self, d_hat: &mut [f64]) {
        d_hat.copy_from_slice(self.estimator().disturbance().as_slice());
    }
    fn reset(&mut self, q0: &[f64], tau0: &[f64]) -> Result<(), Failure> {
        let estimator = self.estimator();
        let (dynamics, params) = (estimator.dynamics().clone(), *estimator.params());
        *self = TimedEstimator::new(dynamics, params, self.time_s(), v(q0), v(tau0))?;
        Ok(())
    }
}

/// A baseline observer of `N` joints.
struct Baseline<const N: usize>(Box<dyn DisturbanceObserver<N> + Send>);

impl<const N: usize> Observe for Baseline<N> {
    fn update(&mut self, q: &[f64], qd: Option<&[f64]>, tau: &[f64], d_hat: &mut [f64]) -> Result<(), Error> {
        let measurement = Measurement { position: v(q), velocity: qd.map(v), torque: v(tau) };
        d_hat.copy_from_slice(self.0.update(&measurement)?.as_slice());
        Ok(())
    }
}

impl<const N: usize, D: Dynamics<N> + Send> Control for ComputedTorque<N, D> {
    fn command(
        &self,
        [q, qd]: [&[f64]; 2],
        [q_des, qd_des, qdd_des]: [&[f64]; 3],
        d_hat: Option<&[f64]>,
        tau: &mut [f64],
    ) -> Result<(), Error> {
        let reference = Reference { position: v(q_des), velocity: v(qd_des), acceleration: v(qdd_des) };
        let d_hat = d_hat.map(v::<N>);
        let command = ComputedTorque::command(self, &v(q), &v(qd), &reference, d_hat.as_ref())?;
        tau.copy_from_slice(command.torque.as_slice());
        Ok(())
    }
}

/// The shipped arm called `name`: its generated code.
pub(crate) fn shipped(name: &str) -> Result<Box<dyn ArmModel>, Failure> {
    struct Generated;
    impl ForArm for Generated {
        type Output = Box<dyn ArmModel>;
        fn call<const N: usize>(self, arm: Arm<N>) -> Box<dyn ArmModel> {
            Box::new(Fixed::<N> { dynamics: Arc::new(arm.nominal) })
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
            Ok(Box::new(Fixed::<N> { dynamics: Arc::new(dynamics) }))
        }
    }
    let (name, dof) = (model.name().to_owned(), model.dof());
    with_joints(dof, Tree(model)).unwrap_or(Err(Failure::JointCount { model: name, dof }))
}
