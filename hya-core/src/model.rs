//! The runtime kinematic-tree model of a fixed-base arm, and its generic dynamics algorithms:
//! RNEA (inverse dynamics), CRBA (mass matrix), `Cᵀq̇`, forward dynamics, frame poses and
//! geometric Jacobians (Featherstone, *Rigid Body Dynamics Algorithms*, 2008).
//!
//! One body per moving joint; fixed joints are merged into their parent body by the loader
//! (`hya-codegen`). Bodies are stored parents-first, so body `i`'s parent has an index below `i`.
//! Body `i`'s frame is the URDF frame of its link; `tree_transform` places its joint frame (at
//! `q = 0`) in the parent body's frame. This model is the reference that generated code is
//! checked and benchmarked against.

use alloc::string::String;
use alloc::vec;
use alloc::vec::Vec;

use nalgebra::{DMatrix, Matrix3, SMatrix, Vector3};

use crate::spatial::{axis_angle, Force, Motion, RigidBodyInertia, Transform};
use crate::{Dynamics, JointMatrix, JointVector};

/// Standard gravity along the base's −z, m/s² (the paper's and Pinocchio's value).
pub const STANDARD_GRAVITY: f64 = 9.81;

/// How a joint moves its child body.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JointKind {
    /// Rotation by `q` rad about the unit axis (URDF `revolute` and `continuous`).
    Revolute,
    /// Translation by `q` m along the unit axis.
    Prismatic,
}

/// Joint limits as the robot description gives them; `None` where it gives none.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct JointLimits {
    /// Lower position limit, rad or m.
    pub lower: Option<f64>,
    /// Upper position limit, rad or m.
    pub upper: Option<f64>,
    /// Velocity limit, rad/s or m/s.
    pub velocity: Option<f64>,
    /// Effort limit, N·m or N.
    pub effort: Option<f64>,
}

/// One moving body: the joint that moves it and everything rigidly attached to it.
#[derive(Debug, Clone, PartialEq)]
pub struct Body {
    /// Name of the link whose frame is the body frame.
    pub link: String,
    /// Name of the joint that moves the body.
    pub joint: String,
    /// Index of the parent body; `None` for a body attached to the fixed base.
    pub parent: Option<usize>,
    /// Revolute or prismatic.
    pub kind: JointKind,
    /// Unit joint axis in the body frame.
    pub axis: Vector3<f64>,
    /// Parent body frame to this body's frame at `q = 0`.
    pub tree_transform: Transform,
    /// Spatial inertia of the body (merged links included) about the body frame's origin.
    pub inertia: RigidBodyInertia,
    /// Limits from the description.
    pub limits: JointLimits,
}

impl Body {
    /// Joint transform `X_J(q)`: from the frame at `q = 0` to the moved body frame.
    fn joint_transform(&self, q: f64) -> Transform {
        match self.kind {
            JointKind::Revolute => Transform::from_pose(axis_angle(&self.axis, q), Vector3::zeros()),
            JointKind::Prismatic => Transform { rotation: Matrix3::identity(), translation: self.axis * q },
        }
    }

    /// Parent body frame to this body's frame at joint position `q`.
    fn transform(&self, q: f64) -> Transform {
        self.tree_transform.then(&self.joint_transform(q))
    }

    /// Motion subspace `S`: the body's spatial velocity per unit joint velocity.
    pub fn subspace(&self) -> Motion {
        match self.kind {
            JointKind::Revolute => Motion::new(self.axis, Vector3::zeros()),
            JointKind::Prismatic => Motion::new(Vector3::zeros(), self.axis),
        }
    }
}

/// A named frame attached to a body (or to the base): every link of the description, merged
/// links included.
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    /// The link's name.
    pub name: String,
    /// The body it is rigidly attached to; `None` for the base.
    pub body: Option<usize>,
    /// Body frame to this frame.
    pub placement: Transform,
}

/// Why a model could not be built or queried.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ModelError {
    /// A body's parent index is not below its own.
    #[error("body {index} (link `{link}`): parent {parent} must come before it")]
    ParentOrder {
        /// The body's index.
        index: usize,
        /// The body's link name.
        link: String,
        /// The offending parent index.
        parent: usize,
    },
    /// A body's axis is not of unit length.
    #[error("joint `{joint}`: axis must have unit length")]
    AxisNotUnit {
        /// The joint's name.
        joint: String,
    },
    /// An argument has the wrong number of entries.
    #[error("{what}: expected {expected} values, got {got}")]
    Dimension {
        /// Which argument.
        what: &'static str,
        /// The model's degrees of freedom.
        expected: usize,
        /// What was given.
        got: usize,
    },
    /// No frame of that name.
    #[error("no frame named `{0}`")]
    UnknownFrame(String),
}

/// Per-body scratch space of the algorithms; `[BodyState; N]` on the stack for a fixed `N`.
#[derive(Debug, Clone, Copy, Default)]
pub struct BodyState {
    transform: Transform,
    velocity: Motion,
    acceleration: Motion,
    force: Force,
    composite: RigidBodyInertia,
}

/// A fixed-base kinematic tree with rigid bodies, ready for the dynamics algorithms.
#[derive(Debug, Clone, PartialEq)]
pub struct TreeModel {
    name: String,
    bodies: Vec<Body>,
    frames: Vec<Frame>,
    gravity: Vector3<f64>,
}

impl TreeModel {
    /// A model from bodies in parents-first order and named frames; gravity 9.81 m/s² along −z.
    pub fn new(name: impl Into<String>, bodies: Vec<Body>, frames: Vec<Frame>) -> Result<Self, ModelError> {
        for (index, body) in bodies.iter().enumerate() {
            if let Some(parent) = body.parent.filter(|&p| p >= index) {
                return Err(ModelError::ParentOrder { index, link: body.link.clone(), parent });
            }
            if (body.axis.norm() - 1.0).abs() > 1e-9 {
                return Err(ModelError::AxisNotUnit { joint: body.joint.clone() });
            }
        }
        Ok(Self { name: name.into(), bodies, frames, gravity: Vector3::new(0.0, 0.0, -STANDARD_GRAVITY) })
    }

    /// The same model with gravity `g` (m/s², base coordinates).
    pub fn with_gravity(mut self, gravity: Vector3<f64>) -> Self {
        self.gravity = gravity;
        self
    }

    /// The robot's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Degrees of freedom (one per body).
    pub fn dof(&self) -> usize {
        self.bodies.len()
    }

    /// The bodies, parents first; body `i` is moved by joint `i`.
    pub fn bodies(&self) -> &[Body] {
        &self.bodies
    }

    /// Every named frame.
    pub fn frames(&self) -> &[Frame] {
        &self.frames
    }

    /// Gravity in base coordinates, m/s².
    pub fn gravity_vector(&self) -> Vector3<f64> {
        self.gravity
    }

    /// Joint names in the model's order.
    pub fn joint_names(&self) -> impl Iterator<Item = &str> {
        self.bodies.iter().map(|b| b.joint.as_str())
    }

    fn check(&self, what: &'static str, values: &[f64]) -> Result<(), ModelError> {
        if values.len() == self.dof() {
            Ok(())
        } else {
            Err(ModelError::Dimension { what, expected: self.dof(), got: values.len() })
        }
    }

    /// Inverse dynamics `τ = M(q) q̈ + C(q, q̇) + G(q)`.
    pub fn inverse_dynamics(&self, q: &[f64], qd: &[f64], qdd: &[f64]) -> Result<Vec<f64>, ModelError> {
        self.check("q", q)?;
        self.check("qd", qd)?;
        self.check("qdd", qdd)?;
        let mut tau = vec![0.0; self.dof()];
        self.rnea(q, Some(qd), Some(qdd), true, &mut vec![BodyState::default(); self.dof()], &mut tau);
        Ok(tau)
    }

    /// Gravity torques `G(q)`.
    pub fn gravity(&self, q: &[f64]) -> Result<Vec<f64>, ModelError> {
        self.check("q", q)?;
        let mut tau = vec![0.0; self.dof()];
        self.rnea(q, None, None, true, &mut vec![BodyState::default(); self.dof()], &mut tau);
        Ok(tau)
    }

    /// Mass matrix `M(q)`.
    pub fn mass_matrix(&self, q: &[f64]) -> Result<DMatrix<f64>, ModelError> {
        self.check("q", q)?;
        let n = self.dof();
        let mut m = DMatrix::zeros(n, n);
        self.crba(q, &mut vec![BodyState::default(); n], |i, j, value| m[(i, j)] = value);
        Ok(m)
    }

    /// The recursive Newton-Euler algorithm. `None` rates are zero; `with_gravity` folds gravity
    /// into the base acceleration (`a_0 = −g`).
    ///
    /// ```text
    /// v_i = X_i v_λ + S_i q̇_i,   a_i = X_i a_λ + S_i q̈_i + v_i ×ₘ S_i q̇_i
    /// f_i = I_i a_i + v_i ×* I_i v_i,   τ_i = S_i · f_i,   f_λ += X_iᵀ f_i
    /// ```
    pub fn rnea(
        &self,
        q: &[f64],
        qd: Option<&[f64]>,
        qdd: Option<&[f64]>,
        with_gravity: bool,
        states: &mut [BodyState],
        tau: &mut [f64],
    ) {
        let base_acceleration =
            Motion::new(Vector3::zeros(), if with_gravity { -self.gravity } else { Vector3::zeros() });
        for (i, body) in self.bodies.iter().enumerate() {
            let x = body.transform(q[i]);
            let s = body.subspace();
            let (parent_velocity, parent_acceleration) = match body.parent {
                Some(p) => (states[p].velocity, states[p].acceleration),
                None => (Motion::default(), base_acceleration),
            };
            let joint_velocity = s * qd.map_or(0.0, |v| v[i]);
            let velocity = x.apply_motion(&parent_velocity) + joint_velocity;
            let acceleration = x.apply_motion(&parent_acceleration)
                + s * qdd.map_or(0.0, |a| a[i])
                + velocity.cross_motion(&joint_velocity);
            let force = body.inertia.apply(&acceleration) + velocity.cross_force(&body.inertia.apply(&velocity));
            states[i] = BodyState { transform: x, velocity, acceleration, force, ..states[i] };
        }
        for (i, body) in self.bodies.iter().enumerate().rev() {
            tau[i] = body.subspace().dot(&states[i].force);
            if let Some(p) = body.parent {
                let to_parent = states[i].transform.apply_transpose_force(&states[i].force);
                states[p].force += to_parent;
            }
        }
    }

    /// The composite-rigid-body algorithm; `store(i, j, M_ij)` receives every entry of `M(q)`.
    ///
    /// ```text
    /// I^c_λ += X_iᵀ I^c_i X_i (leaves first);   F = I^c_i S_i,   M_ii = S_i · F
    /// up the tree: F = X_jᵀ F, j = λ(j),   M_ij = M_ji = S_j · F
    /// ```
    pub fn crba(&self, q: &[f64], states: &mut [BodyState], mut store: impl FnMut(usize, usize, f64)) {
        for (i, body) in self.bodies.iter().enumerate() {
            states[i].transform = body.transform(q[i]);
            states[i].composite = body.inertia;
        }
        for (i, body) in self.bodies.iter().enumerate().rev() {
            if let Some(p) = body.parent {
                let in_parent = states[i].composite.expressed_in_parent(&states[i].transform);
                states[p].composite += in_parent;
            }
        }
        for (i, body) in self.bodies.iter().enumerate() {
            let mut force = states[i].composite.apply(&body.subspace());
            store(i, i, body.subspace().dot(&force));
            let mut j = i;
            while let Some(p) = self.bodies[j].parent {
                force = states[j].transform.apply_transpose_force(&force);
                j = p;
                let value = self.bodies[j].subspace().dot(&force);
                store(i, j, value);
                store(j, i, value);
            }
        }
    }

    /// `C_matᵀ q̇` (with `Ṁ = C_mat + C_matᵀ`), from the subtree momenta `h^C_i`:
    ///
    /// ```text
    /// h_i = I_i v_i,   h^C_λ += X_iᵀ h^C_i (leaves first),   (Cᵀq̇)_i = (v_i ×ₘ S_i) · h^C_i
    /// ```
    ///
    /// (From `ṗ = M q̈ + Ṁ q̇` for the generalized momentum `p_i = S_i · h^C_i`, whose rate is
    /// `S_i · ḣ^C_i + (v_i ×ₘ S_i) · h^C_i` with `S_i · ḣ^C_i = (M q̈ + C)_i`.)
    pub fn coriolis_transpose_times_velocity_into(
        &self,
        q: &[f64],
        qd: &[f64],
        states: &mut [BodyState],
        out: &mut [f64],
    ) {
        for (i, body) in self.bodies.iter().enumerate() {
            let x = body.transform(q[i]);
            let parent_velocity = body.parent.map_or(Motion::default(), |p| states[p].velocity);
            let velocity = x.apply_motion(&parent_velocity) + body.subspace() * qd[i];
            states[i] = BodyState { transform: x, velocity, force: body.inertia.apply(&velocity), ..states[i] };
        }
        for (i, body) in self.bodies.iter().enumerate().rev() {
            out[i] = states[i].velocity.cross_motion(&body.subspace()).dot(&states[i].force);
            if let Some(p) = body.parent {
                let to_parent = states[i].transform.apply_transpose_force(&states[i].force);
                states[p].force += to_parent;
            }
        }
    }

    /// `C_matᵀ q̇`; see [`coriolis_transpose_times_velocity_into`](Self::coriolis_transpose_times_velocity_into).
    pub fn coriolis_transpose_times_velocity(&self, q: &[f64], qd: &[f64]) -> Result<Vec<f64>, ModelError> {
        self.check("q", q)?;
        self.check("qd", qd)?;
        let mut out = vec![0.0; self.dof()];
        self.coriolis_transpose_times_velocity_into(q, qd, &mut vec![BodyState::default(); self.dof()], &mut out);
        Ok(out)
    }

    /// Base frame to body `i`'s frame at `q`, for every body.
    fn body_placements(&self, q: &[f64]) -> Vec<Transform> {
        let mut placements: Vec<Transform> = Vec::with_capacity(self.dof());
        for (i, body) in self.bodies.iter().enumerate() {
            let parent = body.parent.map_or(Transform::identity(), |p| placements[p]);
            placements.push(parent.then(&body.transform(q[i])));
        }
        placements
    }

    fn frame(&self, name: &str) -> Result<&Frame, ModelError> {
        self.frames.iter().find(|f| f.name == name).ok_or_else(|| ModelError::UnknownFrame(name.into()))
    }

    /// Pose of the named frame in the base at `q`: as a transform from base to frame, so its
    /// [`orientation`](Transform::orientation) and `translation` are the frame's axes and origin.
    pub fn frame_pose(&self, frame: &str, q: &[f64]) -> Result<Transform, ModelError> {
        self.check("q", q)?;
        let frame = self.frame(frame)?;
        let body = frame.body.map_or(Transform::identity(), |b| self.body_placements(q)[b]);
        Ok(body.then(&frame.placement))
    }

    /// Geometric Jacobian of the named frame at `q`, in base coordinates: rows 0..3 map `q̇` to
    /// the linear velocity of the frame's origin, rows 3..6 to its angular velocity.
    pub fn frame_jacobian(&self, frame: &str, q: &[f64]) -> Result<DMatrix<f64>, ModelError> {
        self.check("q", q)?;
        let target = self.frame(frame)?;
        let placements = self.body_placements(q);
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

    /// The same model with every body's inertia replaced by `f(body index, inertia)`.
    pub fn map_inertias(&self, mut f: impl FnMut(usize, &RigidBodyInertia) -> RigidBodyInertia) -> TreeModel {
        let mut model = self.clone();
        for (i, body) in model.bodies.iter_mut().enumerate() {
            body.inertia = f(i, &body.inertia);
        }
        model
    }

    /// The same model carrying a point mass (kg) at the origin of the named frame, as a payload
    /// held by the end effector.
    pub fn with_point_mass(&self, frame: &str, mass: f64) -> Result<TreeModel, ModelError> {
        let target = self.frame(frame)?;
        let Some(body) = target.body else {
            // A mass on the fixed base changes no joint torque.
            return Ok(self.clone());
        };
        let point = RigidBodyInertia::from_centre_of_mass(
            mass,
            target.placement.point_to_parent(&Vector3::zeros()),
            Matrix3::zeros(),
        );
        Ok(self.map_inertias(|i, inertia| if i == body { *inertia + point } else { *inertia }))
    }

    /// This model as a [`Dynamics<N>`], checking that it has `N` degrees of freedom.
    pub fn into_dynamics<const N: usize>(self) -> Result<TreeDynamics<N>, ModelError> {
        if self.dof() == N {
            Ok(TreeDynamics { model: self })
        } else {
            Err(ModelError::Dimension { what: "degrees of freedom", expected: N, got: self.dof() })
        }
    }
}

impl crate::SliceDynamics for TreeModel {
    fn dof(&self) -> usize {
        self.bodies.len()
    }
    fn inverse_dynamics_into(&self, q: &[f64], qd: &[f64], qdd: &[f64], tau: &mut [f64]) {
        self.rnea(q, Some(qd), Some(qdd), true, &mut vec![BodyState::default(); self.dof()], tau);
    }
    fn gravity_into(&self, q: &[f64], tau: &mut [f64]) {
        self.rnea(q, None, None, true, &mut vec![BodyState::default(); self.dof()], tau);
    }
    fn mass_matrix_into(&self, q: &[f64], mass: &mut [f64]) {
        let n = self.dof();
        self.crba(q, &mut vec![BodyState::default(); n], |i, j, value| mass[i * n + j] = value);
    }
}

/// A [`TreeModel`] with exactly `N` degrees of freedom: the generic [`Dynamics<N>`], allocation
/// free (scratch space lives on the stack).
#[derive(Debug, Clone, PartialEq)]
pub struct TreeDynamics<const N: usize> {
    model: TreeModel,
}

impl<const N: usize> TreeDynamics<N> {
    /// The underlying model.
    pub fn model(&self) -> &TreeModel {
        &self.model
    }
}

impl<const N: usize> Dynamics<N> for TreeDynamics<N> {
    fn inverse_dynamics(&self, q: &JointVector<N>, qd: &JointVector<N>, qdd: &JointVector<N>) -> JointVector<N> {
        let mut tau = JointVector::<N>::zeros();
        let mut states = [BodyState::default(); N];
        self.model.rnea(q.as_slice(), Some(qd.as_slice()), Some(qdd.as_slice()), true, &mut states, tau.as_mut_slice());
        tau
    }

    fn coriolis_transpose_times_velocity(&self, q: &JointVector<N>, qd: &JointVector<N>) -> JointVector<N> {
        let mut out = JointVector::<N>::zeros();
        let mut states = [BodyState::default(); N];
        self.model.coriolis_transpose_times_velocity_into(q.as_slice(), qd.as_slice(), &mut states, out.as_mut_slice());
        out
    }

    fn gravity(&self, q: &JointVector<N>) -> JointVector<N> {
        let mut tau = JointVector::<N>::zeros();
        self.model.rnea(q.as_slice(), None, None, true, &mut [BodyState::default(); N], tau.as_mut_slice());
        tau
    }

    fn velocity_terms(&self, q: &JointVector<N>, qd: &JointVector<N>) -> JointVector<N> {
        let mut tau = JointVector::<N>::zeros();
        let states = &mut [BodyState::default(); N];
        self.model.rnea(q.as_slice(), Some(qd.as_slice()), None, false, states, tau.as_mut_slice());
        tau
    }

    fn mass_matrix(&self, q: &JointVector<N>) -> JointMatrix<N> {
        let mut m = SMatrix::zeros();
        self.model.crba(q.as_slice(), &mut [BodyState::default(); N], |i, j, value| m[(i, j)] = value);
        m
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::robots::PlanarTwoLink;

    /// The closed-form two-link arm as a tree: z axes, links along x, gravity along −y.
    fn two_link_tree(arm: &PlanarTwoLink) -> TreeDynamics<2> {
        let link = |i: usize, parent: Option<usize>, offset: f64| Body {
            link: alloc::format!("link{i}"),
            joint: alloc::format!("joint{i}"),
            parent,
            kind: JointKind::Revolute,
            axis: Vector3::z(),
            tree_transform: Transform { rotation: Matrix3::identity(), translation: Vector3::new(offset, 0.0, 0.0) },
            inertia: RigidBodyInertia::from_centre_of_mass(
                arm.mass_kg[i],
                Vector3::new(arm.com_m[i], 0.0, 0.0),
                Matrix3::from_diagonal(&Vector3::new(0.0, 0.0, arm.inertia_kg_m2[i])),
            ),
            limits: JointLimits::default(),
        };
        let bodies = vec![link(0, None, 0.0), link(1, Some(0), arm.length1_m)];
        let tip = Frame {
            name: "tip".into(),
            body: Some(1),
            placement: Transform { rotation: Matrix3::identity(), translation: Vector3::new(0.4, 0.0, 0.0) },
        };
        TreeModel::new("two-link", bodies, vec![tip])
            .unwrap()
            .with_gravity(Vector3::new(0.0, -arm.gravity_m_s2, 0.0))
            .into_dynamics()
            .unwrap()
    }

    #[test]
    fn tree_algorithms_match_the_closed_form_two_link_arm() {
        let arm = PlanarTwoLink::default();
        let tree = two_link_tree(&arm);
        let q = JointVector::from([0.7, -1.3]);
        let qd = JointVector::from([1.1, 2.4]);
        let qdd = JointVector::from([-0.5, 3.0]);
        let close = |a: JointVector<2>, b: JointVector<2>| (a - b).norm() < 1e-12;
        assert!(close(tree.inverse_dynamics(&q, &qd, &qdd), arm.inverse_dynamics(&q, &qd, &qdd)));
        assert!(close(tree.gravity(&q), arm.gravity(&q)));
        assert!(close(tree.velocity_terms(&q, &qd), arm.velocity_terms(&q, &qd)));
        assert!((tree.mass_matrix(&q) - arm.mass_matrix(&q)).norm() < 1e-12);
        let ct = tree.coriolis_transpose_times_velocity(&q, &qd);
        assert!(close(ct, arm.coriolis_transpose_times_velocity(&q, &qd)), "{ct}");
    }

    #[test]
    fn frame_pose_and_jacobian_of_the_tip() {
        let tree = two_link_tree(&PlanarTwoLink::default());
        let model = tree.model();
        let q = [0.3, 0.5];
        let pose = model.frame_pose("tip", &q).unwrap();
        let expected =
            Vector3::new(0.5 * 0.3f64.cos() + 0.4 * 0.8f64.cos(), 0.5 * 0.3f64.sin() + 0.4 * 0.8f64.sin(), 0.0);
        assert!((pose.translation - expected).norm() < 1e-12);
        // The Jacobian's linear rows agree with central differences of the pose.
        let jacobian = model.frame_jacobian("tip", &q).unwrap();
        for j in 0..2 {
            let mut plus = q;
            let mut minus = q;
            plus[j] += 1e-6;
            minus[j] -= 1e-6;
            let rate = (model.frame_pose("tip", &plus).unwrap().translation
                - model.frame_pose("tip", &minus).unwrap().translation)
                / 2e-6;
            assert!((jacobian.fixed_view::<3, 1>(0, j) - rate).norm() < 1e-8);
            assert_eq!(jacobian[(5, j)], 1.0);
        }
        assert!(matches!(model.frame_pose("nowhere", &q), Err(ModelError::UnknownFrame(_))));
        assert!(matches!(model.inverse_dynamics(&[0.0], &[0.0], &[0.0]), Err(ModelError::Dimension { .. })));
    }
}
