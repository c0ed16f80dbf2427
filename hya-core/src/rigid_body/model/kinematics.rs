//! Frame kinematics of a [`TreeModel`]: a named frame's pose, its geometric Jacobian and the
//! classical acceleration `J̇ q̇` of its origin, all in base coordinates (Pinocchio's
//! `LOCAL_WORLD_ALIGNED`: the frame's origin, the base's axes), or in the frame's own axes.
//!
//! For body `j` with parent `p`, joint axis `z_j` (base coordinates) and origin `p_j` on it,
//! `r = p_j − p_p`, the bias pass (`q̈ = 0`) is
//!
//! ```text
//! revolute:   ω_j = ω_p + z_j q̇_j    α_j = α_p + ω_p × z_j q̇_j    a_j = a_p + α_p × r + ω_p × (ω_p × r)
//! prismatic:  ω_j = ω_p              α_j = α_p                    a_j = … + 2 ω_p × z_j q̇_j
//! ```
//!
//! and a frame at `o` on body `b` has `J̇ q̇ = (a_b + α_b × (o − p_b) + ω_b × (ω_b × (o − p_b)), α_b)`:
//! the classical (not spatial) acceleration, what a point of the tool does when `q̈ = 0`.

use alloc::vec;

use nalgebra::{DMatrix, Vector3};

use super::algorithms::check_len;
use super::{Frame, JointKind, ModelError, TreeModel};
use crate::rigid_body::spatial::Transform;

impl TreeModel {
    /// The frame called `name` (every link of the description); an error listing the model's
    /// frames otherwise, which every front end passes on.
    pub fn frame(&self, name: &str) -> Result<&Frame, ModelError> {
        self.frames.iter().find(|f| f.name == name).ok_or_else(|| {
            let frames: alloc::vec::Vec<&str> = self.frames.iter().map(|f| f.name.as_str()).collect();
            ModelError::UnknownFrame { name: name.into(), frames: frames.join(", ") }
        })
    }

    /// Pose of the named frame in the base at `q`: as a transform from base to frame, so its
    /// [`orientation`](Transform::orientation) and `translation` are the frame's axes and origin.
    pub fn frame_pose(&self, frame: &str, q: &[f64]) -> Result<Transform, ModelError> {
        let placements = self.body_placements(q)?;
        let frame = self.frame(frame)?;
        let body = frame.body.map_or(Transform::identity(), |b| placements[b]);
        Ok(body.then(&frame.placement))
    }

    /// Geometric Jacobian of the named frame at `q`, in base coordinates: rows 0..3 map `q̇` to
    /// the linear velocity of the frame's origin, rows 3..6 to its angular velocity.
    pub fn frame_jacobian(&self, frame: &str, q: &[f64]) -> Result<DMatrix<f64>, ModelError> {
        let placements = self.body_placements(q)?;
        let target = self.frame(frame)?;
        let origin = target.body.map_or(Transform::identity(), |b| placements[b]).then(&target.placement).translation;
        let mut jacobian = DMatrix::zeros(6, self.dof());
        let mut next = target.body;
        while let Some(j) = next {
            let axis = placements[j].orientation() * self.bodies[j].axis;
            let (linear, angular) = match self.bodies[j].kind {
                JointKind::Revolute => (axis.cross(&(origin - placements[j].translation)), axis),
                JointKind::Prismatic => (axis, Vector3::zeros()),
            };
            jacobian.fixed_view_mut::<3, 1>(0, j).copy_from(&linear);
            jacobian.fixed_view_mut::<3, 1>(3, j).copy_from(&angular);
            next = self.bodies[j].parent;
        }
        Ok(jacobian)
    }

    /// The Jacobian of [`frame_jacobian`](Self::frame_jacobian) in the frame's own axes
    /// (Pinocchio's `LOCAL`): both halves rotated by the frame's orientation `Rᵀ`.
    pub fn frame_jacobian_local(&self, frame: &str, q: &[f64]) -> Result<DMatrix<f64>, ModelError> {
        let to_local = self.frame_pose(frame, q)?.orientation().transpose();
        let mut jacobian = self.frame_jacobian(frame, q)?;
        for j in 0..self.dof() {
            for half in [0, 3] {
                let column: Vector3<f64> = jacobian.fixed_view::<3, 1>(half, j).into_owned();
                jacobian.fixed_view_mut::<3, 1>(half, j).copy_from(&(to_local * column));
            }
        }
        Ok(jacobian)
    }

    /// `J̇(q, q̇) q̇` of the named frame: the classical acceleration of its origin (linear, first
    /// three) and its angular acceleration (last three) at `q̈ = 0`, in base coordinates, so that
    /// the frame's acceleration is `J q̈ + J̇ q̇` (see the module's notes).
    pub fn frame_acceleration_bias(&self, frame: &str, q: &[f64], qd: &[f64]) -> Result<[f64; 6], ModelError> {
        check_len(self, "joint velocities", qd)?;
        let placements = self.body_placements(q)?;
        let target = self.frame(frame)?;
        let Some(body) = target.body else {
            return Ok([0.0; 6]);
        };
        // Per body, in base coordinates: angular velocity, angular acceleration, and the classical
        // acceleration of its origin. Parents come before their children.
        let n = self.dof();
        let (mut omega, mut alpha, mut accel) =
            (vec![Vector3::zeros(); n], vec![Vector3::zeros(); n], vec![Vector3::zeros(); n]);
        for j in 0..n {
            let (w, dw, a, origin) = match self.bodies[j].parent {
                Some(p) => (omega[p], alpha[p], accel[p], placements[p].translation),
                None => (Vector3::zeros(), Vector3::zeros(), Vector3::zeros(), Vector3::zeros()),
            };
            let r = placements[j].translation - origin;
            let axis = placements[j].orientation() * self.bodies[j].axis;
            let carried = a + dw.cross(&r) + w.cross(&w.cross(&r));
            (omega[j], alpha[j], accel[j]) = match self.bodies[j].kind {
                JointKind::Revolute => (w + axis * qd[j], dw + w.cross(&axis) * qd[j], carried),
                JointKind::Prismatic => (w, dw, carried + w.cross(&axis) * (2.0 * qd[j])),
            };
        }
        let r = placements[body].then(&target.placement).translation - placements[body].translation;
        let (w, dw) = (omega[body], alpha[body]);
        let linear = accel[body] + dw.cross(&r) + w.cross(&w.cross(&r));
        Ok([linear.x, linear.y, linear.z, dw.x, dw.y, dw.z])
    }
}
