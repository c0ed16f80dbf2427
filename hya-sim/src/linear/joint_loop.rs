//! One joint holding a pose, linearised with its delays: its loop, its margins, and what a lagged
//! cancellation of viscous friction does to it.
//!
//! [`JointLoop`] linearises one joint holding a pose (`q_des = 0`), every signal SISO:
//!
//! ```text
//! plant        J s² q = τ_a − F_v s q
//! actuator     τ_a = A(s) e^{−s T_c} Z(s) τ_cmd,  A = 1, ω_a/(s + ω_a) or
//!              ω_n² e^{−s T_a}/(s² + 2ζ ω_n s + ω_n²),  Z = (1 − e^{−sT})/(sT)
//! measurement  q_m = e^{−s T_m} q,  τ_m = e^{−s T_m} τ_a
//! velocity     v = V(s) q_m
//! command      τ_cmd = −K_P q_m − K_D v − c
//! ```
//!
//! with the compensation `c` none, `K_I/s q_m` (PID) or an estimate `d̂ = H(s)(J s² q_m − τ_m)`.
//! Broken at `τ_cmd`, the loop is `τ_cmd = −L τ_cmd`, closed `1 + L`, with
//!
//! ```text
//! L = e^{−s T_m} A e^{−s T_c} Z [ (K_P + K_D V + c_q) P − c_τ ],   P = 1/(J s² + F_v s)
//! ```
//!
//! `c_q` and `c_τ` the compensation's paths from `q_m` and `τ_m`. With an estimator and the exact
//! model, `H (J s² P − 1) = −H F_v s P`: the estimate cancels the plant's own damping, late.
//!
//! # Lagged cancellation of viscous friction
//!
//! With `d̂ ≈ d(t − τ_d)` and `d = −F_v q̇`, the residual is `d − d̂ ≈ −F_v τ_d q̈`, so
//! `(J + F_v τ_d) q̈ = u`: cancelling viscous friction late makes the joint look *heavier*
//! ([`effective_inertia`]), not lighter. With its own damping cancelled as well, the joint under
//! the PD has the closed loop `J_eff s² + K_D s + K_P` in place of `J s² + (K_D + F_v) s + K_P`:
//! a lower natural frequency `√(K_P/J_eff)` and a lower damping ratio `K_D/(2√(K_P J_eff))`.
//! `τ_d` counts the loop's own lag too ([`JointLoop::cancellation_lag_s`]); the margins of the
//! whole loop ([`JointLoop::margins`]) show the rest.

use nalgebra::Complex;

use crate::config::scenario::Method;
use crate::error::{ParameterError, SimError};
use crate::linear::designs::{non_negative, positive, ObserverDesign};
use crate::linear::phasors::{delay, jw};

/// The effective inertia of a joint whose viscous friction `F_v` is cancelled by an estimate
/// lagging by `τ_d`, kg·m²:
///
/// ```text
/// d = −F_v q̇,  d̂ ≈ d(t − τ_d) ≈ d − τ_d ḋ   ⇒   d − d̂ ≈ −F_v τ_d q̈
/// J q̈ = u + d − d̂   ⇒   (J + F_v τ_d) q̈ = u,   J_eff = J + F_v τ_d
/// ```
///
/// The inertia *grows*: a lagged cancellation makes the joint heavier, never lighter. `τ_d` is
/// the whole lag from the friction to its cancellation: the estimator's low-frequency delay plus
/// the loop's own ([`JointLoop::cancellation_lag_s`]).
pub fn effective_inertia(inertia: f64, viscous: f64, lag_s: f64) -> f64 {
    inertia + viscous * lag_s
}

/// The residual of cancelling viscous friction through an estimate `d̂ = H(s) d` at one frequency,
/// exactly: an inertia the joint gains and a damping it keeps.
///
/// ```text
/// d − d̂ = −F_v (1 − H(s)) s q ≡ −(m_a s² + c_a s) q   at s = jω
///   ⇒   c_a + jω m_a = F_v (1 − H(jω)),   m_a = F_v Im(1 − H)/ω,   c_a = F_v Re(1 − H)
/// ```
///
/// so the joint moves as `(J + m_a) q̈ + c_a q̇ = u` at that frequency. As `ω → 0`,
/// `1 − H ≈ τ_d jω`: `m_a → F_v τ_d` ([`effective_inertia`]) and `c_a → 0`; as `ω → ∞`, `H → 0`:
/// nothing is cancelled, `m_a → 0` and `c_a → F_v`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViscousResidual {
    /// `m_a`, kg·m².
    pub added_inertia: f64,
    /// `c_a`, N·m·s/rad.
    pub kept_damping: f64,
}

impl ViscousResidual {
    /// The residual of `viscous` (`F_v`) cancelled through `design` at `omega` rad/s (> 0).
    pub fn at(design: &ObserverDesign, viscous: f64, omega: f64) -> Self {
        let rest = Complex::from(1.0) - design.response(omega);
        Self { added_inertia: viscous * rest.im / omega, kept_damping: viscous * rest.re }
    }
}

/// The velocity the PD (and chen's and the momentum observer) reads, `v = V(s) q_m`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum VelocityModel {
    /// A velocity sensor: `V = s`.
    Sensor,
    /// The backward difference through a first-order low-pass at `ω_c`, as the simulator steps
    /// it, `v_k = a v_{k−1} + (1 − a)(q_k − q_{k−1})/T`, `a = e^{−ω_c T}`, taken exactly at
    /// `z = e^{jωT}`: `V = (1 − a)(1 − z⁻¹) / (T (1 − a z⁻¹))`.
    Difference {
        /// The low-pass corner `ω_c`, rad/s.
        cutoff_rad_s: f64,
    },
    /// `q̂̇` of a filter on the angles: `V = s H(s)` (the paper's: [`ObserverDesign::Lu`]).
    Filter(ObserverDesign),
}

impl VelocityModel {
    /// `V(jω)` with the control period `period_s`.
    pub fn response(&self, omega: f64, period_s: f64) -> Complex<f64> {
        match self {
            Self::Sensor => jw(omega),
            Self::Difference { cutoff_rad_s } => {
                let a = (-cutoff_rad_s * period_s).exp();
                let z_inv = delay(omega, period_s);
                (Complex::from(1.0) - z_inv) * (1.0 - a) / ((Complex::from(1.0) - z_inv * a) * period_s)
            }
            Self::Filter(design) => jw(omega) * design.response(omega),
        }
    }

    fn check(&self) -> Result<(), ParameterError> {
        match self {
            Self::Sensor => Ok(()),
            Self::Difference { cutoff_rad_s } => positive("velocity.cutoff_rad_s", *cutoff_rad_s).map(|_| ()),
            Self::Filter(design) => design.check(),
        }
    }
}

/// What the command subtracts besides the PD, `c`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Compensation {
    /// Nothing: `c = 0`.
    None,
    /// The PID's integral: `c = (K_I/s) q_m`.
    Integral {
        /// `K_I`, N·m/(rad·s) (the simulator's `K_P ω_n · integral_zero_ratio`).
        ki: f64,
    },
    /// An estimate from the angles: `c = d̂ = H(s)(J s² q_m − τ_m)` (lu, eso).
    Estimator(ObserverDesign),
    /// An estimate from the measured velocity: `c = d̂ = H(s)(J s v − τ_m)` (chen, momentum;
    /// the same as [`Compensation::Estimator`] with a velocity sensor).
    VelocityEstimator(ObserverDesign),
}

impl Compensation {
    /// What `method` subtracts: its observer at `bandwidth_rad_s` reading the angles (lu, eso)
    /// or the velocity (chen, momentum), or the integral `K_I = integral_gain` (pid).
    pub fn of(method: Method, bandwidth_rad_s: f64, integral_gain: f64) -> Self {
        match (method, ObserverDesign::of(method, bandwidth_rad_s)) {
            (Method::Pid, _) => Self::Integral { ki: integral_gain },
            (Method::Chen | Method::Momentum, Some(design)) => Self::VelocityEstimator(design),
            (_, Some(design)) => Self::Estimator(design),
            (_, None) => Self::None,
        }
    }

    /// The observer, if the compensation is an estimate.
    pub fn design(&self) -> Option<&ObserverDesign> {
        match self {
            Self::Estimator(design) | Self::VelocityEstimator(design) => Some(design),
            Self::None | Self::Integral { .. } => None,
        }
    }

    fn check(&self) -> Result<(), ParameterError> {
        match self {
            Self::None => Ok(()),
            Self::Integral { ki } => positive("compensation.ki", *ki).map(|_| ()),
            Self::Estimator(design) | Self::VelocityEstimator(design) => design.check(),
        }
    }
}

/// One joint of the arm holding a pose, linearised (see the module's equations).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointLoop {
    /// `J`, the joint's `M_ii` at the pose, kg·m² (the model is exact: the estimators use it too).
    pub inertia: f64,
    /// Viscous friction `F_v`, N·m·s/rad.
    pub viscous: f64,
    /// `K_P`, N·m/rad.
    pub kp: f64,
    /// `K_D`, N·m·s/rad.
    pub kd: f64,
    /// The velocity the PD reads.
    pub velocity: VelocityModel,
    /// What the command subtracts besides the PD.
    pub compensation: Compensation,
    /// The actuator's torque response `A(s)`.
    pub actuator: ActuatorModel,
    /// `T_m`, the delay of the readings, s.
    pub measurement_delay_s: f64,
    /// `T_c`, the delay of the commands (beyond the hold), s.
    pub command_delay_s: f64,
    /// `T`, the control period, s (the zero-order hold `Z = (1 − e^{−sT})/(sT)`, exact).
    pub period_s: f64,
}

/// An actuator's torque over its command, `A(s)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ActuatorModel {
    /// `A = 1`.
    Ideal,
    /// `A = ω_a / (s + ω_a)`.
    Lag {
        /// `ω_a`, rad/s.
        bandwidth_rad_s: f64,
    },
    /// `A = ω_n² e^{−s T_a} / (s² + 2ζ ω_n s + ω_n²)`: a torque loop with a resonance and a
    /// dead time, as fitted to measured responses ([`crate::torque_response`]).
    SecondOrder {
        /// `ω_n`, rad/s.
        natural_rad_s: f64,
        /// `ζ`.
        damping: f64,
        /// `T_a`, s.
        delay_s: f64,
    },
}

impl ActuatorModel {
    /// `A(jω)`.
    pub fn response(&self, omega: f64) -> Complex<f64> {
        let s = jw(omega);
        match *self {
            Self::Ideal => Complex::from(1.0),
            Self::Lag { bandwidth_rad_s: w } => Complex::from(w) / (s + w),
            Self::SecondOrder { natural_rad_s: w, damping, delay_s } => {
                Complex::from(w * w) / (s * s + s * (2.0 * damping * w) + w * w) * delay(omega, delay_s)
            }
        }
    }

    /// The group delay at `ω → 0`, s: 0, `1/ω_a`, `2ζ/ω_n + T_a`.
    pub fn low_frequency_delay(&self) -> f64 {
        match *self {
            Self::Ideal => 0.0,
            Self::Lag { bandwidth_rad_s } => 1.0 / bandwidth_rad_s,
            Self::SecondOrder { natural_rad_s, damping, delay_s } => 2.0 * damping / natural_rad_s + delay_s,
        }
    }

    /// Checks that rates and damping are finite and positive and the delay not negative.
    pub fn check(&self) -> Result<(), ParameterError> {
        match *self {
            Self::Ideal => Ok(()),
            Self::Lag { bandwidth_rad_s } => positive("joint.actuator_bandwidth", bandwidth_rad_s).map(drop),
            Self::SecondOrder { natural_rad_s, damping, delay_s } => {
                positive("joint.actuator_natural_frequency", natural_rad_s)?;
                positive("joint.actuator_damping", damping)?;
                non_negative("joint.actuator_delay_s", delay_s).map(drop)
            }
        }
    }
}

/// The stability margins of one [`JointLoop`].
///
/// With integral action, or an estimator that cancels the plant's damping, the loop can cross
/// `|L| = 1` and the negative real axis several times (conditionally stable): every crossing is
/// found and the worst margin reported. Stability itself is decided by the Nyquist criterion
/// (the winding of `1 + L(jω)` round the origin), not by the sign of one margin.
#[derive(Debug, Clone, PartialEq)]
pub struct Margins {
    /// Every gain crossover, `|L(jω)| = 1`, ascending, rad/s.
    pub crossovers_rad_s: Vec<f64>,
    /// The crossover of the worst phase margin, rad/s.
    pub crossover_rad_s: f64,
    /// The worst phase margin, `180° + ∠L` wrapped to (−180°, 180°], degrees.
    pub phase_margin_deg: f64,
    /// How much the loop gain may grow, the smallest `−20 log10 |L|` at a crossing of the
    /// negative real axis with `|L| < 1`, dB; `None` if there is none (infinite).
    pub gain_margin_db: Option<f64>,
    /// How much the loop gain may shrink, the crossing of the negative real axis with `|L| > 1`
    /// closest to 0 dB, dB (negative); `None` if there is none.
    pub lower_gain_margin_db: Option<f64>,
    /// The extra loop delay that first makes the loop marginal, `min over crossovers of
    /// ((∠L + 180°) mod 360°)/ω_c`, s; zero for an unstable loop.
    pub delay_margin_s: f64,
    /// Closed-loop poles in the right half-plane, from the Nyquist criterion.
    pub unstable_poles: usize,
    /// Whether the closed loop is stable (no pole in the right half-plane).
    pub stable: bool,
}

/// Points per decade of the frequency grid.
const POINTS_PER_DECADE: f64 = 4000.0;

/// The grid's default ends, rad/s, widened until `|L|` is far above and far below 1.
const GRID_RAD_S: (f64, f64) = (1e-2, 1e4);

/// Halvings of a bracket in `ln ω` when refining a crossing.
const BISECTIONS: usize = 60;

impl JointLoop {
    /// A joint under the simulator's computed-torque PD: `K_P = J ω_n²`, `K_D = 2ζ √(K_P J)`,
    /// a velocity sensor, no compensation, an ideal actuator, no delay, period `period_s`.
    pub fn computed_torque(
        inertia: f64,
        viscous: f64,
        natural_frequency: f64,
        damping_ratio: f64,
        period_s: f64,
    ) -> Self {
        let kp = inertia * natural_frequency * natural_frequency;
        Self {
            inertia,
            viscous,
            kp,
            kd: 2.0 * damping_ratio * (kp * inertia).sqrt(),
            velocity: VelocityModel::Sensor,
            compensation: Compensation::None,
            actuator: ActuatorModel::Ideal,
            measurement_delay_s: 0.0,
            command_delay_s: 0.0,
            period_s,
        }
    }

    /// Checks every number: `J`, `K_P`, `T` strictly positive, `F_v`, `K_D`, delays not
    /// negative, all finite, the actuator's bandwidth and the designs as their own checks ask.
    pub fn check(&self) -> Result<(), ParameterError> {
        positive("joint.inertia", self.inertia)?;
        non_negative("joint.viscous", self.viscous)?;
        positive("joint.kp", self.kp)?;
        non_negative("joint.kd", self.kd)?;
        non_negative("joint.measurement_delay_s", self.measurement_delay_s)?;
        non_negative("joint.command_delay_s", self.command_delay_s)?;
        positive("joint.period_s", self.period_s)?;
        self.actuator.check()?;
        self.velocity.check()?;
        self.compensation.check()
    }

    /// `P(jω) = 1/(J s² + F_v s)`, rad/N·m.
    pub fn plant(&self, omega: f64) -> Complex<f64> {
        let s = jw(omega);
        Complex::from(1.0) / (s * s * self.inertia + s * self.viscous)
    }

    /// `τ_a/τ_cmd = A(jω) e^{−jωT_c} Z(jω)`, the exact zero-order hold
    /// `Z = (1 − e^{−sT})/(sT)` (1 − sT/2 below `ωT = 10⁻⁶`).
    pub fn actuator(&self, omega: f64) -> Complex<f64> {
        let s = jw(omega);
        let lag = self.actuator.response(omega);
        let t = self.period_s;
        let hold = if omega * t < 1e-6 {
            Complex::from(1.0) - s * (t / 2.0)
        } else {
            (Complex::from(1.0) - delay(omega, t)) / (s * t)
        };
        lag * delay(omega, self.command_delay_s) * hold
    }

    /// The compensation's paths `(c_q, c_τ)`: `c = c_q q_m − c_τ τ_m` (before the sign of the
    /// command): `(K_I/s, 0)`, `(H J s², H)` or `(H J s V, H)`.
    fn compensation_paths(&self, omega: f64) -> (Complex<f64>, Complex<f64>) {
        let s = jw(omega);
        let zero = Complex::from(0.0);
        match self.compensation {
            Compensation::None => (zero, zero),
            Compensation::Integral { ki } => (Complex::from(ki) / s, zero),
            Compensation::Estimator(design) => {
                let h = design.response(omega);
                (h * s * s * self.inertia, h)
            }
            Compensation::VelocityEstimator(design) => {
                let h = design.response(omega);
                (h * s * self.velocity.response(omega, self.period_s) * self.inertia, h)
            }
        }
    }

    /// The loop broken at `τ_cmd`, `L(jω)`, so that the closed loop is `1 + L`:
    /// `L = e^{−sT_m} A e^{−sT_c} Z [(K_P + K_D V + c_q) P − c_τ]`.
    pub fn open_loop(&self, omega: f64) -> Complex<f64> {
        let (c_q, c_tau) = self.compensation_paths(omega);
        let controller = Complex::from(self.kp) + self.velocity.response(omega, self.period_s) * self.kd + c_q;
        delay(omega, self.measurement_delay_s) * self.actuator(omega) * (controller * self.plant(omega) - c_tau)
    }

    /// The poles of `L` at `s = 0`: the plant's integrator, a second one without viscous
    /// friction, and the PID's.
    pub fn origin_poles(&self) -> usize {
        1 + usize::from(self.viscous == 0.0) + usize::from(matches!(self.compensation, Compensation::Integral { .. }))
    }

    /// The whole lag from the friction to its cancellation, s: the estimator's low-frequency
    /// delay plus the loop's own, `T_m + τ_a + T_c + T/2` with `τ_a` the actuator's low-frequency
    /// delay ([`ActuatorModel::low_frequency_delay`]); `None` without an estimator.
    pub fn cancellation_lag_s(&self) -> Option<f64> {
        let design = self.compensation.design()?;
        let actuator = self.actuator.low_frequency_delay();
        Some(
            design.low_frequency_delay()
                + self.measurement_delay_s
                + actuator
                + self.command_delay_s
                + self.period_s / 2.0,
        )
    }

    /// The margins of the loop on a log grid of 4000 points a decade, from `10⁻² rad/s` to
    /// `10⁴ rad/s`, widened until `|L| > 10³` at the bottom and `< 10⁻³` at the top; every
    /// crossing refined by bisection.
    pub fn margins(&self) -> Result<Margins, SimError> {
        self.check()?;
        let grid = self.grid()?;
        let values: Vec<Complex<f64>> = grid.iter().map(|w| self.open_loop(*w)).collect();
        let crossovers = self.gain_crossovers(&grid, &values);
        let worst = crossovers
            .iter()
            .map(|&w| (w, phase_margin_deg(self.open_loop(w))))
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .ok_or_else(|| SimError::Numerical("the loop gain never crosses 1".into()))?;
        let (upper, lower) = self.gain_margins(&grid, &values);
        let unstable_poles = self.unstable_poles(&values)?;
        let stable = unstable_poles == 0;
        let delay_margin_s = if stable {
            crossovers
                .iter()
                .map(|&w| phase_margin_deg(self.open_loop(w)).rem_euclid(360.0).to_radians() / w)
                .fold(f64::INFINITY, f64::min)
        } else {
            0.0
        };
        Ok(Margins {
            crossovers_rad_s: crossovers,
            crossover_rad_s: worst.0,
            phase_margin_deg: worst.1,
            gain_margin_db: upper,
            lower_gain_margin_db: lower,
            delay_margin_s,
            unstable_poles,
            stable,
        })
    }

    /// The log grid, its ends widened (by decades, at most to `10⁻⁸` and `10⁹` rad/s) until
    /// `|L|` is far from 1 at both.
    fn grid(&self) -> Result<Vec<f64>, SimError> {
        let (mut lo, mut hi) = GRID_RAD_S;
        while self.open_loop(lo).norm() < 1e3 && lo > 1e-8 {
            lo /= 10.0;
        }
        while self.open_loop(hi).norm() > 1e-3 && hi < 1e9 {
            hi *= 10.0;
        }
        if self.open_loop(lo).norm() < 1e3 || self.open_loop(hi).norm() > 1e-3 {
            return Err(SimError::Numerical(format!(
                "the loop gain does not leave 1 between {lo:e} and {hi:e} rad/s: no margins"
            )));
        }
        let points = ((hi / lo).log10() * POINTS_PER_DECADE).ceil() as usize;
        Ok((0..=points).map(|k| lo * (hi / lo).powf(k as f64 / points as f64)).collect())
    }

    /// Where `|L| = 1`, refined in every grid interval whose ends straddle it.
    fn gain_crossovers(&self, grid: &[f64], values: &[Complex<f64>]) -> Vec<f64> {
        let above = |l: &Complex<f64>| l.norm() > 1.0;
        (1..grid.len())
            .filter(|&k| above(&values[k - 1]) != above(&values[k]))
            .map(|k| bisect(grid[k - 1], grid[k], |w| above(&self.open_loop(w))))
            .collect()
    }

    /// The upper and lower gain margins, dB, from every crossing of the negative real axis.
    fn gain_margins(&self, grid: &[f64], values: &[Complex<f64>]) -> (Option<f64>, Option<f64>) {
        let upper_half = |l: &Complex<f64>| l.im >= 0.0;
        let crossings: Vec<f64> = (1..grid.len())
            .filter(|&k| upper_half(&values[k - 1]) != upper_half(&values[k]))
            .map(|k| bisect(grid[k - 1], grid[k], |w| upper_half(&self.open_loop(w))))
            .map(|w| self.open_loop(w))
            .filter(|l| l.re < 0.0)
            .map(|l| -20.0 * l.norm().log10())
            .collect();
        let upper = crossings.iter().copied().filter(|g| *g > 0.0).reduce(f64::min);
        let lower = crossings.iter().copied().filter(|g| *g <= 0.0).reduce(f64::max);
        (upper, lower)
    }

    /// Closed-loop poles in the right half-plane by the Nyquist criterion. `L` has no pole in
    /// the open right half-plane and `p` at the origin; on the D-contour (indented right of the
    /// origin) `1 + L` turns by `2Δφ − pπ`, `Δφ` the unwrapped change of `∠(1 + L(jω))` over the
    /// grid, the indentation adding `−pπ` and the large arc nothing (`L → 0`); the contour runs
    /// clockwise, so `Z = (pπ − 2Δφ)/(2π)`.
    fn unstable_poles(&self, values: &[Complex<f64>]) -> Result<usize, SimError> {
        let turn: f64 = values.windows(2).map(|pair| ((pair[1] + 1.0) / (pair[0] + 1.0)).arg()).sum();
        let poles = self.origin_poles() as f64;
        let z = (poles * std::f64::consts::PI - 2.0 * turn) / std::f64::consts::TAU;
        if (z - z.round()).abs() > 0.25 || z.round() < 0.0 {
            return Err(SimError::Numerical(format!("the Nyquist count is not a whole number of poles ({z:.3})")));
        }
        Ok(z.round() as usize)
    }
}

/// `180° + ∠L`, wrapped to (−180°, 180°]: `∠(−L)`.
fn phase_margin_deg(l: Complex<f64>) -> f64 {
    (-l).arg().to_degrees()
}

/// The point in `[lo, hi]` where `side` changes, by [`BISECTIONS`] halvings in `ln ω`.
fn bisect(mut lo: f64, mut hi: f64, side: impl Fn(f64) -> bool) -> f64 {
    let start = side(lo);
    for _ in 0..BISECTIONS {
        let mid = (lo * hi).sqrt();
        if side(mid) == start {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    (lo * hi).sqrt()
}
