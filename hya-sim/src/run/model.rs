//! The controller's and observers' model: the robot's nominal dynamics, or the rigid body of the
//! URDF a scenario names (`controller.model_urdf`, an identified one), plus the joint friction it
//! names (`controller.friction_toml`), as `hya identify` defines both:
//!
//! ```text
//! ID_c(q, q̇, q̈) = ID(q, q̇, q̈) + τ_f(q̇),   τ_f = c tanh(q̇/s) + v q̇ + o
//! ```
//!
//! The computed-torque command `ID_c(q, q̇, q̈_cmd) − d̂` then carries the friction as a
//! feed-forward at the measured velocity, and every observer's `d̂` is what `ID_c` leaves.

use hya_core::{Dynamics, Gains, JointVector};

use crate::config::settings::{ModelFiles, Setup};
use crate::error::SimError;
use crate::robot::Robot;
use hya_ident::{JointFriction, WithFriction};

/// The model of `files` for the controller and observers on `robot` (see the module's notes),
/// where they name one; `None` for the robot's own nominal dynamics, which the caller then uses
/// as they are (no added indirection in the loop).
pub fn controller_model<'a, const N: usize>(
    files: &ModelFiles,
    robot: &'a Robot<N>,
) -> Result<Option<Box<dyn Dynamics<N> + Send + Sync + 'a>>, SimError> {
    if files.urdf.is_none() && files.friction.is_none() {
        return Ok(None);
    }
    let rigid: Box<dyn Dynamics<N> + Send + Sync + 'a> = match &files.urdf {
        None => Box::new(robot.nominal.as_ref()),
        Some(path) => {
            let model = hya_urdf::load_file(path)?.model;
            if let Some(why) = hya_urdf::joints_differ(&model, &robot.model, "the robot's") {
                let path = hya_core::Clipped(path, 200);
                return Err(SimError::NamedFile {
                    setting: "controller.model_urdf",
                    message: format!("{path}: {why}"),
                });
            }
            Box::new(model.into_dynamics::<N>()?)
        }
    };
    Ok(Some(match &files.friction {
        None => rigid,
        Some(path) => {
            let friction = JointFriction::from_file(std::path::Path::new(path), N)
                .map_err(|message| SimError::NamedFile { setting: "controller.friction_toml", message })?;
            Box::new(WithFriction::new(rigid, friction))
        }
    }))
}

/// The model the closed loop of a scenario runs on: the one its settings name
/// ([`controller_model`]), else the robot's nominal dynamics. Every analysis of that loop (its
/// gains, its linearised margins) takes the same, so that it describes the loop that runs.
pub struct LoopModel<'a, const N: usize> {
    named: Option<Box<dyn Dynamics<N> + Send + Sync + 'a>>,
    nominal: &'a (dyn Dynamics<N> + Send + Sync),
}

impl<'a, const N: usize> LoopModel<'a, N> {
    /// The loop model of `files` on `robot`.
    pub fn of(files: &ModelFiles, robot: &'a Robot<N>) -> Result<Self, SimError> {
        Ok(Self { named: controller_model(files, robot)?, nominal: robot.nominal.as_ref() })
    }

    /// The dynamics.
    pub fn dynamics(&self) -> &(dyn Dynamics<N> + Send + Sync + 'a) {
        self.named.as_deref().unwrap_or(self.nominal)
    }

    /// The loop's design at the scenario's start pose, as the closed loop makes it: the PD
    /// ([`gains`](super::gains)), the model's `M_ii(q0)`, and the PID's `K_D` and `K_I` with the joints
    /// whose gain is capped ([`pid_gains`](super::pid_gains)).
    pub fn design(&self, joints: &Setup<N>) -> Result<LoopDesign<N>, SimError> {
        self.design_at(joints, &joints.initial_position)
    }

    /// [`design`](Self::design) with the PID's `M_ii` taken at `q0`, where the loop's reference
    /// starts (the closed loop's; the PD's gains are the scenario's start pose's either way).
    pub fn design_at(&self, joints: &Setup<N>, q0: &JointVector<N>) -> Result<LoopDesign<N>, SimError> {
        let pd = super::gains(self.dynamics(), joints)?;
        let inertia = self.dynamics().mass_matrix(q0).diagonal();
        let (pid_kd, integral, capped) = super::pid_gains(&pd, &inertia, joints);
        Ok(LoopDesign { pd, pose: *q0, inertia, pid_kd, integral, capped })
    }
}

/// [`LoopModel::design`].
pub struct LoopDesign<const N: usize> {
    /// `K_P`, `K_D`.
    pub pd: Gains<N>,
    /// The pose `q0` of `M_ii`, rad.
    pub pose: JointVector<N>,
    /// `M_ii(q0)`, kg·m².
    pub inertia: JointVector<N>,
    /// The PID's `K_D`, N·m·s/rad (`pd`'s but for [`crate::config::scenario::IntegralRule::PolePlacement`]).
    pub pid_kd: JointVector<N>,
    /// The PID's `K_I`, N·m/(rad·s).
    pub integral: JointVector<N>,
    /// Joints whose `K_I` the stability bound capped.
    pub capped: [bool; N],
}

impl<const N: usize> LoopDesign<N> {
    /// The design of the loop of `joints` on `robot` at its start pose, as its closed loop makes
    /// it: its model loaded ([`LoopModel::design`]).
    pub fn of(joints: &Setup<N>, robot: &Robot<N>) -> Result<Self, SimError> {
        LoopModel::of(&joints.loop_model, robot)?.design(joints)
    }
}

/// How the report names the loop model of `files`: "the robot's nominal model", or the URDF and
/// friction file they name.
pub fn describe(files: &ModelFiles) -> String {
    let rigid = match &files.urdf {
        None => "the robot's nominal model".to_owned(),
        Some(path) => format!("the model of `{path}` ({}, `controller.model_urdf`)", file_digest(path)),
    };
    match &files.friction {
        None => rigid,
        Some(path) => format!(
            "{rigid}, plus the joint friction `τ_f(q̇)` of `{path}` ({}, `controller.friction_toml`)",
            file_digest(path)
        ),
    }
}

/// `SHA-256 …` of the file at `path`, so that a report names exactly what it ran on.
pub fn file_digest(path: &str) -> String {
    match crate::io::input::sha256_of(std::path::Path::new(path)) {
        Ok(sha256) => format!("SHA-256 `{sha256}`"),
        Err(why) => format!("no SHA-256: the file {why} now"),
    }
}
