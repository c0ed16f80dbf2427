//! `hya reproduce` and `hya run`: the paper's experiments, or a scenario of your own.

use std::path::{Path, PathBuf};

use hya_sim::{report, run_method, RunOutcome, Scenario, JOINTS};
use indicatif::{ProgressBar, ProgressStyle};

use crate::CliError;

/// Parameters of `hya reproduce`.
#[derive(Debug, clap::Args)]
pub struct ReproduceArgs {
    /// Where the report goes.
    #[arg(long, default_value = "hya-report")]
    out: PathBuf,
    /// Shortened scenarios (event times and durations scaled), well under a minute in release.
    #[arg(long)]
    quick: bool,
    /// Replace the hya report already in `--out` (its report files are removed first).
    #[arg(long)]
    force: bool,
}

/// Parameters of `hya run`.
#[derive(Debug, clap::Args)]
pub struct RunArgs {
    /// The scenario file (TOML; see `hya-sim/scenarios/` for the format).
    file: PathBuf,
    /// Where the report goes.
    #[arg(long, default_value = "hya-report")]
    out: PathBuf,
    /// Shorten the scenario as `hya reproduce --quick` does.
    #[arg(long)]
    quick: bool,
    /// Replace the hya report already in `--out` (its report files are removed first).
    #[arg(long)]
    force: bool,
}

fn sim(e: hya_sim::SimError) -> CliError {
    CliError::Input(e.to_string())
}

/// Runs every method of every scenario with a progress bar, then writes the report.
fn run_all(scenarios: Vec<Scenario>, out: &Path, quick: bool, force: bool) -> Result<(), CliError> {
    for kept in hya_sim::output::prepare(out, force).map_err(sim)? {
        eprintln!("warning: {} is not a report file; left in place", kept.display());
    }
    let scenarios: Vec<Scenario> = scenarios.into_iter().map(|s| if quick { s.quick() } else { s }).collect();
    let total: f64 = scenarios.iter().map(|s| s.duration_s * s.methods.len() as f64).sum();
    let bar = ProgressBar::new(total.ceil() as u64).with_style(
        ProgressStyle::with_template("{msg:32} [{bar:40}] {pos}/{len} simulated s ({eta} left)")
            .map_err(|e| CliError::Input(e.to_string()))?
            .progress_chars("=> "),
    );
    let mut outcomes: Vec<RunOutcome<JOINTS>> = Vec::new();
    for scenario in &scenarios {
        for &method in &scenario.methods {
            bar.set_message(format!("{} / {}", scenario.name, method.name()));
            outcomes.push(run_method(scenario, method).map_err(sim)?);
            bar.inc(scenario.duration_s.round() as u64);
        }
    }
    bar.finish_and_clear();
    let summary = report::write(out, &scenarios, &outcomes, quick).map_err(sim)?;
    for claim in &summary.claims {
        let verdict = match claim.reproduced {
            Some(true) => "reproduced",
            Some(false) => "NOT reproduced",
            None => "not run",
        };
        eprintln!("{verdict:>15}: {} ({})", claim.claim, claim.evidence);
    }
    eprintln!("report: {}", out.join("report.md").display());
    Ok(())
}

/// `hya reproduce`.
pub fn reproduce(args: &ReproduceArgs) -> Result<(), CliError> {
    let scenarios = Scenario::builtin_names().map(Scenario::builtin).collect::<Result<Vec<_>, _>>().map_err(sim)?;
    run_all(scenarios, &args.out, args.quick, args.force)
}

/// `hya run FILE.toml`.
pub fn run(args: &RunArgs) -> Result<(), CliError> {
    let text = std::fs::read_to_string(&args.file)
        .map_err(|e| CliError::Input(format!("{}: cannot read: {e}", args.file.display())))?;
    let scenario = Scenario::from_toml(&text, &args.file.display().to_string()).map_err(sim)?;
    run_all(vec![scenario], &args.out, args.quick, args.force)
}
