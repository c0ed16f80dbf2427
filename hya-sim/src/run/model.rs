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

use hya_core::{Dynamics, Gains, JointMatrix, JointVector};

use crate::config::scenario::Scenario;
use crate::config::settings::JointSettings;
use crate::error::{SettingError, SimError};
use crate::robot::Robot;
use hya_ident::JointFriction;

/// Rigid-body dynamics `D` with joint friction, and the armature `I_a q̈` where the friction file
/// has one, added to the torque it takes.
pub struct WithFriction<D> {
    dynamics: D,
    friction: JointFriction,
}

impl<D> WithFriction<D> {
    /// `dynamics` plus `friction` (checked for the arm's joints by its reader).
    pub fn new(dynamics: D, friction: JointFriction) -> Self {
        Self { dynamics, friction }
    }

    fn torque<const N: usize>(&self, qd: &JointVector<N>) -> JointVector<N> {
        JointVector::from_fn(|i, _| self.friction.torque(i, qd[i]))
    }
}

impl<const N: usize, D: Dynamics<N>> Dynamics<N> for WithFriction<D> {
    /// `ID(q, q̇, q̈) + τ_f(q̇) + I_a q̈`.
    fn inverse_dynamics(&self, q: &JointVector<N>, qd: &JointVector<N>, qdd: &JointVector<N>) -> JointVector<N> {
        let armature = JointVector::<N>::from_fn(|i, _| self.friction.armature(i) * qdd[i]);
        self.dynamics.inverse_dynamics(q, qd, qdd) + self.torque(qd) + armature
    }

    /// The rigid body's: friction stores no momentum.
    fn coriolis_transpose_times_velocity(&self, q: &JointVector<N>, qd: &JointVector<N>) -> JointVector<N> {
        self.dynamics.coriolis_transpose_times_velocity(q, qd)
    }

    /// The rigid body's plus the armature `diag(I_a)`: friction does not depend on `q̈`.
    fn mass_matrix(&self, q: &JointVector<N>) -> JointMatrix<N> {
        let mut mass = self.dynamics.mass_matrix(q);
        for i in 0..N {
            mass[(i, i)] += self.friction.armature(i);
        }
        mass
    }

    /// The rigid body's, with `∂τ_f,i/∂q̇_i = (c/s) sech²(q̇_i/s) + v` on the diagonal.
    fn inverse_dynamics_derivatives(
        &self,
        q: &JointVector<N>,
        qd: &JointVector<N>,
        qdd: &JointVector<N>,
    ) -> (JointMatrix<N>, JointMatrix<N>) {
        let (d_dq, mut d_dqd) = self.dynamics.inverse_dynamics_derivatives(q, qd, qdd);
        let f = &self.friction;
        for i in 0..N {
            let sech = 1.0 / (qd[i] / f.smoothing_rad_s).cosh();
            d_dqd[(i, i)] += f.coulomb_nm[i] / f.smoothing_rad_s * sech * sech + f.viscous_nm_s[i];
        }
        (d_dq, d_dqd)
    }
}

/// The model the scenario's controller and observers use on `robot` (see the module's notes),
/// where the scenario names one; `None` for the robot's own nominal dynamics, which the caller
/// then uses as they are (no added indirection in the loop).
pub fn controller_model<'a, const N: usize>(
    scenario: &Scenario,
    robot: &'a Robot<N>,
) -> Result<Option<Box<dyn Dynamics<N> + Send + Sync + 'a>>, SimError> {
    let controller = &scenario.controller;
    if controller.model_urdf.is_none() && controller.friction_toml.is_none() {
        return Ok(None);
    }
    let rigid: Box<dyn Dynamics<N> + Send + Sync + 'a> = match &controller.model_urdf {
        None => Box::new(robot.nominal.as_ref()),
        Some(path) => {
            let model = hya_urdf::load_file(path)?.model;
            if let Some(why) = hya_urdf::joints_differ(&model, &robot.model, "the robot's") {
                let path = hya_core::Clipped(path, 200);
                return Err(SettingError::new("controller.model_urdf", None, format!("{path}: {why}")).into());
            }
            Box::new(model.into_dynamics::<N>()?)
        }
    };
    Ok(Some(match &controller.friction_toml {
        None => rigid,
        Some(path) => {
            let friction = JointFriction::from_file(std::path::Path::new(path), N)
                .map_err(|e| SettingError::new("controller.friction_toml", None, e))?;
            Box::new(WithFriction::new(rigid, friction))
        }
    }))
}

/// The model the closed loop of a scenario runs on: the one the scenario names
/// ([`controller_model`]), else the robot's nominal dynamics. Every analysis of that loop (its
/// gains, its linearised margins) takes the same, so that it describes the loop that runs.
pub struct LoopModel<'a, const N: usize> {
    named: Option<Box<dyn Dynamics<N> + Send + Sync + 'a>>,
    nominal: &'a (dyn Dynamics<N> + Send + Sync),
}

impl<'a, const N: usize> LoopModel<'a, N> {
    /// `scenario`'s loop model on `robot`.
    pub fn of(scenario: &Scenario, robot: &'a Robot<N>) -> Result<Self, SimError> {
        Ok(Self { named: controller_model(scenario, robot)?, nominal: robot.nominal.as_ref() })
    }

    /// The dynamics.
    pub fn dynamics(&self) -> &(dyn Dynamics<N> + Send + Sync + 'a) {
        self.named.as_deref().unwrap_or(self.nominal)
    }

    /// The loop's design at the scenario's start pose, as the closed loop makes it: the PD
    /// ([`gains`](super::gains)), the model's `M_ii(q0)`, and the PID's `K_D` and `K_I` with the joints
    /// whose gain is capped ([`pid_gains`](super::pid_gains)).
    pub fn design(&self, scenario: &Scenario, joints: &JointSettings<N>) -> Result<LoopDesign<N>, SimError> {
        let pd = super::gains(self.dynamics(), scenario, joints)?;
        let inertia = self.dynamics().mass_matrix(&joints.initial_position).diagonal();
        let (pid_kd, integral, capped) = super::pid_gains(&pd, &inertia, scenario, joints);
        Ok(LoopDesign { pd, inertia, pid_kd, integral, capped })
    }
}

/// [`LoopModel::design`].
pub struct LoopDesign<const N: usize> {
    /// `K_P`, `K_D`.
    pub pd: Gains<N>,
    /// `M_ii(q0)`, kg·m².
    pub inertia: JointVector<N>,
    /// The PID's `K_D`, N·m·s/rad (`pd`'s but for [`crate::config::scenario::IntegralRule::PolePlacement`]).
    pub pid_kd: JointVector<N>,
    /// The PID's `K_I`, N·m/(rad·s).
    pub integral: JointVector<N>,
    /// Joints whose `K_I` the stability bound capped.
    pub capped: [bool; N],
}

/// How the report names the loop model of a scenario whose controller settings are
/// `controller`: "the robot's nominal model", or the URDF and friction file it names.
pub fn describe(controller: &crate::config::scenario::ControllerConfig) -> String {
    let rigid = match &controller.model_urdf {
        None => "the robot's nominal model".to_owned(),
        Some(path) => format!("the model of `{path}` ({}, `controller.model_urdf`)", file_digest(path)),
    };
    match &controller.friction_toml {
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

#[cfg(test)]
mod tests {
    use super::*;
    use hya_core::model::TreeModel;

    fn planar() -> TreeModel {
        hya_urdf::load_str(include_str!("../../../robots/urdf/planar2.urdf"), "planar2")
            .unwrap_or_else(|e| panic!("{e}"))
            .model
    }

    #[test]
    fn friction_adds_to_the_torque_and_its_derivative_matches_differences() {
        let rigid = planar().into_dynamics::<2>().unwrap_or_else(|e| panic!("{e}"));
        let friction = JointFriction::from_toml(
            "smoothing_rad_s = 0.1\ncoulomb_nm = [1.5, 0.8]\nviscous_nm_s = [0.6, 0.3]\noffset_nm = [0.1, -0.2]\n",
            2,
        )
        .unwrap_or_else(|e| panic!("{e}"));
        let model = WithFriction::new(&rigid, friction.clone());
        let (q, qd, qdd) =
            (JointVector::from([0.3, -0.4]), JointVector::from([0.05, -0.2]), JointVector::from([1.0, 2.0]));
        let added = model.inverse_dynamics(&q, &qd, &qdd) - rigid.inverse_dynamics(&q, &qd, &qdd);
        let want = JointVector::from([friction.torque(0, 0.05), friction.torque(1, -0.2)]);
        assert!((added - want).amax() < 1e-12, "{added} vs {want}");
        assert_eq!(model.mass_matrix(&q), rigid.mass_matrix(&q));
        let (_, exact) = model.inverse_dynamics_derivatives(&q, &qd, &qdd);
        let step = 1e-6;
        for j in 0..2 {
            let unit = JointVector::from_fn(|i, _| if i == j { step } else { 0.0 });
            let difference = (model.inverse_dynamics(&q, &(qd + unit), &qdd)
                - model.inverse_dynamics(&q, &(qd - unit), &qdd))
                / (2.0 * step);
            for i in 0..2 {
                assert!(
                    (exact[(i, j)] - difference[i]).abs() < 1e-7,
                    "∂τ{i}/∂q̇{j}: {} vs {}",
                    exact[(i, j)],
                    difference[i]
                );
            }
        }
    }
}
