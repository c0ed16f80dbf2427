//! A log of rows `(t, q, τ)` filtered into the fit's samples `(q̂, q̂̇, q̂̈, τ̂)`.
//!
//! `q̂, q̂̇, q̂̈` come from the paper's third-order filter on `q` (no numerical differentiation)
//! and `τ̂` from the same filter on `τ`, so that both carry the same lag, as in the estimator:
//! the filters are [`hya_core::FilterPair`]. With timestamps each step is filtered over its own
//! length (first-order hold, [`hya_core::StepClock`], as [`hya_core::TimedEstimator`] does); a
//! step longer than the log's longest step is a gap, across which the derivatives would be
//! guesses: both filters restart at rest on the row after it.
//!
//! After every (re)start the filters settle for `10/ω` seconds before a sample is taken; then one
//! sample is taken per `1/ω` seconds, the time over which the filters make neighbouring rows'
//! noise alike, so that the fit's residuals are near independent, as its standard deviations
//! assume.
//!
//! A joint's row of a sample is left out of the fit ([`Sample::fitted`]) where the joint's
//! filtered velocity changes sign, or comes within [`crate::fit::Law::least_speed_rad_s`] of
//! zero, within `10/ω` seconds before or after it. The filter commutes
//! with the linear terms of the model, not with friction's switch: through a reversal the
//! filtered torque holds `F[c tanh(q̇/s)]`, smeared over the filters' memory, while the model
//! sees `c tanh(F[q̇]/s)`, which switches at once. No parameter explains that difference, and
//! it repeats at every reversal, so it would move the fit's parameters (on the simulated HyA
//! several standard deviations, `tools/identification_study.py`) rather than average out.
//!
//! The command line (`hya identify`) and Python (`hya.identify`) both feed their rows here, so
//! both refuse the same rows with the same words.

use hya_core::{FilterPair, FilterParams, JointVector, Next, Short, StepClock};

use crate::fit::Sample;

/// How the rows are timed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Timing {
    /// One row per filter step (`t = k · dt`).
    Fixed,
    /// Rows carry their time; a step longer than this, s, is a gap.
    Stamped {
        /// The longest step that is not a gap, s.
        max_step_s: f64,
    },
}

/// A row the log filter refuses, with why; the caller adds where the row is.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct RowError(pub String);

/// The samples taken from a log.
#[derive(Debug, Clone, Default)]
pub struct Filtered {
    /// The samples, in time order.
    pub samples: Vec<Sample>,
    /// Each sample's time, s (the log's timestamps, or `k · dt`).
    pub time_s: Vec<f64>,
    /// The rows read.
    pub rows: usize,
    /// The gaps across which the filters restarted.
    pub gaps: usize,
    /// How long the filters settled after each start before samples were taken, s.
    pub settling_s: f64,
    /// The time between samples, s.
    pub spacing_s: f64,
}

/// Filters a log row by row for an arm of `N` joints.
#[derive(Debug, Clone)]
pub struct LogFilter<const N: usize> {
    params: FilterParams,
    timing: Timing,
    /// The filters, from the first row on.
    pair: Option<FilterPair<N>>,
    /// The log's time, from the first row on, for [`Timing::Stamped`] rows: kept across gaps,
    /// so its discretisations are computed once per step length for the whole log.
    clock: Option<StepClock>,
    next_sample_s: f64,
    /// Per sample, how many gaps came before it: samples of one stretch share it.
    stretch: Vec<usize>,
    out: Filtered,
}

/// What a row does to the filters.
enum Advance {
    /// They stepped to it.
    Stepped,
    /// They start at rest on it: the first row.
    First,
    /// They restart at rest on it: the row after a gap.
    AfterGap,
}

impl<const N: usize> LogFilter<N> {
    /// A filter with `params` (designed at the log's nominal step) for rows timed by `timing`.
    /// A gap limit that is not a positive number of seconds is refused.
    pub fn new(params: FilterParams, timing: Timing) -> Result<Self, RowError> {
        if let Timing::Stamped { max_step_s } = timing {
            if !(max_step_s.is_finite() && max_step_s > 0.0) {
                return Err(RowError(format!("max step {}: must be a positive number of seconds", Short(max_step_s))));
            }
        }
        // The filters settle for 10/ω after each start; then one sample per 1/ω.
        let omega = params.omega1_rad_s();
        let out = Filtered { settling_s: 10.0 / omega, spacing_s: 1.0 / omega, ..Filtered::default() };
        Ok(Self { params, timing, pair: None, clock: None, next_sample_s: 0.0, stretch: Vec::new(), out })
    }

    /// The next row: its time `t` (ignored for [`Timing::Fixed`], whose rows are `k · dt`), the
    /// joint angles `q`, rad, and torques `τ`, N·m (`N` each). A row refused leaves the filter
    /// as it was.
    pub fn push(&mut self, t: f64, q: &[f64], tau: &[f64]) -> Result<(), RowError> {
        if q.len() != N || tau.len() != N {
            return Err(RowError(format!("{} angles and {} torques for an arm of {N} joints", q.len(), tau.len())));
        }
        let (q, tau) = (JointVector::<N>::from_column_slice(q), JointVector::<N>::from_column_slice(tau));
        let refused = |e: hya_core::Error| RowError(e.to_string());
        let t = match self.timing {
            Timing::Fixed => self.out.rows as f64 * self.params.dt_s(),
            Timing::Stamped { .. } => t,
        };
        if !t.is_finite() {
            return Err(RowError(format!("t = {t}: times must be finite")));
        }
        let advance = match (self.pair.as_mut(), self.clock.as_mut()) {
            (None, _) => Advance::First,
            (Some(pair), None) => {
                let next = pair.peek(&q, &tau).map_err(refused)?;
                pair.commit(next, &q, &tau);
                Advance::Stepped
            }
            (Some(pair), Some(clock)) => {
                let previous = clock.time_s();
                match clock.next(t) {
                    Err(_) if t <= previous => {
                        return Err(RowError(format!(
                            "t = {} s is not after the previous row's t = {} s: times must strictly increase",
                            Short(t),
                            Short(previous)
                        )))
                    }
                    Err(e) => return Err(refused(e)),
                    Ok(Next::Step(step, _)) => {
                        let next = pair.peek_over(step, &q, &tau).map_err(refused)?;
                        pair.commit(next, &q, &tau);
                        Advance::Stepped
                    }
                    Ok(Next::Gap(_)) => Advance::AfterGap,
                }
            }
        };
        match (advance, self.pair.as_mut()) {
            (Advance::Stepped, _) => {}
            (Advance::AfterGap, Some(pair)) => {
                pair.reset(q, tau).map_err(refused)?;
                self.out.gaps += 1;
                self.next_sample_s = t + self.out.settling_s;
            }
            _ => {
                let pair = FilterPair::new(self.params, q, tau).map_err(refused)?;
                if let Timing::Stamped { max_step_s } = self.timing {
                    self.clock = Some(StepClock::new(self.params, t, max_step_s).map_err(refused)?);
                }
                self.pair = Some(pair);
                self.next_sample_s = t + self.out.settling_s;
            }
        }
        if let Some(clock) = self.clock.as_mut() {
            clock.arrive(t);
        }
        self.out.rows += 1;
        // Half a row early counts as on time: `k · dt` need not meet `m / ω` exactly.
        if t >= self.next_sample_s - 0.5 * self.params.dt_s() {
            if let Some(pair) = &self.pair {
                let angles = pair.angles();
                self.out.samples.push(Sample {
                    q: angles.x1.as_slice().to_vec(),
                    qd: angles.x2.as_slice().to_vec(),
                    qdd: angles.x3.as_slice().to_vec(),
                    tau: pair.torques().as_slice().to_vec(),
                    speed_margin_rad_s: vec![0.0; N],
                });
                self.out.time_s.push(t);
                self.stretch.push(self.out.gaps);
            }
            self.next_sample_s += self.out.spacing_s;
        }
        Ok(())
    }

    /// The samples taken, each with every joint's least speed over the filters' settling time
    /// `10/ω` before and after it, 0 where the velocity changes sign there
    /// ([`Sample::speed_margin_rad_s`]; see the module's notes).
    pub fn finish(mut self) -> Filtered {
        let (memory, out) = (self.out.settling_s, &mut self.out);
        let velocities: Vec<[f64; N]> = out.samples.iter().map(|s| core::array::from_fn(|i| s.qd[i])).collect();
        for k in 0..out.samples.len() {
            let near =
                |j: &usize| self.stretch[*j] == self.stretch[k] && (out.time_s[*j] - out.time_s[k]).abs() <= memory;
            let first = (0..k).rev().take_while(|j| near(j)).last().unwrap_or(k);
            let last = (k + 1..out.samples.len()).take_while(|j| near(j)).last().unwrap_or(k);
            for i in 0..N {
                let around = velocities[first..=last].iter().map(|v| v[i]);
                let one_way = around.clone().all(|v| v > 0.0) || around.clone().all(|v| v < 0.0);
                out.samples[k].speed_margin_rad_s[i] =
                    if one_way { around.map(f64::abs).fold(f64::INFINITY, f64::min) } else { 0.0 };
            }
        }
        self.out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(k: usize) -> ([f64; 2], [f64; 2]) {
        let x = k as f64 * 1e-3;
        ([x.sin(), 0.5 * x], [3.0 * x.cos(), 1.0 - x])
    }

    #[test]
    fn a_joint_has_no_speed_margin_within_the_filters_memory_of_its_reversal() {
        // Joint 0 turns back (q = sin t, q̇ = cos t, once, at t = π/2); joint 1 moves at 0.5 rad/s.
        let params = FilterParams::new(0.8, 50.0, 50.0, 1e-3).unwrap();
        let mut log = LogFilter::<2>::new(params, Timing::Fixed).unwrap();
        for k in 0..3000 {
            let t = k as f64 * 1e-3;
            log.push(t, &[t.sin(), 0.5 * t], &[0.0, 0.0]).unwrap();
        }
        let log = log.finish();
        let memory = log.settling_s;
        // Where the filtered velocity of joint 0 changes sign.
        let k = log.samples.windows(2).position(|w| w[0].qd[0] > 0.0 && w[1].qd[0] <= 0.0).unwrap();
        let turn = log.time_s[k + 1];
        for (s, t) in log.samples.iter().zip(&log.time_s) {
            let margin = s.speed_margin_rad_s[0];
            if (t - turn).abs() < memory - log.spacing_s {
                assert_eq!(margin, 0.0, "t = {t}");
            } else if (t - turn).abs() > memory + log.spacing_s {
                // The least |q̂̇| over the window, never above the sample's own.
                assert!(margin > 0.0 && margin <= s.qd[0].abs(), "t = {t}: {margin}");
            }
            assert!((s.speed_margin_rad_s[1] - 0.5).abs() < 1e-2, "t = {t}: {}", s.speed_margin_rad_s[1]);
        }
        // Far from the turn the margin is the window's least speed: at t = 0.5 s, about
        // |cos| at the window's later end, a little lagged by the filter.
        let early = log.time_s.iter().position(|t| *t >= 0.5).unwrap();
        let margin = log.samples[early].speed_margin_rad_s[0];
        assert!(margin < log.samples[early].qd[0] && margin > (0.5f64 + memory).cos() - 0.05, "{margin}");
    }

    #[test]
    fn fixed_and_stamped_rows_on_an_exact_grid_give_the_same_samples() {
        let dt = 1.0 / 1024.0; // exact in binary: every step of the stamped rows is exactly dt
        let params = FilterParams::new(0.8, 50.0, 50.0, dt).unwrap();
        let mut fixed = LogFilter::<2>::new(params, Timing::Fixed).unwrap();
        let mut stamped = LogFilter::<2>::new(params, Timing::Stamped { max_step_s: 2.5 * dt }).unwrap();
        for k in 0..2000 {
            let (q, tau) = row(k);
            fixed.push(f64::NAN, &q, &tau).unwrap();
            stamped.push(k as f64 * dt, &q, &tau).unwrap();
        }
        let (fixed, stamped) = (fixed.finish(), stamped.finish());
        assert!(!fixed.samples.is_empty());
        assert_eq!(fixed.samples, stamped.samples);
        assert_eq!(fixed.time_s, stamped.time_s);
    }

    #[test]
    fn a_gap_restarts_the_filters_and_bad_times_are_refused_without_effect() {
        let params = FilterParams::new(0.8, 50.0, 50.0, 1e-3).unwrap();
        let mut log = LogFilter::<2>::new(params, Timing::Stamped { max_step_s: 2.5e-3 }).unwrap();
        let (q, tau) = row(0);
        log.push(0.0, &q, &tau).unwrap();
        log.push(1e-3, &q, &tau).unwrap();
        let refused = log.push(1e-3, &q, &tau).unwrap_err().to_string();
        assert!(refused.contains("strictly increase"), "{refused}");
        assert!(log.push(f64::NAN, &q, &tau).unwrap_err().to_string().contains("finite"));
        assert!(log.push(2e-3, &[f64::NAN, 0.0], &tau).is_err());
        log.push(10e-3, &q, &tau).unwrap();
        let out = log.finish();
        assert_eq!((out.rows, out.gaps), (3, 1));
        assert!(LogFilter::<2>::new(params, Timing::Stamped { max_step_s: -1.0 }).is_err());
    }
}
