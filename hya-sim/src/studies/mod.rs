//! The studies `hya reproduce` runs beside the scenarios' own runs, each returning data: the
//! bandwidth sweep of the Pareto fronts, the sensitivity to the modelling choices, Chen's gain
//! designs and matchings, the actuators' measured torque responses, the observers' measured
//! frequency responses, the runs behind the limit-cycle and gain-rule tables, and the open-loop
//! arm's step responses and gap to MuJoCo. [`crate::report`] renders them; it runs none of these.

pub mod cartesian;
pub mod chen_designs;
pub mod gain_rule;
pub mod limit_cycles;
pub mod sensitivity;
pub mod step_responses;

use crate::analysis::seeds::MetricTable;
use crate::analysis::sweep::{run_on, Plan, Shard, Sweep};
use crate::config::cost::Cost;
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

/// The scenario the observers' frequency responses are measured on: HyA's first noise scenario.
fn noise_base(scenarios: &[Scenario]) -> Option<&Scenario> {
    scenarios.iter().find(|s| s.name.starts_with("estimator_noise") && s.robot == "hya")
}

/// The bandwidth sweep's grid where the goto task is among `scenarios` and every scenario of
/// the grid runs on its robot: the report's reduced grid, or with `full_sweep` `hya sweep`'s
/// (shortened with `quick`).
fn fronts_plan(goto: Option<&Scenario>, (quick, full_sweep): (bool, bool)) -> Result<Option<Plan>, SimError> {
    let Some(goto) = goto else { return Ok(None) };
    let plan = if full_sweep { Plan::standard(quick)? } else { Plan::report(quick)? };
    Ok(plan.scenarios.iter().all(|s| s.robot == goto.robot).then_some(plan))
}

/// What [`run`] costs on `scenarios` (checked) where the report runs `seeds` seeds of each on an
/// arm of `joints` joints, known before any run: every study's runs, one study after another.
pub fn cost(scenarios: &[Scenario], seeds: usize, joints: usize, options: (bool, bool)) -> Result<Cost, SimError> {
    let goto = hya_scenarios(scenarios, &["goto_internal"]).first().copied();
    let noise = noise_base(scenarios);
    let on_goto = |f: &dyn Fn(&Scenario) -> Cost| goto.map_or(Cost::NONE, f);
    Ok([
        fronts_plan(goto, options)?.map_or(Cost::NONE, |plan| plan.cost(Shard::ALL)),
        sensitivity::cost(scenarios, seeds),
        chen_designs::cost(scenarios, seeds),
        on_goto(&|base| crate::torque_response::cost(base, joints)),
        noise.map_or(Cost::NONE, |base| crate::frequency::cost(base, &crate::frequency::FREQUENCIES_HZ, joints)),
        on_goto(&limit_cycles::cost),
        on_goto(&gain_rule::cost),
        scenarios.first().map_or(Cost::NONE, |first| step_responses::cost(first, joints)),
    ]
    .into_iter()
    .fold(Cost::NONE, Cost::then))
}

/// Runs every study whose scenarios are among `scenarios` (`table` holds their runs); the
/// fronts on the report's reduced grid, or with `full_sweep` on `hya sweep`'s (shortened with
/// `quick`). `progress` is told the simulated seconds done as the studies go, in all
/// [`cost`]'s.
pub fn run<const N: usize>(
    robot: &crate::robot::Robot<N>,
    scenarios: &[Scenario],
    table: &MetricTable,
    options: (bool, bool),
    progress: &(dyn Fn(f64) + Sync),
) -> Result<Studies, SimError> {
    let goto = hya_scenarios(scenarios, &["goto_internal"]).first().copied();
    let noise = noise_base(scenarios);
    let fronts = match fronts_plan(goto, options)? {
        Some(plan) => {
            let sweep = run_on(robot, &plan, Shard::ALL, options.0, progress)?;
            Some((plan, sweep))
        }
        None => None,
    };
    let sensitivity = sensitivity::run(robot, scenarios, table, progress)?;
    let chen_designs = chen_designs::run(robot, scenarios, table, progress)?;
    // The studies that are not closed-loop runs tell their whole cost once done.
    let whole = |cost: Cost| progress(cost.simulated_s);
    let torque_responses = goto
        .map(|base| {
            crate::torque_response::measure(robot, base).inspect(|_| whole(crate::torque_response::cost(base, N)))
        })
        .transpose()?
        .flatten();
    let frequencies = &crate::frequency::FREQUENCIES_HZ;
    let frequency = noise
        .map(|base| {
            crate::frequency::measure(robot, base, frequencies)
                .inspect(|_| whole(crate::frequency::cost(base, frequencies, N)))
        })
        .transpose()?;
    let limit_cycles = goto.map(|base| limit_cycles::run(robot, base, progress)).transpose()?;
    let gain_rule = goto.map(|base| gain_rule::run(robot, base, progress)).transpose()?;
    let open_loop = scenarios
        .first()
        .map(|first| step_responses::run(robot, first).inspect(|_| whole(step_responses::cost(first, N))))
        .transpose()?;
    Ok(Studies { fronts, sensitivity, chen_designs, torque_responses, frequency, limit_cycles, gain_rule, open_loop })
}
