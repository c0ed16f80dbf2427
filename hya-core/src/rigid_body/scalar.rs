//! The number type the rigid-body algorithms are written on.
//!
//! Spatial algebra and the algorithms of [`crate::rigid_body::model`] (RNEA, CRBA, `Cᵀq̇`, ABA, frame poses)
//! are written once, generic over [`Real`]. Three number types run them:
//!
//! - `f64`, for the run-time model;
//! - [`Dual`](crate::rigid_body::dual::Dual), forward-mode dual numbers, for derivatives of the same code;
//! - the code generator's tracing type (in `hya-codegen`), which records every operation as a
//!   statement of straight-line Rust and folds what is known at generation time.
//!
//! This is the pattern of Pinocchio's templated `Scalar`: one `rnea.hxx` for `double`, CasADi
//! and CppAD.

use core::fmt::Debug;
use core::ops::{Add, Div, Mul, Neg, Sub};

/// What a value computed by an algorithm is, for a number type that names its values (the
/// generator names them `elbow_v_wz`, `wrist_f_fx`); `f64` ignores it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Label {
    /// The body (and its joint) the value belongs to.
    pub body: usize,
    /// What the value is.
    pub quantity: Quantity,
    /// Which component: 0..3 angular, 3..6 linear for spatial vectors, 0 for scalars.
    pub component: u8,
}

/// The quantities an algorithm names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Quantity {
    /// `sin q_i`.
    Sine,
    /// `cos q_i`.
    Cosine,
    /// Spatial velocity `v_i`.
    Velocity,
    /// Spatial acceleration `a_i`.
    Acceleration,
    /// Spatial force `f_i` (RNEA) or momentum `h_i`.
    Force,
    /// Articulated-body bias force `p_i` (ABA).
    Bias,
    /// `U_i = I^A_i S_i` (ABA).
    InertiaTimesAxis,
    /// `D_i = S_i · U_i` (ABA).
    JointInertia,
    /// `u_i = τ_i − S_i · p_i` (ABA).
    JointForce,
    /// A joint-space output: `τ_i` or `q̈_i`.
    Joint,
}

impl Quantity {
    /// Short name used in generated identifiers.
    pub fn short_name(self) -> &'static str {
        match self {
            Quantity::Sine => "s",
            Quantity::Cosine => "c",
            Quantity::Velocity => "v",
            Quantity::Acceleration => "a",
            Quantity::Force => "f",
            Quantity::Bias => "p",
            Quantity::InertiaTimesAxis => "u",
            Quantity::JointInertia => "d",
            Quantity::JointForce => "u",
            Quantity::Joint => "out",
        }
    }
}

/// The passes of the tree algorithms, for a number type that marks them in its output.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Pass {
    /// Base to tips: transforms, velocities, accelerations, body forces.
    Forward,
    /// Tips to base: forces, inertias and joint outputs.
    Backward,
    /// Base to tips again (ABA's accelerations, CRBA's rows of `M`).
    Final,
}

/// A real number type: what the dynamics algorithms need of their numbers.
pub trait Real:
    Copy
    + PartialEq
    + Debug
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// True for number types that trace operations: the algorithms then keep constant
    /// structure apart (a joint's constant tree transform from its moving part), so that it
    /// folds; numeric types combine them, which costs fewer operations at run time.
    const TRACES: bool = false;

    /// A number known in advance (a model constant, 0, 1).
    fn constant(value: f64) -> Self;

    /// `(sin x, cos x)`.
    fn sin_cos(self) -> (Self, Self);

    /// The same value, named `label` where the number type names values; the identity else.
    #[inline]
    fn labelled(self, _label: Label) -> Self {
        self
    }

    /// Marks that the algorithm begins `pass` for `body`; a no-op but for number types that
    /// annotate what they record.
    #[inline]
    fn begin_pass(_body: usize, _pass: Pass) {}

    /// Zero.
    #[inline]
    fn zero() -> Self {
        Self::constant(0.0)
    }
}

impl Real for f64 {
    #[inline]
    fn constant(value: f64) -> Self {
        value
    }

    #[inline]
    fn sin_cos(self) -> (Self, Self) {
        crate::sin_cos(self)
    }
}
