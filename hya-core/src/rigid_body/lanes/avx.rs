//! [`F64x4`]: four `f64` in one AVX register, the lanes [`batch`](super::batch) runs on x86-64.
//!
//! A private type: values exist only inside [`with_vector_fma`](super::with_vector_fma)'s
//! function compiled for AVX2 and FMA, run after the CPU was found to have both, which is what
//! makes its intrinsics sound. (Arrays of four, as [`Lanes`](super::Lanes), are split into
//! scalars by the compiler in functions this long.)
//!
//! Every intrinsic is called either from an `#[inline(always)]` method, which lands in that
//! compiled function, or from a function compiled for AVX2 and FMA itself ([`sin_cos_all`] and
//! the functions it calls).
//! No closure stands between them: LLVM may keep a closure out of line, compiled for the
//! baseline, where an intrinsic becomes a call of its own.

use core::arch::x86_64::{
    __m256d, __m256i, _mm256_add_epi64, _mm256_add_pd, _mm256_and_si256, _mm256_andnot_pd, _mm256_blendv_pd,
    _mm256_castpd_si256, _mm256_castsi256_pd, _mm256_cmp_pd, _mm256_cmpeq_epi64, _mm256_div_pd, _mm256_fmadd_pd,
    _mm256_movemask_pd, _mm256_mul_pd, _mm256_permute2f128_pd, _mm256_permute4x64_epi64, _mm256_set1_epi64x,
    _mm256_set1_pd, _mm256_slli_epi64, _mm256_sub_pd, _mm256_xor_pd, _CMP_NLE_UQ,
};
use core::ops::{Add, Div, Mul, Neg, Sub};

use super::Arithmetic;
use crate::rigid_body::trig::{
    by_libm_outside_reduction, COS, PIO2_1, PIO2_2, PIO2_3, QUADRANT_SHIFT, REDUCTION_LIMIT, SIN,
};

#[derive(Clone, Copy)]
#[repr(transparent)]
pub struct F64x4(__m256d);

/// Runs an AVX or FMA intrinsic.
macro_rules! avx {
    ($e:expr) => {
        // SAFETY: an `F64x4` exists only inside `with_vector_fma`'s function, compiled for
        // AVX2 and FMA and called once the CPU was found to have them (see the module's docs).
        unsafe { $e }
    };
}

impl From<f64> for F64x4 {
    #[inline(always)]
    fn from(value: f64) -> Self {
        Self(avx!(_mm256_set1_pd(value)))
    }
}

/// `F64x4 ∘ F64x4` by one intrinsic.
macro_rules! register {
    ($intrinsic:ident, $a:expr, $b:expr) => {
        F64x4(avx!($intrinsic($a.0, $b.0)))
    };
}

register_operators!(
    F64x4, register,
    Add add _mm256_add_pd, Sub sub _mm256_sub_pd, Mul mul _mm256_mul_pd, Div div _mm256_div_pd
);

impl Neg for F64x4 {
    type Output = Self;
    /// Flips the sign bits, as `-x` does on `f64`.
    #[inline(always)]
    fn neg(self) -> Self {
        Self(avx!(_mm256_xor_pd(self.0, _mm256_set1_pd(-0.0))))
    }
}

impl F64x4 {
    /// The lanes as an array (a bit cast, no instruction that needs AVX).
    #[inline(always)]
    fn to_array(self) -> [f64; 4] {
        // SAFETY: `__m256d` is four `f64`, with no invalid bit patterns either way.
        unsafe { core::mem::transmute::<__m256d, [f64; 4]>(self.0) }
    }

    /// Lanes from an array (a bit cast).
    #[inline(always)]
    fn from_array(values: [f64; 4]) -> Self {
        // SAFETY: as in `to_array`.
        Self(unsafe { core::mem::transmute::<[f64; 4], __m256d>(values) })
    }
}

impl Arithmetic for F64x4 {
    const LANES: usize = 4;

    #[inline(always)]
    fn mul_add(a: Self, b: impl Into<Self>, c: impl Into<Self>) -> Self {
        Self(avx!(_mm256_fmadd_pd(a.0, b.into().0, c.into().0)))
    }

    /// All values at once, in one function compiled for AVX2, so their independent
    /// polynomials interleave. Where every value repeats its lower two lanes in its upper two
    /// (a batch of one or two states, see [`batch`](super::batch)), pairs of values share a
    /// register and half the polynomials are computed.
    #[inline(always)]
    fn sin_cos_lanes<const K: usize>(x: [Self; K]) -> [(Self, Self); K] {
        // SAFETY: see `avx!`.
        unsafe { sin_cos_all(&x) }
    }

    lanes_by_array!();
}

/// [`F64x4::sin_cos_lanes`]: [`sin_cos_of_pairs`] where two or more values all repeat their
/// lower lanes in their upper ones ([`halves_repeat`]), else [`sin_cos_each`].
#[target_feature(enable = "avx2,fma")]
#[inline]
fn sin_cos_all<const K: usize>(x: &[F64x4; K]) -> [(F64x4, F64x4); K] {
    let zero = F64x4(_mm256_set1_pd(0.0));
    let mut out = [(zero, zero); K];
    // One value gains nothing from sharing.
    if K >= 2 && halves_repeat(x) {
        sin_cos_of_pairs(x, &mut out);
    } else {
        sin_cos_each(x, &mut out);
    }
    out
}

/// Whether every value's lanes 2 and 3 hold the bits of its lanes 0 and 1; a batch of four
/// states fails at the first value.
#[target_feature(enable = "avx2,fma")]
#[inline]
fn halves_repeat(x: &[F64x4]) -> bool {
    for x in x {
        let bits = _mm256_castpd_si256(x.0);
        let swapped = _mm256_permute4x64_epi64::<0b01_00_11_10>(bits);
        if _mm256_movemask_pd(_mm256_castsi256_pd(_mm256_cmpeq_epi64(bits, swapped))) != 0b1111 {
            return false;
        }
    }
    true
}

/// [`sin_cos_each`] of values whose upper two lanes repeat their lower two: the lower halves
/// of two values share a register, and each result's halves are its lower half twice. Equal
/// to [`sin_cos_each`] of `x` lane for lane, on half the registers.
#[target_feature(enable = "avx2,fma")]
#[inline]
fn sin_cos_of_pairs<const K: usize>(x: &[F64x4; K], out: &mut [(F64x4, F64x4); K]) {
    let mut packed = [F64x4(_mm256_set1_pd(0.0)); K];
    let pairs = K.div_ceil(2);
    for (p, packed) in packed[..pairs].iter_mut().enumerate() {
        let (low, high) = (x[2 * p].0, x[(2 * p + 1).min(K - 1)].0);
        *packed = F64x4(_mm256_permute2f128_pd::<0x20>(low, high));
    }
    let mut results = [(packed[0], packed[0]); K];
    sin_cos_each(&packed[..pairs], &mut results[..pairs]);
    for (k, out) in out.iter_mut().enumerate() {
        let (sin, cos) = (results[k / 2].0 .0, results[k / 2].1 .0);
        *out = match k % 2 {
            0 => (F64x4(_mm256_permute2f128_pd::<0x00>(sin, sin)), F64x4(_mm256_permute2f128_pd::<0x00>(cos, cos))),
            _ => (F64x4(_mm256_permute2f128_pd::<0x11>(sin, sin)), F64x4(_mm256_permute2f128_pd::<0x11>(cos, cos))),
        };
    }
}

/// [`sin_cos_lanes_fused`](crate::sin_cos_lanes_fused) of every lane of every value of `x`
/// into `out`, bit for bit: the same reduction, fused series and quadrant selects, each
/// operation on four lanes.
#[target_feature(enable = "avx2,fma")]
#[inline]
fn sin_cos_each(x: &[F64x4], out: &mut [(F64x4, F64x4)]) {
    // Macros rather than closures, which might be compiled apart from the AVX2 function.
    macro_rules! splat {
        ($v:expr) => {
            _mm256_set1_pd($v)
        };
    }
    macro_rules! bits {
        ($v:expr) => {
            _mm256_set1_epi64x($v)
        };
    }
    /// `±` by bit 1 of the quadrant: that bit moved to the sign.
    macro_rules! sign {
        ($q:expr) => {
            _mm256_castsi256_pd(_mm256_slli_epi64::<62>(_mm256_and_si256($q, bits!(2))))
        };
    }
    let mut outside = 0;
    for (x, out) in x.iter().zip(out.iter_mut()) {
        let x = x.0;
        let shifted = _mm256_add_pd(_mm256_mul_pd(x, splat!(core::f64::consts::FRAC_2_PI)), splat!(QUADRANT_SHIFT));
        let k = _mm256_sub_pd(shifted, splat!(QUADRANT_SHIFT));
        let r = _mm256_sub_pd(
            _mm256_sub_pd(_mm256_sub_pd(x, _mm256_mul_pd(k, splat!(PIO2_1))), _mm256_mul_pd(k, splat!(PIO2_2))),
            _mm256_mul_pd(k, splat!(PIO2_3)),
        );
        let z = _mm256_mul_pd(r, r);
        let (s, c) = (_mm256_mul_pd(r, horner(&SIN, z)), horner(&COS, z));
        let quadrant: __m256i = _mm256_castpd_si256(shifted);
        let odd = _mm256_castsi256_pd(_mm256_cmpeq_epi64(_mm256_and_si256(quadrant, bits!(1)), bits!(1)));
        let sin = _mm256_xor_pd(_mm256_blendv_pd(s, c, odd), sign!(quadrant));
        let cos = _mm256_xor_pd(_mm256_blendv_pd(c, s, odd), sign!(_mm256_add_epi64(quadrant, bits!(1))));
        *out = (F64x4(sin), F64x4(cos));
        // Not finite, or beyond the reduction's range: `!(|x| ≤ limit)`.
        let magnitude = _mm256_andnot_pd(splat!(-0.0), x);
        outside |= _mm256_movemask_pd(_mm256_cmp_pd::<_CMP_NLE_UQ>(magnitude, splat!(REDUCTION_LIMIT)));
    }
    if outside != 0 {
        for (x, out) in x.iter().zip(out.iter_mut()) {
            let (sin, cos) = (out.0.to_array(), out.1.to_array());
            let mut pairs: [(f64, f64); 4] = core::array::from_fn(|l| (sin[l], cos[l]));
            by_libm_outside_reduction(&x.to_array(), &mut pairs);
            *out = (F64x4::from_array(pairs.map(|p| p.0)), F64x4::from_array(pairs.map(|p| p.1)));
        }
    }
}

/// `Σ c_k z^k` by Horner's rule, each step one fused multiply-add, as in
/// [`sin_cos_lanes_fused`](crate::sin_cos_lanes_fused).
#[target_feature(enable = "avx2,fma")]
#[inline]
fn horner(coefficients: &[f64], z: __m256d) -> __m256d {
    let mut sum = _mm256_set1_pd(0.0);
    for &c in coefficients.iter().rev() {
        sum = _mm256_fmadd_pd(sum, z, _mm256_set1_pd(c));
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rigid_body::lanes::with_vector_fma;

    /// `sin`/`cos` of `values` (each four lanes) through [`F64x4::sin_cos_lanes`], as arrays,
    /// or `None` without AVX2 and FMA.
    #[allow(clippy::type_complexity)]
    fn sin_cos_of<const K: usize>(values: [[f64; 4]; K]) -> Option<[([f64; 4], [f64; 4]); K]> {
        with_vector_fma(
            #[inline(always)]
            || F64x4::sin_cos_lanes(values.map(F64x4::from_array)).map(|(s, c)| (s.to_array(), c.to_array())),
        )
    }

    /// The shared-register path itself gives each lane the bits that computing every value
    /// alone gives, NaN and the values left to `libm` included.
    #[test]
    fn sharing_registers_gives_the_bits_of_each_value_alone() {
        let x = [[0.3, -1.2, 0.3, -1.2], [2.9, f64::NAN, 2.9, f64::NAN], [1e10, -0.0, 1e10, -0.0]];
        let bits = |results: [(F64x4, F64x4); 3]| {
            results.map(|(s, c)| (s.to_array().map(f64::to_bits), c.to_array().map(f64::to_bits)))
        };
        let Some((shared, alone)) = with_vector_fma(
            #[inline(always)]
            || {
                let (x, zero) = (x.map(F64x4::from_array), F64x4::from(0.0));
                let (mut shared, mut alone) = ([(zero, zero); 3], [(zero, zero); 3]);
                // SAFETY: inside `with_vector_fma`'s function, compiled for AVX2 and FMA and
                // called on a CPU that has both.
                unsafe {
                    sin_cos_of_pairs(&x, &mut shared);
                    sin_cos_each(&x, &mut alone);
                }
                (bits(shared), bits(alone))
            },
        ) else {
            return;
        };
        assert_eq!(shared, alone);
    }

    /// Values whose upper lanes repeat their lower ones (a batch of one or two states) share
    /// registers two by two, in odd and even numbers of values; each lane still equals the
    /// scalar polynomial bit for bit, as for a single value (which shares with none) and when
    /// one value does not repeat.
    #[test]
    fn values_of_two_states_share_registers_and_give_the_same_bits() {
        let pair = |a: f64, b: f64| [a, b, a, b];
        let same = |a: f64, b: f64| a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan());
        let check = |values: &[[f64; 4]], results: &[([f64; 4], [f64; 4])]| {
            for (x, (sin, cos)) in values.iter().zip(results) {
                for (l, (s, c)) in crate::sin_cos_lanes_fused(*x).into_iter().enumerate() {
                    assert!(same(sin[l], s) && same(cos[l], c), "x = {}: ({}, {}) vs ({s}, {c})", x[l], sin[l], cos[l]);
                }
            }
        };
        let three = [pair(0.3, -1.2), pair(2.9, f64::NAN), pair(1e10, -0.0)];
        let Some(results) = sin_cos_of(three) else { return };
        check(&three, &results);
        let six =
            [pair(0.1, 0.2), pair(-3.0, 4.0), pair(5.5, -6.5), pair(7.0, 1e-300), pair(-0.7, 0.7), pair(9.0, 1.0)];
        check(&six, &sin_cos_of(six).unwrap_or_else(|| unreachable!()));
        let one = [[0.25; 4]];
        check(&one, &sin_cos_of(one).unwrap_or_else(|| unreachable!()));
        let mixed = [pair(0.1, 0.2), [0.5, 0.6, 0.5, 0.7], pair(-1.0, 1.0)];
        check(&mixed, &sin_cos_of(mixed).unwrap_or_else(|| unreachable!()));
    }

    /// Every lane of [`sin_cos_each`], bit for bit against the scalar fused polynomial, across
    /// quadrants, signs, the reduction's limit and values it leaves to `libm`.
    #[test]
    fn four_lanes_equal_the_scalar_polynomial_bit_for_bit() {
        let mut values: std::vec::Vec<f64> = (-4000..=4000).map(|i| i as f64 * 1.7e-3).collect();
        values.extend([0.0, -0.0, 1e-300, 1e4, -7.5e4, REDUCTION_LIMIT, REDUCTION_LIMIT * 1.5, 1e10]);
        values.extend([f64::NAN, f64::INFINITY, f64::NEG_INFINITY, core::f64::consts::FRAC_PI_4]);
        let chunks: std::vec::Vec<[f64; 4]> =
            values.chunks(4).map(|c| core::array::from_fn(|l| c[l.min(c.len() - 1)])).collect();
        let lanes = with_vector_fma(
            #[inline(always)]
            || {
                chunks
                    .iter()
                    .map(|&c| {
                        let [(s, c)] = F64x4::sin_cos_lanes([F64x4::from_array(c)]);
                        (s.to_array(), c.to_array())
                    })
                    .collect::<std::vec::Vec<_>>()
            },
        );
        let Some(lanes) = lanes else {
            assert!(!std::is_x86_feature_detected!("avx2") || !std::is_x86_feature_detected!("fma"));
            return;
        };
        let same = |a: f64, b: f64| a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan());
        for (chunk, (sin, cos)) in chunks.iter().zip(lanes) {
            for (l, (s_ref, c_ref)) in crate::sin_cos_lanes_fused(*chunk).into_iter().enumerate() {
                assert!(
                    same(sin[l], s_ref) && same(cos[l], c_ref),
                    "x = {}: ({}, {}) vs ({s_ref}, {c_ref})",
                    chunk[l],
                    sin[l],
                    cos[l]
                );
            }
        }
    }
}
