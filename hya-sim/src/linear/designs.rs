//! The observers' design transfer functions `d̂/d`, and what "equal bandwidth" means between
//! observers of different order.
//!
//! | observer | design `d̂/d` | −3 dB | low-frequency delay |
//! |---|---|---|---|
//! | lu | `ω1 ω2² / ((s + ω1)(s² + 2ζ ω2 s + ω2²))` | ≈ 0.647 ω at `ζ = 0.8`, `ω1 = ω2 = ω` | `1/ω1 + 2ζ/ω2` |
//! | chen, momentum | `β / (s + β)` | `β` | `1/β` |
//! | eso | `ω³ / (s + ω)³` | `ω √(2^{1/3} − 1)` ≈ 0.510 ω | `3/ω` |
//!
//! Equal pole magnitude (the same `ω`) is not equal bandwidth: at `ω = 50 rad/s` the paper's
//! filter passes up to 32 rad/s and lags 52 ms, the first-order observers 50 rad/s and 20 ms.
//! [`equal_bandwidth_table`] gives each observer's parameter for three meanings of "equal".
//!

use nalgebra::Complex;

use crate::config::scenario::Method;
use crate::error::ParameterError;
use crate::linear::phasors::jw;

/// `v` if it is finite and strictly positive, else the error naming `name`.
pub(crate) fn positive(name: &'static str, value: f64) -> Result<f64, ParameterError> {
    match value.is_finite() && value > 0.0 {
        true => Ok(value),
        false => Err(ParameterError { name, value, rule: "finite and strictly positive" }),
    }
}

/// `v` if it is finite and not negative, else the error naming `name`.
pub(crate) fn non_negative(name: &'static str, value: f64) -> Result<f64, ParameterError> {
    match value.is_finite() && value >= 0.0 {
        true => Ok(value),
        false => Err(ParameterError { name, value, rule: "finite and not negative" }),
    }
}

/// One observer's design transfer function `d̂/d` (per joint, continuous time).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ObserverDesign {
    /// The paper's filter: `H = ω1 ω2² / ((s + ω1)(s² + 2ζ ω2 s + ω2²))`.
    Lu {
        /// Damping ratio `ζ` of the second-order factor (the paper: 0.8).
        zeta: f64,
        /// Corner `ω1` of the first-order factor, rad/s.
        omega1_rad_s: f64,
        /// Natural frequency `ω2` of the second-order factor, rad/s.
        omega2_rad_s: f64,
    },
    /// Chen's observer and the momentum observer: `H = β / (s + β)`.
    FirstOrder {
        /// The pole `β`, rad/s.
        beta_rad_s: f64,
    },
    /// The extended state observer, all three poles at `−ω`: `H = ω³ / (s + ω)³`.
    Eso {
        /// The observer's pole magnitude `ω`, rad/s.
        omega_rad_s: f64,
    },
}

/// What "equal bandwidth" is taken to mean between two observers.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum Matching {
    /// The same slowest pole magnitude (what the simulator's one `observer_bandwidth_rad_s` does).
    #[serde(rename = "equal pole magnitude")]
    PoleMagnitude,
    /// The same −3 dB frequency of `|d̂/d|`.
    #[serde(rename = "equal −3 dB bandwidth")]
    Bandwidth3Db,
    /// The same low-frequency group delay of `d̂` behind `d`.
    #[serde(rename = "equal low-frequency delay")]
    LowFrequencyDelay,
}

impl Matching {
    /// Every meaning, in the table's order.
    pub const ALL: [Matching; 3] = [Matching::PoleMagnitude, Matching::Bandwidth3Db, Matching::LowFrequencyDelay];

    /// The name used in tables.
    pub fn name(self) -> &'static str {
        match self {
            Matching::PoleMagnitude => "equal pole magnitude",
            Matching::Bandwidth3Db => "equal −3 dB bandwidth",
            Matching::LowFrequencyDelay => "equal low-frequency delay",
        }
    }

    /// The short name used in lists.
    pub fn short(self) -> &'static str {
        match self {
            Matching::PoleMagnitude => "equal poles",
            Matching::Bandwidth3Db => "equal −3 dB",
            Matching::LowFrequencyDelay => "equal delay",
        }
    }
}

impl ObserverDesign {
    /// The design `method` runs in the simulator at `bandwidth_rad_s` (its
    /// `observer_bandwidth_rad_s`): lu at `ζ = 0.8`, `ω1 = ω2 = bandwidth`; chen and momentum at
    /// `β = bandwidth`; eso at `ω = bandwidth`. `None` for none and pid, which estimate nothing.
    pub fn of(method: Method, bandwidth_rad_s: f64) -> Option<Self> {
        match method {
            Method::Lu => Some(Self::Lu {
                zeta: hya_core::filter::PAPER_ZETA,
                omega1_rad_s: bandwidth_rad_s,
                omega2_rad_s: bandwidth_rad_s,
            }),
            Method::Chen | Method::Momentum => Some(Self::FirstOrder { beta_rad_s: bandwidth_rad_s }),
            Method::Eso => Some(Self::Eso { omega_rad_s: bandwidth_rad_s }),
            Method::None | Method::Pid => None,
        }
    }

    /// Checks that every parameter is finite and strictly positive (so every pole is stable).
    pub fn check(&self) -> Result<(), ParameterError> {
        match *self {
            Self::Lu { zeta, omega1_rad_s, omega2_rad_s } => {
                positive("observer.zeta", zeta)?;
                positive("observer.omega1_rad_s", omega1_rad_s)?;
                positive("observer.omega2_rad_s", omega2_rad_s)?;
            }
            Self::FirstOrder { beta_rad_s } => {
                positive("observer.beta_rad_s", beta_rad_s)?;
            }
            Self::Eso { omega_rad_s } => {
                positive("observer.omega_rad_s", omega_rad_s)?;
            }
        }
        Ok(())
    }

    /// `H(jω)`, the design's `d̂/d` at `ω` rad/s.
    pub fn response(&self, omega: f64) -> Complex<f64> {
        let s = jw(omega);
        match *self {
            Self::Lu { zeta, omega1_rad_s: w1, omega2_rad_s: w2 } => {
                Complex::from(w1 * w2 * w2) / ((s + w1) * (s * s + s * (2.0 * zeta * w2) + w2 * w2))
            }
            Self::FirstOrder { beta_rad_s: b } => Complex::from(b) / (s + b),
            Self::Eso { omega_rad_s: w } => Complex::from(w * w * w) / ((s + w) * (s + w) * (s + w)),
        }
    }

    /// The magnitudes of the poles, rad/s: `ω1, ω2, ω2` (lu), `β`, `ω, ω, ω` (eso).
    pub fn pole_magnitudes(&self) -> Vec<f64> {
        match *self {
            Self::Lu { omega1_rad_s, omega2_rad_s, .. } => vec![omega1_rad_s, omega2_rad_s, omega2_rad_s],
            Self::FirstOrder { beta_rad_s } => vec![beta_rad_s],
            Self::Eso { omega_rad_s } => vec![omega_rad_s; 3],
        }
    }

    /// The design's parameter, its slowest pole magnitude, rad/s: `min(ω1, ω2)`, `β`, `ω`.
    pub fn parameter_rad_s(&self) -> f64 {
        self.pole_magnitudes().into_iter().fold(f64::INFINITY, f64::min)
    }

    /// The group delay `−dφ/dω` at `ω → 0`, s: the sum over poles `p` of `1/p`'s real part,
    /// `1/ω1 + 2ζ/ω2` (lu), `1/β`, `3/ω` (eso).
    pub fn low_frequency_delay(&self) -> f64 {
        match *self {
            Self::Lu { zeta, omega1_rad_s, omega2_rad_s } => 1.0 / omega1_rad_s + 2.0 * zeta / omega2_rad_s,
            Self::FirstOrder { beta_rad_s } => 1.0 / beta_rad_s,
            Self::Eso { omega_rad_s } => 3.0 / omega_rad_s,
        }
    }

    /// The −3 dB bandwidth, rad/s: the lowest `ω` where `|H(jω)|² = 1/2`, found by a scan
    /// upwards from a thousandth of the slowest pole and bisection (60 halvings of the bracket
    /// in `ln ω`). `β` for a first-order design, `ω √(2^{1/3} − 1)` for eso. `NaN` for a design
    /// that fails [`check`](Self::check).
    pub fn bandwidth_3db(&self) -> f64 {
        if self.check().is_err() {
            return f64::NAN;
        }
        let below = |w: f64| self.response(w).norm_sqr() < 0.5;
        let (mut lo, step) = (1e-3 * self.parameter_rad_s(), 1.05_f64);
        // |H| falls as ω⁻¹ or faster far above the fastest pole: the scan ends there.
        let top = 1e3 * self.pole_magnitudes().into_iter().fold(0.0, f64::max);
        while !below(lo * step) && lo < top {
            lo *= step;
        }
        let mut hi = lo * step;
        for _ in 0..60 {
            let mid = (lo * hi).sqrt();
            if below(mid) {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        (lo * hi).sqrt()
    }

    /// The same shape with every pole multiplied by `factor`: `H(s/factor)`, whose bandwidth
    /// is `factor` times and delay `1/factor` times this design's.
    pub fn scaled(&self, factor: f64) -> Self {
        match *self {
            Self::Lu { zeta, omega1_rad_s, omega2_rad_s } => {
                Self::Lu { zeta, omega1_rad_s: omega1_rad_s * factor, omega2_rad_s: omega2_rad_s * factor }
            }
            Self::FirstOrder { beta_rad_s } => Self::FirstOrder { beta_rad_s: beta_rad_s * factor },
            Self::Eso { omega_rad_s } => Self::Eso { omega_rad_s: omega_rad_s * factor },
        }
    }

    /// This design's shape, scaled to match `reference` by `matching`. Each shape is a
    /// one-parameter family `H(s/a)` (bandwidth ∝ `a`, delay ∝ `1/a`), so the factor is one
    /// ratio: of slowest poles, of −3 dB bandwidths, or of delays (inverted).
    pub fn matched_to(&self, reference: &ObserverDesign, matching: Matching) -> Self {
        let factor = match matching {
            Matching::PoleMagnitude => reference.parameter_rad_s() / self.parameter_rad_s(),
            Matching::Bandwidth3Db => reference.bandwidth_3db() / self.bandwidth_3db(),
            Matching::LowFrequencyDelay => self.low_frequency_delay() / reference.low_frequency_delay(),
        };
        self.scaled(factor)
    }
}

/// One row of the "equal bandwidth" table: an observer, how it was matched to the paper's
/// filter, its parameter and what it then passes and lags.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EqualBandwidthRow {
    /// The observer.
    pub method: Method,
    /// How it was matched to lu; `None` for lu's own row.
    pub matching: Option<Matching>,
    /// The design.
    pub design: ObserverDesign,
    /// Its parameter (slowest pole magnitude: `ω1 = ω2`, `β` or `ω`), rad/s.
    pub parameter_rad_s: f64,
    /// Its −3 dB bandwidth, rad/s.
    pub bandwidth_3db_rad_s: f64,
    /// Its low-frequency delay, s.
    pub low_frequency_delay_s: f64,
}

impl EqualBandwidthRow {
    fn new(method: Method, matching: Option<Matching>, design: ObserverDesign) -> Self {
        Self {
            method,
            matching,
            design,
            parameter_rad_s: design.parameter_rad_s(),
            bandwidth_3db_rad_s: design.bandwidth_3db(),
            low_frequency_delay_s: design.low_frequency_delay(),
        }
    }
}

/// The low-frequency delay of the paper's filter at `ζ = 0.8`, `ω1 = ω2 = ω`: `1/ω + 2ζ/ω`, s.
pub fn paper_delay(omega_rad_s: f64) -> f64 {
    ObserverDesign::Lu { zeta: hya_core::filter::PAPER_ZETA, omega1_rad_s: omega_rad_s, omega2_rad_s: omega_rad_s }
        .low_frequency_delay()
}

/// The paper's filter at `ζ = 0.8`, `ω1 = ω2 = omega_rad_s` (its own row first), then chen,
/// momentum and eso each matched to it by [`Matching::ALL`], in that order: ten rows.
pub fn equal_bandwidth_table(omega_rad_s: f64) -> Result<Vec<EqualBandwidthRow>, ParameterError> {
    positive("observer_bandwidth_rad_s", omega_rad_s)?;
    let Some(lu) = ObserverDesign::of(Method::Lu, omega_rad_s) else { return Ok(Vec::new()) };
    let mut rows = vec![EqualBandwidthRow::new(Method::Lu, None, lu)];
    for method in [Method::Chen, Method::Momentum, Method::Eso] {
        let Some(shape) = ObserverDesign::of(method, omega_rad_s) else { continue };
        for matching in Matching::ALL {
            rows.push(EqualBandwidthRow::new(method, Some(matching), shape.matched_to(&lu, matching)));
        }
    }
    Ok(rows)
}
