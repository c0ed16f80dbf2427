//! Cartesian impedance control with the paper's disturbance compensation, beside
//! [`ComputedTorque`](crate::control::ComputedTorque): one frame of the arm (a tool) is held to a
//! pose by a spring and a damper in task space, the rigid body's `C + G` is cancelled, and so is
//! the disturbance estimate `d̂` in joint space, as the paper's controller cancels it:
//!
//! ```text
//! τ = Jᵀ (K_x e − D_x (J q̇ − ẋ_des)) + C(q, q̇) + G(q) − d̂ + P (−K_n (q − q_rest) − D_n q̇)
//! e = (p_des − p,  log(R_des Rᵀ))          P = I − Jᵀ (J Jᵀ + μ² I)⁻¹ J
//! ```
//!
//! `p`, `R` are the frame's origin and axes in the base, `J` its geometric Jacobian in base
//! coordinates (linear rows, then angular: Pinocchio's `LOCAL_WORLD_ALIGNED`), `ẋ_des` the
//! desired twist in the same coordinates, and `log(R_des Rᵀ)` the rotation vector that turns the
//! frame's axes onto the desired ones, in the base. `K_x`, `D_x` are diagonal (N/m and N·m/rad,
//! N·s/m and N·m·s/rad). `P` projects the posture torque onto what exerts no force at the frame
//! (the static projector, damped: `J P = μ² (J Jᵀ + μ² I)⁻¹ J`, zero at `μ = 0` and at most `μ/2`
//! in norm otherwise; `μ` keeps `P` bounded near singular poses, where the undamped one is
//! wrong before its factorisation fails), so that a redundant arm (the Panda's seven joints)
//! holds its elbow near `q_rest` without pulling the tool.
//! `C + G` is one inverse-dynamics pass `ID(q, q̇, 0)`. The sign of `d̂` is the crate's: a positive
//! `d` pushes the joints like a positive `τ`, and compensation subtracts `d̂`.
//!
//! The frame's kinematics come in as a [`FrameState`], from generated code or from the run-time
//! model ([`FrameState::of_tree`], which allocates); [`CartesianImpedance::command`] itself does not.

use nalgebra::{SMatrix, SVector};

use crate::control::{checked_torque_limit, compensated, Command};
use crate::finite::check;
use crate::{Dynamics, Error, JointMatrix, JointVector};

/// A twist or a wrench: linear part (first three), then angular.
pub type Vector6 = SVector<f64, 6>;
/// A point or a rotation vector, m or rad.
pub type Vector3 = nalgebra::Vector3<f64>;
/// An orientation: a frame's axes in base coordinates.
pub type Matrix3 = nalgebra::Matrix3<f64>;

/// Where the controlled frame is at one instant, and how it moves with the joints.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrameState<const N: usize> {
    /// The frame's origin in the base, m.
    pub position: Vector3,
    /// The frame's axes in base coordinates (the columns of `R`).
    pub orientation: Matrix3,
    /// Its geometric Jacobian in base coordinates: linear rows, then angular.
    pub jacobian: SMatrix<f64, 6, N>,
}

impl<const N: usize> FrameState<N> {
    /// From a pose as hya's kinematics give it (a [`Transform`](crate::spatial::Transform) from
    /// the base to the frame, whose `rotation` is `Rᵀ`) and the Jacobian.
    pub fn from_pose(pose: &crate::spatial::Transform, jacobian: SMatrix<f64, 6, N>) -> Self {
        Self { position: pose.translation, orientation: pose.orientation(), jacobian }
    }

    /// The frame `kinematics` gives at `q`: a generated arm's tip, without allocating.
    pub fn of(kinematics: &impl crate::FrameKinematics<N>, q: &JointVector<N>) -> Self {
        Self::from_pose(&kinematics.frame_pose(q), kinematics.frame_jacobian(q))
    }
}

#[cfg(feature = "alloc")]
impl<const N: usize> FrameState<N> {
    /// The named frame of a run-time model at `q` ([`crate::model::TreeModel::frame_pose`] and
    /// [`frame_jacobian`](crate::model::TreeModel::frame_jacobian); allocates). An unknown frame,
    /// or a model that does not have `N` joints, is refused.
    pub fn of_tree(
        model: &crate::model::TreeModel,
        frame: &str,
        q: &JointVector<N>,
    ) -> Result<Self, crate::model::ModelError> {
        let pose = model.frame_pose(frame, q.as_slice())?;
        let jacobian = model.frame_jacobian(frame, q.as_slice())?;
        Ok(Self::from_pose(&pose, SMatrix::<f64, 6, N>::from_fn(|r, c| jacobian[(r, c)])))
    }
}

/// A named frame of a run-time model whose kinematics ([`FrameState`]) are computed into
/// workspaces sized once here: after [`TreeFrame::new`], [`TreeFrame::state`] does not allocate,
/// so a controller on any URDF can run in a real-time loop.
#[cfg(feature = "alloc")]
#[derive(Debug, Clone)]
pub struct TreeFrame<const N: usize> {
    model: crate::model::TreeModel,
    frame: crate::model::Frame,
    bodies: alloc::vec::Vec<crate::model::BodyState>,
    placements: alloc::vec::Vec<crate::spatial::Transform>,
    jacobian: alloc::vec::Vec<f64>,
}

#[cfg(feature = "alloc")]
impl<const N: usize> TreeFrame<N> {
    /// The frame called `frame` of `model` (its last link when `None`); a frame the model does
    /// not have (the error lists its frames), or a model without `N` joints, is refused.
    pub fn new(model: crate::model::TreeModel, frame: Option<&str>) -> Result<Self, crate::model::ModelError> {
        use crate::model::ModelError;
        if model.dof() != N {
            return Err(ModelError::Dimension { what: "joints", expected: N, got: model.dof() });
        }
        let frame = match frame {
            Some(name) => model.frame(name)?.clone(),
            None => model.tip_frame().cloned().ok_or(ModelError::Dimension { what: "frames", expected: 1, got: 0 })?,
        };
        Ok(Self {
            bodies: alloc::vec![crate::model::BodyState::new(); N],
            placements: alloc::vec![crate::spatial::Transform::identity(); N],
            jacobian: alloc::vec![0.0; 6 * N],
            model,
            frame,
        })
    }

    /// The frame's name.
    pub fn name(&self) -> &str {
        &self.frame.name
    }

    /// The frame at `q` (finite: the caller's check), without allocating.
    pub fn state(&mut self, q: &JointVector<N>) -> FrameState<N> {
        use crate::model::{algorithms, kinematics};
        // The workspaces have the model's lengths, fixed at construction: neither call can fail.
        let placed = algorithms::body_placements(&self.model, q.as_slice(), &mut self.bodies, &mut self.placements);
        let jacobian = kinematics::frame_jacobian(&self.model, &self.frame, &self.placements, &mut self.jacobian);
        debug_assert!(placed.is_ok() && jacobian.is_ok());
        let pose = kinematics::frame_placement(&self.frame, &self.placements);
        FrameState::from_pose(&pose, SMatrix::<f64, 6, N>::from_row_slice(&self.jacobian))
    }
}

/// The Cartesian impedance controller on a run-time model's frame ([`TreeFrame`]): the frame's
/// kinematics and the law in one call, without allocating after construction.
#[cfg(feature = "alloc")]
#[derive(Debug, Clone)]
pub struct FrameImpedance<const N: usize, D> {
    controller: CartesianImpedance<N, D>,
    frame: TreeFrame<N>,
}

#[cfg(feature = "alloc")]
impl<const N: usize, D: Dynamics<N>> FrameImpedance<N, D> {
    /// `controller` holding `frame`.
    pub fn new(controller: CartesianImpedance<N, D>, frame: TreeFrame<N>) -> Self {
        Self { controller, frame }
    }

    /// The controlled frame's name.
    pub fn frame_name(&self) -> &str {
        self.frame.name()
    }

    /// The controller.
    pub fn controller(&self) -> &CartesianImpedance<N, D> {
        &self.controller
    }

    /// The frame's kinematics at `q` (finite), without allocating ([`TreeFrame::state`]).
    pub fn frame_state(&mut self, q: &JointVector<N>) -> FrameState<N> {
        self.frame.state(q)
    }

    /// [`CartesianImpedance::command`] with the frame's kinematics at the measured `q`.
    pub fn command(
        &mut self,
        q: &JointVector<N>,
        qd: &JointVector<N>,
        reference: &CartesianReference,
        disturbance_estimate: Option<&JointVector<N>>,
    ) -> Result<Command<N>, Error> {
        // A non-finite `q` gives a non-finite frame, which the law refuses, naming `q` first.
        let frame = self.frame.state(q);
        self.controller.command(q, qd, &frame, reference, disturbance_estimate)
    }
}

/// The desired pose and twist of the frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CartesianReference {
    /// Desired origin in the base, m.
    pub position: Vector3,
    /// Desired axes in base coordinates; must be a rotation.
    pub orientation: Matrix3,
    /// Desired twist in base coordinates (m/s, then rad/s).
    pub twist: Vector6,
}

impl CartesianReference {
    /// Hold still at a pose.
    pub fn hold(position: Vector3, orientation: Matrix3) -> Self {
        Self { position, orientation, twist: Vector6::zeros() }
    }
}

/// The projector's damping `μ` unless set otherwise (m): small against the Jacobian's entries of
/// an arm's links, large enough to keep `(J Jᵀ + μ² I)` factorable at a singular pose.
pub const DEFAULT_REGULARISATION: f64 = 1e-3;

/// The gains of the task-space spring and damper and of the posture in its null space.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Impedance<const N: usize> {
    stiffness: Vector6,
    damping: Vector6,
    posture_stiffness: JointVector<N>,
    posture_damping: JointVector<N>,
    rest: JointVector<N>,
    regularisation: f64,
}

impl<const N: usize> Impedance<N> {
    /// A spring `K_x` (N/m for the first three entries, N·m/rad for the last three) and a damper
    /// `D_x` (N·s/m, N·m·s/rad) at the frame, and no posture term; `μ` =
    /// [`DEFAULT_REGULARISATION`]. Every entry
    /// must be finite and non-negative.
    pub fn new(stiffness: [f64; 6], damping: [f64; 6]) -> Result<Self, Error> {
        non_negative("stiffness", &stiffness)?;
        non_negative("damping", &damping)?;
        Ok(Self {
            stiffness: stiffness.into(),
            damping: damping.into(),
            posture_stiffness: JointVector::zeros(),
            posture_damping: JointVector::zeros(),
            rest: JointVector::zeros(),
            regularisation: DEFAULT_REGULARISATION,
        })
    }

    /// The gains from slices, as the front ends hold them (the C ABI, Python): `stiffness` and
    /// `damping` of six values each ([`Self::new`]), the posture's `[rest, K_n, D_n]` given all
    /// three (`N` values each, [`Self::with_posture`]) or none, and `μ`
    /// ([`Self::with_regularisation`]). Every length is checked here, so all front ends refuse
    /// the same inputs.
    pub fn from_slices(
        stiffness: &[f64],
        damping: &[f64],
        posture: [Option<&[f64]>; 3],
        mu: f64,
    ) -> Result<Self, Error> {
        let six = |name: &'static str, values: &[f64]| -> Result<[f64; 6], Error> {
            values.try_into().map_err(|_| Error::InvalidParameter {
                name,
                value: values.len() as f64,
                requirement: "6 values (the value is how many were given): x, y, z, then the three rotations",
            })
        };
        let joints = |signal: &'static str, values: &[f64]| -> Result<[f64; N], Error> {
            values.try_into().map_err(|_| Error::SliceLength { signal, expected: N, got: values.len() })
        };
        let gains = Self::new(six("stiffness", stiffness)?, six("damping", damping)?)?.with_regularisation(mu)?;
        match posture {
            [None, None, None] => Ok(gains),
            [Some(rest), Some(k), Some(d)] => gains.with_posture(
                joints("posture_rest", rest)?,
                joints("posture_stiffness", k)?,
                joints("posture_damping", d)?,
            ),
            given => Err(Error::InvalidParameter {
                name: "posture",
                value: given.iter().flatten().count() as f64,
                requirement:
                    "posture_rest, posture_stiffness and posture_damping all given or none (the value is how many were)",
            }),
        }
    }

    /// Holds the joints near `rest` (rad) in the task's null space with `K_n` (N·m/rad) and
    /// `D_n` (N·m·s/rad) per joint, finite and non-negative.
    pub fn with_posture(mut self, rest: [f64; N], stiffness: [f64; N], damping: [f64; N]) -> Result<Self, Error> {
        non_negative("posture_stiffness", &stiffness)?;
        non_negative("posture_damping", &damping)?;
        if let Some(&value) = rest.iter().find(|v| !v.is_finite()) {
            return Err(Error::InvalidParameter { name: "rest", value, requirement: "finite" });
        }
        self.rest = rest.into();
        self.posture_stiffness = stiffness.into();
        self.posture_damping = damping.into();
        Ok(self)
    }

    /// The spring `K_x` (N/m for the first three entries, N·m/rad for the last three).
    pub fn stiffness(&self) -> Vector6 {
        self.stiffness
    }

    /// The projector's damping `μ` (finite and `≥ 0`; the same for the linear and the angular
    /// rows; 0 is the exact, undamped projector, wrong near singular poses).
    pub fn with_regularisation(mut self, mu: f64) -> Result<Self, Error> {
        non_negative("mu", &[mu])?;
        self.regularisation = mu;
        Ok(self)
    }
}

/// `Err` naming the first entry of `values` that is not finite and `≥ 0`.
fn non_negative(name: &'static str, values: &[f64]) -> Result<(), Error> {
    match values.iter().find(|v| !(v.is_finite() && **v >= 0.0)) {
        Some(&value) => Err(Error::InvalidParameter { name, value, requirement: "finite and >= 0" }),
        None => Ok(()),
    }
}

/// The rotation vector `θ u` of a rotation matrix `R` (`R = exp([θ u]×)`, `0 ≤ θ ≤ π`):
/// `θ = atan2(‖v‖, (tr R − 1)/2)` with `v = ½ (R₃₂ − R₂₃, R₁₃ − R₃₁, R₂₁ − R₁₂) = sin θ u`; near
/// `θ = π`, where `v` vanishes, `u` is the column of `(R + Rᵀ)/2 − cos θ I = (1 − cos θ) u uᵀ`
/// with the largest diagonal, signed as `v`.
pub fn rotation_vector(r: &Matrix3) -> Vector3 {
    let v = Vector3::new(r[(2, 1)] - r[(1, 2)], r[(0, 2)] - r[(2, 0)], r[(1, 0)] - r[(0, 1)]) * 0.5;
    let cosine = ((r.trace() - 1.0) * 0.5).clamp(-1.0, 1.0);
    let sine = v.norm();
    let angle = libm::atan2(sine, cosine);
    if cosine > -0.9 {
        // θ/sin θ → 1 as θ → 0.
        return if sine > 1e-12 { v * (angle / sine) } else { v };
    }
    // (R + Rᵀ)/2 − cos θ I = (1 − cos θ) u uᵀ: its column of largest diagonal is along u.
    let outer = (r + r.transpose()) * 0.5 - Matrix3::identity() * cosine;
    let column = (0..3).max_by(|&a, &b| outer[(a, a)].total_cmp(&outer[(b, b)])).unwrap_or(0);
    let axis = outer.column(column).normalize();
    let axis = if axis.dot(&v) < 0.0 { -axis } else { axis };
    axis * angle
}

/// Cartesian impedance controller for an arm with `N` joints, generic over its [`Dynamics`].
#[derive(Debug, Clone)]
pub struct CartesianImpedance<const N: usize, D> {
    dynamics: D,
    impedance: Impedance<N>,
    torque_limit: Option<JointVector<N>>,
}

impl<const N: usize, D: Dynamics<N>> CartesianImpedance<N, D> {
    /// The controller of `dynamics` with these gains, no torque limits.
    pub fn new(dynamics: D, impedance: Impedance<N>) -> Self {
        Self { dynamics, impedance, torque_limit: None }
    }

    /// Saturates joint `i` to `[−limit[i], limit[i]]` N·m; every limit must be finite and `> 0`.
    pub fn with_torque_limit(mut self, limit: JointVector<N>) -> Result<Self, Error> {
        self.torque_limit = Some(checked_torque_limit(limit)?);
        Ok(self)
    }

    /// The gains in use.
    pub fn impedance(&self) -> &Impedance<N> {
        &self.impedance
    }

    /// The pose error `e = (p_des − p, log(R_des Rᵀ))` the spring acts on.
    pub fn pose_error(frame: &FrameState<N>, reference: &CartesianReference) -> Vector6 {
        let rotation = rotation_vector(&(reference.orientation * frame.orientation.transpose()));
        let translation = reference.position - frame.position;
        Vector6::new(translation.x, translation.y, translation.z, rotation.x, rotation.y, rotation.z)
    }

    /// The commanded torque for state `(q, q̇)` with the frame at `frame`, the reference and, with
    /// compensation, `d̂` (see the module's notes). Non-finite inputs, a reference orientation
    /// that is not a rotation (`‖R_desᵀ R_des − I‖ > 10⁻⁶`) or a non-finite law are refused; a
    /// non-finite command is never returned.
    pub fn command(
        &self,
        q: &JointVector<N>,
        qd: &JointVector<N>,
        frame: &FrameState<N>,
        reference: &CartesianReference,
        disturbance_estimate: Option<&JointVector<N>>,
    ) -> Result<Command<N>, Error> {
        check("q", q)?;
        check("qd", qd)?;
        check("frame_position", &frame.position)?;
        check("frame_orientation", &frame.orientation)?;
        check("frame_jacobian", &frame.jacobian)?;
        check("position_des", &reference.position)?;
        check("orientation_des", &reference.orientation)?;
        check("twist_des", &reference.twist)?;
        let off_rotation = (reference.orientation.transpose() * reference.orientation - Matrix3::identity()).norm();
        let determinant = reference.orientation.determinant();
        if off_rotation > 1e-6 || determinant < 0.0 {
            return Err(Error::InvalidParameter {
                name: "orientation_des",
                value: if off_rotation > 1e-6 { off_rotation } else { determinant },
                requirement: "a rotation: orthonormal (the value is ‖RᵀR − I‖), determinant +1 (else the value)",
            });
        }
        let gains = &self.impedance;
        let jacobian = &frame.jacobian;
        let twist_error = jacobian * qd - reference.twist;
        let wrench = gains.stiffness.component_mul(&Self::pose_error(frame, reference))
            - gains.damping.component_mul(&twist_error);
        let posture =
            -gains.posture_stiffness.component_mul(&(q - gains.rest)) - gains.posture_damping.component_mul(qd);
        let regularised = jacobian * jacobian.transpose()
            + SMatrix::<f64, 6, 6>::identity() * (gains.regularisation * gains.regularisation);
        let projector = match regularised.cholesky() {
            Some(factor) => JointMatrix::<N>::identity() - jacobian.transpose() * factor.solve(jacobian),
            // Singular without damping: no posture term rather than a wrong one.
            None => JointMatrix::<N>::zeros(),
        };
        let torque = jacobian.transpose() * wrench
            + self.dynamics.inverse_dynamics(q, qd, &JointVector::zeros())
            + projector * posture;
        compensated(torque, disturbance_estimate, self.torque_limit.as_ref())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rotation(axis: Vector3, angle: f64) -> Matrix3 {
        nalgebra::Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(axis), angle).into_inner()
    }

    #[test]
    fn the_rotation_vector_inverts_the_exponential_up_to_half_a_turn() {
        for (axis, angle) in [
            (Vector3::new(1.0, 2.0, -0.5), 0.0),
            (Vector3::new(1.0, 2.0, -0.5), 1e-9),
            (Vector3::new(0.0, 0.0, 1.0), 0.7),
            (Vector3::new(-1.0, 0.3, 0.2), 2.5),
            (Vector3::new(0.3, -1.0, 0.4), 3.0),
            (Vector3::new(0.3, -1.0, 0.4), core::f64::consts::PI - 1e-9),
        ] {
            let expected = axis.normalize() * angle;
            let found = rotation_vector(&rotation(axis, angle));
            assert!((found - expected).norm() < 1e-8, "{angle}: {found:?} vs {expected:?}");
        }
    }
}
