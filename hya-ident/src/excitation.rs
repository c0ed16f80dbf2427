//! Exciting trajectories: a finite Fourier series per joint (Swevers, Ganseman, Tükel, De
//! Schutter & Van Brussel, IEEE TRA 13(5), 1997), periodic with base frequency `ω_f`:
//!
//! ```text
//! q_i(t)  = q_i0 + Σ_{l=1..L} ( a_il/(ω_f l) sin(ω_f l t) − b_il/(ω_f l) cos(ω_f l t) )
//! q̇_i(t)  =        Σ_{l=1..L} (  a_il cos(ω_f l t) + b_il sin(ω_f l t) )
//! q̈_i(t)  =        Σ_{l=1..L} ω_f l ( −a_il sin(ω_f l t) + b_il cos(ω_f l t) )
//! ```
//!
//! Each period starts and ends at rest: `q̇(0) = Σ_l a_il = 0` and `q̈(0) = ω_f Σ_l l b_il = 0`,
//! imposed through the first harmonic (`a_i1 = −Σ_{l≥2} a_il`, `b_i1 = −Σ_{l≥2} l b_il`), so a
//! log may hold several periods and a robot can be brought to `q(0)` and started from there.
//!
//! Design: candidates with coefficients drawn uniformly in `[−1, 1]` (seeded) are each scaled
//! and offset per joint so that, on a grid of the period, the joint stays within the given
//! fraction of its position range (centred in it) and of its velocity limit; the candidate
//! whose stacked regressor over one period has the smallest condition number
//! ([`Conditioning`]) wins. A random search, not an optimiser: it finds a usable trajectory,
//! not the best one.

use core::f64::consts::TAU;

use hya_core::model::TreeModel;
use nalgebra::DMatrix;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::conditioning::Conditioning;
use crate::regressor::Regressor;

/// Why no trajectory could be designed.
#[derive(Debug, thiserror::Error)]
pub enum ExcitationError {
    /// A joint without the limits the design needs.
    #[error("joint `{joint}` has no {what} limit in the description; the trajectory must stay within one")]
    MissingLimit {
        /// The joint's name.
        joint: String,
        /// `position` or `velocity`.
        what: &'static str,
    },
    /// A setting out of its range.
    #[error("{name} = {value}: must be {requirement}")]
    Setting {
        /// The setting.
        name: &'static str,
        /// Its value.
        value: f64,
        /// What it must be.
        requirement: &'static str,
    },
    /// The model refused a state (it should not: the design's states are finite).
    #[error(transparent)]
    Model(#[from] hya_core::model::ModelError),
}

/// The box the trajectory stays in, per joint.
#[derive(Debug, Clone, PartialEq)]
pub struct Limits {
    /// Lowest position, rad (or m).
    pub lower: Vec<f64>,
    /// Highest position, rad (or m).
    pub upper: Vec<f64>,
    /// Largest speed, rad/s (or m/s).
    pub velocity: Vec<f64>,
}

impl Limits {
    /// The description's limits, shrunk to `range_fraction` of each position range (about its
    /// middle) and `velocity_fraction` of each velocity limit.
    pub fn of(model: &TreeModel, range_fraction: f64, velocity_fraction: f64) -> Result<Self, ExcitationError> {
        fraction("range fraction", range_fraction)?;
        fraction("velocity fraction", velocity_fraction)?;
        let (mut lower, mut upper, mut velocity) = (Vec::new(), Vec::new(), Vec::new());
        for body in model.bodies() {
            let missing = |what| ExcitationError::MissingLimit { joint: body.joint.clone(), what };
            let (lo, hi) = match (body.limits.lower, body.limits.upper) {
                (Some(lo), Some(hi)) if hi > lo => (lo, hi),
                _ => return Err(missing("position")),
            };
            let v = body.limits.velocity.filter(|v| *v > 0.0).ok_or_else(|| missing("velocity"))?;
            let (middle, half) = ((lo + hi) / 2.0, (hi - lo) / 2.0 * range_fraction);
            lower.push(middle - half);
            upper.push(middle + half);
            velocity.push(v * velocity_fraction);
        }
        Ok(Self { lower, upper, velocity })
    }
}

fn fraction(name: &'static str, value: f64) -> Result<f64, ExcitationError> {
    if value > 0.0 && value <= 1.0 {
        Ok(value)
    } else {
        Err(ExcitationError::Setting { name, value, requirement: "in (0, 1]" })
    }
}

/// A finite Fourier series per joint.
#[derive(Debug, Clone, PartialEq)]
pub struct FourierTrajectory {
    /// `ω_f`, rad/s.
    base_rad_s: f64,
    /// `q_i0`.
    offset: Vec<f64>,
    /// `a_il`, rad/s, joint-major.
    a: Vec<Vec<f64>>,
    /// `b_il`, rad/s.
    b: Vec<Vec<f64>>,
}

impl FourierTrajectory {
    /// The period `2π/ω_f`, s.
    pub fn period_s(&self) -> f64 {
        TAU / self.base_rad_s
    }

    /// Joints.
    pub fn dof(&self) -> usize {
        self.offset.len()
    }

    /// `(q, q̇, q̈)` at time `t`.
    pub fn at(&self, t: f64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
        let w = self.base_rad_s;
        let n = self.dof();
        let (mut q, mut qd, mut qdd) = (self.offset.clone(), vec![0.0; n], vec![0.0; n]);
        for i in 0..n {
            for (l, (a, b)) in self.a[i].iter().zip(&self.b[i]).enumerate() {
                let wl = w * (l + 1) as f64;
                let (s, c) = (wl * t).sin_cos();
                q[i] += (a * s - b * c) / wl;
                qd[i] += a * c + b * s;
                qdd[i] += wl * (-a * s + b * c);
            }
        }
        (q, qd, qdd)
    }

    /// Coefficients drawn in `[−1, 1]` with the rest conditions imposed, offsets zero.
    fn draw(rng: &mut ChaCha8Rng, dof: usize, harmonics: usize, base_rad_s: f64) -> Self {
        let mut draw_rows = || -> Vec<Vec<f64>> {
            (0..dof).map(|_| (0..harmonics).map(|_| rng.gen_range(-1.0..1.0)).collect()).collect()
        };
        let (mut a, mut b) = (draw_rows(), draw_rows());
        for (a, b) in a.iter_mut().zip(b.iter_mut()) {
            a[0] = -a[1..].iter().sum::<f64>();
            b[0] = -b.iter().enumerate().skip(1).map(|(l, b)| (l + 1) as f64 * b).sum::<f64>();
        }
        Self { base_rad_s, offset: vec![0.0; dof], a, b }
    }

    /// Scales each joint's coefficients and sets its offset so that, on `grid` points of a
    /// period, it stays inside `limits` (centred in the position range).
    fn fit(&mut self, limits: &Limits, grid: usize) {
        let period = self.period_s();
        let samples: Vec<_> = (0..grid).map(|k| self.at(period * k as f64 / grid as f64)).collect();
        for i in 0..self.dof() {
            let (lo, hi) =
                samples.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), s| (lo.min(s.0[i]), hi.max(s.0[i])));
            let speed = samples.iter().fold(0.0_f64, |m, s| m.max(s.1[i].abs()));
            let scale = ((limits.upper[i] - limits.lower[i]) / (hi - lo)).min(limits.velocity[i] / speed);
            for c in self.a[i].iter_mut().chain(self.b[i].iter_mut()) {
                *c *= scale;
            }
            // The scaled path spans [scale·lo, scale·hi] about a zero offset: centre it.
            self.offset[i] = (limits.lower[i] + limits.upper[i]) / 2.0 - scale * (lo + hi) / 2.0;
        }
    }
}

/// Settings of the design.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExcitationDesign {
    /// Harmonics per joint, `L`.
    pub harmonics: usize,
    /// Base frequency `ω_f / 2π`, Hz.
    pub base_hz: f64,
    /// Candidates drawn.
    pub candidates: usize,
    /// States of one period the conditioning is computed on.
    pub samples: usize,
    /// The random draw's seed.
    pub seed: u64,
}

impl Default for ExcitationDesign {
    fn default() -> Self {
        Self { harmonics: 5, base_hz: 0.1, candidates: 50, samples: 100, seed: 1 }
    }
}

/// Grid points per period on which the limits are enforced.
const LIMIT_GRID: usize = 2000;

impl ExcitationDesign {
    /// The best candidate for `model` within `limits`, with its conditioning.
    pub fn run(
        &self,
        model: &TreeModel,
        limits: &Limits,
    ) -> Result<(FourierTrajectory, Conditioning), ExcitationError> {
        if !(1..=20).contains(&self.harmonics) {
            return Err(ExcitationError::Setting {
                name: "harmonics",
                value: self.harmonics as f64,
                requirement: "1 to 20",
            });
        }
        if !(self.base_hz > 0.0 && self.base_hz <= 10.0) {
            return Err(ExcitationError::Setting {
                name: "base frequency (Hz)",
                value: self.base_hz,
                requirement: "in (0, 10]",
            });
        }
        if self.candidates == 0 || self.samples < 2 {
            return Err(ExcitationError::Setting {
                name: "candidates and samples",
                value: self.candidates.min(self.samples) as f64,
                requirement: "at least 1 candidate and 2 samples",
            });
        }
        let mut rng = ChaCha8Rng::seed_from_u64(self.seed);
        let regressor = Regressor::new(model);
        let n = model.dof();
        let mut w = DMatrix::zeros(n * self.samples, regressor.columns());
        let mut evaluate = |rng: &mut ChaCha8Rng| -> Result<(FourierTrajectory, Conditioning), ExcitationError> {
            let mut candidate = FourierTrajectory::draw(rng, n, self.harmonics, TAU * self.base_hz);
            candidate.fit(limits, LIMIT_GRID);
            let period = candidate.period_s();
            for k in 0..self.samples {
                let (q, qd, qdd) = candidate.at(period * k as f64 / self.samples as f64);
                regressor.rows_into((&q, &qd, &qdd), &mut w, n * k)?;
            }
            Ok((candidate, Conditioning::of(&w)))
        };
        let mut best = evaluate(&mut rng)?;
        for _ in 1..self.candidates {
            let candidate = evaluate(&mut rng)?;
            if candidate.1.condition_number < best.1.condition_number {
                best = candidate;
            }
        }
        Ok(best)
    }
}
