//! `hya reproduce` and `hya run`: the paper's experiments, or a scenario of your own.

use std::path::{Path, PathBuf};

use hya_sim::output::OutputDir;

use hya_sim::Scenario;
use indicatif::{ProgressBar, ProgressStyle};

use crate::CliError;

/// The options `hya reproduce` and `hya run` share.
#[derive(Debug, clap::Args)]
pub struct ReportOptions {
    /// Where the report goes (created after the settings are checked; held by this run alone).
    #[arg(long, default_value = "hya-report")]
    out: PathBuf,
    /// Shortened scenarios (event times and durations scaled), well under a minute in release.
    #[arg(long)]
    quick: bool,
    /// Replace the hya report already in `--out`: the files its manifest lists, if unchanged
    /// since hya wrote them, are removed first; anything else is kept.
    #[arg(long)]
    force: bool,
    /// Seeds per scenario and method (default: 20, or 4 with `--quick`).
    #[arg(long, conflicts_with = "merge")]
    seeds: Option<usize>,
    /// Run the report's bandwidth sweep on the full grid of `hya sweep` instead of the reduced one
    /// (its Pareto fronts; several times longer).
    #[arg(long)]
    full_sweep: bool,
    /// Run only shard I of N of the runs (every N-th run from the I-th, from 0), e.g. `--shard
    /// 2/8` in a Slurm array: `--out` gets the shard's runs (`runs.cbor`), no report. `--merge`
    /// then writes the report.
    #[arg(long, conflicts_with = "merge")]
    shard: Option<String>,
    /// Write the report from the runs of these shard folders (each from `--shard`, of the same
    /// scenarios and build): the studies run here, and the report is the one an unsharded run
    /// writes. The seeds and `--quick` are the shards'.
    #[arg(long, num_args = 1.., conflicts_with = "quick")]
    merge: Vec<PathBuf>,
    /// No cost line and no progress bar on stderr (warnings and errors still go there).
    #[arg(short, long)]
    quiet: bool,
    /// The claims' verdicts on stdout as JSON (as in `summary.json`) instead of one line each
    /// (with `--shard`, the shard, its runs and its file).
    #[arg(long)]
    json: bool,
    /// Run even where the run's cost exceeds the documented cap (`hya_sim::cost::MAX_PHYSICS_STEPS`
    /// integration steps or `hya_sim::cost::MAX_TRACE_BYTES` of traces in memory).
    #[arg(long)]
    no_cost_limit: bool,
}

/// Parameters of `hya reproduce`.
#[derive(Debug, clap::Args)]
pub struct ReproduceArgs {
    #[command(flatten)]
    options: ReportOptions,
}

/// Parameters of `hya run`.
#[derive(Debug, clap::Args)]
pub struct RunArgs {
    /// The scenario file (TOML; see `hya-sim/scenarios/` for the format), or the name of a
    /// built-in scenario (`goto_internal`, `panda_goto`, …; `hya scenarios` lists them).
    file: PathBuf,
    #[command(flatten)]
    options: ReportOptions,
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

/// The command line, shortened, to name the run holding `--out`.
fn command_line() -> String {
    let line = std::env::args().collect::<Vec<_>>().join(" ");
    hya_core::Clipped(&line, 120).to_string()
}

/// What one call runs: everything, a shard of the runs, or the report from shards.
enum Part {
    All,
    Shard(hya_sim::sweep::Shard),
    Merge(Vec<(String, hya_sim::seed_shards::RunShard)>),
}

/// Runs every method of every scenario over the seeds on every core, with a progress bar, then
/// writes the report (or, with `--shard`, one shard's runs; with `--merge`, the report from the
/// shards' runs).
fn run_all(
    scenarios: Vec<Scenario>,
    options: &ReportOptions,
    file: Option<&Path>,
    output: &mut impl std::io::Write,
) -> Result<(), CliError> {
    let merged: Vec<(String, hya_sim::seed_shards::RunShard)> = options
        .merge
        .iter()
        .map(|dir| Ok((dir.display().to_string(), hya_sim::seed_shards::read(dir).map_err(sim)?)))
        .collect::<Result<_, CliError>>()?;
    // A merge runs what its shards were run with.
    let shards_key = merged.first().map(|(_, shard)| &shard.experiment);
    let quick = shards_key.map_or(options.quick, |key| key.quick);
    let full_sweep = options.full_sweep;
    let seeds =
        shards_key.map(|key| key.seeds).or(options.seeds).unwrap_or(if quick { QUICK_SEEDS } else { DEFAULT_SEEDS });
    if !(1..=MAX_SEEDS).contains(&seeds) {
        return Err(CliError::Input(format!("--seeds {seeds}: must be between 1 and {MAX_SEEDS}")));
    }
    let scenarios: Vec<Scenario> = scenarios.into_iter().map(|s| if quick { s.quick() } else { s }).collect();
    for s in &scenarios {
        s.check().map_err(sim)?; // a shortened scenario may fall under the warm-up
        s.check_for_robot()
            .map_err(|e| sim(hya_sim::SimError::Scenario { origin: s.name.clone(), message: e.to_string() }))?;
    }
    let runs = hya_sim::seeds::jobs(&scenarios, seeds).len();
    let part = match (&options.shard, merged) {
        (Some(text), _) => Part::Shard(hya_sim::sweep::Shard::parse(text, runs).map_err(CliError::Input)?),
        (None, merged) if !merged.is_empty() => Part::Merge(merged),
        _ => Part::All,
    };
    // A task set in task space is its own experiment, reported at the controlled frame.
    let cartesian = match scenarios.as_slice() {
        [one] if one.task.is_cartesian() => match part {
            Part::All => Some(one),
            _ => {
                return Err(CliError::Input(format!(
                    "{}: a task set in task space does not shard (--shard, --merge)",
                    one.name
                )))
            }
        },
        _ => None,
    };
    // The runs and the studies after them (the bandwidth sweep, the sensitivity variants, …).
    let cost = match &part {
        Part::All if cartesian.is_some() => Ok(hya_sim::cost::Cost::of(&scenarios, seeds)),
        Part::All => hya_sim::Experiment::cost(&scenarios, seeds, (quick, full_sweep)),
        Part::Shard(shard) => hya_sim::seed_shards::cost(&scenarios, seeds, *shard),
        Part::Merge(_) => hya_sim::Experiment::merge_cost(&scenarios, seeds, (quick, full_sweep)),
    }
    .map_err(sim)?;
    if !options.quiet {
        eprintln!("{cost}");
    }
    if !options.no_cost_limit {
        cost.check("shorten duration_s, or run fewer seeds or methods", Some("--no-cost-limit")).map_err(sim)?;
    }
    let provenance = hya_sim::report::Provenance::here(
        command_line(),
        [env!("HYA_BUILD_COMMIT"), env!("HYA_BUILD_RUSTC"), env!("HYA_BUILD_PROFILE"), env!("HYA_BUILD_RUSTFLAGS")],
    );
    // Shards that do not make one experiment are refused before the folder is taken.
    if let Part::Merge(shards) = &part {
        let joints = hya_sim::robot::robot_model(&scenarios[0].robot).map_err(sim)?.dof();
        hya_sim::seed_shards::check(&scenarios, (seeds, quick), (&provenance.build(), joints), shards).map_err(sim)?;
    }
    let shard_files: Vec<PathBuf> =
        options.merge.iter().map(|dir| dir.join(hya_sim::seed_shards::SHARD_FILE)).collect();
    let reads: Vec<&Path> = file
        .into_iter()
        .chain(scenarios.iter().flat_map(Scenario::files_read))
        .chain(shard_files.iter().map(PathBuf::as_path))
        .collect();
    let (out, kept) = OutputDir::open(&options.out, options.force, &provenance.command, &reads).map_err(sim)?;
    for kept in kept {
        eprintln!("warning: {} is not a report file; left in place", kept.display());
    }
    let bar = ProgressBar::new(cost.simulated_s.ceil() as u64).with_style(
        ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len} simulated s ({eta} left)")
            .map_err(|e| CliError::Input(e.to_string()))?
            .progress_chars("=> "),
    );
    bar.set_message(format!("{} runs", cost.runs));
    if options.quiet {
        bar.set_draw_target(indicatif::ProgressDrawTarget::hidden());
    }
    let progress = |seconds: f64| bar.inc(seconds.round() as u64);
    if let Some(scenario) = cartesian {
        let experiment = hya_sim::CartesianExperiment {
            scenario,
            seeds,
            progress: &progress,
            out: &out,
            quick,
            provenance: &provenance,
        };
        let summary = experiment.run().map_err(sim)?;
        bar.finish_and_clear();
        return cartesian_results(&summary, out.path(), options.json, output);
    }
    let experiment = hya_sim::Experiment {
        scenarios: &scenarios,
        seeds,
        progress: &progress,
        out: &out,
        quick,
        full_sweep,
        provenance: &provenance,
    };
    let summary = match &part {
        Part::All => experiment.run(),
        Part::Merge(shards) => experiment.run_merged(shards),
        Part::Shard(shard) => {
            let held = experiment.run_shard(*shard).map_err(sim)?;
            bar.finish_and_clear();
            let file = out.path().join(hya_sim::seed_shards::SHARD_FILE);
            if options.json {
                let json = serde_json::json!({ "shard": format!("{}/{}", shard.index, shard.count), "runs": held, "of": runs, "file": file });
                writeln!(output, "{}", serde_json::to_string_pretty(&json).map_err(|e| CliError::Input(e.to_string()))?)?;
            } else {
                writeln!(output, "shard {}/{}: {held} of {runs} runs in {}", shard.index, shard.count, file.display())?;
            }
            return Ok(());
        }
    }
    .map_err(sim)?;
    bar.finish_and_clear();
    // The results go to stdout (`> file` keeps them); progress and diagnostics to stderr.
    let judged: Vec<_> = summary.claims.iter().filter(|c| c.seeds > 0).collect();
    if options.json {
        let json = serde_json::json!({ "claims": judged, "report": out.path().join("report.md") });
        writeln!(output, "{}", serde_json::to_string_pretty(&json).map_err(|e| CliError::Input(e.to_string()))?)?;
        return Ok(());
    }
    for claim in judged {
        let verdict = claim.verdict.name();
        writeln!(output, "{verdict:>15}: {} ({})", claim.statement, claim.section)?;
    }
    writeln!(output, "report: {}", out.path().join("report.md").display())?;
    Ok(())
}

/// The results of a task-space experiment on stdout: per estimator, what its compensation changes
/// at the controlled frame (the report's "In short"), and the report's path.
fn cartesian_results(
    summary: &hya_sim::report::cartesian::CartesianSummary,
    dir: &Path,
    json: bool,
    output: &mut impl std::io::Write,
) -> Result<(), CliError> {
    let report = dir.join("report.md");
    if json {
        let json = serde_json::json!({ "changes": summary.changes, "report": report });
        writeln!(output, "{}", serde_json::to_string_pretty(&json).map_err(|e| CliError::Input(e.to_string()))?)?;
        return Ok(());
    }
    for change in &summary.changes {
        for r in &change.ratios {
            writeln!(
                output,
                "{:>9}: {} the {} from {} to {} {} (× {} [{}, {}] paired by seed, lower in {} of {} seeds)",
                change.method.name(),
                r.direction(),
                r.name,
                hya_core::Short(r.none_mean),
                hya_core::Short(r.mean),
                r.unit,
                hya_core::Short(r.ratio),
                hya_core::Short(r.low),
                hya_core::Short(r.high),
                r.lower,
                summary.seeds
            )?;
        }
    }
    writeln!(output, "report: {}", report.display())?;
    Ok(())
}

/// Parameters of `hya scenarios`.
#[derive(Debug, clap::Args)]
pub struct ScenariosArgs {
    /// One JSON object per scenario (`name`, `robot`, `duration_s`, `methods`, `description`) in
    /// an array, instead of the table.
    #[arg(long)]
    json: bool,
}

/// `hya scenarios`: the built-in scenarios, one line each (name, robot, duration, methods, the
/// description's first sentence), or as JSON with the whole description.
pub fn scenarios(args: &ScenariosArgs, output: &mut impl std::io::Write) -> Result<(), CliError> {
    let all: Vec<Scenario> = Scenario::builtin_names()
        .chain(Scenario::arm_goto_names())
        .chain(Scenario::task_space_names())
        .map(Scenario::builtin)
        .collect::<Result<_, _>>()
        .map_err(sim)?;
    if args.json {
        let rows: Vec<serde_json::Value> = all
            .iter()
            .map(|s| {
                serde_json::json!({
                    "name": s.name,
                    "robot": s.robot,
                    "duration_s": s.duration_s,
                    "methods": s.methods.iter().map(|m| m.name()).collect::<Vec<_>>(),
                    "description": s.description,
                })
            })
            .collect();
        let text = serde_json::to_string_pretty(&rows).map_err(|e| CliError::Input(e.to_string()))?;
        writeln!(output, "{text}")?;
        return Ok(());
    }
    let width = all.iter().map(|s| s.name.len()).max().unwrap_or(0);
    for s in &all {
        let methods: Vec<&str> = s.methods.iter().map(|m| m.name()).collect();
        writeln!(
            output,
            "{:width$}  {:8} {:>5} s  {:28}  {}",
            s.name,
            s.robot,
            hya_core::Short(s.duration_s),
            methods.join(","),
            s.description.split(". ").next().unwrap_or_default().trim_end_matches('.')
        )?;
    }
    Ok(())
}

/// `hya reproduce`.
pub fn reproduce(args: &ReproduceArgs, output: &mut impl std::io::Write) -> Result<(), CliError> {
    let scenarios = Scenario::builtin_names().map(Scenario::builtin).collect::<Result<Vec<_>, _>>().map_err(sim)?;
    run_all(scenarios, &args.options, None, output)
}

/// `hya run FILE.toml`: a scenario file (at most [`hya_sim::scenario::MAX_SCENARIO_BYTES`]), or a
/// built-in scenario's name.
pub fn run(args: &RunArgs, output: &mut impl std::io::Write) -> Result<(), CliError> {
    let scenario = Scenario::file_or_builtin(&args.file.to_string_lossy()).map_err(sim)?;
    run_all(vec![scenario], &args.options, Some(&args.file), output)
}
