//! `hya sweep`: every observer's bandwidth from 10 to 200 rad/s, sharded for batch schedulers,
//! and the merge of the shards.

use std::path::PathBuf;

use hya_sim::output::OutputDir;
use hya_sim::sweep::{self, Plan, Shard, Sweep};
use indicatif::{ProgressBar, ProgressStyle};

use crate::CliError;

/// Parameters of `hya sweep`.
#[derive(Debug, clap::Args)]
pub struct SweepArgs {
    /// Where `sweep.json` and the Pareto figure go (held by this run alone: shards of one sweep
    /// need folders of their own).
    #[arg(long)]
    out: PathBuf,
    /// Shortened scenarios and one seed per point.
    #[arg(long)]
    quick: bool,
    /// Run only shard I of N (every N-th run from the I-th, from 0), e.g. `--shard 2/8` in a
    /// Slurm array or GNU parallel job, each with its own `--out`.
    #[arg(long, conflicts_with = "merge")]
    shard: Option<String>,
    /// Merge the `sweep.json` of these shard folders instead of running.
    #[arg(long, num_args = 1..)]
    merge: Vec<PathBuf>,
    /// Replace an earlier sweep or report in `--out`.
    #[arg(long)]
    force: bool,
}

fn sim(e: hya_sim::SimError) -> CliError {
    CliError::Input(e.to_string())
}

/// `hya sweep`.
pub fn run(args: &SweepArgs) -> Result<(), CliError> {
    let shards: Vec<(String, Sweep)> = args
        .merge
        .iter()
        .map(|dir| Ok((dir.display().to_string(), sweep::read(dir).map_err(sim)?)))
        .collect::<Result<_, CliError>>()?;
    // A merge rebuilds the plan its shards were run from.
    let quick = shards.first().map_or(args.quick, |(_, s)| s.quick);
    let plan = Plan::standard(quick).map_err(sim)?;
    let shard = args.shard.as_deref().map(|s| Shard::parse(s, plan.runs())).transpose().map_err(CliError::Input)?;
    let result = if shards.is_empty() { None } else { Some(sweep::merge(&plan, &shards).map_err(sim)?) };
    let shard_files: Vec<PathBuf> = args.merge.iter().map(|dir| dir.join("sweep.json")).collect();
    let holder = hya_core::Clipped(&std::env::args().collect::<Vec<_>>().join(" "), 120).to_string();
    let (out, kept) =
        OutputDir::open(&args.out, args.force, &holder, &shard_files.iter().map(PathBuf::as_path).collect::<Vec<_>>())
            .map_err(sim)?;
    for kept in kept {
        eprintln!("warning: {} is not a report file; left in place", kept.display());
    }
    let result = match result {
        Some(merged) => merged,
        None => {
            let shard = shard.unwrap_or(Shard::ALL);
            let cost = plan.cost(shard);
            eprintln!("{cost}");
            let bar = ProgressBar::new(cost.simulated_s.ceil() as u64).with_style(
                ProgressStyle::with_template("sweep [{bar:40}] {pos}/{len} simulated s ({eta} left)")
                    .map_err(|e| CliError::Input(e.to_string()))?
                    .progress_chars("=> "),
            );
            let sweep = sweep::run(&plan, shard, quick, &|seconds| bar.inc(seconds.round() as u64)).map_err(sim)?;
            bar.finish_and_clear();
            sweep
        }
    };
    let json = serde_json::to_string_pretty(&result).map_err(|e| CliError::Input(e.to_string()))?;
    out.save("sweep.json", &json).map_err(sim)?;
    out.save("sweep_pareto.svg", &hya_sim::report::pareto_figure(&result)).map_err(sim)?;
    eprintln!("{} points: {}", result.entries.len(), out.path().join("sweep.json").display());
    Ok(())
}
