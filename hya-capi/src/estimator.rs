//! The paper's disturbance estimator (Lu, Sandy & Buchli): third-order filters on `q` and `τ`,
//! inverse dynamics on the filtered signals, `d̂ = ID(q̂, q̂̇, q̂̈) − τ̂`.

use std::ffi::c_char;

use hya_core::erased::SliceObserver;
use hya_core::FilterParams;

use crate::model::{borrow, HyaModel};
use crate::slices::{input, output, overlap, span};
use crate::status::{create, destroy, last_message, on_handle, Failure, Handle, HyaStatus, Message};

/// The paper's disturbance estimator for one arm (opaque). Made by `hya_estimator_new`, freed by
/// `hya_estimator_free`.
pub struct HyaEstimator {
    estimator: Box<dyn SliceObserver>,
    dof: usize,
    message: Message,
}

impl HyaEstimator {
    /// Refuses a step of the other kind than the estimator was made for: over timestamped
    /// samples (`timed`) or at its fixed sample time.
    fn stepped(&self, timed: bool) -> Result<(), Failure> {
        const FIXED: [&str; 2] = ["hya_estimator_update", "hya_estimator_new"];
        const TIMED: [&str; 2] = ["hya_estimator_update_at", "hya_estimator_new_timed"];
        let ([called, needs], [use_instead, made_by]) = if timed { (TIMED, FIXED) } else { (FIXED, TIMED) };
        if self.estimator.is_timed() == timed {
            return Ok(());
        }
        Err(Failure::Stepping { called, needs, made_by, use_instead })
    }
}

impl Handle for HyaEstimator {
    const KIND: &'static str = "HyaEstimator";
    fn message(&mut self) -> &mut Message {
        &mut self.message
    }
    fn message_ref(&self) -> &Message {
        &self.message
    }
}

/// Makes an estimator on `model`'s dynamics with filter damping `zeta`, bandwidths `omega1`
/// (position filter, rad/s) and `omega2` (rad/s), sample time `dt` (s), started at rest at
/// `(q0, tau0)` (`n` = dof each). The paper uses `zeta = 0.8`, `omega1 = omega2 = 50`.
/// On `HYA_OK`, `*out` is a new handle for `hya_estimator_free`; otherwise null, and
/// `hya_last_error` says why.
///
/// # Safety
/// `model` is null or a live handle; `q0`, `tau0` are null or hold `n` doubles; `out` is null or
/// writable.
#[no_mangle]
pub unsafe extern "C" fn hya_estimator_new(
    model: *const HyaModel,
    zeta: f64,
    omega1: f64,
    omega2: f64,
    dt: f64,
    q0: *const f64,
    tau0: *const f64,
    n: usize,
    out: *mut *mut HyaEstimator,
) -> HyaStatus {
    // SAFETY: the caller's contract, passed on.
    unsafe { new_estimator(model, [zeta, omega1, omega2, dt], None, [q0, tau0], n, out) }
}

/// Makes an estimator for samples with their own timestamps (logs, loops whose period jitters):
/// each update brings its time `t` (s) and both filters advance exactly over that step's own
/// length (first-order hold), the discretisations of recent lengths cached. `dt` is the nominal
/// sample time (the first length cached); the estimator starts at rest at `(t0, q0, tau0)` (`n` =
/// dof each). A step longer than `100 / max(omega1, omega2)` s (2 s at the paper's 50 rad/s)
/// restarts it at rest instead of bridging. Update it with `hya_estimator_update_at` only.
///
/// # Safety
/// As `hya_estimator_new`.
#[no_mangle]
pub unsafe extern "C" fn hya_estimator_new_timed(
    model: *const HyaModel,
    zeta: f64,
    omega1: f64,
    omega2: f64,
    dt: f64,
    t0: f64,
    q0: *const f64,
    tau0: *const f64,
    n: usize,
    out: *mut *mut HyaEstimator,
) -> HyaStatus {
    // SAFETY: the caller's contract, passed on.
    unsafe { new_estimator(model, [zeta, omega1, omega2, dt], Some(t0), [q0, tau0], n, out) }
}

/// Creates an estimator with filter parameters `[ζ, ω1, ω2, dt]`, started at rest at `(q0, τ0)`
/// and, for a timed one, at time `t0`.
///
/// # Safety
/// As `hya_estimator_new`.
unsafe fn new_estimator(
    model: *const HyaModel,
    [zeta, omega1, omega2, dt]: [f64; 4],
    t0: Option<f64>,
    [q0, tau0]: [*const f64; 2],
    n: usize,
    out: *mut *mut HyaEstimator,
) -> HyaStatus {
    // SAFETY: the caller's contract, passed on.
    unsafe {
        create(out, || {
            let arm = borrow(model)?;
            let dof = arm.dof();
            let (q0, tau0) = (input("q0", q0, n, dof)?, input("tau0", tau0, n, dof)?);
            let params = FilterParams::new(zeta, omega1, omega2, dt)?;
            Ok(HyaEstimator { estimator: arm.estimator(params, t0, q0, tau0)?, dof, message: Message::default() })
        })
    }
}

/// The sample at time `t` (s, after the previous sample's): measured `q` and `tau` (`n` = dof
/// each) in, the new `d̂` (N·m) out; `*restarted` (unless null) says whether the step was a gap
/// too long to bridge, after which the estimator restarted at rest. For estimators made by
/// `hya_estimator_new_timed`. A refused sample (a time not after the previous one, NaN, wrong
/// length) leaves the estimator as it was.
///
/// # Safety
/// `estimator` is null or a live handle; each non-null array holds `n` doubles; `restarted` is null or writable.
#[no_mangle]
pub unsafe extern "C" fn hya_estimator_update_at(
    estimator: *mut HyaEstimator,
    t: f64,
    q: *const f64,
    tau: *const f64,
    n: usize,
    d_hat: *mut f64,
    restarted: *mut bool,
) -> HyaStatus {
    // SAFETY: the caller's contract; lengths checked against the estimator.
    unsafe {
        on_handle(estimator, |e| {
            e.stepped(true)?;
            let (q, tau) = (input("q", q, n, e.dof)?, input("tau", tau, n, e.dof)?);
            let d_hat = output("d_hat", d_hat, n, e.dof, &[q, tau])?;
            let flag = span(restarted.cast_const(), usize::from(!restarted.is_null()));
            if [q, tau, &*d_hat].iter().any(|array| overlap(flag, span(array.as_ptr(), array.len()))) {
                return Err(Failure::Aliased("restarted"));
            }
            let gap = e.estimator.update_at(t, q, tau, d_hat)?;
            if let Some(restarted) = restarted.as_mut() {
                *restarted = gap;
            }
            Ok(())
        })
    }
}

/// One step of the sample time `dt`: measured `q` and `tau` (`n` = dof each) in, the new `d̂`
/// (N·m) out. For estimators made by `hya_estimator_new`. A refused step
/// (NaN, wrong length) leaves the estimator as it was.
///
/// # Safety
/// `estimator` is null or a live handle; each non-null array holds `n` doubles.
#[no_mangle]
pub unsafe extern "C" fn hya_estimator_update(
    estimator: *mut HyaEstimator,
    q: *const f64,
    tau: *const f64,
    n: usize,
    d_hat: *mut f64,
) -> HyaStatus {
    // SAFETY: the caller's contract; lengths checked against the estimator.
    unsafe {
        on_handle(estimator, |e| {
            e.stepped(false)?;
            let (q, tau) = (input("q", q, n, e.dof)?, input("tau", tau, n, e.dof)?);
            Ok(e.estimator.update(q, None, tau, output("d_hat", d_hat, n, e.dof, &[q, tau])?)?)
        })
    }
}

/// The latest `d̂` (N·m), `n` = dof entries.
///
/// # Safety
/// `estimator` is null or a live handle; `d_hat` is null or holds `n` doubles.
#[no_mangle]
pub unsafe extern "C" fn hya_estimator_disturbance(
    estimator: *mut HyaEstimator,
    d_hat: *mut f64,
    n: usize,
) -> HyaStatus {
    // SAFETY: the caller's contract; length checked against the estimator.
    unsafe {
        on_handle(estimator, |e| {
            e.estimator.disturbance(output("d_hat", d_hat, n, e.dof, &[])?)?;
            Ok(())
        })
    }
}

/// Restarts the estimator at rest at `(q0, tau0)` (`n` = dof each); a timed one at its latest
/// sample's time.
///
/// # Safety
/// `estimator` is null or a live handle; each non-null array holds `n` doubles.
#[no_mangle]
pub unsafe extern "C" fn hya_estimator_reset(
    estimator: *mut HyaEstimator,
    q0: *const f64,
    tau0: *const f64,
    n: usize,
) -> HyaStatus {
    // SAFETY: the caller's contract; lengths checked against the estimator.
    unsafe {
        on_handle(estimator, |e| {
            let (q0, tau0) = (input("q0", q0, n, e.dof)?, input("tau0", tau0, n, e.dof)?);
            Ok(e.estimator.reset(q0, tau0)?)
        })
    }
}

/// The message of the estimator's last failed call (empty if none); owned by the estimator.
///
/// # Safety
/// `estimator` is null or a live handle.
#[no_mangle]
pub unsafe extern "C" fn hya_estimator_error(estimator: *const HyaEstimator) -> *const c_char {
    // SAFETY: the caller's contract.
    unsafe { last_message(estimator) }
}

/// Frees an estimator (null is a no-op).
///
/// # Safety
/// `estimator` is null or a handle from `hya_estimator_new`, not used afterwards.
#[no_mangle]
pub unsafe extern "C" fn hya_estimator_free(estimator: *mut HyaEstimator) {
    // SAFETY: the caller's contract.
    unsafe { destroy(estimator) }
}
