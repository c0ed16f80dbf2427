//! Computed-torque control with optional disturbance compensation (Lu, Sandy & Buchli, section IV).
//!
//! With the tracking error `e = q − q_des` and `ė = q̇ − q̇_des`:
//!
//! ```text
//! paper form (default):  τ = M(q) q̈_des + C(q, q̇) + G(q) − K_D ė − K_P e − d̂
//! classic form:          τ = M(q) (q̈_des − K_D ė − K_P e) + C(q, q̇) + G(q) − d̂
//! ```
//!
//! `d̂` is omitted without compensation. `M`, `C`, `G` use the current `q`, `q̇`; only `d̂` comes
//! from the filtered estimates. Each form costs one inverse-dynamics pass: the paper form is
//! `ID(q, q̇, q̈_des) − K_D ė − K_P e`, the classic form `ID(q, q̇, q̈_des − K_D ė − K_P e)`.
//!
//! Which velocity `q̇` the loop closes on (measured, or the estimator's filtered `q̂̇`, which lags
//! by about `1/ω1 + 2ζ/ω2`) is the caller's choice: the controller takes it as an argument.

use crate::finite::check;
use crate::{Dynamics, Error, JointMatrix, JointVector};

/// Where the PD feedback enters the control law.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PdPlacement {
    /// The paper's form: torque-level PD, `τ = M q̈_des + C + G − K_D ė − K_P e`.
    #[default]
    OutsideMassMatrix,
    /// The classic form: acceleration-level PD, `τ = M (q̈_des − K_D ė − K_P e) + C + G`, which
    /// gives the error dynamics `ë + K_D ė + K_P e = 0` on an exact model.
    InsideMassMatrix,
}

/// Proportional and derivative gains `K_P`, `K_D`.
///
/// Units depend on the placement: N·m/rad and N·m·s/rad outside the mass matrix, 1/s² and 1/s
/// inside.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gains<const N: usize> {
    kp: JointMatrix<N>,
    kd: JointMatrix<N>,
}

impl<const N: usize> Gains<N> {
    /// Diagonal gains; every entry must be finite and non-negative.
    pub fn diagonal(kp: [f64; N], kd: [f64; N]) -> Result<Self, Error> {
        for (name, values) in [("kp", &kp), ("kd", &kd)] {
            if let Some(&value) = values.iter().find(|v| !(v.is_finite() && **v >= 0.0)) {
                return Err(Error::InvalidParameter { name, value, requirement: "finite and >= 0" });
            }
        }
        Self::full(JointMatrix::from_diagonal(&kp.into()), JointMatrix::from_diagonal(&kd.into()))
    }

    /// Full gain matrices; every entry must be finite.
    pub fn full(kp: JointMatrix<N>, kd: JointMatrix<N>) -> Result<Self, Error> {
        for (name, matrix) in [("kp", &kp), ("kd", &kd)] {
            if let Some(&value) = matrix.iter().find(|v| !v.is_finite()) {
                return Err(Error::InvalidParameter { name, value, requirement: "finite" });
            }
        }
        Ok(Self { kp, kd })
    }

    /// `K_P`.
    pub fn kp(&self) -> &JointMatrix<N> {
        &self.kp
    }

    /// `K_D`.
    pub fn kd(&self) -> &JointMatrix<N> {
        &self.kd
    }
}

/// The desired motion at one instant: `q_des` (rad), `q̇_des` (rad/s), `q̈_des` (rad/s²).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Reference<const N: usize> {
    /// Desired joint angles.
    pub position: JointVector<N>,
    /// Desired joint velocities.
    pub velocity: JointVector<N>,
    /// Desired joint accelerations.
    pub acceleration: JointVector<N>,
}

impl<const N: usize> Reference<N> {
    /// Hold still at `position`.
    pub fn hold(position: JointVector<N>) -> Self {
        Self { position, velocity: JointVector::zeros(), acceleration: JointVector::zeros() }
    }
}

/// One controller output.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Command<const N: usize> {
    /// Commanded joint torques after saturation, N·m.
    pub torque: JointVector<N>,
    /// Which joints hit their torque limit this tick.
    pub saturated: [bool; N],
}

/// Computed-torque controller for an arm with `N` joints, generic over its [`Dynamics`].
#[derive(Debug, Clone)]
pub struct ComputedTorque<const N: usize, D> {
    dynamics: D,
    gains: Gains<N>,
    placement: PdPlacement,
    torque_limit: Option<JointVector<N>>,
}

impl<const N: usize, D: Dynamics<N>> ComputedTorque<N, D> {
    /// The paper's form ([`PdPlacement::OutsideMassMatrix`]), no torque limits.
    pub fn new(dynamics: D, gains: Gains<N>) -> Self {
        Self { dynamics, gains, placement: PdPlacement::default(), torque_limit: None }
    }

    /// Chooses where the PD feedback enters the law.
    pub fn with_placement(mut self, placement: PdPlacement) -> Self {
        self.placement = placement;
        self
    }

    /// Saturates joint `i` to `[−limit[i], limit[i]]` N·m; every limit must be finite and `> 0`.
    pub fn with_torque_limit(mut self, limit: JointVector<N>) -> Result<Self, Error> {
        self.torque_limit = Some(checked_torque_limit(limit)?);
        Ok(self)
    }

    /// The gains in use.
    pub fn gains(&self) -> &Gains<N> {
        &self.gains
    }

    /// The dynamics model the controller uses.
    pub fn dynamics(&self) -> &D {
        &self.dynamics
    }

    /// The commanded torque for state `(q, q̇)`, reference and, with compensation, `d̂`.
    ///
    /// Non-finite inputs, or a non-finite law (e.g. an overflowing model), are reported as
    /// [`Error::NonFinite`]; a non-finite command is never returned.
    pub fn command(
        &self,
        q: &JointVector<N>,
        qd: &JointVector<N>,
        reference: &Reference<N>,
        disturbance_estimate: Option<&JointVector<N>>,
    ) -> Result<Command<N>, Error> {
        let law = self.law(q, qd, reference)?;
        let inverse_dynamics = self.dynamics.inverse_dynamics(q, qd, &law.acceleration);
        self.finish(&law, inverse_dynamics, disturbance_estimate)
    }

    /// The law up to its inverse dynamics: checks the inputs and forms the PD feedback.
    #[inline]
    pub(crate) fn law(
        &self,
        q: &JointVector<N>,
        qd: &JointVector<N>,
        reference: &Reference<N>,
    ) -> Result<Law<N>, Error> {
        check("q", q)?;
        check("qd", qd)?;
        check("q_des", &reference.position)?;
        check("qd_des", &reference.velocity)?;
        check("qdd_des", &reference.acceleration)?;
        let feedback = self.gains.kd * (qd - reference.velocity) + self.gains.kp * (q - reference.position);
        Ok(match self.placement {
            PdPlacement::OutsideMassMatrix => Law { acceleration: reference.acceleration, outside: Some(feedback) },
            PdPlacement::InsideMassMatrix => Law { acceleration: reference.acceleration - feedback, outside: None },
        })
    }

    /// The law from its inverse dynamics `ID(q, q̇, law.acceleration)`: subtracts the feedback
    /// applied outside the mass matrix and `d̂`, checks the result and saturates it.
    #[inline]
    pub(crate) fn finish(
        &self,
        law: &Law<N>,
        inverse_dynamics: JointVector<N>,
        disturbance_estimate: Option<&JointVector<N>>,
    ) -> Result<Command<N>, Error> {
        let torque = match &law.outside {
            Some(feedback) => inverse_dynamics - feedback,
            None => inverse_dynamics,
        };
        compensated(torque, disturbance_estimate, self.torque_limit.as_ref())
    }
}

/// `limit` if every entry is finite and `> 0`.
pub(crate) fn checked_torque_limit<const N: usize>(limit: JointVector<N>) -> Result<JointVector<N>, Error> {
    match limit.iter().find(|v| !(v.is_finite() && **v > 0.0)) {
        Some(&value) => Err(Error::InvalidParameter { name: "torque_limit", value, requirement: "finite and > 0" }),
        None => Ok(limit),
    }
}

/// A controller's command from its law's torque: `d̂` subtracted where given, checked finite,
/// saturated to `limit` where given.
#[inline]
pub(crate) fn compensated<const N: usize>(
    mut torque: JointVector<N>,
    disturbance_estimate: Option<&JointVector<N>>,
    limit: Option<&JointVector<N>>,
) -> Result<Command<N>, Error> {
    if let Some(estimate) = disturbance_estimate {
        check("d_hat", estimate)?;
        torque -= estimate;
    }
    check("tau_cmd", &torque)?;
    let mut saturated = [false; N];
    if let Some(limit) = limit {
        for i in 0..N {
            saturated[i] = torque[i].abs() > limit[i];
            torque[i] = torque[i].clamp(-limit[i], limit[i]);
        }
    }
    Ok(Command { torque, saturated })
}

/// The control law before its one inverse dynamics pass `ID(q, q̇, acceleration)`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Law<const N: usize> {
    /// The acceleration argument: `q̈_des`, or `q̈_des − K_D ė − K_P e` inside the mass matrix.
    pub(crate) acceleration: JointVector<N>,
    /// `K_D ė + K_P e` where it is subtracted after the inverse dynamics (the paper's form).
    outside: Option<JointVector<N>>,
}
