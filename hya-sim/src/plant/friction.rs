//! Joint friction: the LuGre model with true stiction (the default), or the older smooth
//! `tanh` model kept for comparison.
//!
//! LuGre (Canudas de Wit, Olsson, Åström & Lischinsky, IEEE TAC 40(3), 1995), per joint, with
//! the bristle deflection `z` as state:
//!
//! ```text
//! g(q, q̇) = p(q) (F_c + (F_s − F_c) e^{−(q̇/v_s)²})      Stribeck curve, N·m
//! ż       = q̇ − σ0 |q̇| z / g(q, q̇)                       bristle dynamics, rad
//! τ_f     = −(σ0 z + σ1 ż + σ2 q̇)                          friction torque on the joint, N·m
//! ```
//!
//! At rest `ż = 0` and the bristles act as a stiff spring `σ0 z`: a joint loaded below its
//! static level `p(q) F_s` deflects by at most `p F_s / σ0` and sticks; above it, `z` saturates
//! at `g / σ0` and the joint breaks away. In steady sliding `τ_f = −(g(q̇) sgn q̇ + σ2 q̇)`.
//!
//! The levels vary with position by a smooth profile `p(q)`, drawn once per seed: the paper saw
//! the static friction of HyA's joints change between setpoints (section VI-A).

use std::f64::consts::TAU;

use hya_core::JointVector;
use rand::Rng;

use crate::config::plant::{FrictionLevels, FrictionSetup};

/// Harmonics of each joint's position profile.
const PROFILE_HARMONICS: usize = 3;

/// `p(q) = 1 + a Σ_k w_k sin(κ_k q + φ_k)`, with `Σ_k |w_k| = 1`, so `p ∈ [1 − a, 1 + a]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PositionProfile {
    amplitude: f64,
    weights: [f64; PROFILE_HARMONICS],
    wavenumbers_per_rad: [f64; PROFILE_HARMONICS],
    phases: [f64; PROFILE_HARMONICS],
}

impl PositionProfile {
    /// Seeded: wavelengths between 0.4 and 1.6 rad, so that a move of 0.1–0.2 rad (the paper's
    /// setpoint changes) changes the level noticeably.
    pub fn draw(amplitude: f64, rng: &mut impl Rng) -> Self {
        let raw: [f64; PROFILE_HARMONICS] = core::array::from_fn(|_| rng.gen_range(0.2..1.0));
        let total: f64 = raw.iter().sum();
        Self {
            amplitude,
            weights: raw.map(|w| w / total),
            wavenumbers_per_rad: core::array::from_fn(|_| TAU / rng.gen_range(0.4..1.6)),
            phases: core::array::from_fn(|_| rng.gen_range(0.0..TAU)),
        }
    }

    /// `p(q)` (with hya-core's polynomial `sin`, within 2 ulp of libm's, on one lane per
    /// harmonic: the plant evaluates this for every joint at every integrator stage).
    pub fn at(&self, q: f64) -> f64 {
        let angles: [f64; PROFILE_HARMONICS] =
            core::array::from_fn(|k| self.wavenumbers_per_rad[k] * q + self.phases[k]);
        let wave: f64 = hya_core::sin_cos_lanes(angles).iter().zip(self.weights).map(|((sin, _), w)| w * sin).sum();
        1.0 + self.amplitude * wave
    }
}

/// The Stribeck curve's levels of one joint.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Levels {
    coulomb: f64,
    breakaway: f64,
    stribeck_velocity: f64,
}

impl Levels {
    /// `F_c + (F_s − F_c) e^{−(q̇/v_s)²}`, N·m.
    fn stribeck(&self, qd: f64) -> f64 {
        let r = qd / self.stribeck_velocity;
        self.coulomb + (self.breakaway - self.coulomb) * (-r * r).exp()
    }
}

/// LuGre friction per joint.
#[derive(Debug, Clone)]
pub struct LuGre<const N: usize> {
    levels: [Levels; N],
    profile: [PositionProfile; N],
    /// `σ0`, N·m/rad.
    stiffness: JointVector<N>,
    /// `σ1`, N·m·s/rad.
    damping: JointVector<N>,
    /// `σ2`, N·m·s/rad.
    viscous: JointVector<N>,
}

impl<const N: usize> LuGre<N> {
    /// `g(q, q̇)` of joint `i`, N·m.
    pub fn sliding_level(&self, i: usize, q: f64, qd: f64) -> f64 {
        self.profile[i].at(q) * self.levels[i].stribeck(qd)
    }

    /// The static (breakaway) level `p(q) F_s` of joint `i` at `q`, N·m.
    pub fn static_level(&self, i: usize, q: f64) -> f64 {
        self.profile[i].at(q) * self.levels[i].breakaway
    }

    /// `ż` for every joint, rad/s.
    pub fn bristle_rate(&self, q: &JointVector<N>, qd: &JointVector<N>, z: &JointVector<N>) -> JointVector<N> {
        JointVector::from_fn(|i, _| {
            let v = qd[i];
            v - self.stiffness[i] * v.abs() * z[i] / self.sliding_level(i, q[i], v)
        })
    }

    /// The fastest bristle relaxation rate `max_i σ0 |q̇_i| / g_i`, 1/s: the stiff part of the
    /// model in sliding, which bounds the integrator's step.
    pub fn relaxation_rate(&self, q: &JointVector<N>, qd: &JointVector<N>) -> f64 {
        (0..N).map(|i| self.stiffness[i] * qd[i].abs() / self.sliding_level(i, q[i], qd[i])).fold(0.0, f64::max)
    }

    /// `τ_f = −(σ0 z + σ1 ż + σ2 q̇)` given `ż`, N·m.
    pub fn torque(&self, qd: &JointVector<N>, z: &JointVector<N>, z_rate: &JointVector<N>) -> JointVector<N> {
        -(self.stiffness.component_mul(z) + self.damping.component_mul(z_rate) + self.viscous.component_mul(qd))
    }

    /// The steady-sliding friction of joint `i` at constant `q̇` and the nominal levels (`p = 1`),
    /// N·m.
    pub fn nominal_steady_sliding_torque(&self, i: usize, qd: f64) -> f64 {
        -(self.levels[i].stribeck(qd) * qd.signum() + self.viscous[i] * qd)
    }

    /// The steady-sliding friction of joint `i` at constant `q̇` (closed form), N·m.
    pub fn steady_sliding_torque(&self, i: usize, q: f64, qd: f64) -> f64 {
        -(self.sliding_level(i, q, qd) * qd.signum() + self.viscous[i] * qd)
    }
}

/// The smooth model of the first testbed, no stiction:
/// `τ_f = −[(F_c + (F_s − F_c) e^{−(q̇/v_s)²}) (1 + a sin 2q) tanh(q̇/ε) + F_v q̇]`.
#[derive(Debug, Clone)]
pub struct Smooth<const N: usize> {
    levels: [Levels; N],
    viscous: JointVector<N>,
    smoothing: f64,
    position_variation: f64,
}

impl<const N: usize> Smooth<N> {
    /// The friction torque on each joint, N·m (opposes motion).
    pub fn torque(&self, q: &JointVector<N>, qd: &JointVector<N>) -> JointVector<N> {
        JointVector::from_fn(|i, _| {
            let v = qd[i];
            let level = self.levels[i].stribeck(v) * (1.0 + self.position_variation * (2.0 * q[i]).sin());
            -(level * (v / self.smoothing).tanh() + self.viscous[i] * v)
        })
    }
}

/// The plant's friction model.
#[derive(Debug, Clone)]
pub enum Friction<const N: usize> {
    /// None.
    Off,
    /// The smooth model, without a state.
    Smooth(Smooth<N>),
    /// LuGre, with the bristle deflection as state.
    LuGre(LuGre<N>),
}

impl<const N: usize> Friction<N> {
    /// The law of `setup`; the LuGre position profiles are drawn from `rng`.
    pub fn new(setup: &FrictionSetup<N>, rng: &mut impl Rng) -> Self {
        let levels = |l: &FrictionLevels<N>| -> [Levels; N] {
            core::array::from_fn(|i| Levels {
                coulomb: l.coulomb[i],
                breakaway: l.breakaway[i],
                stribeck_velocity: l.stribeck_velocity,
            })
        };
        match setup {
            FrictionSetup::Off => Friction::Off,
            FrictionSetup::Smooth { levels: l, smoothing } => Friction::Smooth(Smooth {
                levels: levels(l),
                viscous: l.viscous,
                smoothing: *smoothing,
                position_variation: l.position_variation,
            }),
            FrictionSetup::LuGre { levels: l, stiffness, damping } => {
                let profile = core::array::from_fn(|_| PositionProfile::draw(l.position_variation, rng));
                Friction::LuGre(LuGre {
                    levels: levels(l),
                    profile,
                    stiffness: *stiffness,
                    damping: *damping,
                    viscous: l.viscous,
                })
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    #[test]
    fn profile_stays_within_its_band_and_varies() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let p = PositionProfile::draw(0.3, &mut rng);
        let values: Vec<f64> = (0..2000).map(|k| p.at(-2.0 + 0.002 * k as f64)).collect();
        let (lo, hi) = values.iter().fold((f64::MAX, f64::MIN), |(l, h), v| (l.min(*v), h.max(*v)));
        assert!(lo >= 0.7 - 1e-12 && hi <= 1.3 + 1e-12, "profile left [0.7, 1.3]: {lo} .. {hi}");
        assert!(hi - lo > 0.2, "profile barely varies: {lo} .. {hi}");
    }
}
