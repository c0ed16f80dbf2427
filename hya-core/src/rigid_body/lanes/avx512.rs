//! [`F64x8`]: eight `f64` in one AVX-512 register, the lanes [`batch`](super::batch) runs on
//! x86-64 CPUs with AVX-512F (twice the states per instruction of [`F64x4`](super::avx::F64x4)).
//!
//! A private type, sound for the same reason as `F64x4`: values exist only inside
//! [`with_avx512`](super::with_avx512)'s function, compiled for AVX-512F, AVX2 and FMA and run
//! after the CPU was found to have them. Every intrinsic is called from an `#[inline(always)]`
//! method, which lands in that function, or from a function compiled for AVX-512F itself
//! ([`sin_cos_each`], [`horner`] and [`xor`]). Only AVX-512F instructions are used (the `pd`
//! logic operations of AVX-512DQ are done on the integer view); the CPU test is for AVX-512F,
//! AVX2 and FMA, which the rest of the function is compiled for.

use core::arch::x86_64::{
    __m512d, __m512i, _mm512_abs_pd, _mm512_add_epi64, _mm512_add_pd, _mm512_and_si512, _mm512_castpd_si512,
    _mm512_castsi512_pd, _mm512_cmp_pd_mask, _mm512_cmpeq_epi64_mask, _mm512_div_pd, _mm512_fmadd_pd,
    _mm512_mask_blend_pd, _mm512_mul_pd, _mm512_set1_epi64, _mm512_set1_pd, _mm512_slli_epi64, _mm512_sub_pd,
    _mm512_xor_si512, _CMP_NLE_UQ,
};
use core::ops::{Add, Div, Mul, Neg, Sub};

use super::Arithmetic;
use crate::rigid_body::trig::{
    by_libm_outside_reduction, COS, PIO2_1, PIO2_2, PIO2_3, QUADRANT_SHIFT, REDUCTION_LIMIT, SIN,
};

#[derive(Clone, Copy)]
#[repr(transparent)]
pub struct F64x8(__m512d);

/// Runs an AVX-512F intrinsic.
macro_rules! avx512 {
    ($e:expr) => {
        // SAFETY: an `F64x8` exists only inside `with_avx512`'s function, compiled for
        // AVX-512F, AVX2 and FMA and called once the CPU was found to have them (module docs).
        unsafe { $e }
    };
}

impl From<f64> for F64x8 {
    #[inline(always)]
    fn from(value: f64) -> Self {
        Self(avx512!(_mm512_set1_pd(value)))
    }
}

/// `F64x8 ∘ F64x8` by one intrinsic.
macro_rules! register {
    ($intrinsic:ident, $a:expr, $b:expr) => {
        F64x8(avx512!($intrinsic($a.0, $b.0)))
    };
}

register_operators!(
    F64x8, register,
    Add add _mm512_add_pd, Sub sub _mm512_sub_pd, Mul mul _mm512_mul_pd, Div div _mm512_div_pd
);

/// `a ^ b` on the bits of two registers of `f64` (AVX-512F has no `pd` form).
#[target_feature(enable = "avx512f")]
#[inline]
fn xor(a: __m512d, b: __m512i) -> __m512d {
    _mm512_castsi512_pd(_mm512_xor_si512(_mm512_castpd_si512(a), b))
}

impl Neg for F64x8 {
    type Output = Self;
    /// Flips the sign bits, as `-x` does on `f64`.
    #[inline(always)]
    fn neg(self) -> Self {
        Self(avx512!(xor(self.0, _mm512_set1_epi64(i64::MIN))))
    }
}

impl F64x8 {
    /// The lanes as an array (a bit cast).
    #[inline(always)]
    fn to_array(self) -> [f64; 8] {
        // SAFETY: `__m512d` is eight `f64`, with no invalid bit patterns either way.
        unsafe { core::mem::transmute::<__m512d, [f64; 8]>(self.0) }
    }

    /// Lanes from an array (a bit cast).
    #[inline(always)]
    fn from_array(values: [f64; 8]) -> Self {
        // SAFETY: as in `to_array`.
        Self(unsafe { core::mem::transmute::<[f64; 8], __m512d>(values) })
    }
}

impl Arithmetic for F64x8 {
    const LANES: usize = 8;

    #[inline(always)]
    fn mul_add(a: Self, b: impl Into<Self>, c: impl Into<Self>) -> Self {
        Self(avx512!(_mm512_fmadd_pd(a.0, b.into().0, c.into().0)))
    }

    /// All values at once, in one function compiled for AVX-512F, so their independent
    /// polynomials interleave.
    #[inline(always)]
    fn sin_cos_lanes<const K: usize>(x: [Self; K]) -> [(Self, Self); K] {
        let zero = Self::from(0.0);
        let mut out = [(zero, zero); K];
        // SAFETY: see `avx512!`.
        unsafe { sin_cos_each(&x, &mut out) };
        out
    }

    #[inline(always)]
    fn lane(self, l: usize) -> f64 {
        self.to_array()[l]
    }

    #[inline(always)]
    fn from_lanes(f: impl FnMut(usize) -> f64) -> Self {
        Self::from_array(super::each(0.0, f))
    }
}

/// [`sin_cos_lanes_fused`](crate::sin_cos_lanes_fused) of every lane of every value of `x`
/// into `out`, bit for bit: the same reduction, fused series and quadrant selects, each
/// operation on eight lanes (selects by mask registers).
#[target_feature(enable = "avx512f")]
#[inline]
fn sin_cos_each(x: &[F64x8], out: &mut [(F64x8, F64x8)]) {
    // Macros rather than closures, which might be compiled apart from the AVX-512 function.
    macro_rules! splat {
        ($v:expr) => {
            _mm512_set1_pd($v)
        };
    }
    macro_rules! bits {
        ($v:expr) => {
            _mm512_set1_epi64($v)
        };
    }
    /// `±` by bit 1 of the quadrant: that bit moved to the sign.
    macro_rules! sign {
        ($q:expr) => {
            _mm512_slli_epi64::<62>(_mm512_and_si512($q, bits!(2)))
        };
    }
    let mut outside = 0u8;
    for (x, out) in x.iter().zip(out.iter_mut()) {
        let x = x.0;
        let shifted = _mm512_add_pd(_mm512_mul_pd(x, splat!(core::f64::consts::FRAC_2_PI)), splat!(QUADRANT_SHIFT));
        let k = _mm512_sub_pd(shifted, splat!(QUADRANT_SHIFT));
        let r = _mm512_sub_pd(
            _mm512_sub_pd(_mm512_sub_pd(x, _mm512_mul_pd(k, splat!(PIO2_1))), _mm512_mul_pd(k, splat!(PIO2_2))),
            _mm512_mul_pd(k, splat!(PIO2_3)),
        );
        let z = _mm512_mul_pd(r, r);
        let (s, c) = (_mm512_mul_pd(r, horner(&SIN, z)), horner(&COS, z));
        let quadrant: __m512i = _mm512_castpd_si512(shifted);
        let odd = _mm512_cmpeq_epi64_mask(_mm512_and_si512(quadrant, bits!(1)), bits!(1));
        // `mask_blend(m, a, b)` takes `b` where `m` is set.
        let sin = xor(_mm512_mask_blend_pd(odd, s, c), sign!(quadrant));
        let cos = xor(_mm512_mask_blend_pd(odd, c, s), sign!(_mm512_add_epi64(quadrant, bits!(1))));
        *out = (F64x8(sin), F64x8(cos));
        // Not finite, or beyond the reduction's range: `!(|x| ≤ limit)`.
        outside |= _mm512_cmp_pd_mask::<_CMP_NLE_UQ>(_mm512_abs_pd(x), splat!(REDUCTION_LIMIT));
    }
    if outside != 0 {
        for (x, out) in x.iter().zip(out.iter_mut()) {
            let (sin, cos) = (out.0.to_array(), out.1.to_array());
            let mut pairs: [(f64, f64); 8] = core::array::from_fn(|l| (sin[l], cos[l]));
            by_libm_outside_reduction(&x.to_array(), &mut pairs);
            *out = (F64x8::from_array(pairs.map(|p| p.0)), F64x8::from_array(pairs.map(|p| p.1)));
        }
    }
}

/// `Σ c_k z^k` by Horner's rule, each step one fused multiply-add, as in
/// [`sin_cos_lanes_fused`](crate::sin_cos_lanes_fused).
#[target_feature(enable = "avx512f")]
#[inline]
fn horner(coefficients: &[f64], z: __m512d) -> __m512d {
    let mut sum = _mm512_set1_pd(0.0);
    for &c in coefficients.iter().rev() {
        sum = _mm512_fmadd_pd(sum, z, _mm512_set1_pd(c));
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rigid_body::lanes::with_avx512;

    /// Every lane of [`sin_cos_each`], bit for bit against the scalar fused polynomial, across
    /// quadrants, signs, the reduction's limit and values it leaves to `libm`.
    #[test]
    fn eight_lanes_equal_the_scalar_polynomial_bit_for_bit() {
        let mut values: std::vec::Vec<f64> = (-4000..=4000).map(|i| i as f64 * 1.7e-3).collect();
        values.extend([0.0, -0.0, 1e-300, 1e4, -7.5e4, REDUCTION_LIMIT, REDUCTION_LIMIT * 1.5, 1e10]);
        values.extend([f64::NAN, f64::INFINITY, f64::NEG_INFINITY, core::f64::consts::FRAC_PI_4]);
        let chunks: std::vec::Vec<[f64; 8]> =
            values.chunks(8).map(|c| core::array::from_fn(|l| c[l.min(c.len() - 1)])).collect();
        let lanes = with_avx512(
            #[inline(always)]
            || {
                chunks
                    .iter()
                    .map(|&c| {
                        let [(s, c), (s2, c2)] =
                            F64x8::sin_cos_lanes([F64x8::from_array(c), -F64x8::from_array(c) * 0.5]);
                        (s.to_array(), c.to_array(), s2.to_array(), c2.to_array())
                    })
                    .collect::<std::vec::Vec<_>>()
            },
        );
        let Some(lanes) = lanes else {
            assert!(!std::is_x86_feature_detected!("avx512f"));
            return;
        };
        let same = |a: f64, b: f64| a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan());
        for (chunk, (sin, cos, sin2, cos2)) in chunks.iter().zip(lanes) {
            let halved = chunk.map(|x| -x * 0.5);
            let reference = crate::sin_cos_lanes_fused(*chunk).into_iter().zip(crate::sin_cos_lanes_fused(halved));
            for (l, ((s, c), (s2, c2))) in reference.enumerate() {
                assert!(same(sin[l], s) && same(cos[l], c), "x = {}: ({}, {}) vs ({s}, {c})", chunk[l], sin[l], cos[l]);
                assert!(same(sin2[l], s2) && same(cos2[l], c2), "x = {}", halved[l]);
            }
        }
    }
}
