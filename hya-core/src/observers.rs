//! Disturbance observers behind one per-tick interface: the paper's estimator and the baselines it
//! is compared against (Lu, Sandy & Buchli, section V).
//!
//! Every observer reads one [`Measurement`] per control tick (measured `q`, optionally measured
//! `q̇`, and the measured or commanded `τ`) and returns `d̂` for the model
//! `M(q) q̈ + C(q, q̇) + G(q) = τ + d`; compensation subtracts `d̂`.
//!
//! | observer | needs `q̇_m` | `d̂ / d` on a linear plant |
//! |---|---|---|
//! | [`DisturbanceEstimator`] (Lu et al.) | no | `H(s)`, third order |
//! | [`NonlinearDisturbanceObserver`] (Chen 2000) | yes | `L / (s + L)`, `L = y M⁻¹` |
//! | [`MomentumObserver`] (De Luca; Haddadin 2017) | yes | `k / (s + k)` per joint |
//! | [`ExtendedStateObserver`] (Han; Gao) | no | `ω³ / (s + ω)³` per joint |

use nalgebra::{Matrix3, SMatrix, Vector3};

use crate::finite::{check, positive};
use crate::linalg::matrix_exponential;
use crate::{DisturbanceEstimator, Dynamics, Error, JointMatrix, JointVector};

/// What an observer reads at one control tick.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Measurement<const N: usize> {
    /// Measured joint positions `q_m`, rad.
    pub position: JointVector<N>,
    /// Measured joint velocities `q̇_m`, rad/s, where a sensor provides them.
    pub velocity: Option<JointVector<N>>,
    /// Measured (or commanded) joint torques `τ_m`, N·m.
    pub torque: JointVector<N>,
}

impl<const N: usize> Measurement<N> {
    fn required_velocity(&self) -> Result<JointVector<N>, Error> {
        let velocity = self.velocity.ok_or(Error::MissingMeasurement { signal: "qd_m" })?;
        check("qd_m", &velocity)?;
        Ok(velocity)
    }

    fn checked(&self) -> Result<(), Error> {
        check("q_m", &self.position)?;
        check("tau_m", &self.torque)
    }
}

/// A disturbance observer stepped once per control tick.
pub trait DisturbanceObserver<const N: usize> {
    /// Advances one tick and returns the new `d̂`, N·m. A failed update leaves the state as it was.
    fn update(&mut self, measurement: &Measurement<N>) -> Result<JointVector<N>, Error>;
    /// The latest `d̂`, N·m.
    fn disturbance(&self) -> &JointVector<N>;
}

impl<const N: usize, D: Dynamics<N>> DisturbanceObserver<N> for DisturbanceEstimator<N, D> {
    fn update(&mut self, measurement: &Measurement<N>) -> Result<JointVector<N>, Error> {
        DisturbanceEstimator::update(self, &measurement.position, &measurement.torque)
    }
    fn disturbance(&self) -> &JointVector<N> {
        DisturbanceEstimator::disturbance(self)
    }
}

/// The nonlinear disturbance observer of Chen et al. (IEEE TIE 2000) with the general gain of
/// Mohammadi et al. (Control Eng. Practice 2013), `Y = y I`:
///
/// ```text
/// p = y q̇,   L = y M⁻¹(q),   ż = −L z + L (C + G − τ − p),   d̂ = z + p
/// ```
///
/// so that `d̂̇ = L (d − d̂)`. Stepped implicitly, `(M + T y I) z_{k+1} = M z_k + T y (C + G − τ − p)`,
/// because `L` is stiff for light distal links. Measured velocity noise reaches `d̂` with gain `y`.
#[derive(Debug, Clone)]
pub struct NonlinearDisturbanceObserver<const N: usize, D> {
    dynamics: D,
    gain: f64,
    dt_s: f64,
    z: JointVector<N>,
    disturbance: JointVector<N>,
}

/// Mohammadi's gain for [`NonlinearDisturbanceObserver`]: `y = ½ (ξ + 2 β σ)` for convergence
/// rate `β` (1/s), `σ ≥ λmax(M)` (kg·m²) and `ξ ≥ ‖Ṁ‖` (kg·m²/s).
pub fn mohammadi_gain(convergence_rate: f64, sigma: f64, xi: f64) -> Result<f64, Error> {
    let beta = positive("convergence_rate", convergence_rate)?;
    let sigma = positive("sigma", sigma)?;
    if !(xi.is_finite() && xi >= 0.0) {
        return Err(Error::InvalidParameter { name: "xi", value: xi, requirement: "finite and >= 0" });
    }
    Ok(0.5 * (xi + 2.0 * beta * sigma))
}

impl<const N: usize, D: Dynamics<N>> NonlinearDisturbanceObserver<N, D> {
    /// An observer with gain `y` (N·m·s/rad) at sample time `dt`, started at `z0 = −y q̇0`
    /// (so `d̂ = 0`).
    pub fn new(dynamics: D, gain: f64, dt_s: f64, qd0: JointVector<N>) -> Result<Self, Error> {
        check("qd0", &qd0)?;
        let gain = positive("gain", gain)?;
        Ok(Self { dynamics, gain, dt_s: positive("dt_s", dt_s)?, z: -qd0 * gain, disturbance: JointVector::zeros() })
    }
}

impl<const N: usize, D: Dynamics<N>> DisturbanceObserver<N> for NonlinearDisturbanceObserver<N, D> {
    fn update(&mut self, m: &Measurement<N>) -> Result<JointVector<N>, Error> {
        m.checked()?;
        let qd = m.required_velocity()?;
        let (y, t) = (self.gain, self.dt_s);
        let p = qd * y;
        let bias = self.dynamics.inverse_dynamics(&m.position, &qd, &JointVector::zeros());
        let mass = self.dynamics.mass_matrix(&m.position);
        let system = mass + JointMatrix::<N>::identity() * (t * y);
        let rhs = mass * self.z + (bias - m.torque - p) * (t * y);
        let z = system.cholesky().ok_or(Error::SingularMassMatrix)?.solve(&rhs);
        let disturbance = z + p;
        check("d_hat", &disturbance)?;
        self.z = z;
        self.disturbance = disturbance;
        Ok(disturbance)
    }
    fn disturbance(&self) -> &JointVector<N> {
        &self.disturbance
    }
}

/// The generalized-momentum observer (De Luca & Mattone; Haddadin et al., T-RO 2017):
///
/// ```text
/// p = M q̇,   r = K_O (p − ∫ (τ + Cᵀq̇ − G + r) dt − p0)   ⇒   r = k / (s + k) d per joint
/// ```
///
/// With `w = K_O p − r` this is the first-order lag `ẇ = K_O (u − w)`, `u = τ − G + Cᵀq̇ + K_O p`,
/// and `r = K_O p − w`. It is stepped exactly for `u` linear between samples (first-order hold),
/// `a = e^{−K_O T}`:
///
/// ```text
/// w_k = a w_{k−1} + c_now u_k + c_prev u_{k−1},   c_now = 1 − (1 − a)/(K_O T),   c_prev = (1 − a) − c_now
/// ```
///
/// The zero-order-hold form `w_k = a w_{k−1} + (1 − a) u_k` would be exact only for held inputs,
/// but `p = M q̇` and a measured torque vary within a tick; it loses 2 % of gain at `ω = K_O`
/// for `T = 1 ms` (measured by this crate's observer tests).
#[derive(Debug, Clone)]
pub struct MomentumObserver<const N: usize, D> {
    dynamics: D,
    gain: JointVector<N>,
    decay: JointVector<N>,
    weight_now: JointVector<N>,
    w: JointVector<N>,
    last_input: JointVector<N>,
    disturbance: JointVector<N>,
}

impl<const N: usize, D: Dynamics<N>> MomentumObserver<N, D> {
    /// An observer with per-joint gains `k` (1/s) at sample time `dt`, started with `r = 0` at
    /// `(q0, q̇0)` with torque `τ0`.
    pub fn new(
        dynamics: D,
        gain: JointVector<N>,
        dt_s: f64,
        q0: JointVector<N>,
        qd0: JointVector<N>,
        tau0: JointVector<N>,
    ) -> Result<Self, Error> {
        for &k in gain.iter() {
            positive("gain", k)?;
        }
        let dt = positive("dt_s", dt_s)?;
        let initial = Measurement { position: q0, velocity: Some(qd0), torque: tau0 };
        initial.checked()?;
        let decay = gain.map(|k| libm::exp(-k * dt));
        let weight_now = gain.zip_map(&decay, |k, a| 1.0 - (1.0 - a) / (k * dt));
        let mut observer = Self {
            decay,
            weight_now,
            w: JointVector::zeros(),
            last_input: JointVector::zeros(),
            gain,
            dynamics,
            disturbance: JointVector::zeros(),
        };
        let (input, scaled_momentum) = observer.lag_input(&initial, &qd0);
        observer.w = scaled_momentum;
        observer.last_input = input;
        Ok(observer)
    }

    /// `(u, K_O p)` for one measurement.
    fn lag_input(&self, m: &Measurement<N>, qd: &JointVector<N>) -> (JointVector<N>, JointVector<N>) {
        let q = &m.position;
        let scaled_momentum = self.gain.component_mul(&(self.dynamics.mass_matrix(q) * qd));
        let input = m.torque - self.dynamics.gravity(q)
            + self.dynamics.coriolis_transpose_times_velocity(q, qd)
            + scaled_momentum;
        (input, scaled_momentum)
    }
}

impl<const N: usize, D: Dynamics<N>> DisturbanceObserver<N> for MomentumObserver<N, D> {
    fn update(&mut self, m: &Measurement<N>) -> Result<JointVector<N>, Error> {
        m.checked()?;
        let qd = m.required_velocity()?;
        let (input, scaled_momentum) = self.lag_input(m, &qd);
        let weight_previous = JointVector::repeat(1.0) - self.decay - self.weight_now;
        let w = self.decay.component_mul(&self.w)
            + self.weight_now.component_mul(&input)
            + weight_previous.component_mul(&self.last_input);
        let disturbance = scaled_momentum - w;
        check("d_hat", &disturbance)?;
        self.w = w;
        self.last_input = input;
        self.disturbance = disturbance;
        Ok(disturbance)
    }
    fn disturbance(&self) -> &JointVector<N> {
        &self.disturbance
    }
}

/// The model-assisted extended state observer (Han; Gao's bandwidth parameterisation), per joint:
///
/// ```text
/// ż1 = z2 + β1 (q − z1)
/// ż2 = z3 + f + β2 (q − z1),   f = [M⁻¹(q) (τ − C(q, z2) − G(q))]_i
/// ż3 = β3 (q − z1)
/// β1 = 3ω, β2 = 3ω², β3 = ω³,   d̂ = M(q) z3
/// ```
///
/// so `z3 / (d/M) = ω³ / (s + ω)³` on a linear plant. Needs only `q`, like the paper's method.
/// Stepped exactly for `q` and `f` held over a tick.
#[derive(Debug, Clone)]
pub struct ExtendedStateObserver<const N: usize, D> {
    dynamics: D,
    transition: Matrix3<f64>,
    input_position: Vector3<f64>,
    input_model: Vector3<f64>,
    state: SMatrix<f64, 3, N>,
    disturbance: JointVector<N>,
}

impl<const N: usize, D: Dynamics<N>> ExtendedStateObserver<N, D> {
    /// An observer with bandwidth `ω` (rad/s) at sample time `dt`, started at `z = (q0, 0, 0)`.
    pub fn new(dynamics: D, bandwidth_rad_s: f64, dt_s: f64, q0: JointVector<N>) -> Result<Self, Error> {
        let w = positive("bandwidth_rad_s", bandwidth_rad_s)?;
        let dt = positive("dt_s", dt_s)?;
        check("q0", &q0)?;
        let (b1, b2, b3) = (3.0 * w, 3.0 * w * w, w * w * w);
        let mut augmented = SMatrix::<f64, 5, 5>::zeros();
        let a = Matrix3::new(-b1, 1.0, 0.0, -b2, 0.0, 1.0, -b3, 0.0, 0.0);
        augmented.fixed_view_mut::<3, 3>(0, 0).copy_from(&(a * dt));
        augmented.fixed_view_mut::<3, 1>(0, 3).copy_from(&(Vector3::new(b1, b2, b3) * dt));
        augmented.fixed_view_mut::<3, 1>(0, 4).copy_from(&(Vector3::new(0.0, 1.0, 0.0) * dt));
        let e = matrix_exponential(&augmented);
        let mut state = SMatrix::<f64, 3, N>::zeros();
        state.set_row(0, &q0.transpose());
        Ok(Self {
            dynamics,
            transition: e.fixed_view::<3, 3>(0, 0).into(),
            input_position: e.fixed_view::<3, 1>(0, 3).into(),
            input_model: e.fixed_view::<3, 1>(0, 4).into(),
            state,
            disturbance: JointVector::zeros(),
        })
    }
}

impl<const N: usize, D: Dynamics<N>> DisturbanceObserver<N> for ExtendedStateObserver<N, D> {
    fn update(&mut self, m: &Measurement<N>) -> Result<JointVector<N>, Error> {
        m.checked()?;
        let q = &m.position;
        let velocity_estimate: JointVector<N> = self.state.row(1).transpose();
        let model_acceleration = self.dynamics.forward_dynamics(q, &velocity_estimate, &m.torque)?;
        let state = self.transition * self.state
            + self.input_position * q.transpose()
            + self.input_model * model_acceleration.transpose();
        let disturbance = self.dynamics.mass_matrix(q) * state.row(2).transpose();
        check("d_hat", &disturbance)?;
        self.state = state;
        self.disturbance = disturbance;
        Ok(disturbance)
    }
    fn disturbance(&self) -> &JointVector<N> {
        &self.disturbance
    }
}
