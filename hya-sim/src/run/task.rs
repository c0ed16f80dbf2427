//! Reference trajectories: hold, goto (minimum-jerk transition) and sine.

use std::f64::consts::PI;

use hya_core::{JointVector, Reference};

use crate::config::scenario::Task;
use crate::error::{SettingError, SimError};

/// A reference trajectory `(q_des, q̇_des, q̈_des)(t)` around the start pose.
#[derive(Debug, Clone)]
pub struct Trajectory<const N: usize> {
    start: JointVector<N>,
    shape: Shape<N>,
}

#[derive(Debug, Clone)]
enum Shape<const N: usize> {
    Hold,
    Goto { start_s: f64, transition_s: f64, delta: JointVector<N> },
    Sine { amplitude: JointVector<N>, frequency_hz: f64, ramp_s: f64 },
}

impl<const N: usize> Trajectory<N> {
    /// The task's trajectory from `start`; `per_joint` is the goto task's step or the sine
    /// task's amplitudes ([`JointSettings::task`](crate::config::settings::JointSettings::task)).
    pub fn new(task: &Task, per_joint: JointVector<N>, start: JointVector<N>) -> Result<Self, SimError> {
        let shape = match task {
            Task::Hold {} => Shape::Hold,
            Task::Goto { start_s, transition_s, .. } => {
                if transition_s.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
                    return Err(SettingError::new("task.transition_s", Some(*transition_s), "must be > 0").into());
                }
                Shape::Goto { start_s: *start_s, transition_s: *transition_s, delta: per_joint }
            }
            Task::Sine { frequency_hz, ramp_s, .. } => {
                Shape::Sine { amplitude: per_joint, frequency_hz: *frequency_hz, ramp_s: ramp_s.max(0.0) }
            }
        };
        Ok(Self { start, shape })
    }

    /// The reference at time `t`.
    pub fn at(&self, t: f64) -> Reference<N> {
        match &self.shape {
            Shape::Hold => Reference::hold(self.start),
            Shape::Goto { start_s, transition_s, delta } => {
                // Minimum jerk: s(τ) = 10τ³ − 15τ⁴ + 6τ⁵ on τ = (t − t0)/T ∈ [0, 1].
                let tau = ((t - start_s) / transition_s).clamp(0.0, 1.0);
                let inside = (0.0..1.0).contains(&tau) && t >= *start_s;
                let s = tau.powi(3) * (10.0 - 15.0 * tau + 6.0 * tau * tau);
                let ds = if inside { 30.0 * tau * tau * (1.0 - tau).powi(2) / transition_s } else { 0.0 };
                let dds =
                    if inside { 60.0 * tau * (1.0 - tau) * (1.0 - 2.0 * tau) / transition_s.powi(2) } else { 0.0 };
                Reference { position: self.start + delta * s, velocity: delta * ds, acceleration: delta * dds }
            }
            Shape::Sine { amplitude, frequency_hz, ramp_s } => {
                // A(t) = A r(t) with the smooth ramp r = minimum jerk over [0, ramp_s].
                let w = 2.0 * PI * frequency_hz;
                let (r, dr, ddr) = if *ramp_s > 0.0 && t < *ramp_s {
                    let u = (t / ramp_s).max(0.0);
                    (
                        u.powi(3) * (10.0 - 15.0 * u + 6.0 * u * u),
                        30.0 * u * u * (1.0 - u).powi(2) / ramp_s,
                        60.0 * u * (1.0 - u) * (1.0 - 2.0 * u) / ramp_s.powi(2),
                    )
                } else {
                    (1.0, 0.0, 0.0)
                };
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
        }
    }
}
