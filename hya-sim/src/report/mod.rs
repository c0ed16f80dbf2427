//! The reproduction report: `summary.json`, `report.md`, CSV time series and SVG figures.
//!
//! Each of the paper's claims is judged by a rule fixed in [`crate::claims`] before any run: the
//! verdict is the rule applied to the numbers, and the deciding numbers are printed next to it.
//! Here: the summary (`summary`), CSV (`csv`), figures, text helpers and the markdown,
//! with the plant's and the viscous-friction sections apart. The report renders the runs and
//! what [`crate::studies`] found; it runs no simulation of its own.

pub mod cartesian;
mod chen_designs;
mod csv;
mod figures;
mod fronts;
mod gain_rule;
mod headline;
mod limit_cycles;
mod loops;
mod markdown;
mod plant;
mod provenance;
mod sensitivity;
mod summary;
mod text;
mod torque_loops;

pub use fronts::pareto_figure;
pub use provenance::Provenance;
pub use summary::{RunSummary, Summary};

use crate::analysis::claims::judge_all;
use crate::analysis::seeds::MetricTable;
use crate::analysis::simulate::RunOutcome;
use crate::config::scenario::Scenario;
use crate::error::SimError;
use crate::studies::Studies;
use csv::csv;
use markdown::{frequency_section, markdown};
use summary::run_summary;

/// Writes the whole report into `dir`, held by this run: `outcomes` are the first seed's runs
/// (with traces, for figures), `table` every seed's metrics, `studies` what the studies found
/// ([`crate::studies::run`]). Nothing here runs the simulator.
#[allow(clippy::too_many_arguments)]
pub fn write<const N: usize>(
    robot: &crate::robot::Robot<N>,
    dir: &crate::io::output::OutputDir,
    scenarios: &[Scenario],
    outcomes: &[RunOutcome<N>],
    table: &MetricTable,
    studies: Studies,
    quick: bool,
    provenance: &Provenance,
) -> Result<Summary, SimError> {
    let save = |name: &str, text: &str| dir.save(name, text);
    let Studies { fronts, sensitivity, chen_designs, torque_responses, frequency, limit_cycles, gain_rule, open_loop } =
        studies;
    // The Pareto fronts of a bandwidth sweep, with the paper's experiments on HyA only.
    let (fronts_section, fronts_files) = match &fronts {
        Some((plan, sweep)) => fronts::section_of(robot, plan, sweep)?,
        None => (String::new(), Vec::new()),
    };
    for (name, text) in &fronts_files {
        save(name, text)?;
    }
    let sweep = fronts.map(|(_, sweep)| serde_json::to_value(sweep)).transpose()?;
    let loop_base = scenarios.iter().find(|s| s.name == "goto_internal" && s.robot == "hya");
    let summary = Summary {
        robot: robot.name.clone(),
        quick,
        seeds: outcomes.first().map_or(0, |o| table.seeds(&o.scenario, o.method)),
        runs: outcomes.iter().map(|o| run_summary(table, &o.scenario, o.method, o.bandwidth_rad_s.clone())).collect(),
        claims: judge_all(table),
        provenance: provenance.clone(),
        sweep,
        sensitivity,
        chen_designs,
        torque_responses,
    };
    let json = serde_json::to_string_pretty(&summary)?;
    save("summary.json", &json)?;
    for o in outcomes {
        let name = format!("{}_{}.csv", o.scenario, o.method.name());
        save(&name, &csv(o, &robot.model, &name)?)?;
    }
    let mut figure_names = std::collections::BTreeMap::new();
    for s in scenarios {
        let runs: Vec<&RunOutcome<N>> = outcomes.iter().filter(|o| o.scenario == s.name).collect();
        if runs.is_empty() {
            continue;
        }
        let mut names = Vec::new();
        for (name, svg) in figures::scenario_figures(s, &runs, table) {
            save(&name, &svg)?;
            names.push(name);
        }
        figure_names.insert(s.name.clone(), names);
    }
    let (mut plant_section, figures) =
        plant::section(robot, scenarios, outcomes, (summary.torque_responses.as_ref(), open_loop.as_ref()))?;
    for (name, svg) in &figures {
        save(name, svg)?;
    }
    // The viscous-friction and frequency sweeps are HyA's experiments, on HyA only.
    let sensitivity_section = summary.sensitivity.as_ref().map(sensitivity::section).unwrap_or_default();
    let viscous_section = sensitivity_section
        + &match loop_base {
            Some(base) => {
                fronts_section
                    + &loops::section(robot, base, summary.torque_responses.as_ref())?
                    + &limit_cycles
                        .as_ref()
                        .map(|runs| limit_cycles::section::<N>(base, table, runs))
                        .unwrap_or_default()
                    + &gain_rule.as_ref().map(|runs| gain_rule::section::<N>(base, runs)).unwrap_or_default()
            }
            None => String::new(),
        };
    if let Some(points) = &frequency {
        save("frequency.svg", &crate::frequency::figure(points))?;
        plant_section.push_str(&frequency_section(points));
    }
    save(
        "report.md",
        &markdown(
            robot,
            scenarios,
            outcomes,
            table,
            &summary,
            (quick, provenance),
            (&plant_section, &figure_names, &viscous_section),
        )?,
    )?;
    Ok(summary)
}

/// The loop design of `scenario` on `robot` at its start pose, as its closed loop makes it
/// ([`crate::run::model::LoopDesign::of`] on the scenario's checked settings).
fn loop_design<const N: usize>(
    scenario: &Scenario,
    robot: &crate::robot::Robot<N>,
) -> Result<crate::run::model::LoopDesign<N>, SimError> {
    crate::run::model::LoopDesign::of(&crate::config::settings::Setup::of(scenario)?, robot)
}
