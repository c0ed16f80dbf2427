//! `hya sweep`: every observer's bandwidth from 10 to 200 rad/s, sharded for batch schedulers,
//! and the merge of the shards.

use std::path::PathBuf;

use hya_sim::sweep::{self, Plan, Shard, Sweep};
use indicatif::{ProgressBar, ProgressStyle};

use crate::CliError;

/// Parameters of `hya sweep`.
#[derive(Debug, clap::Args)]
pub struct SweepArgs {
    /// Where `sweep.json` and the Pareto figure go.
    #[arg(long)]
    out: PathBuf,
    /// Shortened scenarios and one seed per point.
    #[arg(long)]
    quick: bool,
    /// Run only shard I of N (every N-th run from the I-th, from 0), e.g. `--shard 2/8` in a
    /// Slurm array or GNU parallel job.
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

fn read(dir: &std::path::Path) -> Result<Sweep, CliError> {
    let path = dir.join("sweep.json");
    let text =
        std::fs::read_to_string(&path).map_err(|e| CliError::Input(format!("{}: cannot read: {e}", path.display())))?;
    serde_json::from_str(&text).map_err(|e| CliError::Input(format!("{}: not a sweep: {e}", path.display())))
}

/// `hya sweep`.
pub fn run(args: &SweepArgs) -> Result<(), CliError> {
    let shards: Vec<Sweep> = args.merge.iter().map(|d| read(d)).collect::<Result<_, _>>()?;
    let shard = args.shard.as_deref().map(Shard::parse).transpose().map_err(CliError::Input)?.unwrap_or(Shard::ALL);
    for kept in hya_sim::output::prepare(&args.out, args.force).map_err(sim)? {
        eprintln!("warning: {} is not a report file; left in place", kept.display());
    }
    let result = if args.merge.is_empty() {
        let plan = Plan::standard(args.quick).map_err(sim)?;
        let runs = plan.scenarios.len() * plan.methods.len() * plan.bandwidths_rad_s.len() * plan.seeds;
        let total: f64 = plan.scenarios.iter().map(|s| s.duration_s).sum::<f64>()
            * (runs / plan.scenarios.len()) as f64
            / shard.count as f64;
        let bar = ProgressBar::new(total.ceil() as u64).with_style(
            ProgressStyle::with_template("sweep [{bar:40}] {pos}/{len} simulated s ({eta} left)")
                .map_err(|e| CliError::Input(e.to_string()))?
                .progress_chars("=> "),
        );
        let sweep = sweep::run(&plan, shard, &|seconds| bar.inc(seconds.round() as u64)).map_err(sim)?;
        bar.finish_and_clear();
        sweep
    } else {
        sweep::merge(&shards).map_err(sim)?
    };
    let json = serde_json::to_string_pretty(&result).map_err(|e| CliError::Input(e.to_string()))?;
    hya_sim::output::save(&args.out, "sweep.json", &json).map_err(sim)?;
    hya_sim::output::save(&args.out, "sweep_pareto.svg", &sweep::pareto_figure(&result)).map_err(sim)?;
    eprintln!("{} points: {}", result.entries.len(), args.out.join("sweep.json").display());
    Ok(())
}
