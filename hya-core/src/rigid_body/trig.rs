//! `sin` and `cos` in one call, without the platform's libm on the hot path.
//!
//! Generated dynamics take all joints in one [`sin_cos_lanes`] call, which dominates their cost for small
//! arms. Method: reduce `x = k π/2 + r` with `π/2` split into three parts (Cody–Waite; each of
//! the first two parts has 33 significant bits, so `k · part` is exact for `|k| < 2²⁰`), then sum
//! the Taylor series of `sin r` and `cos r` on `|r| ≤ π/4` to the `r¹⁵` and `r¹⁶` terms
//! (truncation below half an ulp) by Horner's rule: within 2 units in the last
//! place of 1.0 of `libm` (tested) for `|x| ≤ 1e5`; larger or non-finite inputs go to `libm`.

/// Leading bits of π/2.
pub(crate) const PIO2_1: f64 = 1.570_796_326_734_125_6;
/// The next bits of π/2.
pub(crate) const PIO2_2: f64 = 6.077_100_506_303_966e-11;
/// The rest of π/2.
pub(crate) const PIO2_3: f64 = 2.022_266_248_711_166_4e-21;
/// Beyond this, the reduction above loses accuracy.
pub(crate) const REDUCTION_LIMIT: f64 = 1e5;

/// `1.5·2⁵²`: added to `x·2/π`, it leaves the nearest integer `k` in the low bits of the sum.
pub(crate) const QUADRANT_SHIFT: f64 = 6_755_399_441_055_744.0;

/// `(−1)ᵏ / (2k + 1)!`, k = 0..7: the Taylor coefficients of `sin r / r` in `z = r²`. The next
/// term, `(π/4)¹⁷/17! ≈ 4e-17` relative, is below half an ulp.
pub(crate) const SIN: [f64; 8] = [
    1.0,
    -1.0 / 6.0,
    1.0 / 120.0,
    -1.0 / 5_040.0,
    1.0 / 362_880.0,
    -1.0 / 39_916_800.0,
    1.0 / 6_227_020_800.0,
    -1.0 / 1_307_674_368_000.0,
];

/// `(−1)ᵏ / (2k)!`, k = 0..8: the Taylor coefficients of `cos r` in `z = r²`.
pub(crate) const COS: [f64; 9] = [
    1.0,
    -1.0 / 2.0,
    1.0 / 24.0,
    -1.0 / 720.0,
    1.0 / 40_320.0,
    -1.0 / 3_628_800.0,
    1.0 / 479_001_600.0,
    -1.0 / 87_178_291_200.0,
    1.0 / 20_922_789_888_000.0,
];

/// `Σ c_k z^k` by Horner's rule (more accurate here than Estrin's scheme), each step
/// `sum·z + c` rounded once (`FUSED`, by [`mul_add`](crate::mul_add)) or twice.
#[inline(always)]
fn horner<const FUSED: bool>(coefficients: &[f64], z: f64) -> f64 {
    coefficients.iter().rev().fold(0.0, |sum, &c| if FUSED { crate::mul_add(sum, z, c) } else { sum * z + c })
}

/// `(sin x, cos x)`: [`sin_cos_lanes`] on one lane.
#[inline]
pub fn sin_cos(x: f64) -> (f64, f64) {
    sin_cos_lanes([x])[0]
}

/// `(sin x, cos x)` for every lane of `x`: the same reduction and series as [`sin_cos`], with
/// the quadrant chosen by selects instead of a branch, so the compiler runs the lanes through
/// one vectorised polynomial and mispredicts nothing when the angles' quadrants vary.
///
/// The quadrant `k mod 4` is read from the low bits of `x·2/π + 1.5·2⁵²`, whose last place is
/// 1: the integer `k` sits in the mantissa (two's complement for negative `k`). With
/// `(s, c) = (sin r, cos r)`, `sin x = ±(s or c)` and `cos x = ±(c or s)`:
///
/// ```text
/// k mod 4 :   0    1    2    3
/// sin x   :   s    c   −s   −c        odd k swaps, bit 1 of k negates
/// cos x   :   c   −s   −c    s        odd k swaps, bit 1 of k + 1 negates
/// ```
///
/// Lanes beyond the reduction's range, or not finite, are recomputed by `libm` (a branch
/// never taken for joint angles). Each lane's result does not depend on the others (tested).
///
/// Always inlined: a call from code compiled for FMA or AVX2 (generated dynamics run in such
/// functions, see [`with_fma`](crate::with_fma)) would otherwise run the baseline build's
/// polynomial, without fused multiply-adds and on narrower registers.
#[inline(always)]
pub fn sin_cos_lanes<const N: usize>(x: [f64; N]) -> [(f64, f64); N] {
    sin_cos_lanes_rounded::<false, N>(x)
}

/// [`sin_cos_lanes`] with each step of the series a fused multiply-add: half the operations
/// and half the polynomial's latency where the CPU has the instruction, as accurate (tested).
/// What generated dynamics take on their fused arithmetic ([`crate::rigid_body::lanes::Fused`]), so that
/// a batch lane and a single call agree bit for bit.
#[inline(always)]
pub fn sin_cos_lanes_fused<const N: usize>(x: [f64; N]) -> [(f64, f64); N] {
    sin_cos_lanes_rounded::<true, N>(x)
}

/// [`sin_cos_lanes`], the series rounded as [`horner`] says: fused for `FUSED`.
#[inline(always)]
pub(crate) fn sin_cos_lanes_rounded<const FUSED: bool, const N: usize>(x: [f64; N]) -> [(f64, f64); N] {
    let magic = QUADRANT_SHIFT;
    let mut out = [(0.0, 0.0); N];
    for (x, out) in x.iter().zip(out.iter_mut()) {
        let shifted = x * core::f64::consts::FRAC_2_PI + magic;
        let k = shifted - magic;
        let quadrant = shifted.to_bits();
        let r = ((x - k * PIO2_1) - k * PIO2_2) - k * PIO2_3;
        let z = r * r;
        let (s, c) = (r * horner::<FUSED>(&SIN, z), horner::<FUSED>(&COS, z));
        let odd = quadrant & 1 == 1;
        let (sin_base, cos_base) = if odd { (c, s) } else { (s, c) };
        let sin_sign = (quadrant & 2) << 62;
        let cos_sign = (quadrant.wrapping_add(1) & 2) << 62;
        *out = (f64::from_bits(sin_base.to_bits() ^ sin_sign), f64::from_bits(cos_base.to_bits() ^ cos_sign));
    }
    if x.iter().any(outside_reduction) {
        by_libm_outside_reduction(&x, &mut out);
    }
    out
}

/// True where [`sin_cos_lanes`]' reduction loses accuracy.
#[inline(always)]
fn outside_reduction(x: &f64) -> bool {
    x.is_nan() || x.abs() > REDUCTION_LIMIT
}

/// Recomputes by `libm` the lanes [`outside_reduction`]: a cold call, kept out of line so that
/// the inlined polynomial stays small.
#[cold]
#[inline(never)]
pub(crate) fn by_libm_outside_reduction<const N: usize>(x: &[f64; N], out: &mut [(f64, f64); N]) {
    for (x, out) in x.iter().zip(out.iter_mut()) {
        if outside_reduction(x) {
            *out = libm::sincos(*x);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Both roundings of the series against `libm`.
    fn check(x: f64) {
        let (s_ref, c_ref) = libm::sincos(x);
        for (s, c) in [sin_cos(x), sin_cos_lanes_fused([x])[0]] {
            // Two units in the last place of 1.0.
            assert!(
                (s - s_ref).abs() <= 4.5e-16 && (c - c_ref).abs() <= 4.5e-16,
                "x = {x}: ({s}, {c}) vs ({s_ref}, {c_ref})"
            );
        }
    }

    #[test]
    fn agrees_with_libm_across_the_reduced_range() {
        // Dense over the joint range, then sparse out to the reduction limit.
        for i in -200_000..=200_000 {
            check(i as f64 * 5e-5);
        }
        let mut x = 10.0;
        while x < REDUCTION_LIMIT {
            check(x);
            check(-x * 1.000_123);
            x *= 1.013;
        }
        for x in [0.0, -0.0, 1e-300, core::f64::consts::FRAC_PI_4, core::f64::consts::FRAC_PI_2, core::f64::consts::PI]
        {
            check(x);
        }
    }

    #[test]
    fn each_lane_is_computed_as_if_alone() {
        let mut x = [0.0; 7];
        for i in -100_000..=100_000 {
            for (lane, x) in x.iter_mut().enumerate() {
                *x = i as f64 * 1.1e-4 + lane as f64 * 0.37;
            }
            for (x, (s, c)) in x.iter().zip(sin_cos_lanes(x)) {
                let (s_ref, c_ref) = sin_cos(*x);
                assert!(s.to_bits() == s_ref.to_bits() && c.to_bits() == c_ref.to_bits(), "x = {x}");
            }
            for (x, (s, c)) in x.iter().zip(sin_cos_lanes_fused(x)) {
                let [(s_ref, c_ref)] = sin_cos_lanes_fused([*x]);
                assert!(s.to_bits() == s_ref.to_bits() && c.to_bits() == c_ref.to_bits(), "fused, x = {x}");
            }
        }
        let odd = [1e10, f64::NAN, -0.0, f64::INFINITY, -3.0, REDUCTION_LIMIT * 1.5];
        for (x, (s, c)) in odd.iter().zip(sin_cos_lanes(odd)) {
            let (s_ref, c_ref) = sin_cos(*x);
            assert!(s.to_bits() == s_ref.to_bits() || (s.is_nan() && s_ref.is_nan()), "sin {x}");
            assert!(c.to_bits() == c_ref.to_bits() || (c.is_nan() && c_ref.is_nan()), "cos {x}");
        }
    }

    #[test]
    fn large_and_non_finite_inputs_fall_back() {
        assert_eq!(sin_cos(1e10), libm::sincos(1e10));
        assert!(sin_cos(f64::NAN).0.is_nan() && sin_cos(f64::INFINITY).1.is_nan());
    }
}
