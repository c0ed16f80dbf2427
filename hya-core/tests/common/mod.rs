//! What the integration tests of hya-core share: a plant integrated from the true dynamics, and
//! a least-squares sine fit to read amplitude and phase off a time series.
#![allow(dead_code)]

use hya_core::{Dynamics, JointVector};
use nalgebra::Complex;

/// `M q̈ + C + G = τ + d`, integrated with classic RK4; `d` may depend on time.
pub struct Plant<const N: usize, D> {
    pub dynamics: D,
    pub q: JointVector<N>,
    pub qd: JointVector<N>,
    pub time: f64,
}

impl<const N: usize, D: Dynamics<N>> Plant<N, D> {
    pub fn new(dynamics: D, q: JointVector<N>) -> Self {
        Self { dynamics, q, qd: JointVector::zeros(), time: 0.0 }
    }

    /// One RK4 step of length `h`; `torque(t, q, q̇)` is the total applied torque `τ + d`.
    pub fn step(&mut self, h: f64, torque: impl Fn(f64, &JointVector<N>, &JointVector<N>) -> JointVector<N>) {
        let acceleration = |t: f64, q: &JointVector<N>, qd: &JointVector<N>| {
            self.dynamics.forward_dynamics(q, qd, &torque(t, q, qd)).expect("the test arm's mass matrix is regular")
        };
        let (t, q, qd) = (self.time, self.q, self.qd);
        let k1v = qd;
        let k1a = acceleration(t, &q, &qd);
        let k2v = qd + k1a * (h / 2.0);
        let k2a = acceleration(t + h / 2.0, &(q + k1v * (h / 2.0)), &k2v);
        let k3v = qd + k2a * (h / 2.0);
        let k3a = acceleration(t + h / 2.0, &(q + k2v * (h / 2.0)), &k3v);
        let k4v = qd + k3a * h;
        let k4a = acceleration(t + h, &(q + k3v * h), &k4v);
        self.q += (k1v + k2v * 2.0 + k3v * 2.0 + k4v) * (h / 6.0);
        self.qd += (k1a + k2a * 2.0 + k3a * 2.0 + k4a) * (h / 6.0);
        self.time += h;
    }
}

/// The complex amplitude `A` of `y(t) ≈ Im(A e^{jωt}) + c` by least squares over the samples.
pub fn fit_sine(omega: f64, samples: &[(f64, f64)]) -> Complex<f64> {
    // Normal equations of y = a sin ωt + b cos ωt + c; then A = a + j b.
    let mut normal = nalgebra::Matrix3::<f64>::zeros();
    let mut rhs = nalgebra::Vector3::<f64>::zeros();
    for &(t, y) in samples {
        let basis = nalgebra::Vector3::new((omega * t).sin(), (omega * t).cos(), 1.0);
        normal += basis * basis.transpose();
        rhs += basis * y;
    }
    let coefficients = normal.lu().solve(&rhs).expect("samples span the sine");
    Complex::new(coefficients[0], coefficients[1])
}
