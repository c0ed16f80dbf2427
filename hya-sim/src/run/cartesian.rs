//! The closed loop's controller for a task set in task space: the Cartesian impedance controller
//! ([`hya_core::CartesianImpedance`]) holding one frame of the arm to a reference pose that
//! moves by a minimum-jerk profile `s(t)` ([`super::task::minimum_jerk`]):
//!
//! ```text
//! p_des(t) = p₀ + s(t) Δp        R_des(t) = exp([s(t) θ]×) R₀        ẋ_des(t) = ṡ(t) (Δp, θ)
//! ```
//!
//! with `(p₀, R₀)` the frame's pose at the start pose, `Δp` the task's offset and `θ` its
//! rotation vector, both in the base: the turn keeps one axis, so the desired angular velocity is
//! `ṡ θ`. The frame's kinematics come from the robot's run-time model, into buffers sized once
//! ([`hya_core::TreeFrame`]): a tick does not allocate.

use hya_core::cartesian::{Matrix3, Vector3, Vector6};
use hya_core::model::TreeModel;
use hya_core::{CartesianImpedance, CartesianReference, Dynamics, FrameImpedance, FrameState, JointVector};

use crate::config::settings::{CartesianSetup, TaskSetup};
use crate::error::SimError;
use crate::run::task::minimum_jerk;

/// The loop's dynamics, as the closed loop holds them.
type LoopDynamics<'a, const N: usize> = &'a (dyn Dynamics<N> + Send + Sync + 'a);

/// A Cartesian task's controller and its moving reference.
#[derive(Clone)]
pub struct CartesianLaw<'a, const N: usize> {
    law: FrameImpedance<N, LoopDynamics<'a, N>>,
    start: (Vector3, Matrix3),
    offset: Vector3,
    rotation: Vector3,
    times: (f64, f64),
}

impl<'a, const N: usize> CartesianLaw<'a, N> {
    /// The controller of `setup` on the loop's dynamics `nominal`, with `torque_limit`, moving
    /// the frame as `task` says from its pose at `q0` on `model` (the robot's kinematics); `None`
    /// unless `task` is Cartesian.
    pub fn new(
        (setup, task): (&CartesianSetup<N>, &TaskSetup<N>),
        nominal: LoopDynamics<'a, N>,
        model: &TreeModel,
        (q0, torque_limit): (&JointVector<N>, JointVector<N>),
    ) -> Result<Option<Self>, SimError> {
        let TaskSetup::Cartesian { start_s, transition_s, offset, rotation } = *task else { return Ok(None) };
        let controller = CartesianImpedance::new(nominal, setup.impedance)
            .with_torque_limit(torque_limit)
            .map_err(|source| SimError::Setup { setting: "controller.torque_limit_nm".into(), source })?;
        let mut law = FrameImpedance::new(controller, setup.tree_frame(model)?);
        let at_start = law.frame_state(q0);
        Ok(Some(Self {
            law,
            start: (at_start.position, at_start.orientation),
            offset: offset.into(),
            rotation: rotation.into(),
            times: (start_s, transition_s),
        }))
    }

    /// The spring `K_x` (N/m, then N·m/rad).
    pub fn stiffness(&self) -> Vector6 {
        self.law.controller().impedance().stiffness()
    }

    /// The controlled frame's name.
    pub fn frame(&self) -> &str {
        self.law.frame_name()
    }

    /// The reference pose and twist at `t` (see the module's notes).
    pub fn reference(&self, t: f64) -> CartesianReference {
        let (s, ds, _) = minimum_jerk(t, self.times.0, self.times.1);
        let (p0, r0) = self.start;
        let turn = nalgebra::Rotation3::new(self.rotation * s).into_inner();
        let twist = Vector6::new(
            self.offset.x * ds,
            self.offset.y * ds,
            self.offset.z * ds,
            self.rotation.x * ds,
            self.rotation.y * ds,
            self.rotation.z * ds,
        );
        CartesianReference { position: p0 + self.offset * s, orientation: turn * r0, twist }
    }

    /// The frame's kinematics at `q` (finite), without allocating.
    pub fn frame_state(&mut self, q: &JointVector<N>) -> FrameState<N> {
        self.law.frame_state(q)
    }

    /// The pose error `(p_des − p, log(R_des Rᵀ))` at `t` with the arm at `q` (finite; m, rad).
    pub fn pose_error(&mut self, t: f64, q: &JointVector<N>) -> Vector6 {
        let frame = self.frame_state(q);
        CartesianImpedance::<N, LoopDynamics<'a, N>>::pose_error(&frame, &self.reference(t))
    }

    /// The command at `t` from the measured `q`, `q̇`, compensating `d̂` when given.
    pub fn command(
        &mut self,
        t: f64,
        (q, qd): (&JointVector<N>, &JointVector<N>),
        compensation: Option<&JointVector<N>>,
    ) -> Result<JointVector<N>, SimError> {
        let reference = self.reference(t);
        let command = self.law.command(q, qd, &reference, compensation);
        Ok(command.map_err(|source| SimError::Step { time_s: t, source })?.torque)
    }
}
