//! The reproduction report: `summary.json`, `report.md`, CSV time series and SVG figures.
//!
//! Each of the paper's claims is judged by a rule fixed in [`crate::claims`] before any run: the
//! verdict is the rule applied to the numbers, and the deciding numbers are printed next to it.
//! Here: the summary (`summary`), CSV (`csv`), figures, text helpers and the markdown,
//! with the plant's and the viscous-friction sections apart.

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

pub use provenance::Provenance;
pub use summary::{RunSummary, Summary};

use crate::analysis::claims::judge_all;
use crate::analysis::seeds::MetricTable;
use crate::analysis::simulate::RunOutcome;
use crate::config::scenario::Scenario;
use crate::error::SimError;
use csv::csv;
use markdown::{frequency_section, markdown};
use summary::run_summary;

/// Writes the whole report into `dir`, held by this run:
/// `outcomes` are the first seed's runs (with traces, for figures), `table` every seed's metrics.
pub fn write<const N: usize>(
    robot: &crate::robot::Robot<N>,
    dir: &crate::io::output::OutputDir,
    scenarios: &[Scenario],
    outcomes: &[RunOutcome<N>],
    table: &MetricTable,
    (quick, full_sweep): (bool, bool),
    provenance: &Provenance,
) -> Result<Summary, SimError> {
    let save = |name: &str, text: &str| dir.save(name, text);
    // The Pareto fronts of a bandwidth sweep, with the paper's experiments on HyA only.
    let (fronts_section, fronts_files) = match scenarios.iter().any(|s| s.name == "goto_internal" && s.robot == "hya") {
        true if full_sweep => fronts::section_of(robot, &crate::analysis::sweep::Plan::standard(quick)?, quick)?,
        true => fronts::section(robot, quick)?,
        false => (String::new(), Vec::new()),
    };
    let mut sweep = None;
    for (name, text) in &fronts_files {
        if name.ends_with(".json") {
            sweep = Some(serde_json::from_str(text)?);
        }
        save(name, text)?;
    }
    let sensitivity = sensitivity::run(robot, scenarios, table)?;
    let chen_designs = chen_designs::run(robot, scenarios, table)?;
    // HyA's actuators measured on its goto task's plant: the Plant section shows them, the
    // linearised loops use the fitted model.
    let loop_base = scenarios.iter().find(|s| s.name == "goto_internal" && s.robot == "hya");
    let torque_responses = match loop_base {
        Some(base) => crate::torque_response::measure(robot, base)?,
        None => None,
    };
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
    let (mut plant_section, figures) = plant::section(robot, scenarios, outcomes, summary.torque_responses.as_ref())?;
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
                    + &limit_cycles::section(robot, base, table)?
                    + &gain_rule::section(robot, base)?
            }
            None => String::new(),
        };
    if let Some(base) = scenarios.iter().find(|s| s.name.starts_with("estimator_noise") && s.robot == "hya") {
        let points = crate::frequency::measure(robot, base, &crate::frequency::FREQUENCIES_HZ)?;
        save("frequency.svg", &crate::frequency::figure(&points))?;
        plant_section.push_str(&frequency_section(&points));
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
