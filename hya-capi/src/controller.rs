//! The computed-torque controller (Lu, Sandy & Buchli, section IV), with `e = q − q_des`:
//!
//! ```text
//! paper form:    τ = M(q) q̈_des + C(q, q̇) + G(q) − K_D ė − K_P e − d̂
//! classic form:  τ = M(q) (q̈_des − K_D ė − K_P e) + C(q, q̇) + G(q) − d̂
//! ```

use std::ffi::c_char;

use hya_core::PdPlacement;

use crate::model::{borrow, HyaModel};
use crate::slices::{command_output, input, optional_input};
use crate::status::{create, destroy, last_message, on_handle, Failure, Handle, HyaStatus, Message};
use hya_core::erased::SliceController;

/// Where the PD feedback enters the computed-torque law.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HyaPdPlacement {
    /// The paper's form: torque-level PD, gains in N·m/rad and N·m·s/rad.
    HyaPdOutsideMassMatrix = 0,
    /// The classic form: acceleration-level PD, gains in 1/s² and 1/s.
    HyaPdInsideMassMatrix = 1,
}

/// A computed-torque controller (opaque). Made by `hya_controller_new`, freed by
/// `hya_controller_free`.
pub struct HyaController {
    controller: Box<dyn SliceController>,
    dof: usize,
    message: Message,
}

impl Handle for HyaController {
    const KIND: &'static str = "HyaController";
    fn message(&mut self) -> &mut Message {
        &mut self.message
    }
    fn message_ref(&self) -> &Message {
        &self.message
    }
}

/// Makes a controller on `model`'s dynamics with diagonal gains `kp`, `kd` (`n` = dof each,
/// finite and non-negative) and the PD placement `placement` (an `HyaPdPlacement` value; any
/// other is `HYA_ERR_INVALID`). On `HYA_OK`, `*out` is a new handle for `hya_controller_free`;
/// otherwise null, and `hya_last_error` says why.
///
/// # Safety
/// `model` is null or a live handle; `kp`, `kd` are null or hold `n` doubles; `out` is null or
/// writable.
#[no_mangle]
pub unsafe extern "C" fn hya_controller_new(
    model: *const HyaModel,
    kp: *const f64,
    kd: *const f64,
    n: usize,
    placement: u32,
    out: *mut *mut HyaController,
) -> HyaStatus {
    // SAFETY: the caller's contract, passed on.
    unsafe {
        create(out, || {
            let arm = borrow(model)?;
            let dof = arm.dof();
            let (kp, kd) = (input("kp", kp, n, dof)?, input("kd", kd, n, dof)?);
            let placement = match placement {
                0 => PdPlacement::OutsideMassMatrix,
                1 => PdPlacement::InsideMassMatrix,
                other => {
                    return Err(Failure::Core(hya_core::Error::InvalidParameter {
                        name: "placement",
                        value: f64::from(other),
                        requirement: "HYA_PD_OUTSIDE_MASS_MATRIX (0) or HYA_PD_INSIDE_MASS_MATRIX (1)",
                    }))
                }
            };
            Ok(HyaController { controller: arm.controller(kp, kd, placement)?, dof, message: Message::default() })
        })
    }
}

/// The commanded torque `tau` for the state `(q, qd)`, the reference `(q_des, qd_des,
/// qdd_des)` and, unless `d_hat` is null, the compensation `− d̂`; `n` = dof each.
///
/// # Safety
/// `controller` is null or a live handle; each non-null array holds `n` doubles.
#[no_mangle]
pub unsafe extern "C" fn hya_controller_command(
    controller: *mut HyaController,
    q: *const f64,
    qd: *const f64,
    q_des: *const f64,
    qd_des: *const f64,
    qdd_des: *const f64,
    d_hat: *const f64,
    n: usize,
    tau: *mut f64,
) -> HyaStatus {
    // SAFETY: the caller's contract; lengths checked against the controller.
    unsafe {
        on_handle(controller, |c| {
            let dof = c.dof;
            let state = [input("q", q, n, dof)?, input("qd", qd, n, dof)?];
            let reference =
                [input("q_des", q_des, n, dof)?, input("qd_des", qd_des, n, dof)?, input("qdd_des", qdd_des, n, dof)?];
            let d_hat = optional_input("d_hat", d_hat, n, dof)?;
            let tau = command_output(tau, (n, dof), state, reference, d_hat)?;
            Ok(c.controller.command(state, reference, d_hat, tau)?)
        })
    }
}

/// The message of the controller's last failed call (empty if none); owned by the controller.
///
/// # Safety
/// `controller` is null or a live handle.
#[no_mangle]
pub unsafe extern "C" fn hya_controller_error(controller: *const HyaController) -> *const c_char {
    // SAFETY: the caller's contract.
    unsafe { last_message(controller) }
}

/// Frees a controller (null is a no-op).
///
/// # Safety
/// `controller` is null or a handle from `hya_controller_new`, not used afterwards.
#[no_mangle]
pub unsafe extern "C" fn hya_controller_free(controller: *mut HyaController) {
    // SAFETY: the caller's contract.
    unsafe { destroy(controller) }
}
