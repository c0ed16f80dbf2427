//! The simulator's error type, and the one for a setting that breaks its rule.

use hya_core::dispatch::MAX_JOINTS;
use hya_core::Short;

/// A setting that breaks its rule: the key (as in the scenario's TOML, with the joint index for a
/// per-joint list), the value where it is one number, and the rule.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("invalid setting `{key}`{}: {rule}", value.map(|v| format!(" = {}", Short(v))).unwrap_or_default())]
pub struct SettingError {
    /// The key, e.g. `plant.coulomb_nm[2]`.
    pub key: String,
    /// The value, where it is one number.
    pub value: Option<f64>,
    /// What the value must satisfy.
    pub rule: String,
}

impl SettingError {
    /// The setting `key` = `value` breaks `rule`.
    pub fn new(key: impl Into<String>, value: Option<f64>, rule: impl Into<String>) -> Self {
        Self { key: key.into(), value, rule: rule.into() }
    }
}

/// A parameter of a linearised loop or an observer's design transfer function
/// ([`crate::linear`]) that breaks its rule: a design's input, not a scenario's setting.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("loop parameter `{name}` = {}: must be {rule}", Short(*value))]
pub struct ParameterError {
    /// The parameter, e.g. `joint.kp`.
    pub name: &'static str,
    /// Its value.
    pub value: f64,
    /// What it must satisfy.
    pub rule: &'static str,
}

/// Errors of the simulator, naming the setting or the moment at fault.
#[derive(Debug, thiserror::Error)]
pub enum SimError {
    /// A scenario file that does not parse or check.
    #[error("scenario {origin}: {message}")]
    Scenario {
        /// The file or built-in name.
        origin: String,
        /// What is wrong.
        message: String,
    },
    /// A sweep shard that cannot be merged.
    #[error("shard {shard}: {message}")]
    Shard {
        /// Where the shard came from.
        shard: String,
        /// What is wrong with it.
        message: String,
    },
    /// A scenario whose setting breaks its rule.
    #[error("scenario {origin}: {setting}")]
    InvalidScenario {
        /// The file or built-in name.
        origin: String,
        /// The setting.
        setting: SettingError,
    },
    /// A sampled reference (`hya track`'s rows) the loop cannot follow: the sample, from 1, and
    /// the value that breaks the rule.
    #[error("invalid reference sample {sample} = {}: {rule}", Short(*value))]
    Reference {
        /// The sample, and where it says more (its time, the joint).
        sample: String,
        /// The value.
        value: f64,
        /// What it must satisfy.
        rule: String,
    },
    /// A robot that is neither a shipped arm nor a URDF file (the message suggests the nearest
    /// name), or a registry that disagrees with itself.
    #[error("robot: {0}")]
    UnknownRobot(String),
    /// A file a setting names (the controller's model or friction) whose content does not fit:
    /// the setting, the file and why.
    #[error("the file of `{setting}`: {message}")]
    NamedFile {
        /// The setting, e.g. `controller.model_urdf`.
        setting: &'static str,
        /// The file and what is wrong with it.
        message: String,
    },
    /// A linearised loop's parameter that breaks its rule.
    #[error(transparent)]
    Parameter(#[from] ParameterError),
    /// A setting that breaks its rule, or does not fit the robot.
    #[error(transparent)]
    Setting(#[from] SettingError),
    /// A per-joint list with another number of values than the arm has joints.
    #[error("invalid setting `{key}`: expected {expected} values (one per joint), got {got}")]
    ListLength {
        /// The list's key, e.g. `plant.coulomb_nm`.
        key: String,
        /// The arm's joints.
        expected: usize,
        /// The values the list has.
        got: usize,
    },
    /// Several per-joint lists that do not fit the arm, all named at once.
    #[error(
        "{count} per-joint settings do not fit the arm's {expected} joints: {lists} (set each in the scenario, one \
         value per joint; a list left out takes HyA's six-joint default)"
    )]
    ListLengths {
        /// How many.
        count: usize,
        /// The arm's joints.
        expected: usize,
        /// Each list's key and length.
        lists: String,
    },
    /// A call with nothing to work on.
    #[error("nothing to do: {0}")]
    Nothing(&'static str),
    /// Shards of a sweep are missing from a merge.
    #[error("missing shards: {0}")]
    MissingShards(String),
    /// Reference data (the MuJoCo rollouts) that does not parse.
    #[error("reference data: {0}")]
    ReferenceData(String),
    /// The robot's description did not load.
    #[error(transparent)]
    Robot(#[from] hya_urdf::LoadError),
    /// A robot with another number of joints than the code asking for it.
    #[error("robot `{robot}` has {found} joints, not {expected}")]
    JointCount {
        /// The robot.
        robot: String,
        /// The joints asked for.
        expected: usize,
        /// The joints it has.
        found: usize,
    },
    /// A robot with more joints than the simulator is compiled for.
    #[error("robot `{robot}` has {dof} joints: the simulator runs arms of 1 to {MAX_JOINTS} joints")]
    TooManyJoints {
        /// The robot.
        robot: String,
        /// Its joints.
        dof: usize,
    },
    /// The robot's model does not fit what was asked of it.
    #[error(transparent)]
    Model(#[from] hya_core::model::ModelError),
    /// A filter, observer or controller refused its settings.
    #[error("{setting}: {source}")]
    Setup {
        /// What was being set up (`lu`, `sensors.velocity = "filter"`, …).
        setting: String,
        /// What it refused.
        source: hya_core::Error,
    },
    /// A filter, observer or controller refused a step of the closed loop.
    #[error("numerical failure at t = {time_s:.3} s: {source}")]
    Step {
        /// Simulated time, s.
        time_s: f64,
        /// What failed.
        source: hya_core::Error,
    },
    /// The simulated arm ran away: a joint passed a speed no arm reaches, then a dynamics call
    /// failed (or the state became non-finite). Names the joint, when and how fast, so the
    /// failure is not blamed on the model (a mass matrix positive definite everywhere).
    #[error(
        "the simulated arm diverged: joint {joint} {} at t = {} s; at t = {} s then: {cause} (the torques or the \
         plant's settings drive it faster than the step follows)",
        if velocity.is_finite() {
            format!("passed {} rad/s, a speed no arm reaches,", Short(*limit_rad_s))
        } else {
            "reached a non-finite state".into()
        },
        Short(*runaway_s), Short(*time_s)
    )]
    Diverged {
        /// When the integration broke down, s.
        time_s: f64,
        /// The joint, from 1.
        joint: usize,
        /// When it first passed the plausible speed, s.
        runaway_s: f64,
        /// Its velocity then, rad/s.
        velocity: f64,
        /// The speed it passed, rad/s: the plant's plausible limit.
        limit_rad_s: f64,
        /// What failed.
        cause: String,
    },
    /// A run whose cost is beyond a documented cap ([`crate::config::cost`]).
    #[error("{0}")]
    Cost(String),
    /// The summary could not be serialised.
    #[error("summary.json: {0}")]
    Json(#[from] serde_json::Error),
    /// One run of many failed: which one, and why.
    #[error("{run}: {source}")]
    Run {
        /// Scenario, method and seed.
        run: String,
        /// What failed.
        source: Box<SimError>,
    },
    /// The simulation broke down numerically.
    #[error("numerical failure: {0}")]
    Numerical(String),
    /// The report folder cannot be used as asked (nothing was written or removed).
    #[error("--out {dir}: {message}")]
    Output {
        /// The folder.
        dir: String,
        /// Why.
        message: String,
    },
    /// Writing the report failed.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: String,
        /// The operating system's error.
        source: std::io::Error,
    },
}
