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

use crate::finite::{check, discretisable, positive};
use crate::rigid_body::linalg::matrix_exponential;
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

/// The nonlinear disturbance observer of Chen et al. (IEEE TIE 2000) with the general gain `Y` of
/// Mohammadi et al. (Control Eng. Practice 2013):
///
/// ```text
/// p = Y q̇,   L = Y M⁻¹(q),   ż = −L z + L (C + G − τ − p),   d̂ = z + p
/// ```
///
/// so that `d̂̇ = L (d − d̂)`: the observer's rates are the eigenvalues of `L(q)`. Two designs:
/// Mohammadi's scalar `Y = y I` ([`mohammadi_gain`]; global convergence, but rates spread by the
/// inertia ratio), and `Y = β M(q0)` ([`Self::with_bandwidth`]), for which `L = β I` at `q0`
/// (equal per-joint bandwidth `β` near the operating point). Stepped implicitly, because `L` is
/// stiff for light distal links: `(I + T L) z_{k+1} = z_k + T L r`, `r = C + G − τ − p`, solved
/// as `(M + T Y) w = M Y⁻¹ z_k + T r`, `z_{k+1} = Y w` (symmetric positive definite). Measured
/// velocity noise reaches `d̂` through `Y`.
#[derive(Debug, Clone)]
pub struct NonlinearDisturbanceObserver<const N: usize, D> {
    dynamics: D,
    gain: JointMatrix<N>,
    gain_inverse: JointMatrix<N>,
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
    /// An observer with the scalar gain `Y = y I` (`y` in N·m·s/rad) at sample time `dt`, started
    /// at `z0 = −Y q̇0` (so `d̂ = 0`).
    pub fn new(dynamics: D, gain: f64, dt_s: f64, qd0: JointVector<N>) -> Result<Self, Error> {
        let gain = positive("gain", gain)?;
        Self::with_gain_matrix(dynamics, JointMatrix::<N>::identity() * gain, dt_s, qd0)
    }

    /// An observer with `Y = β M(q0)`: rates `L = β I` at `q0`, equal per-joint bandwidth `β`
    /// (1/s) near the operating point, at sample time `dt`; started at `z0 = −Y q̇0`.
    ///
    /// `β dt` at most [`MAX_RATE_TIMES_DT`](crate::MAX_RATE_TIMES_DT), the bound every filter and
    /// observer here takes (thirty times the Nyquist limit). The implicit step is stable for any
    /// `β`, but its pole `1 / (1 + β dt)` realises the rate `ln(1 + β dt) / dt`, not `β`, and for
    /// `β dt ≫ 1` the observer becomes a one-step differentiator, `d̂ ≈ C + G − τ + M Δq̇ / dt`,
    /// which passes velocity noise at `1 / dt`; far beyond (`β dt` of 1e9 and more) `d̂ = z + p`
    /// also loses the disturbance to rounding. The bound holds at `q0`: elsewhere
    /// `L(q) = β M(q0) M⁻¹(q)` departs from `β` with the inertia.
    pub fn with_bandwidth(
        dynamics: D,
        bandwidth: f64,
        dt_s: f64,
        q0: &JointVector<N>,
        qd0: JointVector<N>,
    ) -> Result<Self, Error> {
        let bandwidth = discretisable("bandwidth", bandwidth, positive("dt_s", dt_s)?)?;
        check("q0", q0)?;
        let gain = dynamics.mass_matrix(q0) * bandwidth;
        Self::unbounded(dynamics, gain, dt_s, qd0)
    }

    /// An observer with the gain matrix `Y` (symmetric positive definite, N·m·s/rad), e.g.
    /// `β M(q0)` for equal rates `β` at `q0` ([`Self::with_bandwidth`]); started at
    /// `z0 = −Y q̇0`.
    ///
    /// The slowest rate of `L = Y M⁻¹(q)` at `q = 0` (the observer's guaranteed convergence
    /// rate: Mohammadi's `β ≈ y / λmax(M)` for `Y = y I`) times `dt` must be at most
    /// [`MAX_RATE_TIMES_DT`](crate::MAX_RATE_TIMES_DT), the bound [`Self::with_bandwidth`] puts
    /// on `β` (why: there). The faster rates of light joints may exceed it, as the scalar design
    /// makes them do (the implicit step is stable for any rate). This constructor takes no
    /// operating point, so the bound holds at the zero pose. A scalar gain far beyond it (`y` =
    /// 1e300 once gave `d̂` ≈ 1e284 on a moving arm) is refused by name; a gain matrix with one
    /// small eigenvalue can still make other rates as fast as it likes (the C ABI and Python
    /// take only `Y = y I`).
    pub fn with_gain_matrix(dynamics: D, gain: JointMatrix<N>, dt_s: f64, qd0: JointVector<N>) -> Result<Self, Error> {
        let observer = Self::unbounded(dynamics, gain, dt_s, qd0)?;
        let slowest = observer.rates(&JointVector::zeros())?.min();
        if slowest * observer.dt_s <= crate::MAX_RATE_TIMES_DT {
            Ok(observer)
        } else {
            Err(Error::InvalidParameter {
                name: "gain",
                value: observer.gain.amax(),
                requirement: "such that the observer's slowest rate at q = 0 (its convergence rate, y / λmax(M) for a \
                              scalar gain) times dt_s is at most 100 (thirty times the Nyquist limit)",
            })
        }
    }

    /// [`Self::with_gain_matrix`] without the bound on its rates (checked by the caller).
    fn unbounded(dynamics: D, gain: JointMatrix<N>, dt_s: f64, qd0: JointVector<N>) -> Result<Self, Error> {
        check("qd0", &qd0)?;
        let symmetric = (gain - gain.transpose()).amax() <= 1e-12 * gain.amax();
        let gain_inverse = match gain.cholesky() {
            Some(c) if symmetric && gain.iter().all(|x| x.is_finite()) => c.inverse(),
            _ => {
                return Err(Error::InvalidParameter {
                    name: "gain",
                    value: gain.amax(),
                    requirement: "a finite, symmetric positive definite matrix",
                })
            }
        };
        Ok(Self {
            dynamics,
            gain,
            gain_inverse,
            dt_s: positive("dt_s", dt_s)?,
            z: -(gain * qd0),
            disturbance: JointVector::zeros(),
        })
    }

    /// The observer's rates at `q`: the eigenvalues of `L = Y M⁻¹(q)`, ascending, 1/s (real and
    /// positive: `L` is similar to `M^{-1/2} Y M^{-1/2}`).
    pub fn rates(&self, q: &JointVector<N>) -> Result<JointVector<N>, Error> {
        let mass = self.dynamics.mass_matrix(q);
        let root_inverse = mass.cholesky().ok_or(Error::SingularMassMatrix)?.inverse();
        // M⁻¹ = Aᵀ A with A the inverse Cholesky factor's transpose gives a symmetric similar form.
        let factor = root_inverse.cholesky().ok_or(Error::SingularMassMatrix)?.l();
        let symmetric = factor.transpose() * self.gain * factor;
        Ok(crate::rigid_body::linalg::symmetric_eigenvalues(&symmetric))
    }
}

impl<const N: usize, D: Dynamics<N>> DisturbanceObserver<N> for NonlinearDisturbanceObserver<N, D> {
    fn update(&mut self, m: &Measurement<N>) -> Result<JointVector<N>, Error> {
        m.checked()?;
        let qd = m.required_velocity()?;
        let t = self.dt_s;
        let p = self.gain * qd;
        let bias = self.dynamics.inverse_dynamics(&m.position, &qd, &JointVector::zeros());
        // With z = Y w the system is symmetric positive definite: (M + T Y) w' = M Y⁻¹ z + T r.
        let mass = self.dynamics.mass_matrix(&m.position);
        let rhs = mass * (self.gain_inverse * self.z) + (bias - m.torque - p) * t;
        let w = (mass + self.gain * t).cholesky().ok_or(Error::SingularMassMatrix)?.solve(&rhs);
        let z = self.gain * w;
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
        let dt = positive("dt_s", dt_s)?;
        for &k in gain.iter() {
            discretisable("gain", k, dt)?;
        }
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
        let dt = positive("dt_s", dt_s)?;
        let w = discretisable("bandwidth_rad_s", bandwidth_rad_s, dt)?;
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
