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
    #[error("{name} = {}: must be {requirement}", hya_core::Short(*value))]
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

/// The most candidates a design draws ([`ExcitationDesign::candidates`]).
pub const MAX_CANDIDATES: usize = 100_000;

/// Grid points per period on which the limits are enforced.
const LIMIT_GRID: usize = 2000;

impl ExcitationDesign {
    /// The best candidate for `model` within `limits`, with its conditioning.
    pub fn run(
        &self,
        model: &TreeModel,
        limits: &Limits,
    ) -> Result<(FourierTrajectory, Conditioning), ExcitationError> {
        self.run_observed(model, limits, |_| {})
    }

    /// [`Self::run`], calling `done(k)` after the `k`-th candidate (from 1), e.g. to time the
    /// first and say how long the rest will take.
    pub fn run_observed(
        &self,
        model: &TreeModel,
        limits: &Limits,
        mut done: impl FnMut(usize),
    ) -> Result<(FourierTrajectory, Conditioning), ExcitationError> {
        crate::check_joint_count(model)?;
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
        if self.candidates > MAX_CANDIDATES {
            return Err(ExcitationError::Setting {
                name: "candidates",
                value: self.candidates as f64,
                requirement: "at most 100000 (about 9 ms each on a 7-joint arm: 15 minutes)",
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
        done(1);
        for k in 2..=self.candidates {
            let candidate = evaluate(&mut rng)?;
            if candidate.1.condition_number < best.1.condition_number {
                best = candidate;
            }
            done(k);
        }
        Ok(best)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use hya_core::model::{Body, JointKind, JointLimits};
    use hya_core::spatial::{RigidBodyInertia, Transform};
    use nalgebra::{Matrix3, Vector3};

    /// A planar two-link arm (joints about y, gravity along −z, in the arm's plane).
    fn planar() -> TreeModel {
        let link = |name: &str, parent: Option<usize>, offset: f64, mass: f64| Body {
            link: format!("{name}_link"),
            joint: name.to_owned(),
            parent,
            kind: JointKind::Revolute,
            axis: Vector3::y(),
            tree_transform: Transform::from_arrays(
                [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
                [offset, 0.0, 0.0],
            ),
            inertia: RigidBodyInertia::from_centre_of_mass(
                mass,
                Vector3::new(0.25, 0.0, 0.02),
                Matrix3::from_diagonal(&Vector3::new(0.01, 0.02, 0.03)),
            ),
            limits: JointLimits { lower: Some(-2.0), upper: Some(1.0), velocity: Some(3.0), effort: None },
        };
        TreeModel::new("planar", vec![link("shoulder", None, 0.0, 2.0), link("elbow", Some(0), 0.5, 1.5)], vec![])
            .unwrap()
    }

    fn design(candidates: usize) -> (FourierTrajectory, Conditioning, Limits) {
        let model = planar();
        let limits = Limits::of(&model, 0.8, 0.5).unwrap();
        let (trajectory, conditioning) =
            ExcitationDesign { candidates, samples: 60, ..ExcitationDesign::default() }.run(&model, &limits).unwrap();
        (trajectory, conditioning, limits)
    }

    #[test]
    fn each_period_starts_and_ends_at_rest() {
        let (trajectory, _, _) = design(3);
        let period = trajectory.period_s();
        for t in [0.0, period, 3.0 * period] {
            let (q, qd, qdd) = trajectory.at(t);
            let (q0, _, _) = trajectory.at(0.0);
            for i in 0..2 {
                assert!(qd[i].abs() < 1e-12 && qdd[i].abs() < 1e-12, "t = {t}: q̇ = {qd:?}, q̈ = {qdd:?}");
                assert!((q[i] - q0[i]).abs() < 1e-9, "not periodic at t = {t}");
            }
        }
    }

    #[test]
    fn the_trajectory_stays_within_its_limits_between_grid_points_too() {
        let (trajectory, _, limits) = design(3);
        let steps = 10 * LIMIT_GRID;
        for k in 0..=steps {
            let (q, qd, _) = trajectory.at(trajectory.period_s() * k as f64 / steps as f64);
            for i in 0..2 {
                // The grid's limit holds between its points to within a few parts per million.
                let slack = 1e-5 * (limits.upper[i] - limits.lower[i]);
                assert!(q[i] >= limits.lower[i] - slack && q[i] <= limits.upper[i] + slack, "q[{i}] = {}", q[i]);
                assert!(qd[i].abs() <= limits.velocity[i] * (1.0 + 1e-5), "q̇[{i}] = {}", qd[i]);
            }
        }
    }

    #[test]
    fn velocity_and_acceleration_are_the_derivatives_of_position() {
        let (trajectory, _, _) = design(2);
        let h = 1e-5;
        for k in 1..50 {
            let t = trajectory.period_s() * k as f64 / 50.0;
            let ((qm, qdm, _), (qp, qdp, _), (_, qd, qdd)) =
                (trajectory.at(t - h), trajectory.at(t + h), trajectory.at(t));
            for i in 0..2 {
                assert!(((qp[i] - qm[i]) / (2.0 * h) - qd[i]).abs() < 1e-6, "q̇ at t = {t}");
                assert!(((qdp[i] - qdm[i]) / (2.0 * h) - qdd[i]).abs() < 1e-5, "q̈ at t = {t}");
            }
        }
    }

    /// A planar 2R arm with gravity in its plane has six base parameters (Khalil and Dombre):
    /// link 2's inertia about its axis and its two in-plane first moments; link 1's the same,
    /// with link 2's mass lumped at the elbow (`I_1 + m_2 l_1²`, `h_1x + m_2 l_1`, `h_1z`).
    #[test]
    fn a_planar_two_link_arm_identifies_six_combinations() {
        let (_, conditioning, _) = design(4);
        assert_eq!(conditioning.rank, 6);
        assert!(conditioning.condition_number.is_finite() && conditioning.condition_number >= 1.0);
    }

    #[test]
    fn joints_without_limits_and_bad_settings_are_refused_by_name() {
        let mut model = planar();
        let mut bodies = model.bodies().to_vec();
        bodies[1].limits.velocity = None;
        model = TreeModel::new("planar", bodies, vec![]).unwrap();
        let message = Limits::of(&model, 0.8, 0.5).unwrap_err().to_string();
        assert!(message.contains("`elbow`") && message.contains("velocity"), "{message}");
        assert!(Limits::of(&planar(), 0.0, 0.5).is_err());
        let limits = Limits::of(&planar(), 0.8, 0.5).unwrap();
        for design in [
            ExcitationDesign { harmonics: 0, ..ExcitationDesign::default() },
            ExcitationDesign { base_hz: f64::NAN, ..ExcitationDesign::default() },
            ExcitationDesign { candidates: 0, ..ExcitationDesign::default() },
        ] {
            assert!(matches!(design.run(&planar(), &limits), Err(ExcitationError::Setting { .. })));
        }
    }
}
