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
//!
//! Both are written once over any [`Real`] ([`frame_jacobian`], [`frame_acceleration_bias`]):
//! the run-time model runs them on `f64`, and the generator traces them into each arm's code for
//! its last link ([`TreeModel::tip_frame`]).

use alloc::vec;
use alloc::vec::Vec;

use nalgebra::{DMatrix, Vector3};

use super::algorithms::check_len;
use super::{Frame, JointKind, ModelError, TreeModel};
use crate::rigid_body::scalar::Real;
use crate::rigid_body::spatial::vector::{add3, cross, mat_tr_vec, scale3, sub3};
use crate::rigid_body::spatial::{constant_vector, zero_vector, Transform};

/// `frame`'s pose in the base: its body's placement (the base's for a frame on the base) then
/// the frame's own. `placements` are the bodies' ([`super::algorithms::body_placements`]).
pub fn frame_placement<S: Real>(frame: &Frame, placements: &[Transform<S>]) -> Transform<S> {
    let body = frame.body.map_or_else(Transform::identity, |b| placements[b]);
    body.then(&Transform::constant(&frame.placement))
}

/// Geometric Jacobian of `frame` in base coordinates (see the module's notes) into `jacobian`,
/// 6 × n row-major: rows 0..3 map `q̇` to the linear velocity of the frame's origin, rows 3..6
/// to its angular velocity. `placements` are the bodies' ([`super::algorithms::body_placements`]).
pub fn frame_jacobian<S: Real>(
    model: &TreeModel,
    frame: &Frame,
    placements: &[Transform<S>],
    jacobian: &mut [S],
) -> Result<(), ModelError> {
    let n = model.dof();
    check_len(model, "placements", placements)?;
    if jacobian.len() != 6 * n {
        return Err(ModelError::Dimension {
            what: "jacobian (6 rows per joint)",
            expected: 6 * n,
            got: jacobian.len(),
        });
    }
    jacobian.fill(S::zero());
    let Some(body) = frame.body else { return Ok(()) };
    let origin = frame_placement(frame, placements).translation;
    let mut next = Some(body);
    while let Some(j) = next {
        let joint = &model.bodies()[j];
        let axis = mat_tr_vec(&placements[j].rotation, &constant_vector(&joint.axis));
        let (linear, angular) = match joint.kind {
            JointKind::Revolute => (cross(&axis, &sub3(&origin, &placements[j].translation)), axis),
            JointKind::Prismatic => (axis, zero_vector()),
        };
        for r in 0..3 {
            jacobian[r * n + j] = linear[r];
            jacobian[(r + 3) * n + j] = angular[r];
        }
        next = joint.parent;
    }
    Ok(())
}

/// `J̇(q, q̇) q̇` of `frame` (see the module's notes): the classical acceleration of its origin
/// (linear, first three) and its angular acceleration at `q̈ = 0`, in base coordinates.
/// `placements` are the bodies' at `q`.
pub fn frame_acceleration_bias<S: Real>(
    model: &TreeModel,
    frame: &Frame,
    placements: &[Transform<S>],
    qd: &[S],
) -> Result<[S; 6], ModelError> {
    check_len(model, "placements", placements)?;
    check_len(model, "joint velocities", qd)?;
    let Some(body) = frame.body else { return Ok([S::zero(); 6]) };
    // Per body, in base coordinates: angular velocity, angular acceleration, and the classical
    // acceleration of its origin. Parents come before their children.
    let n = model.dof();
    let zeros = || -> Vec<Vector3<S>> { vec![zero_vector(); n] };
    let (mut omega, mut alpha, mut accel) = (zeros(), zeros(), zeros());
    for (j, joint) in model.bodies().iter().enumerate() {
        let (w, dw, a, origin) = match joint.parent {
            Some(p) => (omega[p], alpha[p], accel[p], placements[p].translation),
            None => (zero_vector(), zero_vector(), zero_vector(), zero_vector()),
        };
        let r = sub3(&placements[j].translation, &origin);
        let axis = mat_tr_vec(&placements[j].rotation, &constant_vector(&joint.axis));
        let carried = add3(&add3(&a, &cross(&dw, &r)), &cross(&w, &cross(&w, &r)));
        (omega[j], alpha[j], accel[j]) = match joint.kind {
            JointKind::Revolute => {
                (add3(&w, &scale3(&axis, qd[j])), add3(&dw, &scale3(&cross(&w, &axis), qd[j])), carried)
            }
            JointKind::Prismatic => {
                let coriolis = scale3(&cross(&w, &axis), qd[j] + qd[j]);
                (w, dw, add3(&carried, &coriolis))
            }
        };
    }
    let r = sub3(&frame_placement(frame, placements).translation, &placements[body].translation);
    let (w, dw) = (omega[body], alpha[body]);
    let linear = add3(&add3(&accel[body], &cross(&dw, &r)), &cross(&w, &cross(&w, &r)));
    Ok([linear[0], linear[1], linear[2], dw[0], dw[1], dw[2]])
}

impl TreeModel {
    /// The frame called `name` (every link of the description); an error listing the model's
    /// frames otherwise, which every front end passes on.
    pub fn frame(&self, name: &str) -> Result<&Frame, ModelError> {
        self.frames.iter().find(|f| f.name == name).ok_or_else(|| {
            let frames: alloc::vec::Vec<&str> = self.frames.iter().map(|f| f.name.as_str()).collect();
            ModelError::UnknownFrame { name: name.into(), frames: frames.join(", ") }
        })
    }

    /// The description's last link: the frame a command takes when none is named, and whose
    /// Jacobian and `J̇ q̇` generated code holds; `None` for a model without links.
    pub fn tip_frame(&self) -> Option<&Frame> {
        self.frames.last()
    }

    /// Pose of the named frame in the base at `q`: as a transform from base to frame, so its
    /// [`orientation`](Transform::orientation) and `translation` are the frame's axes and origin.
    pub fn frame_pose(&self, frame: &str, q: &[f64]) -> Result<Transform, ModelError> {
        let placements = self.body_placements(q)?;
        Ok(frame_placement(self.frame(frame)?, &placements))
    }

    /// Geometric Jacobian of the named frame at `q`, in base coordinates: rows 0..3 map `q̇` to
    /// the linear velocity of the frame's origin, rows 3..6 to its angular velocity
    /// ([`frame_jacobian`]).
    pub fn frame_jacobian(&self, frame: &str, q: &[f64]) -> Result<DMatrix<f64>, ModelError> {
        let placements = self.body_placements(q)?;
        let mut rows = vec![0.0; 6 * self.dof()];
        frame_jacobian(self, self.frame(frame)?, &placements, &mut rows)?;
        Ok(DMatrix::from_row_slice(6, self.dof(), &rows))
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
    /// the frame's acceleration is `J q̈ + J̇ q̇` ([`frame_acceleration_bias`]).
    pub fn frame_acceleration_bias(&self, frame: &str, q: &[f64], qd: &[f64]) -> Result<[f64; 6], ModelError> {
        let placements = self.body_placements(q)?;
        frame_acceleration_bias(self, self.frame(frame)?, &placements, qd)
    }
}
