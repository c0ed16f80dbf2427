//! [`F64x4`]: four `f64` in two NEON registers, the lanes [`batch`](super::batch) runs on
//! aarch64.
//!
//! Compiled where the target has NEON, which every standard aarch64 target (Linux, macOS) does,
//! and run only where [`with_vector_fma`](super::with_vector_fma) runs it. Each operation is one
//! intrinsic per register: nothing is left for LLVM to unroll and vectorise again. On arrays of
//! four ([`Lanes`](super::Lanes)), thousands of operations per kernel had kept its optimiser
//! busy for more than 58 CPU-minutes in a release build of the shipped arms, unfinished.

use core::arch::aarch64::{float64x2_t, vaddq_f64, vdivq_f64, vdupq_n_f64, vfmaq_f64, vmulq_f64, vnegq_f64, vsubq_f64};
use core::ops::{Add, Div, Mul, Neg, Sub};

use super::Arithmetic;

#[derive(Clone, Copy)]
#[repr(transparent)]
pub struct F64x4([float64x2_t; 2]);

/// Runs a NEON intrinsic.
macro_rules! neon {
    ($e:expr) => {
        // SAFETY: this module is compiled only where the target has NEON, so the CPU has the
        // instructions these intrinsics emit.
        unsafe { $e }
    };
}

/// `$intrinsic` on both registers, lane by lane.
macro_rules! both {
    ($intrinsic:ident, $($v:expr),+) => {
        F64x4([neon!($intrinsic($($v.0[0]),+)), neon!($intrinsic($($v.0[1]),+))])
    };
}

impl From<f64> for F64x4 {
    #[inline(always)]
    fn from(value: f64) -> Self {
        let half = neon!(vdupq_n_f64(value));
        Self([half, half])
    }
}

register_operators!(F64x4, both, Add add vaddq_f64, Sub sub vsubq_f64, Mul mul vmulq_f64, Div div vdivq_f64);

impl Neg for F64x4 {
    type Output = Self;
    /// Flips the sign bits, as `-x` does on `f64`.
    #[inline(always)]
    fn neg(self) -> Self {
        both!(vnegq_f64, self)
    }
}

impl F64x4 {
    /// The lanes as an array (a bit cast).
    #[inline(always)]
    fn to_array(self) -> [f64; 4] {
        // SAFETY: two `float64x2_t` are four `f64`, with no invalid bit patterns either way.
        unsafe { core::mem::transmute::<[float64x2_t; 2], [f64; 4]>(self.0) }
    }

    /// Lanes from an array (a bit cast).
    #[inline(always)]
    fn from_array(values: [f64; 4]) -> Self {
        // SAFETY: as in `to_array`.
        Self(unsafe { core::mem::transmute::<[f64; 4], [float64x2_t; 2]>(values) })
    }
}

impl Arithmetic for F64x4 {
    const LANES: usize = 4;

    /// `vfmaq_f64(c, a, b)` is `c + a·b`, rounded once.
    #[inline(always)]
    fn mul_add(a: Self, b: impl Into<Self>, c: impl Into<Self>) -> Self {
        let (b, c) = (b.into(), c.into());
        both!(vfmaq_f64, c, a, b)
    }

    /// Each value's four lanes through the scalar fused polynomial
    /// ([`sin_cos_lanes_fused`](crate::sin_cos_lanes_fused)), so that every lane equals the
    /// single call bit for bit; a handful per kernel beside its hundreds of vector operations.
    #[inline(always)]
    fn sin_cos_lanes<const K: usize>(x: [Self; K]) -> [(Self, Self); K] {
        let zero = Self::from(0.0);
        let mut out = [(zero, zero); K];
        for (x, out) in x.iter().zip(out.iter_mut()) {
            let pairs = crate::sin_cos_lanes_fused(x.to_array());
            *out = (Self::from_array(pairs.map(|p| p.0)), Self::from_array(pairs.map(|p| p.1)));
        }
        out
    }

    lanes_by_array!();
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each operation, lane by lane, equals the scalar one bit for bit (`mul_add` rounded once).
    #[test]
    fn every_operation_equals_the_scalar_one_in_every_lane() {
        let a = [1.0 + f64::EPSILON * 2f64.powi(22), -3.5, f64::NAN, f64::INFINITY];
        let b = [a[0], 0.25, -7.0, 2.0];
        let c = [-1.0, 1e300, 0.0, -0.0];
        let (x, y, z) = (F64x4::from_array(a), F64x4::from_array(b), F64x4::from_array(c));
        for l in 0..4 {
            let (a, b, c) = (a[l], b[l], c[l]);
            let same = |got: F64x4, want: f64| {
                let got = got.lane(l);
                assert!(
                    got.to_bits() == want.to_bits() || (got.is_nan() && want.is_nan()),
                    "lane {l}: {got} vs {want}"
                );
            };
            same(x + y, a + b);
            same(x - y, a - b);
            same(x * y, a * b);
            same(x / y, a / b);
            same(-x, -a);
            same(x * 3.0, a * 3.0);
            same(F64x4::mul_add(x, y, z), crate::mul_add(a, b, c));
            same(F64x4::from_lanes(|k| [a, b, c, 0.0][k]), [a, b, c, 0.0][l]);
        }
    }

    /// `sin` and `cos` of every lane equal the scalar fused polynomial's bit for bit, across
    /// quadrants, signs and values left to `libm` (beyond the reduction's range, not finite).
    #[test]
    fn sin_cos_of_every_lane_equals_the_scalar_polynomial() {
        let mut values: std::vec::Vec<f64> = (-400..=400).map(|i| i as f64 * 1.7e-2).collect();
        values.extend([0.0, -0.0, 1e-300, 1e4, -7.5e4, 1e10, f64::NAN, f64::INFINITY, f64::NEG_INFINITY]);
        let same = |a: f64, b: f64| a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan());
        for chunk in values.chunks(8) {
            let chunk: [f64; 8] = core::array::from_fn(|i| chunk[i.min(chunk.len() - 1)]);
            let x = [
                F64x4::from_array([chunk[0], chunk[1], chunk[2], chunk[3]]),
                F64x4::from_array([chunk[4], chunk[5], chunk[6], chunk[7]]),
            ];
            let lanes = F64x4::sin_cos_lanes(x);
            let scalar = crate::sin_cos_lanes_fused(chunk);
            for (i, (sin, cos)) in scalar.into_iter().enumerate() {
                let (s, c) = lanes[i / 4];
                assert!(same(s.lane(i % 4), sin) && same(c.lane(i % 4), cos), "x = {}", chunk[i]);
            }
        }
    }
}
