//! `sin` and `cos` in one call, without the platform's libm on the hot path.
//!
//! Generated dynamics call this once per revolute joint, so it dominates their cost for small
//! arms. Method: reduce `x = k π/2 + r` with `π/2` split into three parts (Cody–Waite; each of
//! the first two parts has 33 significant bits, so `k · part` is exact for `|k| < 2²⁰`), then sum
//! the Taylor series of `sin r` and `cos r` on `|r| ≤ π/4` to the `r¹⁵` and `r¹⁶` terms
//! (truncation below half an ulp) by Horner's rule: within 2 units in the last
//! place of 1.0 of `libm` (tested) for `|x| ≤ 1e5`; larger or non-finite inputs go to `libm`.

/// Leading bits of π/2.
const PIO2_1: f64 = 1.570_796_326_734_125_6;
/// The next bits of π/2.
const PIO2_2: f64 = 6.077_100_506_303_966e-11;
/// The rest of π/2.
const PIO2_3: f64 = 2.022_266_248_711_166_4e-21;
/// Beyond this, the reduction above loses accuracy.
const REDUCTION_LIMIT: f64 = 1e5;

/// `(−1)ᵏ / (2k + 1)!`, k = 0..7: the Taylor coefficients of `sin r / r` in `z = r²`. The next
/// term, `(π/4)¹⁷/17! ≈ 4e-17` relative, is below half an ulp.
const SIN: [f64; 8] = [
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
const COS: [f64; 9] = [
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

/// `Σ c_k z^k` by Horner's rule (more accurate here than Estrin's scheme, and as fast).
#[inline(always)]
fn horner(coefficients: &[f64], z: f64) -> f64 {
    coefficients.iter().rev().fold(0.0, |sum, c| sum * z + c)
}

/// `(sin x, cos x)`.
#[inline]
pub fn sin_cos(x: f64) -> (f64, f64) {
    if x.is_nan() || x.abs() > REDUCTION_LIMIT {
        return libm::sincos(x);
    }
    // Round to nearest by the magic constant 1.5·2⁵²: exact for |x·2/π| < 2⁵¹, two additions.
    let magic = 6_755_399_441_055_744.0;
    let k = (x * core::f64::consts::FRAC_2_PI + magic) - magic;
    let r = ((x - k * PIO2_1) - k * PIO2_2) - k * PIO2_3;
    let z = r * r;
    let (s, c) = (r * horner(&SIN, z), horner(&COS, z));
    match (k as i64) & 3 {
        0 => (s, c),
        1 => (c, -s),
        2 => (-s, -c),
        _ => (-c, s),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(x: f64) {
        let (s, c) = sin_cos(x);
        let (s_ref, c_ref) = libm::sincos(x);
        // Two units in the last place of 1.0.
        assert!(
            (s - s_ref).abs() <= 4.5e-16 && (c - c_ref).abs() <= 4.5e-16,
            "x = {x}: ({s}, {c}) vs ({s_ref}, {c_ref})"
        );
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
    fn large_and_non_finite_inputs_fall_back() {
        assert_eq!(sin_cos(1e10), libm::sincos(1e10));
        assert!(sin_cos(f64::NAN).0.is_nan() && sin_cos(f64::INFINITY).1.is_nan());
    }
}
