//! The kinematic-tree model of a fixed-base arm (Pinocchio's `Model`), its per-body workspace
//! ([`BodyState`], Pinocchio's `Data`), and the dynamics algorithms written once for any number
//! type ([`algorithms`], [`derivatives`]): RNEA, CRBA, `Cᵀq̇`, ABA, frame placements and
//! Jacobians (Featherstone, *Rigid Body Dynamics Algorithms*, 2008).
//!
//! One body per moving joint; fixed joints are merged into their parent body by the loader
//! (`hya-urdf`). Bodies are stored parents-first, so body `i`'s parent has an index below `i`.
//! Body `i`'s frame is the URDF frame of its link; `tree_transform` places its joint frame (at
//! `q = 0`) in the parent body's frame. This model is the reference that generated code is
//! checked and benchmarked against.

use alloc::string::String;
use alloc::vec;
use alloc::vec::Vec;

use nalgebra::{DMatrix, Matrix3, SMatrix, Vector3};

pub mod algorithms;
pub mod derivatives;
pub mod kinematics;
mod workspace;

use algorithms::ModelInertias;
pub use workspace::{BodyState, JointTransform};

use crate::dispatch::{with_joints, ForJoints};
use crate::rigid_body::dynamics::write_row_major;
use crate::rigid_body::spatial::{Motion, RigidBodyInertia, Transform};
use crate::rigid_body::through_inverse::through_inverse;
use crate::{Dynamics, Error, JointMatrix, JointVector};

pub use crate::STANDARD_GRAVITY;

/// How a joint moves its child body.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JointKind {
    /// Rotation by `q` rad about the unit axis (URDF `revolute` and `continuous`).
    Revolute,
    /// Translation by `q` m along the unit axis.
    Prismatic,
}

impl JointKind {
    /// The unit of the joint's position: `rad` or `m`.
    pub fn position_unit(self) -> &'static str {
        match self {
            Self::Revolute => "rad",
            Self::Prismatic => "m",
        }
    }

    /// The unit of the effort that moves it: `N m` or `N`.
    pub fn effort_unit(self) -> &'static str {
        match self {
            Self::Revolute => "N m",
            Self::Prismatic => "N",
        }
    }
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
    #[error("no frame `{name}`; the model's frames are {frames}")]
    UnknownFrame {
        /// The name asked for.
        name: String,
        /// The model's frames, comma-separated.
        frames: String,
    },
    /// A model with more joints (or none) than an algorithm takes: refused before the
    /// algorithm allocates what grows with the joint count.
    #[error("`{model}` has {dof} joints; {algorithm} handles arms of 1 to {limit}")]
    JointCount {
        /// The model's name, clipped and escaped ([`ModelError::joint_count`]).
        model: String,
        /// Its joints.
        dof: usize,
        /// What refused it.
        algorithm: &'static str,
        /// The most joints it takes.
        limit: usize,
    },
    /// A joint meets no positive inertia: the mass matrix is singular or indefinite there.
    #[error("joint `{joint}`: the articulated inertia about its axis is not positive")]
    SingularJoint {
        /// The joint's name.
        joint: String,
    },
}

impl ModelError {
    /// `Ok(dof)` if `model` has 1 to `limit` joints, else [`ModelError::JointCount`] naming
    /// `algorithm`.
    pub fn joint_count(model: &TreeModel, algorithm: &'static str, limit: usize) -> Result<usize, Self> {
        let dof = model.dof();
        if (1..=limit).contains(&dof) {
            Ok(dof)
        } else {
            let model = alloc::format!("{}", crate::Clipped(model.name(), 60));
            Err(ModelError::JointCount { model, dof, algorithm, limit })
        }
    }
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

    fn workspace(&self) -> Vec<BodyState> {
        vec![BodyState::new(); self.dof()]
    }

    /// Inverse dynamics `τ = M(q) q̈ + C(q, q̇) + G(q)` ([`algorithms::inverse_dynamics`]).
    pub fn inverse_dynamics(&self, q: &[f64], qd: &[f64], qdd: &[f64]) -> Result<Vec<f64>, ModelError> {
        let mut tau = vec![0.0; self.dof()];
        algorithms::inverse_dynamics(self, &ModelInertias(self), (q, qd, qdd), &mut self.workspace(), &mut tau)?;
        Ok(tau)
    }

    /// Gravity torques `G(q)`.
    pub fn gravity(&self, q: &[f64]) -> Result<Vec<f64>, ModelError> {
        let mut tau = vec![0.0; self.dof()];
        algorithms::gravity(self, &ModelInertias(self), q, &mut self.workspace(), &mut tau)?;
        Ok(tau)
    }

    /// Mass matrix `M(q)` ([`algorithms::mass_matrix`]).
    pub fn mass_matrix(&self, q: &[f64]) -> Result<DMatrix<f64>, ModelError> {
        let n = self.dof();
        let mut m = DMatrix::zeros(n, n);
        algorithms::mass_matrix(self, &ModelInertias(self), q, &mut self.workspace(), |i, j, value| {
            m[(i, j)] = value;
            m[(j, i)] = value;
        })?;
        Ok(m)
    }

    /// `C_matᵀ q̇` ([`algorithms::coriolis_transpose_times_velocity`]).
    pub fn coriolis_transpose_times_velocity(&self, q: &[f64], qd: &[f64]) -> Result<Vec<f64>, ModelError> {
        let mut out = vec![0.0; self.dof()];
        algorithms::coriolis_transpose_times_velocity(
            self,
            &ModelInertias(self),
            (q, qd),
            &mut self.workspace(),
            &mut out,
        )?;
        Ok(out)
    }

    /// `(∂τ/∂q, ∂τ/∂q̇)` of inverse dynamics at `(q, q̇, q̈)`, analytic
    /// ([`derivatives::inverse_dynamics_derivatives`]); row `i` of each is `∂τ_i`.
    pub fn inverse_dynamics_derivatives(
        &self,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
    ) -> Result<(DMatrix<f64>, DMatrix<f64>), ModelError> {
        let n = self.dof();
        let (mut d_dq, mut d_dqd) = (vec![0.0; n * n], vec![0.0; n * n]);
        self.derivatives_into((q, qd, qdd), &mut d_dq, &mut d_dqd)?;
        Ok((DMatrix::from_row_slice(n, n, &d_dq), DMatrix::from_row_slice(n, n, &d_dqd)))
    }

    /// `∂τ/∂q` and `∂τ/∂q̇`, row-major, into the caller's slices.
    fn derivatives_into(
        &self,
        inputs: (&[f64], &[f64], &[f64]),
        d_dq: &mut [f64],
        d_dqd: &mut [f64],
    ) -> Result<(), ModelError> {
        let n = self.dof();
        derivatives::inverse_dynamics_derivatives(
            self,
            &ModelInertias(self),
            inputs,
            &mut vec![derivatives::DerivativeState::new(); n],
            &mut vec![0.0; n],
            (d_dq, d_dqd),
        )
    }

    /// Forward dynamics `q̈` by the articulated-body algorithm ([`algorithms::forward_dynamics`]);
    /// an error if a joint meets no positive inertia.
    pub fn forward_dynamics(&self, q: &[f64], qd: &[f64], tau: &[f64]) -> Result<Vec<f64>, ModelError> {
        let mut qdd = vec![0.0; self.dof()];
        self.forward_dynamics_checked((q, qd, tau), &mut qdd)?;
        Ok(qdd)
    }

    /// ABA into `qdd`, then the check that every joint met a positive inertia.
    fn forward_dynamics_checked(&self, inputs: (&[f64], &[f64], &[f64]), qdd: &mut [f64]) -> Result<(), ModelError> {
        let mut states = self.workspace();
        algorithms::forward_dynamics(self, &ModelInertias(self), inputs, &mut states, qdd)?;
        check_joint_inertias(self, &states)
    }

    /// Base frame to body `i`'s frame at `q`, for every body.
    fn body_placements(&self, q: &[f64]) -> Result<Vec<Transform>, ModelError> {
        let mut placements = vec![Transform::identity(); self.dof()];
        algorithms::body_placements(self, q, &mut self.workspace(), &mut placements)?;
        Ok(placements)
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

/// Lengths are the caller's to check (see [`SliceDynamics`](crate::SliceDynamics)).
const SLICE_CONTRACT: &str = "SliceDynamics: every slice has dof() entries (dof² for the mass matrix)";

impl crate::SliceDynamics for TreeModel {
    fn dof(&self) -> usize {
        self.bodies.len()
    }
    fn inverse_dynamics_into(&self, q: &[f64], qd: &[f64], qdd: &[f64], tau: &mut [f64]) {
        algorithms::inverse_dynamics(self, &ModelInertias(self), (q, qd, qdd), &mut self.workspace(), tau)
            .expect(SLICE_CONTRACT);
    }
    fn gravity_into(&self, q: &[f64], tau: &mut [f64]) {
        algorithms::gravity(self, &ModelInertias(self), q, &mut self.workspace(), tau).expect(SLICE_CONTRACT);
    }
    fn mass_matrix_into(&self, q: &[f64], mass: &mut [f64]) {
        let n = self.dof();
        assert_eq!(mass.len(), n * n, "{SLICE_CONTRACT}");
        algorithms::mass_matrix(self, &ModelInertias(self), q, &mut self.workspace(), |i, j, value| {
            mass[i * n + j] = value;
            mass[j * n + i] = value;
        })
        .expect(SLICE_CONTRACT);
    }
    fn forward_dynamics_into(&self, q: &[f64], qd: &[f64], tau: &[f64], qdd: &mut [f64]) -> Result<(), Error> {
        self.forward_dynamics_checked((q, qd, tau), qdd).map_err(|e| match e {
            ModelError::SingularJoint { .. } => Error::SingularMassMatrix,
            other => panic!("{SLICE_CONTRACT}: {other}"),
        })
    }
    fn inverse_dynamics_derivatives_into(
        &self,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        d_dq: &mut [f64],
        d_dqd: &mut [f64],
    ) {
        self.derivatives_into((q, qd, qdd), d_dq, d_dqd).expect(SLICE_CONTRACT);
    }
    /// As [`Dynamics::forward_dynamics_derivatives`]: `−M⁻¹ ∂ID/∂(q, q̇)` at `q̈ = FD(q, q̇, τ)`.
    fn forward_dynamics_derivatives_into(
        &self,
        q: &[f64],
        qd: &[f64],
        tau: &[f64],
        [by_q, by_qd, inverse]: [&mut [f64]; 3],
    ) -> Result<(), Error> {
        let n = self.dof();
        let mut qdd = vec![0.0; n];
        self.forward_dynamics_into(q, qd, tau, &mut qdd)?;
        self.inverse_dynamics_derivatives_into(q, qd, &qdd, by_q, by_qd);
        self.mass_matrix_into(q, inverse);
        // Up to `MAX_JOINTS`, the fixed-size models' last step, so that a URDF and its generated
        // arm take the same one; nalgebra's Cholesky beyond.
        if let Some(done) = with_joints(n, ThroughInverseRows([by_q, by_qd, inverse])) {
            return done;
        }
        let mass = DMatrix::from_row_slice(n, n, inverse);
        let mass_inverse = mass.cholesky().ok_or(Error::SingularMassMatrix)?.inverse();
        // Row-major in and out: the transposes' column-major storage.
        for out in [by_q, by_qd] {
            // `0 − x`, not `−x`: an exact zero stays +0.
            let product = (&mass_inverse * DMatrix::from_row_slice(n, n, out)).map(|x| 0.0 - x);
            out.copy_from_slice(product.transpose().as_slice());
        }
        inverse.copy_from_slice(mass_inverse.transpose().as_slice());
        Ok(())
    }
}

/// `through_inverse` on row-major `N × N` slices: `[∂ID/∂q, ∂ID/∂q̇, M]` in,
/// `[∂q̈/∂q, ∂q̈/∂q̇, M⁻¹]` out.
struct ThroughInverseRows<'a>([&'a mut [f64]; 3]);

impl ForJoints for ThroughInverseRows<'_> {
    type Output = Result<(), Error>;
    fn call<const N: usize>(self) -> Result<(), Error> {
        let [by_q, by_qd, mass] = self.0;
        let [rows_q, rows_qd, rows_mass] = [&*by_q, &*by_qd, &*mass].map(JointMatrix::<N>::from_row_slice);
        let (dq, dqd, inverse) = through_inverse(&rows_mass, &rows_q, &rows_qd)?;
        write_row_major([by_q, by_qd, mass], [&dq, &dqd, &inverse]);
        Ok(())
    }
}

/// `Err` unless every joint meets a positive, finite inertia `D_i` in the articulated-body
/// algorithm: then `M(q)` is positive definite and ABA's `q̈` can be trusted.
fn check_joint_inertias(model: &TreeModel, states: &[BodyState]) -> Result<(), ModelError> {
    match states.iter().position(|s| !(s.joint_inertia() > 0.0 && s.joint_inertia().is_finite())) {
        Some(i) => Err(ModelError::SingularJoint { joint: model.bodies[i].joint.clone() }),
        None => Ok(()),
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

    /// Runs `algorithm` on the model with a stack workspace; the lengths are `N` by
    /// construction ([`TreeModel::into_dynamics`]), so it cannot fail on them.
    fn run<T>(
        &self,
        algorithm: impl FnOnce(&TreeModel, &ModelInertias, &mut [BodyState; N]) -> Result<T, ModelError>,
    ) -> T {
        algorithm(&self.model, &ModelInertias(&self.model), &mut [BodyState::new(); N])
            .expect("TreeDynamics<N> holds a model with N joints")
    }
}

impl<const N: usize> Dynamics<N> for TreeDynamics<N> {
    fn inverse_dynamics(&self, q: &JointVector<N>, qd: &JointVector<N>, qdd: &JointVector<N>) -> JointVector<N> {
        let mut tau = JointVector::<N>::zeros();
        let inputs = (q.as_slice(), qd.as_slice(), qdd.as_slice());
        self.run(|m, i, ws| algorithms::inverse_dynamics(m, i, inputs, ws, tau.as_mut_slice()));
        tau
    }

    fn coriolis_transpose_times_velocity(&self, q: &JointVector<N>, qd: &JointVector<N>) -> JointVector<N> {
        let mut out = JointVector::<N>::zeros();
        let inputs = (q.as_slice(), qd.as_slice());
        self.run(|m, i, ws| algorithms::coriolis_transpose_times_velocity(m, i, inputs, ws, out.as_mut_slice()));
        out
    }

    fn gravity(&self, q: &JointVector<N>) -> JointVector<N> {
        let mut tau = JointVector::<N>::zeros();
        self.run(|m, i, ws| algorithms::gravity(m, i, q.as_slice(), ws, tau.as_mut_slice()));
        tau
    }

    fn velocity_terms(&self, q: &JointVector<N>, qd: &JointVector<N>) -> JointVector<N> {
        let mut tau = JointVector::<N>::zeros();
        let inputs = (q.as_slice(), qd.as_slice());
        self.run(|m, i, ws| algorithms::velocity_terms(m, i, inputs, ws, tau.as_mut_slice()));
        tau
    }

    fn mass_matrix(&self, q: &JointVector<N>) -> JointMatrix<N> {
        let mut m = SMatrix::zeros();
        self.run(|model, i, ws| {
            algorithms::mass_matrix(model, i, q.as_slice(), ws, |r, c, value| {
                m[(r, c)] = value;
                m[(c, r)] = value;
            })
        });
        m
    }

    fn inverse_dynamics_derivatives(
        &self,
        q: &JointVector<N>,
        qd: &JointVector<N>,
        qdd: &JointVector<N>,
    ) -> (JointMatrix<N>, JointMatrix<N>) {
        let (mut d_dq, mut d_dqd) = (JointMatrix::<N>::zeros(), JointMatrix::<N>::zeros());
        let mut tau = JointVector::<N>::zeros();
        // The derivatives keep their own per-body state, not `run`'s.
        self.run(|model, inertias, _| {
            derivatives::inverse_dynamics_derivatives(
                model,
                inertias,
                (q.as_slice(), qd.as_slice(), qdd.as_slice()),
                &mut [derivatives::DerivativeState::new(); N],
                tau.as_mut_slice(),
                (d_dq.as_mut_slice(), d_dqd.as_mut_slice()),
            )
        });
        // Written row-major into column-major storage: the transposes.
        (d_dq.transpose(), d_dqd.transpose())
    }

    fn forward_dynamics(
        &self,
        q: &JointVector<N>,
        qd: &JointVector<N>,
        tau: &JointVector<N>,
    ) -> Result<JointVector<N>, Error> {
        let mut qdd = JointVector::<N>::zeros();
        let inputs = (q.as_slice(), qd.as_slice(), tau.as_slice());
        let singular = self.run(|m, i, ws| {
            algorithms::forward_dynamics(m, i, inputs, ws, qdd.as_mut_slice())?;
            Ok(check_joint_inertias(m, ws).is_err())
        });
        if singular {
            Err(Error::SingularMassMatrix)
        } else {
            Ok(qdd)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_arms::PlanarTwoLink;

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
        let tau = JointVector::from([4.0, -1.5]);
        let by_aba = tree.forward_dynamics(&q, &qd, &tau).unwrap();
        assert!(close(by_aba, arm.forward_dynamics(&q, &qd, &tau).unwrap()), "{by_aba}");
        // Analytic derivatives against the trait's central differences of the closed form.
        let (by_q, by_qd) = tree.inverse_dynamics_derivatives(&q, &qd, &qdd);
        let (fd_q, fd_qd) = arm.inverse_dynamics_derivatives(&q, &qd, &qdd);
        assert!((by_q - fd_q).norm() < 1e-7 && (by_qd - fd_qd).norm() < 1e-7, "{by_q} {fd_q} {by_qd} {fd_qd}");
    }

    /// On slices, up to `MAX_JOINTS` joints, the run-time model takes the fixed-size model's
    /// last step of `∇FD`: the two give the same numbers, bit for bit.
    #[test]
    fn forward_dynamics_derivatives_on_slices_equal_the_fixed_size_models() {
        let tree = two_link_tree(&PlanarTwoLink::default());
        let (q, qd, tau) = ([0.7, -1.3], [1.1, 2.4], [4.0, -1.5]);
        let mut out = [[0.0; 4]; 3];
        let [a, b, c] = &mut out;
        crate::SliceDynamics::forward_dynamics_derivatives_into(tree.model(), &q, &qd, &tau, [a, b, c]).unwrap();
        let fixed = tree.forward_dynamics_derivatives(&q.into(), &qd.into(), &tau.into()).unwrap();
        for (slice, matrix) in out.iter().zip([fixed.0, fixed.1, fixed.2]) {
            assert_eq!(slice[..], matrix.transpose().as_slice()[..]);
        }
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
        assert!(matches!(model.frame_pose("nowhere", &q), Err(ModelError::UnknownFrame { .. })));
        assert!(matches!(model.inverse_dynamics(&[0.0], &[0.0], &[0.0]), Err(ModelError::Dimension { .. })));
    }
}
