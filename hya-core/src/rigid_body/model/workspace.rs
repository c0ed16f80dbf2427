//! Per-body scratch space of the algorithms (Pinocchio's `Data`), and the joint transform
//! `X_i(q_i)` each of them starts from.

use nalgebra::Vector3;

use super::{Body, JointKind};
use crate::rigid_body::scalar::{Label, Quantity, Real};
use crate::rigid_body::spatial::{revolute_rotation, ArticulatedInertia, Force, Motion, RigidBodyInertia, Transform};

/// A body's transform from its parent's frame, `X_i(q) = X_J(q) X_tree`.
///
/// For a tracing number type the constant tree part and the joint part are kept apart and
/// applied one after the other, so that each folds with its own sparsity; numeric types apply
/// them combined, which costs fewer operations.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointTransform<S = f64> {
    tree: Option<Transform<S>>,
    joint: Transform<S>,
}

impl<S: Real> JointTransform<S> {
    /// The transform of body `index` at joint position `q`. For a revolute joint `sin q` and
    /// `cos q` are taken once (labelled) and `E_J = R(a, q)ᵀ`; a prismatic joint moves the
    /// origin by `a q`.
    pub fn new(index: usize, body: &Body, q: S) -> Self {
        let joint = match body.kind {
            JointKind::Revolute => {
                let (s, c) = q.sin_cos();
                let label = |quantity| Label { body: index, quantity, component: 0 };
                let (s, c) = (s.labelled(label(Quantity::Sine)), c.labelled(label(Quantity::Cosine)));
                Transform {
                    rotation: revolute_rotation(&body.axis, s, c),
                    translation: Vector3::from_fn(|_, _| S::zero()),
                }
            }
            JointKind::Prismatic => Transform {
                rotation: Transform::<S>::identity().rotation,
                translation: Vector3::from_fn(|k, _| S::constant(body.axis[k]) * q),
            },
        };
        let tree = Transform::constant(&body.tree_transform);
        if S::TRACES {
            Self { tree: Some(tree), joint }
        } else {
            Self { tree: None, joint: tree.then(&joint) }
        }
    }

    /// The whole transform as one.
    pub fn combined(&self) -> Transform<S> {
        self.tree.map_or(self.joint, |tree| tree.then(&self.joint))
    }

    /// `X m`: a motion from the parent's frame to the body's.
    pub fn apply_motion(&self, m: &Motion<S>) -> Motion<S> {
        let in_joint_frame = self.tree.map_or(*m, |tree| tree.apply_motion(m));
        self.joint.apply_motion(&in_joint_frame)
    }

    /// `Xᵀ f`: a force from the body's frame to the parent's.
    pub fn apply_transpose_force(&self, f: &Force<S>) -> Force<S> {
        let in_joint_frame = self.joint.apply_transpose_force(f);
        self.tree.map_or(in_joint_frame, |tree| tree.apply_transpose_force(&in_joint_frame))
    }

    /// `Xᵀ I X`: a rigid-body inertia from the body's frame to the parent's.
    pub fn inertia_in_parent(&self, inertia: &RigidBodyInertia<S>) -> RigidBodyInertia<S> {
        let in_joint_frame = inertia.expressed_in_parent(&self.joint);
        self.tree.map_or(in_joint_frame, |tree| in_joint_frame.expressed_in_parent(&tree))
    }

    /// `Xᵀ I^A X`: an articulated-body inertia from the body's frame to the parent's.
    pub fn articulated_in_parent(&self, inertia: &ArticulatedInertia<S>) -> ArticulatedInertia<S> {
        let in_joint_frame = inertia.expressed_in_parent(&self.joint);
        self.tree.map_or(in_joint_frame, |tree| in_joint_frame.expressed_in_parent(&tree))
    }
}

/// What the algorithms keep for one body between their passes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyState<S = f64> {
    pub(crate) transform: JointTransform<S>,
    pub(crate) velocity: Motion<S>,
    pub(crate) acceleration: Motion<S>,
    /// RNEA's force, `Cᵀq̇`'s momentum, ABA's bias force `p_i`.
    pub(crate) force: Force<S>,
    pub(crate) composite: RigidBodyInertia<S>,
    pub(crate) articulated: ArticulatedInertia<S>,
    /// ABA's `U_i = I^A_i S_i`.
    pub(crate) inertia_times_axis: Force<S>,
    /// ABA's `D_i = S_i · U_i`.
    pub(crate) joint_inertia: S,
    /// `1 / D_i`.
    pub(crate) inverse_joint_inertia: S,
}

impl<S: Real> BodyState<S> {
    /// Scratch space holding zeros.
    pub fn new() -> Self {
        let transform = Transform::identity();
        Self {
            transform: JointTransform { tree: None, joint: transform },
            velocity: Motion::zero(),
            acceleration: Motion::zero(),
            force: Force::zero(),
            composite: RigidBodyInertia::zero(),
            articulated: RigidBodyInertia::zero().into(),
            inertia_times_axis: Force::zero(),
            joint_inertia: S::zero(),
            inverse_joint_inertia: S::zero(),
        }
    }

    /// ABA's `D_i = S_i · U_i`, the inertia the joint's own motion meets, after
    /// [`forward_dynamics`](super::algorithms::forward_dynamics).
    pub fn joint_inertia(&self) -> S {
        self.joint_inertia
    }
}

impl<S: Real> Default for BodyState<S> {
    fn default() -> Self {
        Self::new()
    }
}
