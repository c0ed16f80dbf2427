//! The paper's nonlinear disturbance estimator (Lu, Sandy & Buchli, section III).
//!
//! Two identical third-order filters (see [`crate::estimation::filter`]) run on the measured joint angles
//! `q_m` and the measured joint torques `τ_m`:
//!
//! ```text
//! (q̂, q̂̇, q̂̈) = states of the filter fed with q_m,   τ̂ = x1 of the filter fed with τ_m
//! d̂ = ID(q̂, q̂̇, q̂̈) − τ̂ = M(q̂) q̂̈ + C(q̂, q̂̇) + G(q̂) − τ̂
//! ```
//!
//! Filtering `τ_m` with the same filter cancels the filter's phase lag on the `q` side, so that
//! for slowly varying configurations `d̂ ≈ H(s) d`: a constant disturbance is recovered exactly,
//! and a sinusoid of frequency `ω` leaves a residual `|1 − H(jω)|` of its amplitude (32 % at
//! 1 Hz for the paper's `ζ = 0.8`, `ω1 = ω2 = 50 rad/s`). Only joint angles are needed; no
//! measured velocity and no numerical differentiation.

use crate::estimation::filter::{Discretisation, FilterParams, FilterState};
use crate::estimation::filter_pair::{FilterPair, PairState};
use crate::finite::check;
use crate::{Dynamics, Error, JointVector};

/// `d̂ = ID(q̂, q̂̇, q̂̈) − τ̂` from filtered joint angles and torques, for an arm with `N` joints.
///
/// `D` is any [`Dynamics`]: pass a reference (`&robot`) to share one model with a controller.
#[derive(Debug, Clone)]
pub struct DisturbanceEstimator<const N: usize, D> {
    dynamics: D,
    filters: FilterPair<N>,
    disturbance: JointVector<N>,
}

impl<const N: usize, D: Dynamics<N>> DisturbanceEstimator<N, D> {
    /// An estimator at rest: filter states `(q0, 0, 0)` and `(τ0, 0, 0)`, `d̂ = G(q0) − τ0`.
    pub fn new(dynamics: D, params: FilterParams, q0: JointVector<N>, tau0: JointVector<N>) -> Result<Self, Error> {
        let mut estimator =
            Self { filters: FilterPair::new(params, q0, tau0)?, disturbance: JointVector::zeros(), dynamics };
        estimator.disturbance = estimator.estimate(estimator.filters.angles(), &tau0)?;
        Ok(estimator)
    }

    /// One control tick: filters the new measurements and returns the new `d̂`, N·m.
    ///
    /// The update is transactional: a non-finite `q_m` or `τ_m`, or a non-finite estimate, is
    /// reported as [`Error::NonFinite`] and leaves every state as it was, so one bad sample never
    /// poisons the filters. The caller decides what to do for that tick (typically: keep the
    /// previous `d̂`, which [`disturbance`](Self::disturbance) still returns).
    #[inline]
    pub fn update(&mut self, q_m: &JointVector<N>, tau_m: &JointVector<N>) -> Result<JointVector<N>, Error> {
        let filtered = self.peek(q_m, tau_m)?;
        let inverse_dynamics = self.inverse_dynamics(&filtered.angles);
        self.advance(filtered, inverse_dynamics, q_m, tau_m)
    }

    /// As [`update`](Self::update), over a step of another length than the filters' sample time:
    /// `step` discretises both filters over it (first-order hold between the previous samples and
    /// these; built with [`FilterParams::with_dt`] from [`params`](Self::params), or taken from a
    /// [`DiscretisationCache`](crate::estimation::step_cache::DiscretisationCache)). For logs whose rows are
    /// not evenly spaced; see [`TimedEstimator`](crate::estimation::timed::TimedEstimator).
    pub fn update_over(
        &mut self,
        step: &Discretisation,
        q_m: &JointVector<N>,
        tau_m: &JointVector<N>,
    ) -> Result<JointVector<N>, Error> {
        let filtered = self.filters.peek_over(step, q_m, tau_m)?;
        let inverse_dynamics = self.inverse_dynamics(&filtered.angles);
        self.advance(filtered, inverse_dynamics, q_m, tau_m)
    }

    /// The filters' parameters (both filters share them).
    pub fn params(&self) -> &FilterParams {
        self.filters.params()
    }

    /// Both filters' states one sample ahead for the new measurements, not committed.
    #[inline(always)]
    pub(crate) fn peek(&self, q_m: &JointVector<N>, tau_m: &JointVector<N>) -> Result<PairState<N>, Error> {
        self.filters.peek(q_m, tau_m)
    }

    /// `d̂` from peeked filter states and `inverse_dynamics = ID(q̂, q̂̇, q̂̈)` of their joints,
    /// committed with them; nothing is committed if `d̂` is not finite.
    #[inline(always)]
    fn advance(
        &mut self,
        filtered: PairState<N>,
        inverse_dynamics: JointVector<N>,
        q_m: &JointVector<N>,
        tau_m: &JointVector<N>,
    ) -> Result<JointVector<N>, Error> {
        let disturbance = finite_disturbance(filtered.disturbance(inverse_dynamics))?;
        self.commit(filtered, disturbance, q_m, tau_m);
        Ok(disturbance)
    }

    /// Commits peeked filter states, their inputs and the estimate they gave.
    #[inline(always)]
    pub(crate) fn commit(
        &mut self,
        filtered: PairState<N>,
        disturbance: JointVector<N>,
        q_m: &JointVector<N>,
        tau_m: &JointVector<N>,
    ) {
        self.filters.commit(filtered, q_m, tau_m);
        self.disturbance = disturbance;
    }

    /// `ID(x1, x2, x3)` on the estimator's model.
    #[inline(always)]
    fn inverse_dynamics(&self, joints: &FilterState<N>) -> JointVector<N> {
        self.dynamics.inverse_dynamics(&joints.x1, &joints.x2, &joints.x3)
    }

    /// Back to rest at `q0`, `τ0`, as at construction.
    pub fn reset(&mut self, q0: JointVector<N>, tau0: JointVector<N>) -> Result<(), Error> {
        check("q0", &q0)?;
        check("tau0", &tau0)?;
        let disturbance = self.estimate(&FilterState::at_rest(q0), &tau0)?;
        self.filters.reset(q0, tau0)?;
        self.disturbance = disturbance;
        Ok(())
    }

    /// The latest disturbance estimate `d̂`, N·m.
    pub fn disturbance(&self) -> &JointVector<N> {
        &self.disturbance
    }

    /// Filtered joint states: `x1 = q̂` (rad), `x2 = q̂̇` (rad/s), `x3 = q̂̈` (rad/s²).
    pub fn joint_estimate(&self) -> &FilterState<N> {
        self.filters.angles()
    }

    /// Filtered joint torques `τ̂`, N·m.
    pub fn torque_estimate(&self) -> &JointVector<N> {
        self.filters.torques()
    }

    /// The dynamics model the estimator uses.
    pub fn dynamics(&self) -> &D {
        &self.dynamics
    }

    /// `ID(x1, x2, x3) − τ̂` from finite states; refused if the result is not finite.
    fn estimate(&self, joints: &FilterState<N>, filtered_torque: &JointVector<N>) -> Result<JointVector<N>, Error> {
        finite_disturbance(self.inverse_dynamics(joints) - filtered_torque)
    }
}

/// `d̂`, refused as `"d_hat"` if it is not finite.
#[inline(always)]
fn finite_disturbance<const N: usize>(disturbance: JointVector<N>) -> Result<JointVector<N>, Error> {
    check("d_hat", &disturbance)?;
    Ok(disturbance)
}
