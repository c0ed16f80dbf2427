//! The kinematics of one frame of an arm, as a task-space controller reads them at every tick:
//! its pose, its geometric Jacobian `J(q)` and the classical acceleration bias `J̇(q, q̇) q̇`, in
//! base coordinates with linear rows first (Pinocchio's `LOCAL_WORLD_ALIGNED`), so that the
//! frame's origin moves at `v = J_v q̇`, turns at `ω = J_ω q̇` and accelerates at `J q̈ + J̇ q̇`.
//!
//! Generated code implements [`FrameKinematics`] for each arm's last link
//! (`TreeModel::tip_frame`), unrolled and allocation-free; the run-time model gives the same
//! for any frame by name (`TreeModel::frame_jacobian`, `TreeModel::frame_acceleration_bias`).

use nalgebra::{SMatrix, Vector6};

use crate::dynamics::check_batch;
use crate::rigid_body::spatial::Transform;
use crate::{Error, JointVector};

/// A frame's geometric Jacobian: 6 × `N`, rows `(v_x, v_y, v_z, ω_x, ω_y, ω_z)`.
pub type FrameJacobian<const N: usize> = SMatrix<f64, 6, N>;

/// Six components of a frame's motion, linear then angular (as [`FrameJacobian`]'s rows).
pub type FrameVector = Vector6<f64>;

/// Pose, Jacobian and acceleration bias of one frame of an arm with `N` joints (see the
/// module's notes).
pub trait FrameKinematics<const N: usize> {
    /// The frame's name (a link of the description).
    fn frame_name(&self) -> &'static str;

    /// The frame's pose in the base at `q`, as the transform from the base to the frame (its
    /// `translation` is the frame's origin, its `orientation()` the frame's axes).
    fn frame_pose(&self, q: &JointVector<N>) -> Transform;

    /// `J(q)`: rows 0..3 map `q̇` to the velocity of the frame's origin, rows 3..6 to its angular
    /// velocity, both in base coordinates.
    fn frame_jacobian(&self, q: &JointVector<N>) -> FrameJacobian<N>;

    /// `J̇(q, q̇) q̇`: the classical acceleration of the frame's origin (first three) and its
    /// angular acceleration (last three) at `q̈ = 0`, in base coordinates.
    fn frame_acceleration_bias(&self, q: &JointVector<N>, qd: &JointVector<N>) -> FrameVector;

    /// [`frame_jacobian`](Self::frame_jacobian) of every state of `q` (as long as `jacobian`),
    /// into `jacobian`; generated code runs several states per vector register.
    fn frame_jacobian_batch(&self, q: &[JointVector<N>], jacobian: &mut [FrameJacobian<N>]) -> Result<(), Error> {
        check_batch(&[q.len()], jacobian.len())?;
        for (q, out) in q.iter().zip(jacobian) {
            *out = self.frame_jacobian(q);
        }
        Ok(())
    }

    /// [`frame_acceleration_bias`](Self::frame_acceleration_bias) of every state, into `bias`
    /// (all three as long).
    fn frame_acceleration_bias_batch(
        &self,
        q: &[JointVector<N>],
        qd: &[JointVector<N>],
        bias: &mut [FrameVector],
    ) -> Result<(), Error> {
        check_batch(&[q.len(), qd.len()], bias.len())?;
        for ((q, qd), out) in q.iter().zip(qd).zip(bias) {
            *out = self.frame_acceleration_bias(q, qd);
        }
        Ok(())
    }
}
