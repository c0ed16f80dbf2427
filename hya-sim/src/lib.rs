//! # hya-sim
//!
//! A closed-loop testbed for the paper's experiments: a simulated hydraulic arm (true dynamics
//! with perturbed parameters, friction, hydraulic torque loops, sensor noise, external loads)
//! under computed-torque control with each disturbance observer, and a report of what each buys.
//!
//! ```no_run
//! let scenario = hya_sim::Scenario::builtin("goto_internal")?;
//! for outcome in hya_sim::run_scenario(&scenario.quick())? {
//!     println!("{} {}: {:?}", outcome.scenario, outcome.method.name(), outcome.metrics.rmse_q);
//! }
//! # Ok::<(), hya_sim::SimError>(())
//! ```

pub mod claims;
pub mod frequency;
pub mod metrics;
pub mod output;
pub mod plant;
pub mod report;
pub mod rollout;
pub mod run;
pub mod scenario;
pub mod seeds;
pub mod sensors;
pub mod svg;
pub mod sweep;
pub mod task;

use hya_core::model::TreeModel;
use hya_core::spatial::RigidBodyInertia;
use hya_core::Dynamics;

pub use metrics::Metrics;
pub use run::{simulate, RunOutcome, Trace};
pub use scenario::{Method, Scenario};

/// Joints of the arms the simulator runs (HyA, UR5).
pub const JOINTS: usize = 6;

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
    /// A setting that does not fit the robot.
    #[error("{0}")]
    Config(String),
    /// The simulation broke down numerically.
    #[error("numerical failure: {0}")]
    Numerical(String),
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

/// The generated (nominal) dynamics of a 6-joint shipped robot.
fn nominal_dynamics(robot: &str) -> Option<&'static dyn Dynamics<JOINTS>> {
    match robot {
        "hya" => Some(&hya_robots::Hya),
        "ur5" => Some(&hya_robots::Ur5),
        _ => None,
    }
}

/// Body inertias of a model in joint order, as parametric generated dynamics take them.
fn inertias(model: &TreeModel) -> Result<[RigidBodyInertia; JOINTS], SimError> {
    let bodies = model.bodies();
    if bodies.len() != JOINTS {
        return Err(SimError::Config(format!("expected {JOINTS} joints, found {}", bodies.len())));
    }
    Ok(core::array::from_fn(|i| bodies[i].inertia))
}

/// The plant's rigid body: the robot's parameter-holding generated dynamics, fed the perturbed
/// (or loaded) inertias, so the plant runs generated code too.
fn plant_dynamics(robot: &str) -> Box<plant::DynamicsFactory<JOINTS>> {
    match robot {
        "hya" => Box::new(|m: &TreeModel| {
            Ok(Box::new(hya_robots::HyaParametric::new(&inertias(m)?)) as Box<dyn Dynamics<JOINTS>>)
        }),
        "ur5" => Box::new(|m: &TreeModel| {
            Ok(Box::new(hya_robots::Ur5Parametric::new(&inertias(m)?)) as Box<dyn Dynamics<JOINTS>>)
        }),
        _ => Box::new(plant::generic_dynamics::<JOINTS>),
    }
}

/// Runs every method of `scenario`, in order.
pub fn run_scenario(scenario: &Scenario) -> Result<Vec<RunOutcome<JOINTS>>, SimError> {
    scenario.methods.iter().map(|&method| run_method(scenario, method)).collect()
}

/// Runs one method of `scenario`.
pub fn run_method(scenario: &Scenario, method: Method) -> Result<RunOutcome<JOINTS>, SimError> {
    let nominal = nominal_dynamics(&scenario.robot).ok_or_else(|| {
        SimError::Config(format!("robot `{}`: the simulator runs the 6-joint arms `hya` and `ur5`", scenario.robot))
    })?;
    let urdf = hya_robots::find(&scenario.robot).map(|r| r.urdf).unwrap_or_default();
    let model = hya_urdf::load_str(urdf, &scenario.robot).map_err(|e| SimError::Config(e.to_string()))?.model;
    simulate(scenario, method, nominal, &model, &plant_dynamics(&scenario.robot))
}
