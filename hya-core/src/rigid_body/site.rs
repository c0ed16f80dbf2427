//! Where the compiler puts the copy of code that a CPU-feature switch runs.
//!
//! A function compiled for a CPU feature (`#[target_feature]`) is not inlined into its caller,
//! so the generated kernels it runs are compiled as part of it, once per kernel and lane type.
//! rustc places the copies of a generic free function in the codegen unit of the module that
//! defines it: every shipped arm's kernels landed in one unit, which LLVM optimises on one core
//! (`hya-robots` took 6.5 minutes to build at `opt-level = 1`, 6 of them in LLVM with one core
//! idle; `-Z time-passes` and `-Z print-mono-items`). A method of a blanket impl is placed with
//! its `Self` type instead, so switching through [`Site`] on the kernel's own type gives each
//! arm's copies its own units, which compile side by side.

/// Runs a closure inside a function compiled for a CPU feature, placed with `Self`'s code
/// (see the module's notes). Every type is a site; `()` for code that belongs to no kernel.
#[cfg(all(feature = "std", any(target_arch = "x86", target_arch = "x86_64")))]
pub(crate) trait Site {
    /// `f()` compiled for FMA. `f` is an `Fn`, called directly: through `FnOnce`'s call shim,
    /// which LLVM may leave out of line for a large kernel, the kernel would be compiled without
    /// FMA and each `mul_add` would call the C library's `fma` (a single ∇ID call on HyA took
    /// 5–8 µs that way, against 1.3–2 µs).
    ///
    /// # Safety
    /// The CPU must have FMA.
    unsafe fn on_fma<R>(&self, f: impl Fn() -> R) -> R;

    /// `f()` compiled for AVX2 and FMA.
    ///
    /// # Safety
    /// The CPU must have AVX2 and FMA.
    unsafe fn on_avx2_fma<R>(&self, f: impl FnOnce() -> R) -> R;

    /// `f()` compiled for AVX-512F, AVX2 and FMA.
    ///
    /// # Safety
    /// The CPU must have all three.
    #[cfg(target_arch = "x86_64")]
    unsafe fn on_avx512<R>(&self, f: impl FnOnce() -> R) -> R;
}

#[cfg(all(feature = "std", any(target_arch = "x86", target_arch = "x86_64")))]
impl<T: ?Sized> Site for T {
    #[target_feature(enable = "fma")]
    unsafe fn on_fma<R>(&self, f: impl Fn() -> R) -> R {
        f()
    }

    #[target_feature(enable = "avx2,fma")]
    unsafe fn on_avx2_fma<R>(&self, f: impl FnOnce() -> R) -> R {
        f()
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f,avx2,fma")]
    unsafe fn on_avx512<R>(&self, f: impl FnOnce() -> R) -> R {
        f()
    }
}
