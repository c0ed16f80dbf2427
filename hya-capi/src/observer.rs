//! The observers the paper compares its estimator against: Chen's nonlinear disturbance
//! observer, the generalised-momentum observer and the extended-state observer
//! (hya_core::observers), behind one handle type.

use std::ffi::c_char;

use hya_core::erased::SliceObserver;

use crate::arm_model::{ArmModel, ObserverSpec};
use crate::model::{borrow, HyaModel};
use crate::slices::{input, optional_input, output};
use crate::status::{create, destroy, last_message, on_handle, Failure, Handle, HyaStatus, Message};

/// A baseline disturbance observer (opaque). Made by one of `hya_observer_new_*`, freed by
/// `hya_observer_free`.
pub struct HyaObserver {
    observer: Box<dyn SliceObserver>,
    dof: usize,
    message: Message,
}

impl Handle for HyaObserver {
    const KIND: &'static str = "HyaObserver";
    fn message(&mut self) -> &mut Message {
        &mut self.message
    }
    fn message_ref(&self) -> &Message {
        &self.message
    }
}

/// Creates an observer from the model behind `model` with `make`.
unsafe fn new_observer(
    model: *const HyaModel,
    out: *mut *mut HyaObserver,
    make: impl FnOnce(&dyn ArmModel, usize) -> Result<Box<dyn SliceObserver>, Failure>,
) -> HyaStatus {
    // SAFETY: the caller's contract, passed on.
    unsafe {
        create(out, || {
            let arm = borrow(model)?;
            let dof = arm.dof();
            Ok(HyaObserver { observer: make(arm, dof)?, dof, message: Message::default() })
        })
    }
}

/// Chen's nonlinear disturbance observer (IEEE TIE 2000) with Mohammadi's gain `Y = gain · I`:
/// `d̂̇ = Y M⁻¹(q) (d − d̂)`, stepped implicitly at `dt` (s), started at `qd0` (`n` = dof). Its
/// updates need the measured `qd`.
///
/// # Safety
/// `model` is null or a live handle; `qd0` is null or holds `n` doubles; `out` is null or
/// writable.
#[no_mangle]
pub unsafe extern "C" fn hya_observer_new_nonlinear(
    model: *const HyaModel,
    gain: f64,
    dt: f64,
    qd0: *const f64,
    n: usize,
    out: *mut *mut HyaObserver,
) -> HyaStatus {
    // SAFETY: the caller's contract, passed on.
    unsafe {
        new_observer(model, out, |arm, dof| {
            let qd0 = input("qd0", qd0, n, dof)?;
            Ok(arm.observer(ObserverSpec::Nonlinear { gain, dt_s: dt, qd0 })?)
        })
    }
}

/// The generalised-momentum observer (De Luca; Haddadin 2017) with per-joint gains `gain` (1/s):
/// `d̂ / d = k / (s + k)` per joint, at `dt` (s), started at `(q0, qd0, tau0)`; every array has
/// `n` = dof entries. Its updates need the measured `qd`.
///
/// # Safety
/// `model` is null or a live handle; each non-null array holds `n` doubles; `out` is null or
/// writable.
#[no_mangle]
pub unsafe extern "C" fn hya_observer_new_momentum(
    model: *const HyaModel,
    gain: *const f64,
    dt: f64,
    q0: *const f64,
    qd0: *const f64,
    tau0: *const f64,
    n: usize,
    out: *mut *mut HyaObserver,
) -> HyaStatus {
    // SAFETY: the caller's contract, passed on.
    unsafe {
        new_observer(model, out, |arm, dof| {
            let gain = input("gain", gain, n, dof)?;
            let (q0, qd0, tau0) = (input("q0", q0, n, dof)?, input("qd0", qd0, n, dof)?, input("tau0", tau0, n, dof)?);
            Ok(arm.observer(ObserverSpec::Momentum { gain, dt_s: dt, q0, qd0, tau0 })?)
        })
    }
}

/// The extended-state observer (Han; Gao) of bandwidth `bandwidth` (rad/s): `d̂ / d = ω³ / (s +
/// ω)³` per joint, at `dt` (s), started at `q0` (`n` = dof). Needs no measured velocity.
///
/// # Safety
/// `model` is null or a live handle; `q0` is null or holds `n` doubles; `out` is null or
/// writable.
#[no_mangle]
pub unsafe extern "C" fn hya_observer_new_extended_state(
    model: *const HyaModel,
    bandwidth: f64,
    dt: f64,
    q0: *const f64,
    n: usize,
    out: *mut *mut HyaObserver,
) -> HyaStatus {
    // SAFETY: the caller's contract, passed on.
    unsafe {
        new_observer(model, out, |arm, dof| {
            let q0 = input("q0", q0, n, dof)?;
            Ok(arm.observer(ObserverSpec::ExtendedState { bandwidth_rad_s: bandwidth, dt_s: dt, q0 })?)
        })
    }
}

/// One tick: measured `q`, `qd` (null if not measured; the nonlinear and momentum observers
/// need it) and `tau` in, the new `d̂` (N·m) out; `n` = dof each. A refused tick leaves the
/// observer as it was.
///
/// # Safety
/// `observer` is null or a live handle; each non-null array holds `n` doubles.
#[no_mangle]
pub unsafe extern "C" fn hya_observer_update(
    observer: *mut HyaObserver,
    q: *const f64,
    qd: *const f64,
    tau: *const f64,
    n: usize,
    d_hat: *mut f64,
) -> HyaStatus {
    // SAFETY: the caller's contract; lengths checked against the observer.
    unsafe {
        on_handle(observer, |o| {
            let (q, qd, tau) =
                (input("q", q, n, o.dof)?, optional_input("qd", qd, n, o.dof)?, input("tau", tau, n, o.dof)?);
            Ok(o.observer.update(q, qd, tau, output("d_hat", d_hat, n, o.dof, &[q, qd.unwrap_or(&[]), tau])?)?)
        })
    }
}

/// The message of the observer's last failed call (empty if none); owned by the observer.
///
/// # Safety
/// `observer` is null or a live handle.
#[no_mangle]
pub unsafe extern "C" fn hya_observer_error(observer: *const HyaObserver) -> *const c_char {
    // SAFETY: the caller's contract.
    unsafe { last_message(observer) }
}

/// Frees an observer (null is a no-op).
///
/// # Safety
/// `observer` is null or a handle from `hya_observer_new_*`, not used afterwards.
#[no_mangle]
pub unsafe extern "C" fn hya_observer_free(observer: *mut HyaObserver) {
    // SAFETY: the caller's contract.
    unsafe { destroy(observer) }
}
