//! Sensor noise, seeded: the same seed gives the same draws, bit for bit.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

use hya_core::JointVector;

use crate::scenario::{Noise, NoiseConfig};

/// Draws sensor noise from one seeded stream.
#[derive(Debug, Clone)]
pub struct Sensors {
    rng: ChaCha8Rng,
    config: NoiseConfig,
}

impl Sensors {
    /// A stream for `config` from `seed`.
    pub fn new(config: NoiseConfig, seed: u64) -> Self {
        Self { rng: ChaCha8Rng::seed_from_u64(seed), config }
    }

    fn draw<const N: usize>(&mut self, noise: Noise) -> JointVector<N> {
        match noise {
            Noise::Off => JointVector::zeros(),
            Noise::Uniform { bound } => {
                JointVector::from_fn(|_, _| bound * (2.0 * rand::Rng::gen::<f64>(&mut self.rng) - 1.0))
            }
            Noise::Gaussian { sigma } => match Normal::new(0.0, sigma) {
                Ok(normal) => JointVector::from_fn(|_, _| normal.sample(&mut self.rng)),
                Err(_) => JointVector::zeros(),
            },
        }
    }

    /// `(q_m, q̇_m, τ_m)` for the true `(q, q̇, τ)`.
    pub fn measure<const N: usize>(
        &mut self,
        q: &JointVector<N>,
        qd: &JointVector<N>,
        tau: &JointVector<N>,
    ) -> (JointVector<N>, JointVector<N>, JointVector<N>) {
        let (p, v, t) = (self.config.position, self.config.velocity, self.config.torque);
        (q + self.draw(p), qd + self.draw(v), tau + self.draw(t))
    }
}
