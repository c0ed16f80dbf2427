//! The frequency domain's basics: `s = jω`, a pure delay, and the complex amplitude of a sampled
//! signal at one frequency.

use nalgebra::Complex;

/// `s = jω`.
pub fn jw(omega: f64) -> Complex<f64> {
    Complex::new(0.0, omega)
}

/// A pure delay `e^{−jωT}`.
pub(crate) fn delay(omega: f64, t: f64) -> Complex<f64> {
    Complex::from_polar(1.0, -omega * t)
}

/// The complex amplitude of `x` at `ω` over the samples `(t, x)`: `(2/N) Σ x e^{−jωt}` (exact
/// for a sine over whole periods).
pub fn phasor(samples: &[(f64, f64)], omega: f64) -> Complex<f64> {
    let mut sum = PhasorSum::new(omega);
    samples.iter().for_each(|(t, x)| sum.push(*t, *x));
    sum.value()
}

/// [`phasor`] kept up to date sample by sample.
#[derive(Debug, Clone, Copy)]
pub struct PhasorSum {
    omega: f64,
    sum: Complex<f64>,
    count: usize,
}

impl PhasorSum {
    /// No samples yet, at `omega` (rad/s).
    pub fn new(omega: f64) -> Self {
        Self { omega, sum: Complex::new(0.0, 0.0), count: 0 }
    }

    /// Adds the sample `x` at `t`.
    pub fn push(&mut self, t: f64, x: f64) {
        self.sum += Complex::new((self.omega * t).cos(), -(self.omega * t).sin()) * x;
        self.count += 1;
    }

    /// `(2/N) Σ x e^{−jωt}` so far (0 before any sample).
    pub fn value(&self) -> Complex<f64> {
        self.sum * (2.0 / self.count.max(1) as f64)
    }
}
