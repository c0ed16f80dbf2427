//! # hya-capi
//!
//! hya from C and C++: the header `include/hya.h` (generated from this crate by cbindgen and
//! checked against it by `tests/header.rs`) declares everything below.
//!
//! - Models: a shipped arm's generated code by name ([`hya_model_from_arm`]) or any URDF through
//!   the run-time kinematic tree ([`hya_model_from_urdf`]); inverse dynamics, mass matrix,
//!   gravity, forward dynamics and its derivatives, one state per call or many
//!   ([`hya_model_inverse_dynamics_batch`] and its siblings: a shipped arm's SIMD batches).
//! - The paper's disturbance estimator ([`hya_estimator_new`], [`hya_estimator_update`]).
//! - The observers it is compared against ([`hya_observer_new_nonlinear`],
//!   [`hya_observer_new_momentum`], [`hya_observer_new_extended_state`]).
//! - Computed-torque control ([`hya_controller_new`], [`hya_controller_command`]).
//! - Cartesian impedance control on a frame ([`hya_cartesian_new`], [`hya_cartesian_command`]).
//!
//! The joint count is known only at run time: each creation dispatches once to the
//! const-generic code for that count and keeps it as a boxed trait object, so calls after
//! creation neither allocate nor dispatch on the count. Every call returns an [`HyaStatus`];
//! messages are kept in fixed buffers per handle (and per thread for creation failures), panics
//! are caught at the boundary, and null pointers, wrong lengths and non-finite inputs are
//! errors.

mod arm_model;
mod batch;
mod cartesian;
mod controller;
mod estimator;
mod model;
mod observer;
mod slices;
mod status;

pub use batch::*;
pub use cartesian::*;
pub use controller::*;
pub use estimator::*;
pub use model::*;
pub use observer::*;
pub use status::{HyaStatus, HYA_MESSAGE_CAPACITY};
