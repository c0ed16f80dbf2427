//! The Cartesian impedance controller with the paper's compensation, on one frame of a model
//! (`hya_core::CartesianImpedance`):
//!
//! ```text
//! τ = Jᵀ (K_x e − D_x (J q̇ − ẋ_des)) + C(q, q̇) + G(q) − d̂ + P (−K_n (q − q_rest) − D_n q̇)
//! e = (p_des − p, log(R_des Rᵀ))          P = I − Jᵀ (J Jᵀ + μ² I)⁻¹ J
//! ```
//!
//! Poses, twists and the Jacobian are in the base's axes, linear parts first. The frame's
//! kinematics are computed from the model's kinematic tree into buffers made at creation, so
//! a command does not allocate.

use std::ffi::c_char;

use crate::arm_model::CartesianGains;
use crate::model::{borrow_model, text, HyaModel};
use crate::slices::{command_output, input, optional_input};
use crate::status::{create, destroy, last_message, on_handle, Handle, HyaStatus, Message};
use hya_core::erased::SliceCartesian;

/// A Cartesian impedance controller (opaque). Made by `hya_cartesian_new`, freed by
/// `hya_cartesian_free`.
pub struct HyaCartesian {
    controller: Box<dyn SliceCartesian>,
    dof: usize,
    message: Message,
}

impl Handle for HyaCartesian {
    const KIND: &'static str = "HyaCartesian";
    fn message(&mut self) -> &mut Message {
        &mut self.message
    }
    fn message_ref(&self) -> &Message {
        &self.message
    }
}

/// Makes a Cartesian impedance controller on `model`'s dynamics holding frame `frame` (any link
/// of the description; null: the last link) with the spring `stiffness` (6 doubles: N/m for x,
/// y, z, then N·m/rad) and damper `damping` (6: N·s/m, then N·m·s/rad), each finite and
/// non-negative. With `posture_rest`, `posture_stiffness` and `posture_damping` (all three, or
/// all null), the joints are held near the rest pose (rad) in the task's null space (N·m/rad,
/// N·m·s/rad); `mu` (m, finite, ≥ 0; 1e-3 is a fair default) damps the null-space projector near
/// singular poses; unless `torque_limit` is null, joint `i`'s command is saturated to
/// `±torque_limit[i]` N·m (each finite and > 0). The posture and limit arrays hold `n` = dof
/// doubles. A frame the model does not have is `HYA_ERR_INVALID`, the message listing its
/// frames. On `HYA_OK`, `*out` is a new handle for `hya_cartesian_free`; otherwise null, and
/// `hya_last_error` says why.
///
/// # Safety
/// `model` is null or a live handle; `frame` is null or a NUL-terminated string; `stiffness`
/// and `damping` are null or hold 6 doubles; the posture and limit arrays are null or hold `n`
/// doubles; `out` is null or writable.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn hya_cartesian_new(
    model: *const HyaModel,
    frame: *const c_char,
    stiffness: *const f64,
    damping: *const f64,
    posture_rest: *const f64,
    posture_stiffness: *const f64,
    posture_damping: *const f64,
    torque_limit: *const f64,
    n: usize,
    mu: f64,
    out: *mut *mut HyaCartesian,
) -> HyaStatus {
    // SAFETY: the caller's contract, passed on.
    unsafe {
        create(out, || {
            let model = borrow_model(model)?;
            let dof = model.arm.dof();
            let frame = if frame.is_null() { None } else { Some(text("frame", frame)?) };
            let gains = CartesianGains {
                stiffness: input("stiffness", stiffness, 6, 6)?,
                damping: input("damping", damping, 6, 6)?,
                posture: [
                    optional_input("posture_rest", posture_rest, n, dof)?,
                    optional_input("posture_stiffness", posture_stiffness, n, dof)?,
                    optional_input("posture_damping", posture_damping, n, dof)?,
                ],
                regularisation: mu,
                torque_limit: optional_input("torque_limit", torque_limit, n, dof)?,
            };
            let controller = model.arm.cartesian(&model.tree, frame, gains)?;
            Ok(HyaCartesian { controller, dof, message: Message::default() })
        })
    }
}

/// The commanded torque `tau` (`n` = dof) at the measured `(q, qd)` for the frame's desired
/// position `position_des` (3 doubles, m), orientation `orientation_des` (9 doubles: the 3 × 3
/// rotation row-major, whose columns are the frame's desired axes in the base's) and twist
/// `twist_des` (6 doubles: m/s, then rad/s; null: at rest) and, unless `d_hat` is null, the
/// compensation `− d̂`. An orientation that is not a rotation is `HYA_ERR_INVALID`.
///
/// # Safety
/// `controller` is null or a live handle; `q`, `qd`, `d_hat` are null or hold `n` doubles, the
/// reference arrays 3, 9 and 6.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn hya_cartesian_command(
    controller: *mut HyaCartesian,
    q: *const f64,
    qd: *const f64,
    position_des: *const f64,
    orientation_des: *const f64,
    twist_des: *const f64,
    d_hat: *const f64,
    n: usize,
    tau: *mut f64,
) -> HyaStatus {
    // SAFETY: the caller's contract; lengths checked against the controller.
    unsafe {
        on_handle(controller, |c| {
            let dof = c.dof;
            let state = [input("q", q, n, dof)?, input("qd", qd, n, dof)?];
            let at_rest = [0.0; 6];
            let reference = [
                input("position_des", position_des, 3, 3)?,
                input("orientation_des", orientation_des, 9, 9)?,
                optional_input("twist_des", twist_des, 6, 6)?.unwrap_or(&at_rest),
            ];
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
pub unsafe extern "C" fn hya_cartesian_error(controller: *const HyaCartesian) -> *const c_char {
    // SAFETY: the caller's contract.
    unsafe { last_message(controller) }
}

/// Frees a Cartesian controller (null is a no-op).
///
/// # Safety
/// `controller` is null or a handle from `hya_cartesian_new`, not used afterwards.
#[no_mangle]
pub unsafe extern "C" fn hya_cartesian_free(controller: *mut HyaCartesian) {
    // SAFETY: the caller's contract.
    unsafe { destroy(controller) }
}
