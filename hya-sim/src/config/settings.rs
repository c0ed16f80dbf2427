//! A scenario's settings as a closed loop reads them, checked once for an arm of `N` joints
//! ([`Setup`]): every list becomes a [`JointVector<N>`] of the right length, finite and in
//! range, or the scenario is refused with the key named; the controller's scalars, the clock and
//! the sensors come along. The plant, the controller's gain rule, the PID, the task, the loop and
//! its metrics receive these typed settings; none of them reads the scenario again (the loop
//! model's files are loaded by [`crate::run::model::LoopModel`], once per scenario and method
//! with [`crate::run::RunSetup`]).
//!
//! A list is converted only where it acts: the bristle lists for LuGre friction, the time
//! constants for lag actuators, the valve and chamber lists for hydraulic ones, the integral
//! clamp for the PID; so a 7-joint arm with electric actuators need not restate HyA's six
//! hydraulic figures. The static friction levels are always read: the gain rule stiffens
//! against them. The plant's settings are typed by their kind ([`crate::config::plant`]).

use hya_core::model::TreeModel;
use hya_core::JointVector;

use crate::config::lists::{per_joint, per_joint_where, scalar};
use crate::config::plant::PlantSetup;
use crate::config::scenario::{
    CartesianConfig, ChenGain, ControllerConfig, IntegralRule, Method, NoiseConfig, Scenario, SensorConfig, Task,
};
use crate::error::{SettingError, SimError};
use crate::robot::{with_robot, ForRobot, Robot};

/// The start pose of a scenario: its own, else the shipped robot's home pose (`robots.list`),
/// else zeros.
pub fn initial_position(scenario: &Scenario, dof: usize) -> Vec<f64> {
    match (&scenario.initial_position_rad, hya_robots::find(&scenario.robot)) {
        (Some(q), _) => q.clone(),
        (None, Some(robot)) => robot.home.to_vec(),
        (None, None) => vec![0.0; dof],
    }
}

/// The task's reference around the start pose, checked.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TaskSetup<const N: usize> {
    /// Hold the start pose.
    Hold,
    /// A minimum-jerk move by `delta` (rad) from `start_s` over `transition_s > 0`, s.
    Goto {
        /// When the move starts, s.
        start_s: f64,
        /// Its duration, s.
        transition_s: f64,
        /// The step per joint, rad.
        delta: JointVector<N>,
    },
    /// `amplitude` (rad) times `sin 2π f t`, ramped in over `ramp_s ≥ 0` s.
    Sine {
        /// Per joint, rad.
        amplitude: JointVector<N>,
        /// `f > 0`, Hz.
        frequency_hz: f64,
        /// The ramp's duration, s (0: none).
        ramp_s: f64,
    },
    /// Hold the start pose in joint space (the posture's rest); the controlled frame follows a
    /// minimum-jerk move by `offset` (m, in the base) and a turn by the rotation vector
    /// `rotation` (rad, in the base) from `start_s` over `transition_s > 0`, s
    /// ([`crate::run::cartesian`]).
    Cartesian {
        /// When the move starts, s.
        start_s: f64,
        /// Its duration, s.
        transition_s: f64,
        /// The frame's displacement, m.
        offset: [f64; 3],
        /// The frame's turn, rad.
        rotation: [f64; 3],
    },
}

/// Three values as an array, each finite; the error names the key (the scenario's check has
/// held the length to three).
fn three(key: &str, values: &[f64]) -> Result<[f64; 3], SimError> {
    let v: JointVector<3> = per_joint(key, values)?;
    Ok(v.into())
}

impl<const N: usize> TaskSetup<N> {
    /// Checks and converts `task`.
    pub fn of(task: &Task) -> Result<Self, SimError> {
        Ok(match task {
            Task::Hold {} => Self::Hold,
            Task::Goto { start_s, transition_s, delta_rad } => Self::Goto {
                start_s: scalar("task.start_s", *start_s, |_| true, "must be finite")?,
                transition_s: scalar("task.transition_s", *transition_s, |t| t > 0.0, "must be > 0")?,
                delta: per_joint("task.delta_rad", delta_rad)?,
            },
            Task::Sine { amplitude_rad, frequency_hz, ramp_s } => Self::Sine {
                amplitude: per_joint("task.amplitude_rad", amplitude_rad)?,
                frequency_hz: scalar("task.frequency_hz", *frequency_hz, |f| f > 0.0, "must be > 0")?,
                ramp_s: scalar("task.ramp_s", *ramp_s, |r| r >= 0.0, "must be ≥ 0")?,
            },
            Task::Cartesian { start_s, transition_s, offset_m, rotation_rad } => Self::Cartesian {
                start_s: scalar("task.start_s", *start_s, |_| true, "must be finite")?,
                transition_s: scalar("task.transition_s", *transition_s, |t| t > 0.0, "must be > 0")?,
                offset: three("task.offset_m", offset_m)?,
                rotation: three("task.rotation_rad", rotation_rad)?,
            },
        })
    }
}

/// When a task moves, whatever its joints: what a metric's windows wait for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TaskTimes {
    /// Holds still.
    Hold,
    /// Moves over `[start_s, start_s + transition_s]`.
    Goto {
        /// When the move starts, s.
        start_s: f64,
        /// Its duration, s.
        transition_s: f64,
    },
    /// Moves throughout, ramped in over `ramp_s`.
    Sine {
        /// The ramp's duration, s.
        ramp_s: f64,
    },
}

impl TaskTimes {
    /// `task`'s times.
    pub fn of(task: &Task) -> Self {
        match *task {
            Task::Hold {} => Self::Hold,
            Task::Goto { start_s, transition_s, .. } => Self::Goto { start_s, transition_s },
            Task::Sine { ramp_s, .. } => Self::Sine { ramp_s },
            Task::Cartesian { start_s, transition_s, .. } => Self::Goto { start_s, transition_s },
        }
    }
}

impl<const N: usize> TaskSetup<N> {
    /// Its times.
    pub fn times(&self) -> TaskTimes {
        match *self {
            Self::Hold => TaskTimes::Hold,
            Self::Goto { start_s, transition_s, .. } => TaskTimes::Goto { start_s, transition_s },
            Self::Sine { ramp_s, .. } => TaskTimes::Sine { ramp_s },
            Self::Cartesian { start_s, transition_s, .. } => TaskTimes::Goto { start_s, transition_s },
        }
    }
}

/// The controller's scalar settings (the scenario's check has held each to its rule; the control
/// period is the clock's, [`Timing::dt_s`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ControlSetup {
    /// Every observer's pole magnitude, rad/s.
    pub observer_bandwidth_rad_s: f64,
    /// Chen's gain design.
    pub chen_gain: ChenGain,
    /// The PD's damping ratio `ζ`.
    pub damping_ratio: f64,
    /// The stiffest natural frequency the gain rule may give, rad/s.
    pub max_natural_frequency_rad_s: f64,
    /// The error `e_f` at which the PD's torque reaches the static friction, rad.
    pub friction_error_rad: f64,
    /// The PID's rule for `K_I` (and, by pole placement, `K_D`).
    pub integral_rule: IntegralRule,
    /// `K_I / (K_P ω_n)` under [`IntegralRule::ZeroRatio`].
    pub integral_zero_ratio: f64,
}

impl ControlSetup {
    /// `controller`'s scalars.
    pub fn of(controller: &ControllerConfig) -> Self {
        Self {
            observer_bandwidth_rad_s: controller.observer_bandwidth_rad_s,
            chen_gain: controller.chen_gain,
            damping_ratio: controller.damping_ratio,
            max_natural_frequency_rad_s: controller.max_natural_frequency_rad_s,
            friction_error_rad: controller.friction_error_rad,
            integral_rule: controller.integral_rule,
            integral_zero_ratio: controller.integral_zero_ratio,
        }
    }
}

/// A run's clock: the control period, the ticks, the plant's steps per tick.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Timing {
    /// The control period, s.
    pub dt_s: f64,
    /// Control ticks, `round(duration / dt)`.
    pub steps: usize,
    /// Plant integration steps per tick.
    pub substeps: usize,
}

impl Timing {
    /// `scenario`'s clock.
    pub fn of(scenario: &Scenario) -> Self {
        let dt_s = scenario.controller.dt_s;
        Self { dt_s, steps: (scenario.duration_s / dt_s).round() as usize, substeps: scenario.plant.substeps() }
    }

    /// The plant's integration step, s.
    pub fn physics_step_s(&self) -> f64 {
        self.dt_s / self.substeps as f64
    }

    /// The last tick's time, s.
    pub fn last_time_s(&self) -> f64 {
        self.steps.saturating_sub(1) as f64 * self.dt_s
    }
}

/// The files the controller's and observers' model comes from (`controller.model_urdf`,
/// `controller.friction_toml`), loaded by [`crate::run::model::LoopModel`]; neither: the robot's
/// nominal dynamics.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct ModelFiles {
    /// The rigid body's URDF.
    pub urdf: Option<String>,
    /// The joint friction's TOML.
    pub friction: Option<String>,
}

impl ModelFiles {
    /// `controller`'s.
    pub fn of(controller: &ControllerConfig) -> Self {
        Self { urdf: controller.model_urdf.clone(), friction: controller.friction_toml.clone() }
    }
}

/// Every setting of a scenario a closed loop reads, for an arm of `N` joints: the per-joint lists,
/// the task and the plant checked here; the controller's scalars, the clock and the sensors as
/// the scenario's own check left them. What runs below [`crate::config`] (the plant, the
/// sensors, the loop, its metrics) reads these, never the scenario.
#[derive(Debug, Clone, PartialEq)]
pub struct Setup<const N: usize> {
    /// The scenario's name, for errors.
    pub name: String,
    /// Its seed: the one a single run draws its plant, friction profiles and noise from.
    pub seed: u64,
    /// The controller's model.
    pub loop_model: ModelFiles,
    /// The start pose, rad.
    pub initial_position: JointVector<N>,
    /// The task.
    pub task: TaskSetup<N>,
    /// The controller's natural frequencies, rad/s.
    pub natural_frequency: JointVector<N>,
    /// The nominal static friction the gain rule stiffens against, N·m (`plant.static_nm`).
    pub static_friction: JointVector<N>,
    /// The PID's integral clamp, N·m (when the scenario runs `pid`).
    pub integral_limit: Option<JointVector<N>>,
    /// The controller's torque limits, N·m.
    pub torque_limit: JointVector<N>,
    /// The plant's.
    pub plant: PlantSetup<N>,
    /// The controller's scalars.
    pub control: ControlSetup,
    /// The clock.
    pub timing: Timing,
    /// The sensors.
    pub sensors: SensorConfig,
    /// Their noise.
    pub noise: NoiseConfig,
    /// The relative spread of the plant's inertial parameters about the model's.
    pub parameter_spread: f64,
    /// The task-space controller of a Cartesian task (its posture's rest the start pose).
    pub cartesian: Option<CartesianSetup<N>>,
}

/// The Cartesian impedance controller's settings, checked for an arm of `N` joints.
#[derive(Debug, Clone, PartialEq)]
pub struct CartesianSetup<const N: usize> {
    /// The controlled link; `None`: the description's last link.
    pub frame: Option<String>,
    /// The gains, the posture's rest at the start pose.
    pub impedance: hya_core::Impedance<N>,
}

impl<const N: usize> CartesianSetup<N> {
    /// Checks and converts `config`, the posture held around `rest`.
    fn of(config: &CartesianConfig, rest: &JointVector<N>) -> Result<Self, SimError> {
        let key = "controller.cartesian";
        // The posture lists checked here, by key; the rest by the library, as for C and Python.
        let posture = |name: &str, values: &[f64]| {
            per_joint_where::<N>(&format!("{key}.{name}"), values, |v| v >= 0.0, "must be ≥ 0")
        };
        let stiffness = posture("posture_stiffness_nm_rad", &config.posture_stiffness_nm_rad)?;
        let damping = posture("posture_damping_nm_s_rad", &config.posture_damping_nm_s_rad)?;
        let lists = [Some(rest.as_slice()), Some(stiffness.as_slice()), Some(damping.as_slice())];
        let impedance = hya_core::Impedance::from_slices(
            &config.stiffness,
            &config.damping,
            lists,
            hya_core::cartesian::DEFAULT_REGULARISATION,
        )
        .map_err(|source| SimError::Setup { setting: key.into(), source })?;
        Ok(Self { frame: config.frame.clone(), impedance })
    }

    /// The controlled frame of `model`, its kinematics' workspaces sized: the configured link if
    /// the model has it (else an error listing its links), else its last link.
    pub fn tree_frame(&self, model: &TreeModel) -> Result<hya_core::TreeFrame<N>, SimError> {
        hya_core::TreeFrame::new(model.clone(), self.frame.as_deref())
            .map_err(|e| SettingError::new("controller.cartesian.frame", None, e.to_string()).into())
    }
}

impl<const N: usize> Setup<N> {
    /// Checks and converts every per-joint list of `scenario` that acts (the PID's integral
    /// clamp where its methods name pid).
    pub fn of(scenario: &Scenario) -> Result<Self, SimError> {
        Self::reading(scenario, scenario.methods.contains(&Method::Pid))
    }

    /// [`Self::of`], reading the PID's integral clamp where `pid` says.
    fn reading(scenario: &Scenario, pid: bool) -> Result<Self, SimError> {
        let c = &scenario.controller;
        let initial_position = per_joint("initial_position_rad", &initial_position(scenario, N))?;
        Ok(Self {
            name: scenario.name.clone(),
            seed: scenario.seed,
            loop_model: ModelFiles::of(c),
            initial_position,
            task: TaskSetup::of(&scenario.task)?,
            natural_frequency: per_joint("controller.natural_frequency_rad_s", &c.natural_frequency_rad_s)?,
            static_friction: per_joint("plant.static_nm", &scenario.plant.static_nm)?,
            integral_limit: match pid {
                true => Some(per_joint("controller.integral_limit_nm", &c.integral_limit_nm)?),
                false => None,
            },
            torque_limit: per_joint("controller.torque_limit_nm", &c.torque_limit_nm)?,
            plant: PlantSetup::of(&scenario.plant, &scenario.loads)?,
            control: ControlSetup::of(c),
            timing: Timing::of(scenario),
            sensors: scenario.sensors.clone(),
            noise: scenario.noise.clone(),
            parameter_spread: scenario.plant.parameter_spread,
            cartesian: c.cartesian.as_ref().map(|config| CartesianSetup::of(config, &initial_position)).transpose()?,
        })
    }
}

impl<const N: usize> Setup<N> {
    /// The PID's integral clamp, N·m: read where the scenario runs `pid` or the settings are
    /// [`Self::for_run`]'s of a pid run (else an error naming the list; a run of pid has it).
    pub fn pid_integral_limit(&self) -> Result<JointVector<N>, SimError> {
        self.integral_limit.ok_or_else(|| {
            SettingError::new("controller.integral_limit_nm", None, "not read: the scenario's methods do not name pid")
                .into()
        })
    }

    /// [`Self::of`], and the settings that name a link checked against the arm's `model`: the
    /// weight drop's frame ([`PlantSetup::check_against`]) and the Cartesian controller's.
    pub fn for_arm(scenario: &Scenario, model: &TreeModel) -> Result<Self, SimError> {
        Self::of(scenario)?.checked_against(model)
    }

    /// [`Self::for_arm`] for one run of `method`: the PID's integral clamp read for a run of pid
    /// whatever the scenario's methods.
    pub fn for_run(scenario: &Scenario, method: Method, model: &TreeModel) -> Result<Self, SimError> {
        Self::reading(scenario, method == Method::Pid || scenario.methods.contains(&Method::Pid))?
            .checked_against(model)
    }

    /// These settings if the links they name are `model`'s.
    fn checked_against(self, model: &TreeModel) -> Result<Self, SimError> {
        self.plant.check_against(model)?;
        if let Some(cartesian) = &self.cartesian {
            cartesian.tree_frame(model)?;
        }
        Ok(self)
    }
}

/// The scenario checked against its robot: the per-joint lists, which need the joint count.
impl Scenario {
    /// Checks what [`Scenario::check`] cannot without the robot: that it loads, that every
    /// per-joint list that acts fits its joints, naming all lists that do not in one error
    /// ([`SimError::ListLengths`]) rather than one per run, and then everything
    /// [`Setup::for_arm`] checks (each list's values, the task, the plant's settings, the
    /// weight drop's frame). For a command to call before it prints its cost and starts
    /// simulating.
    pub fn check_for_robot(&self) -> Result<(), SimError> {
        struct Lists<'a>(&'a Scenario);
        impl ForRobot for Lists<'_> {
            type Output = ();
            fn call<const N: usize>(self, robot: Robot<N>) -> Result<(), SimError> {
                // Each list that does not fit is noted, then filled to N copies of its first
                // value in a copy of the scenario, so that the next one is found.
                let mut scenario = self.0.clone();
                let mut misfits = Vec::new();
                let first_error = loop {
                    match Setup::<N>::for_arm(&scenario, &robot.model) {
                        Ok(_) => break None,
                        Err(SimError::ListLength { key, got, .. }) if misfits.len() < 64 => {
                            scenario = scenario.with_list_filled(&key, N)?;
                            misfits.push(format!("`{key}` ({got} values)"));
                        }
                        Err(other) => break Some(other),
                    }
                };
                match (misfits.len(), first_error) {
                    (0, None) => Ok(()),
                    (0, Some(error)) => Err(error),
                    // A value check behind the misfits (such as `static_nm ≥ coulomb_nm` against
                    // a filled default) stops the search: it is named too.
                    (count, then) => {
                        let then = then.map(|e| format!("; then, with those filled: {e}")).unwrap_or_default();
                        Err(SimError::ListLengths { count, expected: N, lists: misfits.join(", ") + &then })
                    }
                }
            }
        }
        with_robot(&self.robot, Lists(self))
    }

    /// This scenario with the list at the dotted `key` (`plant.coulomb_nm`) replaced by `n`
    /// copies of its first value (0 if it has none).
    fn with_list_filled(&self, key: &str, n: usize) -> Result<Self, SimError> {
        let bad = |why: String| SimError::Scenario { origin: self.name.clone(), message: why };
        let mut value = toml::Value::try_from(self).map_err(|e| bad(e.to_string()))?;
        let mut slot = &mut value;
        for part in key.split('.') {
            slot = slot.get_mut(part).ok_or_else(|| bad(format!("no setting `{key}` (a bug)")))?;
        }
        let first = slot.as_array().and_then(|a| a.first()).cloned().unwrap_or(toml::Value::Float(0.0));
        *slot = toml::Value::Array(vec![first; n]);
        value.try_into().map_err(|e: toml::de::Error| bad(e.to_string()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lists_are_checked_once_with_their_key_named() {
        let mut scenario = Scenario::builtin("goto_internal").unwrap();
        assert!(Setup::<6>::of(&scenario).is_ok());
        let error = Setup::<7>::of(&scenario).unwrap_err().to_string();
        assert!(error.contains("expected 7 values"), "{error}");
        scenario.plant.bristle_damping_nm_s_rad[2] = -1.0;
        let error = Setup::<6>::of(&scenario).unwrap_err().to_string();
        assert!(error.contains("`plant.bristle_damping_nm_s_rad[2]` = -1"), "{error}");
        // Lists that do not act are not read: lag actuators ignore the hydraulic figures.
        scenario.plant.bristle_damping_nm_s_rad[2] = 1.0;
        scenario.plant.actuator = crate::config::scenario::ActuatorKind::Lag;
        scenario.plant.hydraulic.area_ratio = vec![];
        let plant = Setup::<6>::of(&scenario).unwrap().plant;
        assert!(matches!(plant.actuators, crate::config::plant::ActuatorSetup::Lag(_)));
        // The integral clamp is read only for a scenario that runs the PID.
        scenario.controller.integral_limit_nm = vec![];
        assert!(Setup::<6>::of(&scenario).unwrap_err().to_string().contains("controller.integral_limit_nm"));
        scenario.methods.retain(|m| *m != Method::Pid);
        let joints = Setup::<6>::of(&scenario).unwrap();
        assert!(joints.pid_integral_limit().unwrap_err().to_string().contains("controller.integral_limit_nm"));
        // A run of pid reads it whatever the scenario's methods, and refuses it there.
        let model = crate::robot::robot_model(&scenario.robot).unwrap();
        let error = Setup::<6>::for_run(&scenario, Method::Pid, &model).unwrap_err().to_string();
        assert!(error.contains("controller.integral_limit_nm"), "{error}");
        assert!(Setup::<6>::for_run(&scenario, Method::Lu, &model).is_ok());
    }

    #[test]
    fn the_task_and_the_weights_frame_are_checked_before_a_run() {
        let mut scenario = Scenario::builtin("goto_weight").unwrap();
        let model = crate::robot::robot_model(&scenario.robot).unwrap();
        assert!(Setup::<6>::for_arm(&scenario, &model).is_ok());
        scenario.loads.weight_drop.as_mut().unwrap().frame = "no_such_link".into();
        // `of` reads no model; `for_arm` and the check before a run name the frame.
        assert!(Setup::<6>::of(&scenario).is_ok());
        let error = Setup::<6>::for_arm(&scenario, &model).unwrap_err().to_string();
        assert!(error.contains("`loads.weight_drop.frame`") && error.contains("no_such_link"), "{error}");
        let error = scenario.check_for_robot().unwrap_err().to_string();
        assert!(error.contains("`loads.weight_drop.frame`"), "{error}");
        let task = |task: Task| TaskSetup::<1>::of(&task).unwrap_err().to_string();
        let goto = Task::Goto { start_s: 1.0, transition_s: 0.0, delta_rad: vec![0.1] };
        assert!(task(goto).contains("`task.transition_s` = 0"));
        let sine = Task::Sine { amplitude_rad: vec![0.1], frequency_hz: 0.5, ramp_s: -1.0 };
        assert!(task(sine).contains("`task.ramp_s` = -1"));
        let sine = Task::Sine { amplitude_rad: vec![0.1], frequency_hz: f64::NAN, ramp_s: 1.0 };
        assert!(task(sine).contains("`task.frequency_hz`"));
    }
}
