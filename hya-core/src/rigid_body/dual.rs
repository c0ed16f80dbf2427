//! Forward-mode dual numbers `a + b ε` (`ε² = 0`): run any algorithm written on [`Real`] with
//! one input's tangent seeded to 1, and every output carries its derivative along that input.
//!
//! ```text
//! (a + a' ε)(b + b' ε) = ab + (a b' + a' b) ε,    sin(a + a' ε) = sin a + a' cos a ε
//! ```
//!
//! The tangent is one number (one direction per run); generic over the number type it rides on,
//! so the code generator traces `Dual<Value>` into derivative code.

use core::ops::{Add, Div, Mul, Neg, Sub};

use crate::rigid_body::scalar::{Label, Pass, Real};

/// `value + tangent ε`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dual<S = f64> {
    /// The number itself.
    pub value: S,
    /// Its derivative along the seeded direction.
    pub tangent: S,
}

impl<S: Real> Dual<S> {
    /// An input whose derivative is taken: tangent 1.
    pub fn variable(value: S) -> Self {
        Self { value, tangent: S::constant(1.0) }
    }

    /// An input held fixed: tangent 0.
    pub fn fixed(value: S) -> Self {
        Self { value, tangent: S::zero() }
    }
}

impl<S: Real> Add for Dual<S> {
    type Output = Self;
    fn add(self, rhs: Self) -> Self {
        Self { value: self.value + rhs.value, tangent: self.tangent + rhs.tangent }
    }
}

impl<S: Real> Sub for Dual<S> {
    type Output = Self;
    fn sub(self, rhs: Self) -> Self {
        Self { value: self.value - rhs.value, tangent: self.tangent - rhs.tangent }
    }
}

impl<S: Real> Mul for Dual<S> {
    type Output = Self;
    fn mul(self, rhs: Self) -> Self {
        Self { value: self.value * rhs.value, tangent: self.value * rhs.tangent + self.tangent * rhs.value }
    }
}

impl<S: Real> Div for Dual<S> {
    type Output = Self;
    /// `(a/b)' = (a' − (a/b) b') / b`.
    fn div(self, rhs: Self) -> Self {
        let value = self.value / rhs.value;
        Self { value, tangent: (self.tangent - value * rhs.tangent) / rhs.value }
    }
}

impl<S: Real> Neg for Dual<S> {
    type Output = Self;
    fn neg(self) -> Self {
        Self { value: -self.value, tangent: -self.tangent }
    }
}

impl<S: Real> Real for Dual<S> {
    const TRACES: bool = S::TRACES;

    fn constant(value: f64) -> Self {
        Self::fixed(S::constant(value))
    }

    fn sin_cos(self) -> (Self, Self) {
        let (s, c) = self.value.sin_cos();
        (Self { value: s, tangent: c * self.tangent }, Self { value: c, tangent: -(s * self.tangent) })
    }

    fn labelled(self, label: Label) -> Self {
        Self { value: self.value.labelled(label), tangent: self.tangent }
    }

    fn begin_pass(body: usize, pass: Pass) {
        S::begin_pass(body, pass);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn derivatives_of_products_quotients_and_trigonometry() {
        // f(x) = sin(x) x / (1 + x²) at x = 0.7, against its closed-form derivative.
        let x = 0.7_f64;
        let d = Dual::variable(x);
        let (s, _) = d.sin_cos();
        let f = s * d / (Dual::constant(1.0) + d * d);
        let expected = ((x.cos() * x + x.sin()) * (1.0 + x * x) - x.sin() * x * 2.0 * x) / (1.0 + x * x).powi(2);
        assert!((f.value - x.sin() * x / (1.0 + x * x)).abs() < 1e-15);
        assert!((f.tangent - expected).abs() < 1e-14, "{} vs {expected}", f.tangent);
        let (_, c) = d.sin_cos();
        assert!((c.tangent + x.sin()).abs() < 1e-15);
    }
}
