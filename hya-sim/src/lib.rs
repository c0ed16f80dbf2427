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
pub mod metrics;
pub mod output;
pub mod plant;
pub mod report;
pub mod rollout;
pub mod run;
pub mod scenario;
pub mod seeds;
pub mod sensors;
pub mod settings;
pub mod svg;
pub mod sweep;
pub mod task;

use std::any::Any;

use hya_core::model::TreeModel;
use hya_core::spatial::RigidBodyInertia;
use hya_core::Dynamics;

pub use metrics::Metrics;
pub use run::{simulate, RunOutcome, Trace};
pub use scenario::{Method, Scenario};

/// Joints of HyA, the paper's arm: the size of the experiments that only HyA runs (the plant
/// checks against MuJoCo, the viscous-friction and frequency sweeps, the benchmarks).
pub const HYA_JOINTS: usize = 6;

/// The most joints a simulated arm may have (`hya run` instantiates the simulator for each size
/// from 1 to this).
pub const MAX_JOINTS: usize = 7;

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

/// The start pose of a scenario: its own, else the shipped robot's home pose (`robots.list`),
/// else zeros.
pub fn initial_position(scenario: &Scenario, dof: usize) -> Vec<f64> {
    match (&scenario.initial_position_rad, hya_robots::find(&scenario.robot)) {
        (Some(q), _) => q.clone(),
        (None, Some(robot)) => robot.home.to_vec(),
        (None, None) => vec![0.0; dof],
    }
}

/// The run-time model of a scenario's robot: a shipped robot by name, else a URDF file by path.
pub fn robot_model(robot: &str) -> Result<TreeModel, SimError> {
    Ok(match hya_robots::find(robot) {
        Some(shipped) => hya_urdf::load_str(shipped.urdf, shipped.name)?.model,
        None => hya_urdf::load_file(robot)?.model,
    })
}

/// Body inertias of a model in joint order, as parametric generated dynamics take them.
fn inertias<const N: usize>(model: &TreeModel) -> Result<[RigidBodyInertia; N], SimError> {
    let bodies = model.bodies();
    if bodies.len() != N {
        return Err(SimError::Config(format!("expected {N} joints, found {}", bodies.len())));
    }
    Ok(core::array::from_fn(|i| bodies[i].inertia))
}

/// A robot's nominal dynamics (the controller's and observers' model) and the factory of its
/// plant's rigid body.
type RobotDynamics<const N: usize> = (Box<dyn Dynamics<N> + Send + Sync>, Box<plant::DynamicsFactory<N>>);

/// For a shipped robot with `N` joints: its generated dynamics, and its parameter-holding
/// generated type fed the plant's perturbed inertias, so the plant runs generated code too.
fn shipped_dynamics<const N: usize>(robot: &str) -> Option<RobotDynamics<N>> {
    macro_rules! find {
        ($($module:ident $type:ident $parametric:ident $dof:literal [$($home:expr),*] $doc:literal;)*) => {$(
            if robot == stringify!($module) {
                let nominal: Box<dyn Dynamics<$dof> + Send + Sync> = Box::new(hya_robots::$type);
                let factory: Box<plant::DynamicsFactory<$dof>> = Box::new(|m: &TreeModel| {
                    Ok(Box::new(hya_robots::$parametric::new(&inertias::<$dof>(m)?)) as Box<dyn Dynamics<$dof>>)
                });
                // The pair has the caller's type exactly when the robot has `N` joints.
                let pair: Box<dyn Any> = Box::new((nominal, factory));
                return pair.downcast::<RobotDynamics<N>>().ok().map(|pair| *pair);
            }
        )*};
    }
    hya_robots::for_each_robot!(find);
    None
}

/// The dynamics a scenario runs on: a shipped robot's generated code, else the run-time model
/// of its URDF, for nominal model and plant alike.
fn robot_dynamics<const N: usize>(robot: &str, model: &TreeModel) -> Result<RobotDynamics<N>, SimError> {
    if let Some(found) = shipped_dynamics::<N>(robot) {
        return Ok(found);
    }
    if hya_robots::find(robot).is_some() {
        return Err(SimError::Config(format!("robot `{robot}` does not have {N} joints")));
    }
    let nominal = model.clone().into_dynamics::<N>().map_err(|e| SimError::Config(format!("robot `{robot}`: {e}")))?;
    Ok((Box::new(nominal), Box::new(plant::generic_dynamics::<N>)))
}

/// The nominal dynamics of a scenario's robot, with `N` joints.
pub fn nominal_dynamics<const N: usize>(robot: &str) -> Result<Box<dyn Dynamics<N> + Send + Sync>, SimError> {
    Ok(robot_dynamics::<N>(robot, &robot_model(robot)?)?.0)
}

/// Runs every method of `scenario`, in order.
pub fn run_scenario<const N: usize>(scenario: &Scenario) -> Result<Vec<RunOutcome<N>>, SimError> {
    scenario.methods.iter().map(|&method| run_method(scenario, method)).collect()
}

/// Runs one method of `scenario` on its robot, which must have `N` joints.
pub fn run_method<const N: usize>(scenario: &Scenario, method: Method) -> Result<RunOutcome<N>, SimError> {
    let model = robot_model(&scenario.robot)?;
    let (nominal, plant) = robot_dynamics::<N>(&scenario.robot, &model)?;
    simulate(scenario, method, nominal.as_ref(), &model, &plant)
}

/// Something to do with an arm of `N` joints, `N` known only at run time ([`with_joints`]).
pub trait ForJoints {
    /// What it gives.
    type Output;
    /// Does it for `N` joints.
    fn call<const N: usize>(self) -> Result<Self::Output, SimError>;
}

/// Calls `f` with `N = dof`, for 1 to [`MAX_JOINTS`] joints.
pub fn with_joints<F: ForJoints>(dof: usize, f: F) -> Result<F::Output, SimError> {
    match dof {
        1 => f.call::<1>(),
        2 => f.call::<2>(),
        3 => f.call::<3>(),
        4 => f.call::<4>(),
        5 => f.call::<5>(),
        6 => f.call::<6>(),
        7 => f.call::<7>(),
        _ => Err(SimError::Config(format!("{dof} joints: the simulator runs arms of 1 to {MAX_JOINTS} joints"))),
    }
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
        let dof = robot_model(&first.robot)?.dof();
        with_joints(dof, self)
    }
}

impl ForJoints for Experiment<'_> {
    type Output = report::Summary;
    fn call<const N: usize>(self) -> Result<report::Summary, SimError> {
        let (outcomes, table) = seeds::run_seeds::<N>(self.scenarios, self.seeds, self.progress)?;
        report::write(self.out, self.scenarios, &outcomes, &table, self.quick, self.generated_by)
    }
}
