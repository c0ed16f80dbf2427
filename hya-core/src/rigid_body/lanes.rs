//! The arithmetic generated dynamics are written over, once: plain `f64`, fused multiply-add,
//! and lanes that hold several robot states at a time.
//!
//! The generator emits each function as one body generic over [`Arithmetic`] (a [`Kernel`]);
//! this module runs it:
//! - [`single`]: one state, on [`Fused`] where the CPU has fused multiply-add
//!   ([`with_fma`](crate::with_fma)), else on plain `f64`;
//! - [`batch`]: many states, [`batch_lanes`] at a time in a vector register type, on code
//!   compiled for the CPU's vector unit and its FMA where it has them: eight in an AVX-512
//!   register where the CPU has AVX-512F ([`with_avx512`]), else [`BATCH_LANES`] ([`with_vector_fma`]:
//!   AVX2 and FMA on x86-64 with `std`, chosen once per call by a cached CPUID test; NEON on
//!   aarch64; [`Lanes`] elsewhere), else one state at a time through [`single`].
//!
//! `A::mul_add(a, b, c)` is `a·b + c`: rounded twice on `f64` and plain lanes (exactly the
//! statements `let p = a * b; let s = p + c;`), once on the fused types. Each lane of [`Lanes`]
//! is computed as if alone: a batch's result for a state equals the single call's on the same
//! arithmetic, bit for bit, and differs from the other arithmetic's only by rounding.

use core::ops::{Add, Div, Mul, Neg, Sub};

use crate::{Error, JointVector};

/// Numbers generated dynamics compute with: `f64`, or [`Lanes`] of them.
///
/// Constants enter as `f64` on the right of `+ − × ÷` and as the last two arguments of
/// [`mul_add`](Self::mul_add); `A::from(c)` where neither fits (a constant divided by a value).
pub trait Arithmetic:
    Copy
    + From<f64>
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + Add<f64, Output = Self>
    + Sub<f64, Output = Self>
    + Mul<f64, Output = Self>
    + Div<f64, Output = Self>
{
    /// States held side by side.
    const LANES: usize;

    /// `a·b + c`: one rounding on the fused types, two otherwise.
    fn mul_add(a: Self, b: impl Into<Self>, c: impl Into<Self>) -> Self;

    /// `(sin x, cos x)` of every lane ([`sin_cos_lanes`](crate::sin_cos_lanes)'s method): by
    /// default, [`sin_cos_lanes`](Self::sin_cos_lanes) of the one value.
    #[inline(always)]
    fn sin_cos(self) -> (Self, Self) {
        Self::sin_cos_lanes([self])[0]
    }

    /// `(sin x, cos x)` of several values at once, e.g. all joint angles.
    fn sin_cos_lanes<const K: usize>(x: [Self; K]) -> [(Self, Self); K];

    /// Lane `l`'s number.
    fn lane(self, l: usize) -> f64;

    /// A value whose lane `l` is `f(l)`.
    fn from_lanes(f: impl FnMut(usize) -> f64) -> Self;
}

impl Arithmetic for f64 {
    const LANES: usize = 1;

    #[inline(always)]
    fn mul_add(a: Self, b: impl Into<Self>, c: impl Into<Self>) -> Self {
        a * b.into() + c.into()
    }

    #[inline(always)]
    fn sin_cos(self) -> (Self, Self) {
        crate::sin_cos(self)
    }

    #[inline(always)]
    fn sin_cos_lanes<const K: usize>(x: [Self; K]) -> [(Self, Self); K] {
        crate::sin_cos_lanes(x)
    }

    #[inline(always)]
    fn lane(self, _: usize) -> f64 {
        self
    }

    #[inline(always)]
    fn from_lanes(mut f: impl FnMut(usize) -> f64) -> Self {
        f(0)
    }
}

/// `L` numbers, one per robot state, operated on together (`FUSED`: with one rounding in
/// [`Arithmetic::mul_add`]). Every operation is lane by lane, which the compiler turns into
/// vector instructions.
#[derive(Debug, Clone, Copy, PartialEq)]
#[repr(transparent)]
pub struct Lanes<const L: usize, const FUSED: bool>(pub [f64; L]);

/// `[f(0), f(1), …]` by a loop the compiler always inlines. (`array::map` and
/// `array::from_fn` are calls of their own in functions as long as generated kernels, and one
/// per operation costs more than the operation.)
#[inline(always)]
fn each<T: Copy, const L: usize>(zero: T, mut f: impl FnMut(usize) -> T) -> [T; L] {
    let mut out = [zero; L];
    let mut l = 0;
    while l < L {
        out[l] = f(l);
        l += 1;
    }
    out
}

/// One `f64` with fused multiply-add: the single call's arithmetic where the CPU has FMA.
#[derive(Debug, Clone, Copy, PartialEq)]
#[repr(transparent)]
pub struct Fused(pub f64);

impl From<f64> for Fused {
    #[inline(always)]
    fn from(value: f64) -> Self {
        Self(value)
    }
}

/// `Fused ∘ Fused` and `Fused ∘ f64`, as on `f64`.
macro_rules! fused_operator {
    ($trait:ident, $method:ident, $op:tt) => {
        impl $trait for Fused {
            type Output = Self;
            #[inline(always)]
            fn $method(self, rhs: Self) -> Self {
                Self(self.0 $op rhs.0)
            }
        }
        impl $trait<f64> for Fused {
            type Output = Self;
            #[inline(always)]
            fn $method(self, rhs: f64) -> Self {
                Self(self.0 $op rhs)
            }
        }
    };
}

fused_operator!(Add, add, +);
fused_operator!(Sub, sub, -);
fused_operator!(Mul, mul, *);
fused_operator!(Div, div, /);

impl Neg for Fused {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        Self(-self.0)
    }
}

impl Arithmetic for Fused {
    const LANES: usize = 1;

    #[inline(always)]
    fn mul_add(a: Self, b: impl Into<Self>, c: impl Into<Self>) -> Self {
        Self(crate::mul_add(a.0, b.into().0, c.into().0))
    }

    /// One vectorised [`sin_cos_lanes_fused`](crate::sin_cos_lanes_fused) call across the
    /// values.
    #[inline(always)]
    fn sin_cos_lanes<const K: usize>(x: [Self; K]) -> [(Self, Self); K] {
        let pairs = crate::sin_cos_lanes_fused::<K>(each(0.0, |k| x[k].0));
        each((Self(0.0), Self(0.0)), |k| (Self(pairs[k].0), Self(pairs[k].1)))
    }

    #[inline(always)]
    fn lane(self, _: usize) -> f64 {
        self.0
    }

    #[inline(always)]
    fn from_lanes(mut f: impl FnMut(usize) -> f64) -> Self {
        Self(f(0))
    }
}

/// States per batch step without AVX-512: four `f64` fill a 256-bit AVX register (two NEON
/// registers). With AVX-512F a step takes eight ([`batch_lanes`]).
pub const BATCH_LANES: usize = 4;

/// The most states a batch step may take: 8 by default, [`limit_batch_lanes`] may lower it.
#[cfg(all(feature = "std", target_arch = "x86_64"))]
static WIDEST_LANES: core::sync::atomic::AtomicUsize = core::sync::atomic::AtomicUsize::new(8);

/// Lets batches take at most `lanes` states per step, for the whole process: 4 keeps them on
/// AVX2 where the CPU has AVX-512 too (to compare the two widths, as `hya bench` does); 8, the
/// default, lets them use AVX-512. Any other number is refused ([`Error::InvalidParameter`]).
/// Results do not depend on it: every lane computes its state as the single call does.
pub fn limit_batch_lanes(lanes: usize) -> Result<(), Error> {
    if lanes != 4 && lanes != 8 {
        return Err(Error::InvalidParameter { name: "batch lanes", value: lanes as f64, requirement: "4 or 8" });
    }
    #[cfg(all(feature = "std", target_arch = "x86_64"))]
    WIDEST_LANES.store(lanes, core::sync::atomic::Ordering::Relaxed);
    Ok(())
}

/// The states a [`batch`] step takes on this CPU now: 8 with AVX-512F (unless
/// [`limit_batch_lanes`] said 4; forward dynamics stays on 4, see [`kernels::Width`]),
/// [`BATCH_LANES`] on a vector unit with FMA, else 1.
pub fn batch_lanes() -> usize {
    if with_avx512(|| ()).is_some() {
        8
    } else if with_vector_fma(|| ()).is_some() {
        BATCH_LANES
    } else {
        1
    }
}

impl<const L: usize, const FUSED: bool> From<f64> for Lanes<L, FUSED> {
    #[inline(always)]
    fn from(value: f64) -> Self {
        Self([value; L])
    }
}

/// `Lanes ∘ Lanes` and `Lanes ∘ f64`, lane by lane.
macro_rules! lane_operator {
    ($trait:ident, $method:ident, $op:tt) => {
        impl<const L: usize, const FUSED: bool> $trait for Lanes<L, FUSED> {
            type Output = Self;
            #[inline(always)]
            fn $method(self, rhs: Self) -> Self {
                Self(each(0.0, |l| self.0[l] $op rhs.0[l]))
            }
        }
        impl<const L: usize, const FUSED: bool> $trait<f64> for Lanes<L, FUSED> {
            type Output = Self;
            #[inline(always)]
            fn $method(self, rhs: f64) -> Self {
                Self(each(0.0, |l| self.0[l] $op rhs))
            }
        }
    };
}

lane_operator!(Add, add, +);
lane_operator!(Sub, sub, -);
lane_operator!(Mul, mul, *);
lane_operator!(Div, div, /);

impl<const L: usize, const FUSED: bool> Neg for Lanes<L, FUSED> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        Self(each(0.0, |l| -self.0[l]))
    }
}

impl<const L: usize, const FUSED: bool> Arithmetic for Lanes<L, FUSED> {
    const LANES: usize = L;

    #[inline(always)]
    fn mul_add(a: Self, b: impl Into<Self>, c: impl Into<Self>) -> Self {
        let (b, c) = (b.into(), c.into());
        Self(each(0.0, |l| if FUSED { crate::mul_add(a.0[l], b.0[l], c.0[l]) } else { a.0[l] * b.0[l] + c.0[l] }))
    }

    /// [`sin_cos_lanes`](crate::sin_cos_lanes) across the lanes, its series fused where
    /// `FUSED` ([`sin_cos_lanes_fused`](crate::sin_cos_lanes_fused)).
    #[inline(always)]
    fn sin_cos(self) -> (Self, Self) {
        let pairs = crate::rigid_body::trig::sin_cos_lanes_rounded::<FUSED, L>(self.0);
        (Self(each(0.0, |l| pairs[l].0)), Self(each(0.0, |l| pairs[l].1)))
    }

    /// One lane: one vectorised call across the values (all joints at once, as on `f64`).
    /// Several: one call per value, across its lanes.
    #[inline(always)]
    fn sin_cos_lanes<const K: usize>(x: [Self; K]) -> [(Self, Self); K] {
        let zero = (Self::from(0.0), Self::from(0.0));
        if L == 1 {
            let pairs = crate::rigid_body::trig::sin_cos_lanes_rounded::<FUSED, K>(each(0.0, |k| x[k].0[0]));
            each(zero, |k| (Self::from(pairs[k].0), Self::from(pairs[k].1)))
        } else {
            each(zero, |k| x[k].sin_cos())
        }
    }

    #[inline(always)]
    fn lane(self, l: usize) -> f64 {
        self.0[l]
    }

    #[inline(always)]
    fn from_lanes(f: impl FnMut(usize) -> f64) -> Self {
        Self(each(0.0, f))
    }
}

/// One generated function (`F`, a marker of [`kernels`]) of a robot with `N` joints, written
/// once over any [`Arithmetic`]: `IN` joint vectors in, `OUT` numbers out.
pub trait Kernel<F, const N: usize, const IN: usize, const OUT: usize> {
    /// The function's statements on `A`.
    fn run<A: Arithmetic>(&self, inputs: [&[A; N]; IN]) -> [A; OUT];
}

/// Markers naming the generated functions, so that one type implements [`Kernel`] once for each.
pub mod kernels {
    /// Whether a function's batches take eight lanes where the CPU has AVX-512F
    /// ([`with_avx512`](super::with_avx512)), or stay on four. Chosen by measurement
    /// (`hya bench --json`, both widths side by side, 1024 states per call, on one x86-64 CPU with AVX-512F; BENCHMARKS.md):
    /// the median over rounds of four-lane over eight-lane time was 1.21-1.45 for inverse dynamics
    /// on HyA, UR5, Panda and iiwa14, 1.55-1.80 for its derivatives and 1.01-1.65 for the mass
    /// matrix (UR5's even, single rounds either way), while forward dynamics took 101-105 ns per
    /// state on eight lanes against 72-77 on four on HyA and UR5 (even on the others), so it stays
    /// on four. The last link's Jacobian: 1.46-1.83 on HyA, iiwa14 and the Panda, 0.85-0.95 on
    /// UR5 (three rounds), so eight; its `J̇ q̇`, not measured, follows it. The results are the
    /// same bit for bit either way.
    pub trait Width {
        /// Eight lanes where the CPU has them.
        const WIDE: bool = true;
    }
    impl Width for InverseDynamics {}
    impl Width for Gravity {}
    impl Width for VelocityTerms {}
    impl Width for CoriolisTranspose {}
    impl Width for MassMatrix {}
    impl Width for ForwardDynamics {
        const WIDE: bool = false;
    }
    impl Width for ForwardDynamicsOfBodies {
        const WIDE: bool = false;
    }
    impl Width for InverseDynamicsDerivatives {}
    impl Width for FramePoses {}
    impl Width for FrameJacobian {}
    impl Width for FrameAccelerationBias {}

    /// Inverse dynamics.
    #[derive(Debug, Clone, Copy)]
    pub struct InverseDynamics;
    /// Gravity torques.
    #[derive(Debug, Clone, Copy)]
    pub struct Gravity;
    /// Coriolis and centripetal torques.
    #[derive(Debug, Clone, Copy)]
    pub struct VelocityTerms;
    /// `C_matᵀ q̇`.
    #[derive(Debug, Clone, Copy)]
    pub struct CoriolisTranspose;
    /// The mass matrix's lower triangle.
    #[derive(Debug, Clone, Copy)]
    pub struct MassMatrix;
    /// Forward dynamics, followed by the articulated inertias `D_i` to check.
    #[derive(Debug, Clone, Copy)]
    pub struct ForwardDynamics;
    /// Forward dynamics with each state's bodies as inputs (`BodiesBatch`), followed by the
    /// articulated inertias `D_i` to check.
    #[derive(Debug, Clone, Copy)]
    pub struct ForwardDynamicsOfBodies;
    /// The derivatives of inverse dynamics.
    #[derive(Debug, Clone, Copy)]
    pub struct InverseDynamicsDerivatives;
    /// Every frame's pose.
    #[derive(Debug, Clone, Copy)]
    pub struct FramePoses;
    /// The tip frame's Jacobian.
    #[derive(Debug, Clone, Copy)]
    pub struct FrameJacobian;
    /// The tip frame's `J̇ q̇`.
    #[derive(Debug, Clone, Copy)]
    pub struct FrameAccelerationBias;
}

/// `[&args[0], &args[1], …]`.
#[inline(always)]
fn borrowed<T, const IN: usize>(args: &[T; IN]) -> [&T; IN] {
    each(&args[0], |i| &args[i])
}

/// Runs `kernel` on one state: on [`Fused`] where the CPU has FMA, else on `f64` (see
/// [`with_fma`](crate::with_fma)); `_function` picks which of the type's kernels. One function
/// per kernel, which the single call and [`batch`]'s fallback share.
#[inline]
pub fn single<F, K, const N: usize, const IN: usize, const OUT: usize>(
    kernel: &K,
    _function: F,
    inputs: [&JointVector<N>; IN],
) -> [f64; OUT]
where
    K: Kernel<F, N, IN, OUT>,
{
    let args: [[f64; N]; IN] = each([0.0; N], |i| each(0.0, |j| inputs[i][j]));
    let fused = crate::fma::with_fma_at(
        kernel,
        #[inline(always)]
        || {
            let args: [[Fused; N]; IN] =
                each([Fused::from(0.0); N], |i| each(Fused::from(0.0), |j| Fused::from(args[i][j])));
            let out = kernel.run::<Fused>(borrowed(&args));
            each(0.0, |k| out[k].0)
        },
    );
    fused.unwrap_or_else(
        #[inline(always)]
        || kernel.run::<f64>(borrowed(&args)),
    )
}

/// Runs `kernel` on every state of `inputs` (one slice per argument, all of `count` states) and
/// hands state `k`'s outputs to `store(k, outputs)`: eight states per step in AVX-512 registers
/// where the CPU has AVX-512F ([`with_avx512`]), the function is [`kernels::Width::WIDE`] and the
/// batch holds more than [`BATCH_LANES`] states, [`BATCH_LANES`] on code compiled for the CPU's
/// vector unit and FMA where it has both ([`with_vector_fma`]), else one state at a time
/// through [`single`]. A short last step repeats its states cyclically in the
/// unused lanes, whose results are dropped. Stops at the first error `store` returns (earlier states
/// are stored).
///
/// An error if a slice's length is not `count`.
#[inline(always)]
pub fn batch<F: Copy + kernels::Width, K, const N: usize, const IN: usize, const OUT: usize>(
    kernel: &K,
    function: F,
    inputs: [&[JointVector<N>]; IN],
    count: usize,
    mut store: impl FnMut(usize, [f64; OUT]) -> Result<(), Error>,
) -> Result<(), Error>
where
    K: Kernel<F, N, IN, OUT>,
{
    for (argument, states) in inputs.iter().enumerate() {
        if states.len() != count {
            return Err(Error::BatchLength { argument, expected: count, got: states.len() });
        }
    }
    // A batch of four states or fewer (the control tick's two) fills four lanes at least as well.
    #[cfg(all(feature = "std", target_arch = "x86_64"))]
    if F::WIDE && count > BATCH_LANES {
        if let Some(done) = with_avx512_at(
            kernel,
            #[inline(always)]
            || steps::<avx512::F64x8, F, K, N, IN, OUT>(kernel, inputs, &mut store),
        ) {
            return done;
        }
    }
    let vector = with_vector_fma_at(
        kernel,
        #[inline(always)]
        || steps::<VectorLanes, F, K, N, IN, OUT>(kernel, inputs, &mut store),
    );
    vector.unwrap_or_else(|| {
        (0..count).try_for_each(|k| store(k, single(kernel, function, each(&inputs[0][k], |i| &inputs[i][k]))))
    })
}

/// The lanes [`batch`] runs on where [`with_vector_fma`] does: AVX registers on x86-64.
#[cfg(all(feature = "std", target_arch = "x86_64"))]
pub(crate) type VectorLanes = avx::F64x4;
/// The lanes [`batch`] runs on where [`with_vector_fma`] does: two NEON registers on aarch64.
#[cfg(all(target_arch = "aarch64", target_feature = "neon"))]
pub(crate) type VectorLanes = neon::F64x4;
/// The lanes [`batch`] runs on where [`with_vector_fma`] does: arrays the compiler maps to
/// the target's vector registers itself, which in kernels this long costs LLVM far more time
/// than register types do (see `neon.rs`).
#[cfg(not(any(all(feature = "std", target_arch = "x86_64"), all(target_arch = "aarch64", target_feature = "neon"))))]
pub(crate) type VectorLanes = Lanes<BATCH_LANES, true>;

/// [`batch`]'s loop on the arithmetic `A`.
#[inline(always)]
fn steps<A: Arithmetic, F, K, const N: usize, const IN: usize, const OUT: usize>(
    kernel: &K,
    inputs: [&[JointVector<N>]; IN],
    store: &mut impl FnMut(usize, [f64; OUT]) -> Result<(), Error>,
) -> Result<(), Error>
where
    K: Kernel<F, N, IN, OUT>,
{
    let count = inputs.first().map_or(0, |states| states.len());
    let mut start = 0;
    while start < count {
        let used = A::LANES.min(count - start);
        let zero = A::from(0.0);
        // Unused lanes repeat the used ones cyclically: two states fill four lanes as
        // `[s0, s1, s0, s1]`, whose `sin`/`cos` the AVX type computes on half the registers.
        // (The division only in a short step.)
        let state = |l: usize| start + if used == A::LANES { l } else { l % used };
        let args: [[A; N]; IN] = each([zero; N], |i| each(zero, |j| A::from_lanes(|l| inputs[i][state(l)][j])));
        let outputs = kernel.run::<A>(borrowed(&args));
        for l in 0..used {
            store(start + l, each(0.0, |k| outputs[k].lane(l)))?;
        }
        start += A::LANES;
    }
    Ok(())
}

/// `Some(f())` with `f` compiled for the CPU's vector unit and fused multiply-add if it has
/// both, or `None`: AVX2 and FMA on x86 with `std` (one cached CPUID test), at compile time
/// where the target has FMA (aarch64's NEON, `-C target-cpu=native`). `f` must be
/// `#[inline(always)]`, as for [`with_fma`](crate::with_fma).
#[inline]
pub fn with_vector_fma<R>(f: impl FnOnce() -> R) -> Option<R> {
    with_vector_fma_at(&(), f)
}

/// [`with_vector_fma`], its vector copy compiled with `site`'s code
/// ([`Site`](crate::rigid_body::site::Site)).
#[inline]
fn with_vector_fma_at<S: ?Sized, R>(site: &S, f: impl FnOnce() -> R) -> Option<R> {
    match crate::FMA_SUPPORT {
        crate::FmaSupport::Never => None,
        crate::FmaSupport::Compiled if !cfg!(target_arch = "x86_64") || cfg!(target_feature = "avx2") => Some(f()),
        _ => detected(site, f),
    }
}

/// `f(state)` compiled for the vector unit where [`with_vector_fma`] finds one, else as
/// compiled. For code whose results must not depend on the CPU: Rust never contracts `a * b + c`
/// into a fused operation, so only what `f` asks for explicitly changes.
#[inline(always)]
pub(crate) fn on_vector_unit<T, R>(state: &mut T, f: impl Fn(&mut T) -> R) -> R {
    with_vector_fma(
        #[inline(always)]
        || f(state),
    )
    .unwrap_or_else(|| f(state))
}

/// Runs `f` inside a function compiled for AVX2 and FMA if the CPU has them.
#[cfg(all(feature = "std", any(target_arch = "x86", target_arch = "x86_64")))]
#[inline]
fn detected<S: ?Sized, R>(site: &S, f: impl FnOnce() -> R) -> Option<R> {
    use crate::rigid_body::site::Site;
    if std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma") {
        // SAFETY: the CPU has both, as just detected.
        Some(unsafe { site.on_avx2_fma(f) })
    } else {
        None
    }
}

#[cfg(not(all(feature = "std", any(target_arch = "x86", target_arch = "x86_64"))))]
#[inline]
fn detected<S: ?Sized, R>(_: &S, _: impl FnOnce() -> R) -> Option<R> {
    None
}

/// `Some(f())` with `f` compiled for AVX-512F, AVX2 and FMA if the CPU has them,
/// [`limit_batch_lanes`] allows eight lanes and the build is not `plain-arithmetic`, else `None` (always on targets other than x86-64
/// with `std`). `f` must be `#[inline(always)]`, as for [`with_fma`](crate::with_fma).
#[inline]
pub fn with_avx512<R>(f: impl FnOnce() -> R) -> Option<R> {
    with_avx512_at(&(), f)
}

/// [`with_avx512`], its copy compiled with `site`'s code ([`Site`](crate::rigid_body::site::Site)).
#[cfg(all(feature = "std", target_arch = "x86_64"))]
#[inline]
fn with_avx512_at<S: ?Sized, R>(site: &S, f: impl FnOnce() -> R) -> Option<R> {
    use crate::rigid_body::site::Site;
    // Under `plain-arithmetic` nothing runs fused, these lanes included.
    let allowed = !matches!(crate::FMA_SUPPORT, crate::FmaSupport::Never)
        && WIDEST_LANES.load(core::sync::atomic::Ordering::Relaxed) >= 8;
    if allowed
        && std::is_x86_feature_detected!("avx512f")
        && std::is_x86_feature_detected!("avx2")
        && std::is_x86_feature_detected!("fma")
    {
        // SAFETY: the CPU has all three, as just detected.
        Some(unsafe { site.on_avx512(f) })
    } else {
        None
    }
}

/// `None`: AVX-512 is used on x86-64 with `std` only.
#[cfg(not(all(feature = "std", target_arch = "x86_64")))]
#[inline]
fn with_avx512_at<S: ?Sized, R>(_: &S, _: impl FnOnce() -> R) -> Option<R> {
    None
}

/// `+ − × ÷` on a vector register type, with another of it or with an `f64` (broadcast by
/// `From<f64>`): `$apply!(intrinsic, a, b)` computes one with the named intrinsic. (Unused
/// on targets with neither register type.)
#[allow(unused_macros)]
macro_rules! register_operators {
    ($type:ty, $apply:ident, $($trait:ident $method:ident $intrinsic:ident),+) => {$(
        impl $trait for $type {
            type Output = Self;
            #[inline(always)]
            fn $method(self, rhs: Self) -> Self {
                $apply!($intrinsic, self, rhs)
            }
        }
        impl $trait<f64> for $type {
            type Output = Self;
            #[inline(always)]
            fn $method(self, rhs: f64) -> Self {
                self.$method(Self::from(rhs))
            }
        }
    )+};
}

/// [`Arithmetic::lane`] and [`Arithmetic::from_lanes`] for a register type of four lanes with
/// bit casts `to_array` and `from_array`.
#[allow(unused_macros)]
macro_rules! lanes_by_array {
    () => {
        #[inline(always)]
        fn lane(self, l: usize) -> f64 {
            self.to_array()[l]
        }

        #[inline(always)]
        fn from_lanes(mut f: impl FnMut(usize) -> f64) -> Self {
            Self::from_array([f(0), f(1), f(2), f(3)])
        }
    };
}

/// Four `f64` in one AVX register, for [`batch`] on x86-64.
#[cfg(all(feature = "std", target_arch = "x86_64"))]
mod avx;

/// Eight `f64` in one AVX-512 register, for [`batch`] on x86-64 CPUs with AVX-512F.
#[cfg(all(feature = "std", target_arch = "x86_64"))]
mod avx512;

/// Four `f64` in two NEON registers, for [`batch`] on aarch64.
#[cfg(all(target_arch = "aarch64", target_feature = "neon"))]
mod neon;

#[cfg(test)]
mod tests {
    use super::*;

    /// `x·y + x` and `sin x`, a kernel small enough to check by hand.
    struct Toy;
    impl Kernel<kernels::Gravity, 2, 2, 3> for Toy {
        fn run<A: Arithmetic>(&self, [x, y]: [&[A; 2]; 2]) -> [A; 3] {
            let (s, c) = x[0].sin_cos();
            [A::mul_add(x[0], y[1], x[1]), s, c / 2.0]
        }
    }

    fn states(count: usize) -> (std::vec::Vec<JointVector<2>>, std::vec::Vec<JointVector<2>>) {
        let x = (0..count).map(|k| JointVector::<2>::new(0.1 * k as f64, 1.0 / (k as f64 + 1.0))).collect();
        let y = (0..count).map(|k| JointVector::<2>::new(-0.3 * k as f64, 1.0 + k as f64 / 3.0)).collect();
        (x, y)
    }

    #[test]
    fn a_batch_stores_every_state_once_with_the_single_call_result() {
        for count in [0, 1, 2, 3, 4, 5, 6, 9, 16, 19] {
            let (x, y) = states(count);
            let mut seen = std::vec![None; count];
            batch(&Toy, kernels::Gravity, [&x, &y], count, |k, out| {
                assert!(seen[k].is_none(), "state {k} stored twice");
                seen[k] = Some(out);
                Ok(())
            })
            .unwrap();
            for (k, out) in seen.iter().enumerate() {
                let single = single(&Toy, kernels::Gravity, [&x[k], &y[k]]);
                let out = out.unwrap();
                for (a, b) in out.iter().zip(single) {
                    assert!((a - b).abs() <= 1e-15 * b.abs().max(1.0), "state {k}: {out:?} vs {single:?}");
                }
            }
        }
    }

    #[test]
    fn lengths_that_differ_are_refused_and_store_errors_stop_the_batch() {
        let (x, y) = states(5);
        let refused = batch(&Toy, kernels::Gravity, [&x, &y[..4]], 5, |_, _| Ok(()));
        assert_eq!(refused, Err(Error::BatchLength { argument: 1, expected: 5, got: 4 }));
        let mut stored = 0;
        let stopped = batch(&Toy, kernels::Gravity, [&x, &y], 5, |k, _| {
            stored += 1;
            if k == 2 {
                Err(Error::SingularMassMatrix)
            } else {
                Ok(())
            }
        });
        assert_eq!((stopped, stored), (Err(Error::SingularMassMatrix), 3));
    }

    #[test]
    fn plain_mul_add_rounds_twice_and_fused_once() {
        let a = 1.0 + f64::EPSILON * 2f64.powi(22);
        assert_eq!(<f64 as Arithmetic>::mul_add(a, a, -1.0), a * a - 1.0);
        assert_eq!(<Lanes<2, false> as Arithmetic>::mul_add(a.into(), a, -1.0).0, [a * a - 1.0; 2]);
        assert_eq!(<Fused as Arithmetic>::mul_add(a.into(), a, -1.0).0, crate::mul_add(a, a, -1.0));
    }
}
