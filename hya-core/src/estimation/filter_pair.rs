//! The paper's two filters side by side, and the clock that steps them over a log's timestamps.
//!
//! [`FilterPair`]: one third-order filter on the joint angles, whose states are `(q̂, q̂̇, q̂̈)`,
//! and one on the joint torques, whose `x1` is `τ̂`, with the same parameters so that both carry
//! the same lag. They are stepped together and transactionally: [`FilterPair::peek`] (or
//! [`FilterPair::peek_over`] a step of its own length) computes both next states, and
//! [`FilterPair::commit`] keeps them; a refused input leaves both as they were. The disturbance
//! estimator ([`crate::DisturbanceEstimator`], and through it [`crate::TimedEstimator`]) and the
//! log filtering of identification (`hya_ident::log`) are this pair.
//!
//! [`StepClock`]: a log's time, `t_{k+1} > t_k`, each step's discretisation from a
//! [`DiscretisationCache`], and the gap policy as a number: a step longer than
//! [`StepClock::longest_step_s`] is a gap, across which the caller restarts the filters.

use crate::estimation::filter::{Discretisation, FilterParams, FilterState, ThirdOrderFilter};
use crate::estimation::step_cache::DiscretisationCache;
use crate::finite::check;
use crate::{Error, JointVector};

/// The filters on `q` and on `τ`.
#[derive(Debug, Clone)]
pub struct FilterPair<const N: usize> {
    angles: ThirdOrderFilter<N>,
    torques: ThirdOrderFilter<N>,
}

/// Both filters' states one sample ahead, before they are committed.
#[derive(Debug, Clone, Copy)]
pub struct PairState<const N: usize> {
    /// `(q̂, q̂̇, q̂̈)`.
    pub angles: FilterState<N>,
    /// `τ̂` in `x1`.
    pub torques: FilterState<N>,
}

impl<const N: usize> FilterPair<N> {
    /// Both filters at rest, at `q0` and `τ0`.
    pub fn new(params: FilterParams, q0: JointVector<N>, tau0: JointVector<N>) -> Result<Self, Error> {
        check("q0", &q0)?;
        check("tau0", &tau0)?;
        Ok(Self { angles: ThirdOrderFilter::new(params, q0)?, torques: ThirdOrderFilter::new(params, tau0)? })
    }

    /// The filters' parameters (both share them).
    pub fn params(&self) -> &FilterParams {
        self.angles.params()
    }

    /// Both states one sample (the parameters' own step) ahead for the new `q_m`, `τ_m`.
    #[inline(always)]
    pub fn peek(&self, q_m: &JointVector<N>, tau_m: &JointVector<N>) -> Result<PairState<N>, Error> {
        Ok(PairState { angles: self.angles.peek("q_m", q_m)?, torques: self.torques.peek("tau_m", tau_m)? })
    }

    /// As [`peek`](Self::peek), over the step `step` discretises.
    #[inline(always)]
    pub fn peek_over(
        &self,
        step: &Discretisation,
        q_m: &JointVector<N>,
        tau_m: &JointVector<N>,
    ) -> Result<PairState<N>, Error> {
        Ok(PairState {
            angles: self.angles.peek_over(step, "q_m", q_m)?,
            torques: self.torques.peek_over(step, "tau_m", tau_m)?,
        })
    }

    /// Keeps peeked states, with the inputs they were peeked for.
    #[inline(always)]
    pub fn commit(&mut self, state: PairState<N>, q_m: &JointVector<N>, tau_m: &JointVector<N>) {
        self.angles.commit(state.angles, *q_m);
        self.torques.commit(state.torques, *tau_m);
    }

    /// Both filters back to rest at `q0`, `τ0`.
    pub fn reset(&mut self, q0: JointVector<N>, tau0: JointVector<N>) -> Result<(), Error> {
        check("q0", &q0)?;
        check("tau0", &tau0)?;
        self.angles.reset(q0)?;
        self.torques.reset(tau0)
    }

    /// `(q̂, q̂̇, q̂̈)`.
    pub fn angles(&self) -> &FilterState<N> {
        self.angles.state()
    }

    /// `τ̂`, N·m.
    pub fn torques(&self) -> &JointVector<N> {
        &self.torques.state().x1
    }
}

/// What the next sample's time is to the filters.
#[derive(Debug, Clone, Copy)]
pub enum Next<'a> {
    /// A step to advance over, of this length, s.
    Step(&'a Discretisation, f64),
    /// A gap of this length, s: the filters restart at the sample after it.
    Gap(f64),
}

impl<const N: usize> PairState<N> {
    /// `d̂ = ID(q̂, q̂̇, q̂̈) − τ̂` from `inverse_dynamics = ID(q̂, q̂̇, q̂̈)`, not yet checked.
    #[inline(always)]
    pub fn disturbance(&self, inverse_dynamics: JointVector<N>) -> JointVector<N> {
        inverse_dynamics - self.torques.x1
    }
}

/// A log's time: the last sample's, the discretisations per step length, and the gap policy.
#[derive(Debug, Clone)]
pub struct StepClock {
    cache: DiscretisationCache,
    time_s: f64,
    longest_step_s: f64,
}

impl StepClock {
    /// A clock at `t0` for filters `params`, bridging steps up to `longest_step_s` (longer ones
    /// are gaps). Refused (named `t` or `longest_step_s`) unless both are finite and the longest
    /// step positive.
    pub fn new(params: FilterParams, t0: f64, longest_step_s: f64) -> Result<Self, Error> {
        check("t", &JointVector::<1>::from([t0]))?;
        if !(longest_step_s.is_finite() && longest_step_s > 0.0) {
            return Err(Error::InvalidParameter {
                name: "longest_step_s",
                value: longest_step_s,
                requirement: "finite and positive",
            });
        }
        Ok(Self { cache: DiscretisationCache::new(params), time_s: t0, longest_step_s })
    }

    /// What a sample at `t` is: a step (with its discretisation) or a gap. Nothing changes until
    /// [`arrive`](Self::arrive). A `t` that is not finite or not after the last sample's is
    /// [`Error::InvalidParameter`] named `t`; a step the filters cannot be discretised over is
    /// the error [`FilterParams::with_dt`] gives.
    pub fn next(&mut self, t: f64) -> Result<Next<'_>, Error> {
        let length_s = t - self.time_s;
        if !(t.is_finite() && length_s > 0.0) {
            return Err(Error::InvalidParameter {
                name: "t",
                value: t,
                requirement: "finite and after the previous sample's time",
            });
        }
        if length_s > self.longest_step_s {
            return Ok(Next::Gap(length_s));
        }
        Ok(Next::Step(self.cache.get(length_s)?, length_s))
    }

    /// The sample at `t` is taken: the clock moves to it.
    pub fn arrive(&mut self, t: f64) {
        self.time_s = t;
    }

    /// The last sample's time, s.
    pub fn time_s(&self) -> f64 {
        self.time_s
    }

    /// The longest step bridged, s.
    pub fn longest_step_s(&self) -> f64 {
        self.longest_step_s
    }

    /// The discretisations computed so far, one per new step length.
    pub fn discretisations_computed(&self) -> u64 {
        self.cache.misses()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_refused_input_leaves_both_filters_as_they_were() {
        let params = FilterParams::paper(1e-3).unwrap();
        let mut pair =
            FilterPair::<2>::new(params, JointVector::from([0.1, 0.2]), JointVector::from([1.0, 2.0])).unwrap();
        let before = (*pair.angles(), *pair.torques());
        assert!(pair.peek(&JointVector::from([0.1, f64::NAN]), &JointVector::from([1.0, 2.0])).is_err());
        assert!(pair.peek(&JointVector::from([0.1, 0.2]), &JointVector::from([f64::INFINITY, 2.0])).is_err());
        assert_eq!((pair.angles().x1, pair.angles().x2, *pair.torques()), (before.0.x1, before.0.x2, before.1));
        let (q, tau) = (JointVector::from([0.2, 0.2]), JointVector::from([1.5, 2.0]));
        let next = pair.peek(&q, &tau).unwrap();
        pair.commit(next, &q, &tau);
        assert!(pair.angles().x1[0] > 0.1 && pair.torques()[0] > 1.0, "both moved toward their inputs");
    }

    #[test]
    fn the_clock_tells_steps_from_gaps_and_refuses_time_going_back() {
        let params = FilterParams::paper(1e-3).unwrap();
        let mut clock = StepClock::new(params, 0.0, 2.5e-3).unwrap();
        assert!(matches!(clock.next(1e-3), Ok(Next::Step(_, l)) if l == 1e-3));
        clock.arrive(1e-3);
        assert!(matches!(clock.next(5e-3), Ok(Next::Gap(_))));
        assert!(matches!(clock.next(1e-3), Err(Error::InvalidParameter { name: "t", .. })));
        assert!(matches!(clock.next(f64::NAN), Err(Error::InvalidParameter { name: "t", .. })));
        assert!(StepClock::new(params, 0.0, 0.0).is_err());
    }
}
