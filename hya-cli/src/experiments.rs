//! `hya reproduce` and `hya run`: the paper's experiments, or a scenario of your own.

use std::path::{Path, PathBuf};

use hya_sim::Scenario;
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
    /// Seeds per scenario and method (default: 20, or 4 with `--quick`).
    #[arg(long)]
    seeds: Option<usize>,
}

/// Parameters of `hya run`.
#[derive(Debug, clap::Args)]
pub struct RunArgs {
    /// The scenario file (TOML; see `hya-sim/scenarios/` for the format), or the name of a
    /// built-in scenario (`goto_internal`, `panda_goto`, …).
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
    /// Seeds per scenario and method (default: 20, or 4 with `--quick`).
    #[arg(long)]
    seeds: Option<usize>,
}

fn sim(e: hya_sim::SimError) -> CliError {
    CliError::Input(e.to_string())
}

/// Seeds per scenario and method unless `--seeds` says otherwise.
const DEFAULT_SEEDS: usize = 20;
/// The same with `--quick`.
const QUICK_SEEDS: usize = 4;
/// The most seeds `--seeds` accepts.
const MAX_SEEDS: usize = 1000;

/// Runs every method of every scenario over the seeds on every core, with a progress bar, then
/// writes the report.
fn run_all(
    scenarios: Vec<Scenario>,
    out: &Path,
    quick: bool,
    force: bool,
    seeds: Option<usize>,
    generated_by: &str,
) -> Result<(), CliError> {
    let seeds = seeds.unwrap_or(if quick { QUICK_SEEDS } else { DEFAULT_SEEDS });
    if !(1..=MAX_SEEDS).contains(&seeds) {
        return Err(CliError::Input(format!("--seeds {seeds}: must be between 1 and {MAX_SEEDS}")));
    }
    for kept in hya_sim::output::prepare(out, force).map_err(sim)? {
        eprintln!("warning: {} is not a report file; left in place", kept.display());
    }
    let scenarios: Vec<Scenario> = scenarios.into_iter().map(|s| if quick { s.quick() } else { s }).collect();
    for s in &scenarios {
        s.check().map_err(sim)?; // a shortened scenario may fall under the warm-up
    }
    let total: f64 = scenarios.iter().map(|s| s.duration_s * (s.methods.len() * seeds) as f64).sum();
    let bar = ProgressBar::new(total.ceil() as u64).with_style(
        ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len} simulated s ({eta} left)")
            .map_err(|e| CliError::Input(e.to_string()))?
            .progress_chars("=> "),
    );
    bar.set_message(format!("{} runs", scenarios.iter().map(|s| s.methods.len() * seeds).sum::<usize>()));
    let progress = |seconds: f64| bar.inc(seconds.round() as u64);
    let summary = hya_sim::Experiment { scenarios: &scenarios, seeds, progress: &progress, out, quick, generated_by }
        .run()
        .map_err(sim)?;
    bar.finish_and_clear();
    for claim in summary.claims.iter().filter(|c| c.seeds > 0) {
        let verdict = claim.verdict.name();
        eprintln!("{verdict:>15}: {} ({})", claim.statement, claim.section);
    }
    eprintln!("report: {}", out.join("report.md").display());
    Ok(())
}

/// `hya reproduce`.
pub fn reproduce(args: &ReproduceArgs) -> Result<(), CliError> {
    let scenarios = Scenario::builtin_names().map(Scenario::builtin).collect::<Result<Vec<_>, _>>().map_err(sim)?;
    run_all(scenarios, &args.out, args.quick, args.force, args.seeds, "hya reproduce")
}

/// `hya run FILE.toml`.
pub fn run(args: &RunArgs) -> Result<(), CliError> {
    let name = args.file.to_string_lossy();
    let scenario = match std::fs::read_to_string(&args.file) {
        Ok(text) => Scenario::from_toml(&text, &name).map_err(sim)?,
        Err(_) if !args.file.exists() && Scenario::builtin(&name).is_ok() => Scenario::builtin(&name).map_err(sim)?,
        Err(e) => return Err(CliError::Input(format!("{name}: cannot read: {e}"))),
    };
    run_all(vec![scenario], &args.out, args.quick, args.force, args.seeds, "hya run")
}
