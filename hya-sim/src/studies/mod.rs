//! The studies `hya reproduce` runs beside the scenarios' own runs, each returning data: the
//! bandwidth sweep of the Pareto fronts, the sensitivity to the modelling choices, Chen's gain
//! designs and matchings, the actuators' measured torque responses, the observers' measured
//! frequency responses, the runs behind the limit-cycle and gain-rule tables, and the open-loop
//! arm's step responses and gap to MuJoCo. [`crate::report`] renders them; it runs none of these.

pub mod chen_designs;
pub mod gain_rule;
pub mod limit_cycles;
pub mod sensitivity;
pub mod step_responses;

use crate::analysis::seeds::MetricTable;
use crate::analysis::sweep::{run_on, Plan, Shard, Sweep};
use crate::config::scenario::Scenario;
use crate::error::SimError;

/// What the studies found; `None` where a study's scenarios are not in the run (they are HyA's).
#[derive(Debug, Clone)]
pub struct Studies {
    /// The bandwidth sweep of the Pareto fronts and the grid it ran.
    pub fronts: Option<(Plan, Sweep)>,
    /// The headline comparisons per modelling choice.
    pub sensitivity: Option<sensitivity::Sensitivity>,
    /// The claims that name Chen's observer per gain design and matching.
    pub chen_designs: Option<chen_designs::ChenDesigns>,
    /// HyA's actuators measured on its goto task's plant.
    pub torque_responses: Option<crate::torque_response::TorqueResponses>,
    /// The observers' frequency responses on the noise scenario's plant.
    pub frequency: Option<Vec<crate::frequency::Point>>,
    /// The runs behind the limit-cycle tables (on the goto task).
    pub limit_cycles: Option<limit_cycles::LimitCycleRuns>,
    /// The runs behind the gain-rule table (on the goto task).
    pub gain_rule: Option<gain_rule::GainRuleRuns>,
    /// The open-loop arm of the report's first scenario: step responses, the gap to MuJoCo.
    pub open_loop: Option<step_responses::OpenLoop>,
}

/// HyA's scenarios among `scenarios` whose names are in `names`, in run order: the studies vary
/// HyA's scenarios only.
pub(crate) fn hya_scenarios<'a>(scenarios: &'a [Scenario], names: &[&str]) -> Vec<&'a Scenario> {
    scenarios.iter().filter(|s| s.robot == "hya" && names.contains(&s.name.as_str())).collect()
}

/// Runs every study whose scenarios are among `scenarios` (`table` holds their runs); the
/// fronts on the report's reduced grid, or with `full_sweep` on `hya sweep`'s (shortened with
/// `quick`).
pub fn run<const N: usize>(
    robot: &crate::robot::Robot<N>,
    scenarios: &[Scenario],
    table: &MetricTable,
    (quick, full_sweep): (bool, bool),
) -> Result<Studies, SimError> {
    let goto = hya_scenarios(scenarios, &["goto_internal"]).first().copied();
    let fronts = match goto {
        Some(_) => {
            let plan = if full_sweep { Plan::standard(quick)? } else { Plan::report(quick)? };
            match plan.scenarios.iter().all(|s| s.robot == robot.name) {
                true => {
                    let sweep = run_on(robot, &plan, Shard::ALL, quick, &|_| {})?;
                    Some((plan, sweep))
                }
                false => None,
            }
        }
        None => None,
    };
    let sensitivity = sensitivity::run(robot, scenarios, table)?;
    let chen_designs = chen_designs::run(robot, scenarios, table)?;
    let torque_responses = match goto {
        Some(base) => crate::torque_response::measure(robot, base)?,
        None => None,
    };
    let frequency = match scenarios.iter().find(|s| s.name.starts_with("estimator_noise") && s.robot == "hya") {
        Some(base) => Some(crate::frequency::measure(robot, base, &crate::frequency::FREQUENCIES_HZ)?),
        None => None,
    };
    let limit_cycles = goto.map(|base| limit_cycles::run(robot, base)).transpose()?;
    let gain_rule = goto.map(|base| gain_rule::run(robot, base)).transpose()?;
    let open_loop = scenarios.first().map(|first| step_responses::run(robot, first)).transpose()?;
    Ok(Studies { fronts, sensitivity, chen_designs, torque_responses, frequency, limit_cycles, gain_rule, open_loop })
}
