//! Fused multiply-add, `a·b + c` with one rounding, and the choice at run time of code compiled
//! for it.
//!
//! Rust never contracts `a * b + c` into one instruction by itself, so generated dynamics come
//! in two variants of the same statements: one that calls [`mul_add`] wherever a product feeds
//! a sum, one that does not. [`with_fma`] runs the first where the CPU has the instruction:
//! chosen at compile time when the target has it (`-C target-cpu=native`), else at run time on
//! x86 with `std` (one cached CPUID test), else never.

/// `a·b + c` with one rounding. Without `std`, `libm`'s `fma`.
#[inline(always)]
pub fn mul_add(a: f64, b: f64, c: f64) -> f64 {
    #[cfg(feature = "std")]
    {
        a.mul_add(b, c)
    }
    #[cfg(not(feature = "std"))]
    {
        libm::fma(a, b, c)
    }
}

/// `Some(fused())` with `fused` compiled for the CPU's fused multiply-add, or `None` where the
/// CPU lacks it or it cannot be detected (no `std`): the caller then runs its plain variant.
///
/// `fused` must be marked `#[inline(always)]`: it is compiled with the instruction only as
/// part of the function that enables it, and LLVM would leave a large closure out of line,
/// where each [`mul_add`] becomes a call to the C library's software `fma`.
#[inline]
pub fn with_fma<R>(fused: impl FnOnce() -> R) -> Option<R> {
    #[cfg(target_feature = "fma")]
    {
        Some(fused())
    }
    #[cfg(all(feature = "std", any(target_arch = "x86", target_arch = "x86_64"), not(target_feature = "fma")))]
    {
        /// Runs `f` as part of a function compiled for FMA.
        ///
        /// # Safety
        /// The CPU must have FMA.
        #[target_feature(enable = "fma")]
        unsafe fn compiled_for_fma<R>(f: impl FnOnce() -> R) -> R {
            f()
        }
        if std::is_x86_feature_detected!("fma") {
            // SAFETY: the CPU has FMA, as just detected.
            Some(unsafe { compiled_for_fma(fused) })
        } else {
            None
        }
    }
    #[cfg(not(any(target_feature = "fma", all(feature = "std", any(target_arch = "x86", target_arch = "x86_64")))))]
    {
        let _ = fused;
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mul_add_rounds_once() {
        // (1 + 2⁻³⁰)² = 1 + 2⁻²⁹ + 2⁻⁶⁰: the last term survives only an unrounded product.
        let a = 1.0 + f64::EPSILON * 2f64.powi(22);
        assert_eq!(mul_add(a, a, -1.0), 2f64.powi(-29) + 2f64.powi(-60));
        assert_eq!(a * a - 1.0, 2f64.powi(-29));
    }

    #[test]
    #[cfg(all(feature = "std", any(target_arch = "x86", target_arch = "x86_64")))]
    fn with_fma_runs_the_fused_variant_exactly_when_the_cpu_has_fma() {
        let a = 1.0 + f64::EPSILON * 2f64.powi(22);
        let fused = with_fma(
            #[inline(always)]
            || mul_add(a, a, -1.0),
        );
        let expected = std::is_x86_feature_detected!("fma").then_some(2f64.powi(-29) + 2f64.powi(-60));
        assert_eq!(fused, expected);
    }
}
