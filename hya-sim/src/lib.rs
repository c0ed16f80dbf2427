//! # hya-sim
//!
//! A closed-loop testbed for the paper's experiments: a simulated hydraulic arm (true dynamics
//! with perturbed parameters, friction, hydraulic torque loops, sensor noise, external loads)
//! under computed-torque control with each disturbance observer, and a report of what each buys.
//!
//! ```no_run
//! let scenario = hya_sim::Scenario::builtin("goto_internal")?;
//! for outcome in hya_sim::run_scenario::<6>(&scenario.quick())? {
//!     println!("{} {}: {:?}", outcome.scenario, outcome.method.name(), outcome.metrics.rmse_q);
//! }
//! # Ok::<(), hya_sim::SimError>(())
//! ```

pub mod claims;
pub mod cost;
pub mod frequency;
pub mod input;
pub mod linear;
pub mod metrics;
pub mod output;
pub mod plant;
pub mod report;
pub mod robot;
pub mod rollout;
pub mod run;
pub mod scenario;
pub mod seeds;
pub mod sensors;
pub mod settings;
pub mod svg;
pub mod sweep;
pub mod task;

pub use metrics::Metrics;
pub use robot::{with_robot, ForRobot, Robot};
pub use run::{simulate, RunOutcome, Trace};
pub use scenario::{Method, Scenario};

/// Joints of HyA, the paper's arm: the size of the experiments that only HyA runs (the plant
/// checks against MuJoCo, the viscous-friction and frequency sweeps, the benchmarks).
pub const HYA_JOINTS: usize = 6;

/// The most joints a simulated arm may have (`hya run` instantiates the simulator for each size
/// from 1 to this).
pub const MAX_JOINTS: usize = hya_core::dispatch::MAX_JOINTS;

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
    /// A setting that does not fit the robot.
    #[error("{0}")]
    Config(String),
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
    /// A run whose cost is beyond a documented cap ([`cost`]).
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

/// Runs every method of `scenario`, in order.
pub fn run_scenario<const N: usize>(scenario: &Scenario) -> Result<Vec<RunOutcome<N>>, SimError> {
    let robot = Robot::<N>::load(&scenario.robot)?;
    scenario.methods.iter().map(|&method| simulate(scenario, method, &robot)).collect()
}

/// Runs one method of `scenario` on its robot, which must have `N` joints (see [`Robot::load`];
/// [`robot::with_robot`] finds `N` instead).
pub fn run_method<const N: usize>(scenario: &Scenario, method: Method) -> Result<RunOutcome<N>, SimError> {
    simulate(scenario, method, &Robot::<N>::load(&scenario.robot)?)
}

/// What `hya reproduce` and `hya run` do: every method of every scenario (all on one robot)
/// over `seeds` seeds, then the report in `out`; `progress` is told each run's simulated
/// seconds.
pub struct Experiment<'a> {
    /// The scenarios, checked.
    pub scenarios: &'a [Scenario],
    /// Seeds per scenario and method.
    pub seeds: usize,
    /// Told each finished run's simulated seconds.
    pub progress: &'a (dyn Fn(f64) + Sync),
    /// The report's folder, held by this run.
    pub out: &'a output::OutputDir,
    /// Whether the scenarios were shortened (`--quick`).
    pub quick: bool,
    /// The command that asked, named in the report.
    pub generated_by: &'a str,
}

impl Experiment<'_> {
    /// Runs it on the scenarios' robot, whatever its number of joints.
    pub fn run(self) -> Result<report::Summary, SimError> {
        let Some(first) = self.scenarios.first() else { return Err(SimError::Config("no scenario to run".into())) };
        if let Some(other) = self.scenarios.iter().find(|s| s.robot != first.robot) {
            return Err(SimError::Config(format!(
                "one report covers one robot: `{}` runs `{}`, `{}` runs `{}`",
                first.name, first.robot, other.name, other.robot
            )));
        }
        robot::with_robot(&first.robot.clone(), self)
    }
}

impl ForRobot for Experiment<'_> {
    type Output = report::Summary;
    fn call<const N: usize>(self, robot: Robot<N>) -> Result<report::Summary, SimError> {
        let (outcomes, table) = seeds::run_seeds::<N>(&robot, self.scenarios, self.seeds, self.progress)?;
        report::write(&robot, self.out, self.scenarios, &outcomes, &table, self.quick, self.generated_by)
    }
}
