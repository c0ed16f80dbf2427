//! From a number of joints known at run time (a loaded URDF, a log's width) to the constant `N`
//! that [`Dynamics<N>`](crate::Dynamics) and everything generic over it need.
//!
//! ```
//! use hya_core::dispatch::{with_joints, ForJoints};
//! struct Width;
//! impl ForJoints for Width {
//!     type Output = usize;
//!     fn call<const N: usize>(self) -> usize {
//!         hya_core::JointVector::<N>::zeros().len()
//!     }
//! }
//! assert_eq!(with_joints(6, Width), Some(6));
//! assert_eq!(with_joints(9, Width), None);
//! ```

/// The most joints [`with_joints`] dispatches to (every arm hya ships has at most 7; each size
/// up to this is compiled once into every caller).
pub const MAX_JOINTS: usize = 7;

/// Something to do with an arm of `N` joints, `N` known only at run time ([`with_joints`]).
pub trait ForJoints {
    /// What it gives.
    type Output;
    /// Does it for `N` joints.
    fn call<const N: usize>(self) -> Self::Output;
}

/// Calls `f` with `N = dof`, for 1 to [`MAX_JOINTS`] joints; `None` for any other `dof`.
pub fn with_joints<F: ForJoints>(dof: usize, f: F) -> Option<F::Output> {
    Some(match dof {
        1 => f.call::<1>(),
        2 => f.call::<2>(),
        3 => f.call::<3>(),
        4 => f.call::<4>(),
        5 => f.call::<5>(),
        6 => f.call::<6>(),
        7 => f.call::<7>(),
        _ => return None,
    })
}
