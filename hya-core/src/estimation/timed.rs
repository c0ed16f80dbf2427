//! The disturbance estimator over samples with their own timestamps.
//!
//! Logs of real arms are not one row per exact tick: a 100 Hz controller's rows come 10 to 16 ms
//! apart with gaps of 30 ms, a 1 kHz arm's steps jitter. [`TimedEstimator`] steps both filters
//! over each step's own length `T_k = t_{k+1} − t_k`, exactly for an input linear between the
//! samples (first-order hold):
//!
//! ```text
//! x_{k+1} = e^{A T_k} x_k + (Γa(T_k) − Γb(T_k)) u_k + Γb(T_k) u_{k+1}
//! ```
//!
//! with the discretisations cached per length ([`DiscretisationCache`](crate::estimation::step_cache::DiscretisationCache)). On a regular grid it
//! computes bit for bit what [`DisturbanceEstimator::update`] does at that grid's `dt`.
//!
//! # Gaps
//!
//! A gap is bridged exactly like any other step: the samples on either side are joined by a
//! straight line, and the filters are advanced over it in closed form. The only limit is the
//! matrix exponential's: a step with `ω · T_k >` [`MAX_RATE_TIMES_DT`]
//! for `ω = max(ω1, ω2)` (2 s at the paper's 50 rad/s) restarts the estimator at rest on the
//! sample after it instead. Over such a step the filters' slowest mode, `e^{−ζ ω2 T_k}` or
//! `e^{−ω1 T_k}`, has decayed below `e^{−50}`: what they remembered of the past is gone either
//! way. [`Step::restarted`] says which happened.

use crate::estimation::estimator::DisturbanceEstimator;
use crate::estimation::filter::FilterParams;
use crate::estimation::filter_pair::{Next, StepClock};
use crate::{Dynamics, Error, JointVector, MAX_RATE_TIMES_DT};

/// What one [`TimedEstimator::update`] did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Step<const N: usize> {
    /// The new `d̂`, N·m.
    pub disturbance: JointVector<N>,
    /// The step's length `t − t_previous`, s.
    pub length_s: f64,
    /// Whether the step was too long to bridge and the estimator restarted at rest.
    pub restarted: bool,
}

/// [`DisturbanceEstimator`] stepped by timestamps: each update brings its sample's time `t`, s.
#[derive(Debug, Clone)]
pub struct TimedEstimator<const N: usize, D> {
    estimator: DisturbanceEstimator<N, D>,
    clock: StepClock,
}

impl<const N: usize, D: Dynamics<N>> TimedEstimator<N, D> {
    /// An estimator at rest at the first sample `(t0, q0, τ0)`, as
    /// [`DisturbanceEstimator::new`]; `params`' own sample time is the first length cached.
    pub fn new(
        dynamics: D,
        params: FilterParams,
        t0: f64,
        q0: JointVector<N>,
        tau0: JointVector<N>,
    ) -> Result<Self, Error> {
        let fastest = params.omega1_rad_s().max(params.omega2_rad_s());
        let clock = StepClock::new(params, t0, MAX_RATE_TIMES_DT / fastest)?;
        Ok(Self { estimator: DisturbanceEstimator::new(dynamics, params, q0, tau0)?, clock })
    }

    /// The sample at time `t`: the filters advance over `t − t_previous` (first-order hold), or
    /// restart at rest at `(q_m, τ_m)` if that step is longer than
    /// [`longest_bridge_s`](Self::longest_bridge_s).
    ///
    /// Transactional like [`DisturbanceEstimator::update`]: a `t` that is not finite or not after
    /// the previous sample's ([`Error::InvalidParameter`] named `t`), or a bad measurement,
    /// changes nothing.
    pub fn update(&mut self, t: f64, q_m: &JointVector<N>, tau_m: &JointVector<N>) -> Result<Step<N>, Error> {
        let (disturbance, length_s, restarted) = match self.clock.next(t)? {
            Next::Gap(length_s) => {
                self.estimator.reset(*q_m, *tau_m)?;
                (*self.estimator.disturbance(), length_s, true)
            }
            Next::Step(step, length_s) => (self.estimator.update_over(step, q_m, tau_m)?, length_s, false),
        };
        self.clock.arrive(t);
        Ok(Step { disturbance, length_s, restarted })
    }

    /// The longest step bridged rather than restarted from, `100 / max(ω1, ω2)` s (see the
    /// module's notes on gaps).
    pub fn longest_bridge_s(&self) -> f64 {
        self.clock.longest_step_s()
    }

    /// The latest sample's time, s.
    pub fn time_s(&self) -> f64 {
        self.clock.time_s()
    }

    /// The estimator, for `d̂` and the filtered states.
    pub fn estimator(&self) -> &DisturbanceEstimator<N, D> {
        &self.estimator
    }

    /// The discretisations computed so far, one per new step length.
    pub fn discretisations_computed(&self) -> u64 {
        self.clock.discretisations_computed()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_arms::PlanarTwoLink;

    fn rows(k: usize) -> (JointVector<2>, JointVector<2>) {
        let x = k as f64 * 0.01;
        (JointVector::from([x.sin(), 0.5 * x]), JointVector::from([3.0 * x.cos(), 1.0 - x]))
    }

    #[test]
    fn on_a_regular_grid_it_is_the_fixed_step_estimator_bit_for_bit() {
        let dt = 1.0 / 1024.0; // exact in binary, so every t_{k+1} − t_k is exactly dt
        let params = FilterParams::paper(dt).unwrap();
        let (q0, tau0) = rows(0);
        let mut fixed = DisturbanceEstimator::new(PlanarTwoLink::default(), params, q0, tau0).unwrap();
        let mut timed = TimedEstimator::new(PlanarTwoLink::default(), params, 5.0, q0, tau0).unwrap();
        for k in 1..500 {
            let (q, tau) = rows(k);
            let expected = fixed.update(&q, &tau).unwrap();
            let step = timed.update(5.0 + k as f64 * dt, &q, &tau).unwrap();
            assert_eq!(step.disturbance, expected, "row {k}");
            assert!(!step.restarted);
        }
        assert_eq!(timed.discretisations_computed(), 0);
    }

    #[test]
    fn time_must_increase_and_a_bad_time_changes_nothing() {
        let params = FilterParams::paper(1e-3).unwrap();
        let (q0, tau0) = rows(0);
        let mut timed = TimedEstimator::new(PlanarTwoLink::default(), params, 0.0, q0, tau0).unwrap();
        let (q, tau) = rows(1);
        timed.update(1e-3, &q, &tau).unwrap();
        for bad in [1e-3, 0.0, f64::NAN, f64::INFINITY] {
            let before = *timed.estimator().joint_estimate();
            assert!(matches!(timed.update(bad, &q, &tau), Err(Error::InvalidParameter { name: "t", .. })));
            assert_eq!(*timed.estimator().joint_estimate(), before);
            assert_eq!(timed.time_s(), 1e-3);
        }
    }

    #[test]
    fn a_step_beyond_the_bridge_restarts_at_rest() {
        let params = FilterParams::paper(1e-3).unwrap();
        let (q0, tau0) = rows(0);
        let mut timed = TimedEstimator::new(PlanarTwoLink::default(), params, 0.0, q0, tau0).unwrap();
        assert_eq!(timed.longest_bridge_s(), 2.0);
        let (q, tau) = rows(7);
        let bridged = timed.update(2.0, &q, &tau).unwrap();
        assert!(!bridged.restarted);
        let step = timed.update(4.5, &q, &tau).unwrap();
        assert!(step.restarted);
        let rest = DisturbanceEstimator::new(PlanarTwoLink::default(), params, q, tau).unwrap();
        assert_eq!(step.disturbance, *rest.disturbance());
        assert_eq!(timed.estimator().joint_estimate(), rest.joint_estimate());
    }
}
