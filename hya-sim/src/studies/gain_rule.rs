//! The runs behind the gain-rule table: `none` on the goto task at several `e_f`, the error at
//! which the PD's torque reaches the joint's static friction. [`crate::report`] renders them.

use crate::analysis::seeds::{run_seeds, MetricTable};
use crate::config::cost::Cost;
use crate::config::scenario::{Method, Scenario};
use crate::error::SimError;

/// The `e_f` swept, rad.
pub const FRICTION_ERRORS_RAD: [f64; 4] = [0.01, 0.02, 0.05, 0.1];

/// Seeds per value.
pub const SEEDS: usize = 3;

/// The runs of `none` at every `e_f`: the scenarios, in [`FRICTION_ERRORS_RAD`]'s order, and
/// their metrics.
#[derive(Debug, Clone)]
pub struct GainRuleRuns {
    /// One scenario per `e_f`.
    pub scenarios: Vec<Scenario>,
    /// Their metrics.
    pub table: MetricTable,
}

/// `base` (the goto task) at every `e_f`, `none` alone.
fn scenarios(base: &Scenario) -> Vec<Scenario> {
    FRICTION_ERRORS_RAD
        .iter()
        .map(|e| base.variant(&format!("ef{e}"), Method::None, |s| s.controller.friction_error_rad = *e))
        .collect()
}

/// What [`run`] costs on `base`.
pub fn cost(base: &Scenario) -> Cost {
    Cost::of(&scenarios(base), SEEDS)
}

/// Runs `none` on `base` (the goto task) at every `e_f`, telling `progress` each run's simulated
/// seconds.
pub fn run<const N: usize>(
    robot: &crate::robot::Robot<N>,
    base: &Scenario,
    progress: &(dyn Fn(f64) + Sync),
) -> Result<GainRuleRuns, SimError> {
    let scenarios = scenarios(base);
    let (_, table) = run_seeds(robot, &scenarios, SEEDS, progress)?;
    Ok(GainRuleRuns { scenarios, table })
}
