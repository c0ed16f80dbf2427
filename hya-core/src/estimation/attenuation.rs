//! The paper's control tick as one type: the disturbance estimator (section III) and the
//! computed-torque controller that cancels its estimate (section IV), on one model.
//!
//! A tick needs two inverse dynamics passes, and neither needs the other's result: the
//! estimator's `ID(q̂, q̂̇, q̂̈)` on the filtered states and the controller's `ID(q, q̇, q̈*)` on the
//! measured ones (`q̈* = q̈_des`, or `q̈_des − K_D ė − K_P e` inside the mass matrix). `d̂` enters
//! the command only after its inverse dynamics:
//!
//! ```text
//! d̂ = ID(q̂, q̂̇, q̂̈) − τ̂          τ = ID(q, q̇, q̈*) − [K_D ė + K_P e] − d̂
//! ```
//!
//! [`DisturbanceAttenuation::tick`] therefore hands both to the model as one batch of two states
//! ([`Dynamics::inverse_dynamics_batch`]). Generated dynamics compute them in two lanes of one
//! vector pass, at about the cost of one single call, and equal to the two single calls bit for
//! bit; other models loop over the single call. Either way a tick returns what
//! [`DisturbanceEstimator::update`] followed by [`ComputedTorque::command`] with the new `d̂`
//! returns.

use crate::estimation::control::{Command, ComputedTorque, Gains, PdPlacement, Reference};
use crate::{DisturbanceEstimator, Dynamics, Error, FilterParams, JointVector};

/// The estimator and the controller that compensates its `d̂`, both on one model `D`.
#[derive(Debug, Clone)]
pub struct DisturbanceAttenuation<const N: usize, D> {
    estimator: DisturbanceEstimator<N, D>,
    controller: ComputedTorque<N, D>,
}

impl<const N: usize, D: Dynamics<N> + Clone> DisturbanceAttenuation<N, D> {
    /// The estimator at rest at `(q0, τ0)` ([`DisturbanceEstimator::new`]) and the controller in
    /// the paper's form with `gains`, no torque limits ([`ComputedTorque::new`]), both on
    /// `dynamics` (pass `&robot` to share one model without a copy).
    pub fn new(
        dynamics: D,
        params: FilterParams,
        gains: Gains<N>,
        q0: JointVector<N>,
        tau0: JointVector<N>,
    ) -> Result<Self, Error> {
        let estimator = DisturbanceEstimator::new(dynamics.clone(), params, q0, tau0)?;
        Ok(Self { estimator, controller: ComputedTorque::new(dynamics, gains) })
    }
}

impl<const N: usize, D: Dynamics<N>> DisturbanceAttenuation<N, D> {
    /// Chooses where the controller's PD feedback enters the law ([`ComputedTorque::with_placement`]).
    pub fn with_placement(mut self, placement: PdPlacement) -> Self {
        self.controller = self.controller.with_placement(placement);
        self
    }

    /// Saturates the command ([`ComputedTorque::with_torque_limit`]).
    pub fn with_torque_limit(mut self, limit: JointVector<N>) -> Result<Self, Error> {
        self.controller = self.controller.with_torque_limit(limit)?;
        Ok(self)
    }

    /// One control tick: filters the measured `q_m` and `τ_m` into the new `d̂` and returns the
    /// command for the state `(q_m, q̇)` and `reference` that cancels it.
    ///
    /// `q̇` is the velocity the loop closes on (see [`crate::estimation::control`]). The tick is
    /// transactional: a non-finite input, estimate or command is reported as
    /// [`Error::NonFinite`] (an overflowing filter input as [`Error::Overflow`]) and leaves the
    /// estimator as it was.
    #[inline]
    pub fn tick(
        &mut self,
        q_m: &JointVector<N>,
        qd: &JointVector<N>,
        tau_m: &JointVector<N>,
        reference: &Reference<N>,
    ) -> Result<Command<N>, Error> {
        // The whole tick compiled for the vector unit if there is one; the results do not change.
        crate::rigid_body::lanes::on_vector_unit(
            self,
            #[inline(always)]
            |this: &mut Self| {
                let filtered = this.estimator.peek(q_m, tau_m)?;
                let law = this.controller.law(q_m, qd, reference)?;
                let joints = &filtered.angles;
                let mut passes = [JointVector::zeros(); 2];
                this.controller.dynamics().inverse_dynamics_batch(
                    &[joints.x1, *q_m],
                    &[joints.x2, *qd],
                    &[joints.x3, law.acceleration],
                    &mut passes,
                )?;
                let [estimated, commanded] = passes;
                // `finish` refuses a non-finite `d̂` as `update` would, with the same error.
                let disturbance = filtered.disturbance(estimated);
                let command = this.controller.finish(&law, commanded, Some(&disturbance))?;
                this.estimator.commit(filtered, disturbance, q_m, tau_m);
                Ok(command)
            },
        )
    }

    /// The latest disturbance estimate `d̂`, N·m.
    pub fn disturbance(&self) -> &JointVector<N> {
        self.estimator.disturbance()
    }

    /// The estimator (filtered states, `d̂`, parameters).
    pub fn estimator(&self) -> &DisturbanceEstimator<N, D> {
        &self.estimator
    }

    /// The controller (gains, placement, model).
    pub fn controller(&self) -> &ComputedTorque<N, D> {
        &self.controller
    }
}
