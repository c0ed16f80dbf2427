//! Fused multiply-add, `a·b + c` with one rounding, and the choice at run time of code compiled
//! for it.
//!
//! Rust never contracts `a * b + c` into one instruction by itself, so generated dynamics are
//! written once over [`crate::Arithmetic`], whose `mul_add` rounds once on the fused types and
//! twice on `f64`, and run twice-compiled (see [`crate::rigid_body::lanes::single`]): [`with_fma`] runs the
//! fused arithmetic where the CPU has the instruction: chosen at compile time when the target
//! has it (`-C target-cpu=native`), else at run time on x86 with `std` (one cached CPUID test),
//! else never.

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

/// How generated code meets fused multiply-add in this build: see [`FMA_SUPPORT`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FmaSupport {
    /// The target has FMA (`-C target-cpu=native` on a recent x86, every aarch64 with NEON): the
    /// fused variant always runs.
    Compiled,
    /// x86 with `std`: the fused variant runs if the CPU reports FMA (one cached CPUID test).
    Detected,
    /// The plain variant always runs: FMA is neither known at compile time nor detectable
    /// (no `std`, another architecture), or the `plain-arithmetic` feature asks for it.
    Never,
}

/// How generated code meets fused multiply-add in this build.
pub const FMA_SUPPORT: FmaSupport = if cfg!(feature = "plain-arithmetic") {
    FmaSupport::Never
} else if cfg!(any(target_feature = "fma", all(target_arch = "aarch64", target_feature = "neon"))) {
    FmaSupport::Compiled
} else if cfg!(all(feature = "std", any(target_arch = "x86", target_arch = "x86_64"))) {
    FmaSupport::Detected
} else {
    FmaSupport::Never
};

/// `Some(fused())` with `fused` compiled for the CPU's fused multiply-add if it has one, or
/// `None` (see [`FMA_SUPPORT`]): the caller then runs its plain variant.
///
/// `fused` must be marked `#[inline(always)]`: it is compiled with the instruction only as
/// part of the function that enables it, and LLVM would leave a large closure out of line,
/// where each [`mul_add`] becomes a call to the C library's `fma`, one call per operation. It
/// is an `Fn`, called directly, so no call shim stands between it and that function.
#[inline]
pub fn with_fma<R>(fused: impl Fn() -> R) -> Option<R> {
    with_fma_at(&(), fused)
}

/// [`with_fma`], its fused copy compiled with `site`'s code
/// ([`Site`](crate::rigid_body::site::Site)).
#[inline]
pub(crate) fn with_fma_at<S: ?Sized, R>(site: &S, fused: impl Fn() -> R) -> Option<R> {
    match FMA_SUPPORT {
        FmaSupport::Compiled => Some(fused()),
        FmaSupport::Detected => detected(site, fused),
        FmaSupport::Never => None,
    }
}

/// Runs `fused` inside a function compiled for FMA if the CPU has it.
#[cfg(all(feature = "std", any(target_arch = "x86", target_arch = "x86_64")))]
#[inline]
fn detected<S: ?Sized, R>(site: &S, fused: impl Fn() -> R) -> Option<R> {
    use crate::rigid_body::site::Site;
    if std::is_x86_feature_detected!("fma") {
        // SAFETY: the CPU has FMA, as just detected (which also means the OS saves the AVX
        // registers FMA uses).
        Some(unsafe { site.on_fma(fused) })
    } else {
        None
    }
}

#[cfg(not(all(feature = "std", any(target_arch = "x86", target_arch = "x86_64"))))]
#[inline]
fn detected<S: ?Sized, R>(_: &S, _: impl Fn() -> R) -> Option<R> {
    None
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
    fn the_fused_variant_runs_exactly_when_the_build_and_the_cpu_allow() {
        // Which variant ran; that it ran with the instruction is checked on the release
        // binary (`objdump -d target/release/hya | grep -c vfmadd`), not here.
        let ran = with_fma(
            #[inline(always)]
            || (),
        )
        .is_some();
        #[cfg(all(feature = "std", any(target_arch = "x86", target_arch = "x86_64")))]
        let cpu_has_it = std::is_x86_feature_detected!("fma");
        #[cfg(not(all(feature = "std", any(target_arch = "x86", target_arch = "x86_64"))))]
        let cpu_has_it = true;
        let expected = match FMA_SUPPORT {
            FmaSupport::Compiled => true,
            FmaSupport::Detected => cpu_has_it,
            FmaSupport::Never => false,
        };
        assert_eq!(ran, expected);
        if cfg!(feature = "plain-arithmetic") {
            assert_eq!(FMA_SUPPORT, FmaSupport::Never);
        }
    }
}
