//! Models: a shipped arm's generated dynamics by name, or any URDF through the run-time model;
//! inverse dynamics, mass matrix, gravity and forward dynamics on them.

use std::ffi::{c_char, CStr};

use crate::arm_model::{self, ArmModel};
use crate::slices::{input, output, outputs};
use crate::status::{borrow_live, create, destroy, last_message, on_handle, Failure, Handle, HyaStatus, Message};
use hya_core::model::TreeModel;

/// A robot's rigid-body dynamics (opaque). Made by `hya_model_from_arm` or
/// `hya_model_from_urdf`, freed by `hya_model_free`.
pub struct HyaModel {
    pub(crate) arm: Box<dyn ArmModel>,
    /// The run-time kinematic tree, for frame kinematics (a shipped arm's too).
    pub(crate) tree: TreeModel,
    message: Message,
}

impl Handle for HyaModel {
    const KIND: &'static str = "HyaModel";
    fn message(&mut self) -> &mut Message {
        &mut self.message
    }
    fn message_ref(&self) -> &Message {
        &self.message
    }
}

impl HyaModel {
    fn new(arm: Box<dyn ArmModel>, tree: TreeModel) -> Self {
        Self { arm, tree, message: Message::default() }
    }
}

/// A C string argument as UTF-8.
///
/// # Safety
/// `ptr` is null or a NUL-terminated string.
pub(crate) unsafe fn text<'a>(name: &'static str, ptr: *const c_char) -> Result<&'a str, Failure> {
    if ptr.is_null() {
        return Err(Failure::Null(name));
    }
    // SAFETY: non-null and NUL-terminated by the caller's contract.
    unsafe { CStr::from_ptr(ptr) }.to_str().map_err(|_| Failure::NotUtf8(name))
}

/// The model behind a creation call's `model` argument.
///
/// # Safety
/// `model` is null or a live handle from this library.
pub(crate) unsafe fn borrow<'a>(model: *const HyaModel) -> Result<&'a dyn ArmModel, Failure> {
    // SAFETY: the caller's contract.
    unsafe { borrow_model(model) }.map(|m| &*m.arm)
}

/// The whole model behind a creation call's `model` argument (its kinematic tree too).
///
/// # Safety
/// `model` is null or a live handle from this library.
pub(crate) unsafe fn borrow_model<'a>(model: *const HyaModel) -> Result<&'a HyaModel, Failure> {
    // SAFETY: the caller's contract.
    unsafe { borrow_live("model", model) }
}

/// Makes a model of the shipped arm called `name` (`"hya"`, `"ur5"`, `"panda"`, `"iiwa14"`,
/// `"planar2"`; see `hya_arm_name`): its generated, unrolled dynamics. On `HYA_OK`, `*out` is a
/// new handle for `hya_model_free`; otherwise `*out` is null and `hya_last_error` says why.
///
/// # Safety
/// `name` is null or a NUL-terminated string; `out` is null or writable.
#[no_mangle]
pub unsafe extern "C" fn hya_model_from_arm(name: *const c_char, out: *mut *mut HyaModel) -> HyaStatus {
    // SAFETY: the caller's contract, passed on.
    unsafe {
        create(out, || {
            let name = text("name", name)?;
            let robot = hya_robots::find(name).ok_or_else(|| Failure::UnknownArm(name.to_owned()))?;
            let tree = hya_urdf::load_str(robot.urdf, robot.name).map_err(Failure::Load)?.model;
            Ok(HyaModel::new(arm_model::shipped(name)?, tree))
        })
    }
}

/// Loads the URDF file at `path` as a run-time kinematic-tree model (1 to 7 joints). On `HYA_OK`,
/// `*out` is a new handle for `hya_model_free`; otherwise `*out` is null and `hya_last_error`
/// names the file and the problem in it.
///
/// # Safety
/// `path` is null or a NUL-terminated string; `out` is null or writable.
#[no_mangle]
pub unsafe extern "C" fn hya_model_from_urdf(path: *const c_char, out: *mut *mut HyaModel) -> HyaStatus {
    // SAFETY: the caller's contract, passed on.
    unsafe {
        create(out, || {
            let loaded = hya_urdf::load_file(text("path", path)?).map_err(Failure::Load)?;
            Ok(HyaModel::new(arm_model::tree(loaded.model.clone())?, loaded.model))
        })
    }
}

/// Makes a new model: `model` with the joint law that `hya identify` wrote to the file at `path`
/// (`friction.toml`: Coulomb, viscous and offset per joint, and the armature `I_a` where it has
/// one). Its inverse dynamics is `ID(q, q̇, q̈) + τ_f(q̇) + I_a q̈` and its mass matrix
/// `M(q) + diag(I_a)`, so estimators made from it estimate what the law leaves unexplained, as
/// `hya estimate --friction` does, and controllers made from it feed the law forward at the
/// measured velocity. `model` is unchanged. On `HYA_OK`, `*out` is a new handle for
/// `hya_model_free`; otherwise `*out` is null and `hya_last_error` names the file, the key and
/// the value (a list of the wrong length for this model's joints, a value out of its plausible
/// range).
///
/// # Safety
/// `model` is null or a live handle; `path` is null or a NUL-terminated string; `out` is null or
/// writable.
#[no_mangle]
pub unsafe extern "C" fn hya_model_with_friction(
    model: *const HyaModel,
    path: *const c_char,
    out: *mut *mut HyaModel,
) -> HyaStatus {
    // SAFETY: the caller's contract, passed on.
    unsafe {
        create(out, || {
            // SAFETY: the caller's contract.
            let model = borrow_live("model", model)?;
            let path = std::path::Path::new(text("path", path)?);
            let friction = hya_ident::JointFriction::from_file(path, model.arm.dof()).map_err(Failure::Friction)?;
            Ok(HyaModel::new(model.arm.with_friction(friction), model.tree.clone()))
        })
    }
}

/// Frees a model (null is a no-op). Estimators, observers and controllers made from it stay
/// valid.
///
/// # Safety
/// `model` is null or a handle from `hya_model_from_*`, not used afterwards.
#[no_mangle]
pub unsafe extern "C" fn hya_model_free(model: *mut HyaModel) {
    // SAFETY: the caller's contract.
    unsafe { destroy(model) }
}

/// The model's joint count, or 0 for a null handle.
///
/// # Safety
/// `model` is null or a live handle.
#[no_mangle]
pub unsafe extern "C" fn hya_model_dof(model: *const HyaModel) -> usize {
    // SAFETY: the caller's contract.
    unsafe { borrow(model) }.map_or(0, |arm| arm.dof())
}

/// The message of the model's last failed call (empty if none); owned by the model.
///
/// # Safety
/// `model` is null or a live handle.
#[no_mangle]
pub unsafe extern "C" fn hya_model_error(model: *const HyaModel) -> *const c_char {
    // SAFETY: the caller's contract.
    unsafe { last_message(model) }
}

/// Runs `work` with the model's joint count, checking the handle.
pub(crate) unsafe fn on_model(
    model: *mut HyaModel,
    work: impl FnOnce(&dyn ArmModel, usize) -> Result<(), Failure>,
) -> HyaStatus {
    // SAFETY: the caller's contract.
    unsafe { on_handle(model, |m| work(&*m.arm, m.arm.dof())) }
}

/// Inverse dynamics `τ = M(q) q̈ + C(q, q̇) + G(q)`; every array has `n` = dof entries.
/// `HYA_ERR_NUMERIC` if a torque is not finite (inputs too large for double precision).
///
/// # Safety
/// `model` is null or a live handle; each non-null array holds `n` doubles.
#[no_mangle]
pub unsafe extern "C" fn hya_model_inverse_dynamics(
    model: *mut HyaModel,
    q: *const f64,
    qd: *const f64,
    qdd: *const f64,
    n: usize,
    tau: *mut f64,
) -> HyaStatus {
    // SAFETY: the caller's contract; lengths checked against the model.
    unsafe {
        on_model(model, |arm, dof| {
            let (q, qd, qdd) = (input("q", q, n, dof)?, input("qd", qd, n, dof)?, input("qdd", qdd, n, dof)?);
            let tau = output("tau", tau, n, dof, &[q, qd, qdd])?;
            arm.slices().inverse_dynamics_into(q, qd, qdd, tau);
            Ok(hya_core::finite_result("tau", tau)?)
        })
    }
}

/// The mass matrix `M(q)`: `q` has `n` = dof entries, `mass` has `len` = dof² (symmetric, so
/// row- and column-major agree).
///
/// # Safety
/// `model` is null or a live handle; `q` holds `n` doubles and `mass` `len`.
#[no_mangle]
pub unsafe extern "C" fn hya_model_mass_matrix(
    model: *mut HyaModel,
    q: *const f64,
    n: usize,
    mass: *mut f64,
    len: usize,
) -> HyaStatus {
    // SAFETY: the caller's contract; lengths checked against the model.
    unsafe {
        on_model(model, |arm, dof| {
            let q = input("q", q, n, dof)?;
            let mass = output("mass", mass, len, dof * dof, &[q])?;
            arm.slices().mass_matrix_into(q, mass);
            Ok(hya_core::finite_result("mass", mass)?)
        })
    }
}

/// The gravity torque `G(q)`; both arrays have `n` = dof entries.
///
/// # Safety
/// `model` is null or a live handle; each non-null array holds `n` doubles.
#[no_mangle]
pub unsafe extern "C" fn hya_model_gravity(model: *mut HyaModel, q: *const f64, n: usize, tau: *mut f64) -> HyaStatus {
    // SAFETY: the caller's contract; lengths checked against the model.
    unsafe {
        on_model(model, |arm, dof| {
            let q = input("q", q, n, dof)?;
            let tau = output("tau", tau, n, dof, &[q])?;
            arm.slices().gravity_into(q, tau);
            Ok(hya_core::finite_result("tau", tau)?)
        })
    }
}

/// Forward dynamics `q̈ = M(q)⁻¹ (τ − C(q, q̇) − G(q))`; every array has `n` = dof entries.
/// `HYA_ERR_NUMERIC` if `M(q)` is not positive definite.
///
/// # Safety
/// `model` is null or a live handle; each non-null array holds `n` doubles.
#[no_mangle]
pub unsafe extern "C" fn hya_model_forward_dynamics(
    model: *mut HyaModel,
    q: *const f64,
    qd: *const f64,
    tau: *const f64,
    n: usize,
    qdd: *mut f64,
) -> HyaStatus {
    // SAFETY: the caller's contract; lengths checked against the model.
    unsafe {
        on_model(model, |arm, dof| {
            let (q, qd, tau) = (input("q", q, n, dof)?, input("qd", qd, n, dof)?, input("tau", tau, n, dof)?);
            let qdd = output("qdd", qdd, n, dof, &[q, qd, tau])?;
            arm.slices().forward_dynamics_into(q, qd, tau, qdd)?;
            Ok(hya_core::finite_result("qdd", qdd)?)
        })
    }
}

/// `(∂q̈/∂q, ∂q̈/∂q̇, M⁻¹)` of forward dynamics at `(q, q̇, τ)`: `q`, `qd`, `tau` have `n` = dof
/// entries, `dqdd_dq`, `dqdd_dqd` and `mass_inverse` `len` = dof² each, row-major (row `i` is
/// `∂q̈_i`): `−M⁻¹ ∂ID/∂q` and `−M⁻¹ ∂ID/∂q̇` at `q̈ = FD(q, q̇, τ)`, and `M⁻¹ = ∂q̈/∂τ`.
/// `HYA_ERR_NUMERIC` if `M(q)` is not positive definite.
///
/// The three outputs must lie apart from each other and from the inputs (`HYA_ERR_INVALID` if
/// two share an address). Allocates on a URDF model (run-time code).
///
/// # Safety
/// `model` is null or a live handle; `q`, `qd`, `tau` hold `n` doubles and each output `len`.
#[no_mangle]
pub unsafe extern "C" fn hya_model_forward_dynamics_derivatives(
    model: *mut HyaModel,
    q: *const f64,
    qd: *const f64,
    tau: *const f64,
    n: usize,
    dqdd_dq: *mut f64,
    dqdd_dqd: *mut f64,
    mass_inverse: *mut f64,
    len: usize,
) -> HyaStatus {
    // SAFETY: the caller's contract; lengths checked against the model.
    unsafe {
        on_model(model, |arm, dof| {
            let (q, qd, tau) = (input("q", q, n, dof)?, input("qd", qd, n, dof)?, input("tau", tau, n, dof)?);
            let named = [("dqdd_dq", dqdd_dq), ("dqdd_dqd", dqdd_dqd), ("mass_inverse", mass_inverse)];
            let [by_q, by_qd, inverse] = outputs(named, len, dof * dof, &[q, qd, tau])?;
            arm.slices().forward_dynamics_derivatives_into(q, qd, tau, [&mut *by_q, &mut *by_qd, &mut *inverse])?;
            for (name, values) in [("dqdd_dq", &*by_q), ("dqdd_dqd", &*by_qd), ("mass_inverse", &*inverse)] {
                hya_core::finite_result(name, values)?;
            }
            Ok(())
        })
    }
}

/// The geometric Jacobian of frame `frame` (any link of the description) at `q` (`n` = dof):
/// `jacobian` holds `len` = 6 × dof doubles, row-major, rows 0–2 mapping `q̇` to the linear
/// velocity of the frame's origin and rows 3–5 to its angular velocity, both in the base's axes
/// (Pinocchio's `LOCAL_WORLD_ALIGNED`). `HYA_ERR_INVALID` for a frame the model does not have
/// (the message lists its frames). Allocates (run-time code).
///
/// # Safety
/// `model` is null or a live handle; `frame` is null or a NUL-terminated string; `q` holds `n`
/// doubles and `jacobian` `len`.
#[no_mangle]
pub unsafe extern "C" fn hya_model_frame_jacobian(
    model: *mut HyaModel,
    frame: *const c_char,
    q: *const f64,
    n: usize,
    jacobian: *mut f64,
    len: usize,
) -> HyaStatus {
    // SAFETY: the caller's contract; lengths checked against the model.
    unsafe {
        on_handle(model, |m| {
            let (frame, dof) = (text("frame", frame)?, m.tree.dof());
            let q = input("q", q, n, dof)?;
            // Found before the output is made a slice: `frame` is the caller's memory too.
            let found = m.tree.frame_jacobian(frame, q).map_err(Failure::Model)?;
            let out = output("jacobian", jacobian, len, 6 * dof, &[q])?;
            // Row-major: the transpose's column-major storage.
            out.copy_from_slice(found.transpose().as_slice());
            Ok(hya_core::finite_result("jacobian", out)?)
        })
    }
}

/// `J̇(q, q̇) q̇` of frame `frame`: `bias` holds 6 doubles, the classical acceleration of the
/// frame's origin (m/s²) and its angular acceleration (rad/s²) at `q̈ = 0`, in the base's axes
/// (`q` and `qd` have `n` = dof entries). `HYA_ERR_INVALID` for a frame the model does not have
/// (the message lists its frames). Allocates (run-time code).
///
/// # Safety
/// `model` is null or a live handle; `frame` is null or a NUL-terminated string; `q` and `qd`
/// hold `n` doubles and `bias` `len`.
#[no_mangle]
pub unsafe extern "C" fn hya_model_frame_acceleration_bias(
    model: *mut HyaModel,
    frame: *const c_char,
    q: *const f64,
    qd: *const f64,
    n: usize,
    bias: *mut f64,
    len: usize,
) -> HyaStatus {
    // SAFETY: the caller's contract; lengths checked against the model.
    unsafe {
        on_handle(model, |m| {
            let (frame, dof) = (text("frame", frame)?, m.tree.dof());
            let (q, qd) = (input("q", q, n, dof)?, input("qd", qd, n, dof)?);
            // Found before the output is made a slice: `frame` is the caller's memory too.
            let found = m.tree.frame_acceleration_bias(frame, q, qd).map_err(Failure::Model)?;
            let out = output("bias", bias, len, 6, &[q, qd])?;
            out.copy_from_slice(&found);
            Ok(hya_core::finite_result("bias", out)?)
        })
    }
}

/// The number of shipped arms (for `hya_arm_name`).
#[no_mangle]
pub extern "C" fn hya_arm_count() -> usize {
    hya_robots::ROBOTS.len()
}

/// The name of shipped arm `index` (a static string), or null beyond `hya_arm_count()`.
#[no_mangle]
pub extern "C" fn hya_arm_name(index: usize) -> *const c_char {
    static NAMES: std::sync::OnceLock<Vec<std::ffi::CString>> = std::sync::OnceLock::new();
    let names =
        NAMES.get_or_init(|| hya_robots::ROBOTS.iter().filter_map(|r| std::ffi::CString::new(r.name).ok()).collect());
    names.get(index).map_or(core::ptr::null(), |name| name.as_ptr())
}

/// The home pose of the shipped arm called `name` (rad, `n` = its joint count): a pose inside its
/// joint limits, where the examples start.
///
/// # Safety
/// `name` is null or a NUL-terminated string; `q` is null or holds `n` doubles.
#[no_mangle]
pub unsafe extern "C" fn hya_arm_home(name: *const c_char, q: *mut f64, n: usize) -> HyaStatus {
    let home = || {
        // SAFETY: the caller's contract.
        let name = unsafe { text("name", name) }?;
        let robot = hya_robots::find(name).ok_or_else(|| Failure::UnknownArm(name.to_owned()))?;
        // SAFETY: the caller's contract; length checked against the arm.
        unsafe { output("q", q, n, robot.dof, &[]) }?.copy_from_slice(robot.home);
        Ok(())
    };
    match crate::status::guarded(home) {
        Ok(()) => HyaStatus::HyaOk,
        Err(failure) => crate::status::fail_globally(&failure),
    }
}

/// This thread's last error: the message of the last failed creation, or of a call given a
/// null handle. Owned by hya; valid until the next hya call on this thread.
#[no_mangle]
pub extern "C" fn hya_last_error() -> *const c_char {
    crate::status::last_error_ptr()
}
