//! Reference trajectories: hold, goto (minimum-jerk transition), sine, and samples given by the
//! user (an exciting trajectory from `hya excite`, say).

use std::f64::consts::PI;

use hya_core::{JointVector, Reference, Short};

use crate::config::settings::TaskSetup;
use crate::error::SimError;

/// A reference trajectory `(q_des, q̇_des, q̈_des)(t)` around the start pose.
#[derive(Debug, Clone)]
pub struct Trajectory<const N: usize> {
    start: JointVector<N>,
    shape: Shape<N>,
}

#[derive(Debug, Clone)]
enum Shape<const N: usize> {
    Task(TaskSetup<N>),
    Sampled(Samples<N>),
}

/// A reference given at sample times `t_k` (strictly increasing, from 0): between two samples
/// the position is the cubic Hermite curve through their positions and velocities, the velocity
/// its derivative, and the acceleration linear between theirs; before the first and after the
/// last sample the reference holds that sample's position at rest.
#[derive(Debug, Clone)]
pub struct Samples<const N: usize> {
    time: Vec<f64>,
    points: Vec<Reference<N>>,
}

impl<const N: usize> Samples<N> {
    /// Samples at `time` (strictly increasing, finite, from 0); an error names the first bad one.
    pub fn new(time: Vec<f64>, points: Vec<Reference<N>>) -> Result<Self, SimError> {
        let bad = |k: usize, value: f64, requirement: &str| {
            Err(SimError::Reference { sample: format!("{}", k + 1), value, rule: requirement.into() })
        };
        if time.is_empty() || time.len() != points.len() {
            return bad(0, time.len() as f64, "one time per sample, at least one sample");
        }
        if time[0] != 0.0 {
            return bad(0, time[0], "the first sample's time must be 0");
        }
        for (k, pair) in time.windows(2).enumerate() {
            if !(pair[1].is_finite() && pair[1] > pair[0]) {
                return bad(k + 1, pair[1], "times must be finite and strictly increasing");
            }
        }
        if let Some(k) = points
            .iter()
            .position(|p| p.position.iter().chain(&p.velocity).chain(&p.acceleration).any(|v| !v.is_finite()))
        {
            return bad(k, f64::NAN, "every position, velocity and acceleration must be finite");
        }
        Ok(Self { time, points })
    }

    /// `Ok` if every sample's position lies within `model`'s joint limits where the description
    /// gives them; an error names the sample, its time, the joint and the limits (a reference
    /// at 1e6 rad once ran until the state became non-finite).
    pub fn within_limits(&self, model: &hya_core::model::TreeModel) -> Result<(), SimError> {
        for (k, (t, point)) in self.time.iter().zip(&self.points).enumerate() {
            for (j, body) in model.bodies().iter().enumerate().take(N) {
                let q = point.position[j];
                let (lo, hi) =
                    (body.limits.lower.unwrap_or(f64::NEG_INFINITY), body.limits.upper.unwrap_or(f64::INFINITY));
                if !(lo..=hi).contains(&q) {
                    return Err(SimError::Reference {
                        sample: format!(
                            "{} (t = {} s), joint {}",
                            k + 1,
                            Short(*t),
                            hya_urdf::name_list([body.joint.as_str()])
                        ),
                        value: q,
                        rule: format!(
                            "beyond the joint's limits [{}, {}] rad in the description",
                            Short(lo),
                            Short(hi)
                        ),
                    });
                }
            }
        }
        Ok(())
    }

    /// The last sample's time, s.
    pub fn duration_s(&self) -> f64 {
        self.time[self.time.len() - 1]
    }

    /// The first sample's position, rad.
    pub fn start(&self) -> JointVector<N> {
        self.points[0].position
    }

    /// The reference at `t` (see the type's notes).
    fn at(&self, t: f64) -> Reference<N> {
        let last = self.points.len() - 1;
        if t <= 0.0 || last == 0 {
            return Reference::hold(self.points[0].position);
        }
        if t >= self.time[last] {
            return Reference::hold(self.points[last].position);
        }
        let k = self.time.partition_point(|&tk| tk <= t) - 1;
        let (a, b) = (&self.points[k], &self.points[k + 1]);
        let h = self.time[k + 1] - self.time[k];
        let s = (t - self.time[k]) / h;
        // Cubic Hermite basis on s ∈ [0, 1] and its derivative with respect to t.
        let (s2, s3) = (s * s, s * s * s);
        let (h00, h10, h01, h11) = (2.0 * s3 - 3.0 * s2 + 1.0, s3 - 2.0 * s2 + s, 3.0 * s2 - 2.0 * s3, s3 - s2);
        let (d00, d10, d01, d11) =
            ((6.0 * s2 - 6.0 * s) / h, 3.0 * s2 - 4.0 * s + 1.0, (6.0 * s - 6.0 * s2) / h, 3.0 * s2 - 2.0 * s);
        Reference {
            position: a.position * h00 + a.velocity * (h * h10) + b.position * h01 + b.velocity * (h * h11),
            velocity: a.position * d00 + a.velocity * d10 + b.position * d01 + b.velocity * d11,
            acceleration: a.acceleration * (1.0 - s) + b.acceleration * s,
        }
    }
}

/// The minimum-jerk profile from 0 to 1 over `[start_s, start_s + transition_s]` and its first
/// two time derivatives at `t`: `s(τ) = 10τ³ − 15τ⁴ + 6τ⁵` on `τ = (t − start_s)/T ∈ [0, 1]`,
/// constant outside.
pub fn minimum_jerk(t: f64, start_s: f64, transition_s: f64) -> (f64, f64, f64) {
    let tau = ((t - start_s) / transition_s).clamp(0.0, 1.0);
    let inside = (0.0..1.0).contains(&tau) && t >= start_s;
    let s = tau.powi(3) * (10.0 - 15.0 * tau + 6.0 * tau * tau);
    let ds = if inside { 30.0 * tau * tau * (1.0 - tau).powi(2) / transition_s } else { 0.0 };
    let dds = if inside { 60.0 * tau * (1.0 - tau) * (1.0 - 2.0 * tau) / transition_s.powi(2) } else { 0.0 };
    (s, ds, dds)
}

impl<const N: usize> Trajectory<N> {
    /// `Ok` unless the trajectory is sampled and leaves `model`'s joint limits
    /// ([`Samples::within_limits`]); the other shapes are checked with their scenario.
    pub fn within_limits(&self, model: &hya_core::model::TreeModel) -> Result<(), SimError> {
        match &self.shape {
            Shape::Sampled(samples) => samples.within_limits(model),
            _ => Ok(()),
        }
    }

    /// The trajectory of `task` from `start`.
    pub fn new(task: TaskSetup<N>, start: JointVector<N>) -> Self {
        Self { start, shape: Shape::Task(task) }
    }

    /// The trajectory through `samples`, starting at their first position.
    pub fn sampled(samples: Samples<N>) -> Self {
        Self { start: samples.start(), shape: Shape::Sampled(samples) }
    }

    /// The reference at time `t`.
    pub fn at(&self, t: f64) -> Reference<N> {
        match self.shape {
            // A Cartesian task holds the joints' start pose: the posture's rest.
            Shape::Task(TaskSetup::Hold | TaskSetup::Cartesian { .. }) => Reference::hold(self.start),
            Shape::Task(TaskSetup::Goto { start_s, transition_s, delta }) => {
                let (s, ds, dds) = minimum_jerk(t, start_s, transition_s);
                Reference { position: self.start + delta * s, velocity: delta * ds, acceleration: delta * dds }
            }
            Shape::Task(TaskSetup::Sine { amplitude, frequency_hz, ramp_s }) => {
                // A(t) = A r(t) with the smooth ramp r = minimum jerk over [0, ramp_s].
                let w = 2.0 * PI * frequency_hz;
                let (r, dr, ddr) = if ramp_s > 0.0 { minimum_jerk(t, 0.0, ramp_s) } else { (1.0, 0.0, 0.0) };
                let (s, c) = (w * t).sin_cos();
                let position = r * s;
                let velocity = dr * s + r * w * c;
                let acceleration = ddr * s + 2.0 * dr * w * c - r * w * w * s;
                Reference {
                    position: self.start + amplitude * position,
                    velocity: amplitude * velocity,
                    acceleration: amplitude * acceleration,
                }
            }
            Shape::Sampled(ref samples) => samples.at(t),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `q(t) = t³`, whose acceleration is linear: the samples' interpolation is exact for it.
    fn cubic(t: f64) -> Reference<1> {
        Reference {
            position: JointVector::from([t * t * t]),
            velocity: JointVector::from([3.0 * t * t]),
            acceleration: JointVector::from([6.0 * t]),
        }
    }

    #[test]
    fn sampled_reference_is_exact_for_a_cubic_and_holds_outside_its_samples() {
        let time = vec![0.0, 0.5, 1.0];
        let trajectory =
            Trajectory::sampled(Samples::new(time.clone(), time.iter().map(|&t| cubic(t)).collect()).unwrap());
        for t in [0.1, 0.25, 0.5, 0.8] {
            let (got, want) = (trajectory.at(t), cubic(t));
            assert!((got.position[0] - want.position[0]).abs() < 1e-15, "q at {t}");
            assert!((got.velocity[0] - want.velocity[0]).abs() < 1e-14, "q̇ at {t}");
            assert!((got.acceleration[0] - want.acceleration[0]).abs() < 1e-14, "q̈ at {t}");
        }
        assert_eq!(trajectory.at(2.0), Reference::hold(JointVector::from([1.0])));
        assert_eq!(trajectory.at(-1.0), Reference::hold(JointVector::from([0.0])));
    }

    #[test]
    fn samples_refuse_bad_times_and_values_by_sample() {
        let point = cubic(0.0);
        let error = |time: Vec<f64>, points: Vec<Reference<1>>| Samples::new(time, points).unwrap_err().to_string();
        assert!(error(vec![0.0, 0.0], vec![point; 2]).contains("reference sample 2"));
        assert!(error(vec![1.0], vec![point]).contains("first sample's time must be 0"));
        let bad = Reference { position: JointVector::from([f64::NAN]), ..point };
        assert!(error(vec![0.0, 1.0], vec![point, bad]).contains("reference sample 2"));
        assert!(error(vec![], vec![]).contains("at least one sample"));
    }
}
