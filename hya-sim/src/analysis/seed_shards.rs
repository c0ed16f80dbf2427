//! An experiment's runs split over machines: shard `I/N` runs every `N`-th of the experiment's
//! runs from the `I`-th (the order of [`seeds::jobs`]) and keeps what the report needs of each
//! (its metrics, and the first seed's trace for the figures); the merge checks that the shards
//! come from one experiment and one build and cover every run once, and hands back the runs as
//! an unsharded experiment would have them, so the report written from them is the same.
//!
//! A shard is stored as CBOR ([`SHARD_FILE`]): its numbers keep every bit, NaN included.

use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use hya_core::{Clipped, JointVector};

use crate::analysis::metrics::Metrics;
use crate::analysis::seeds::{self, MetricTable};
use crate::analysis::simulate::RunOutcome;
use crate::analysis::sweep::Shard;
use crate::config::cost::Cost;
use crate::config::scenario::{Method, Scenario};
use crate::error::SimError;
use crate::run::trace::Trace;

pub use crate::io::output::SHARD_FILE;

/// The version of [`SHARD_FILE`]'s layout; a merge refuses another.
const FORMAT: u32 = 1;

/// What makes two shards parts of one experiment's runs: the scenarios (every setting, and the
/// content of every file they name), the seeds and whether they were shortened. (The studies'
/// options are the merge's: they change no run.)
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ExperimentKey {
    /// SHA-256 of the scenarios' settings (as JSON) and of the content of each file they read
    /// (URDFs, friction files), hex.
    pub scenarios_sha256: String,
    /// The scenarios' names, for the messages.
    pub scenario_names: Vec<String>,
    /// Seeds per scenario and method.
    pub seeds: usize,
    /// Whether the scenarios were shortened (`--quick`).
    pub quick: bool,
}

impl ExperimentKey {
    /// The key of an experiment on `scenarios` over `seeds` seeds, shortened if `quick`. A file
    /// a scenario names that cannot be read is refused here, before any run.
    pub fn of(scenarios: &[Scenario], seeds: usize, quick: bool) -> Result<Self, SimError> {
        let refuse = |message: String| SimError::Shard { shard: "this experiment".to_owned(), message };
        let settings =
            serde_json::to_string(scenarios).map_err(|e| refuse(format!("its settings do not serialise: {e}")))?;
        let mut digest = Sha256::new();
        digest.update(settings.as_bytes());
        for s in scenarios {
            // A shipped arm's name is no file: its model is compiled in (the build is checked).
            for path in s.files_read().filter(|p| hya_robots::find(&p.to_string_lossy()).is_none()) {
                let sha256 = crate::io::input::sha256_of(path)
                    .map_err(|why| refuse(format!("{} ({}): {why}", path.display(), s.name)))?;
                digest.update(sha256.as_bytes());
            }
        }
        Ok(Self {
            scenarios_sha256: digest.finalize().iter().map(|b| format!("{b:02x}")).collect(),
            scenario_names: scenarios.iter().map(|s| s.name.clone()).collect(),
            seeds,
            quick,
        })
    }
}

/// One run as a shard keeps it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StoredRun {
    /// Which scenario (index in the experiment).
    pub scenario: usize,
    /// The method.
    pub method: Method,
    /// Which seed (0 is the scenario's own).
    pub seed_index: usize,
    /// The observer's rates at the start pose ([`RunOutcome::bandwidth_rad_s`]).
    pub bandwidth_rad_s: Option<Vec<f64>>,
    /// Its metrics.
    pub metrics: Metrics,
    /// The first seed's trace; `None` for the others, whose traces are not kept.
    pub trace: Option<StoredTrace>,
}

/// A [`Trace`] with its joint vectors laid out flat, tick after tick.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StoredTrace {
    /// [`Trace::stride`].
    pub stride: usize,
    /// [`Trace::time`].
    pub time: Vec<f64>,
    /// `q`, `q_des`, `d_true`, `d_hat`, `tau_cmd`, each flat.
    pub series: [Vec<f64>; 5],
}

impl StoredTrace {
    fn of<const N: usize>(trace: &Trace<N>) -> Self {
        let flat = |v: &[JointVector<N>]| v.iter().flat_map(|x| x.iter().copied()).collect::<Vec<f64>>();
        Self {
            stride: trace.stride,
            time: trace.time.clone(),
            series: [flat(&trace.q), flat(&trace.q_des), flat(&trace.d_true), flat(&trace.d_hat), flat(&trace.tau_cmd)],
        }
    }

    /// The trace, or `None` if a series is not `N` values per tick.
    fn trace<const N: usize>(&self) -> Option<Trace<N>> {
        let ticks = self.time.len();
        let unflat = |v: &[f64]| -> Option<Vec<JointVector<N>>> {
            (v.len() == ticks * N).then(|| v.chunks_exact(N.max(1)).map(JointVector::<N>::from_column_slice).collect())
        };
        let [q, q_des, d_true, d_hat, tau_cmd] = &self.series;
        Some(Trace {
            stride: self.stride,
            time: self.time.clone(),
            q: unflat(q)?,
            q_des: unflat(q_des)?,
            d_true: unflat(d_true)?,
            d_hat: unflat(d_hat)?,
            tau_cmd: unflat(tau_cmd)?,
        })
    }
}

/// One shard's runs, with what a merge checks them by.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunShard {
    /// The version of the file's layout (a merge refuses another).
    pub format: u32,
    /// The experiment it is part of.
    pub experiment: ExperimentKey,
    /// The build and machine that ran it (commit, rustc, profile, flags, fused multiply-add):
    /// runs repeat bit for bit only where these agree.
    pub build: String,
    /// Which shard.
    pub index: usize,
    /// Of how many.
    pub count: usize,
    /// Its runs, in the experiment's order.
    pub runs: Vec<StoredRun>,
}

impl RunShard {
    /// The shard as [`SHARD_FILE`]'s bytes.
    pub fn to_bytes(&self) -> Result<Vec<u8>, SimError> {
        let mut bytes = Vec::new();
        ciborium::into_writer(self, &mut bytes).map_err(|e| SimError::Shard {
            shard: format!("{}/{}", self.index, self.count),
            message: format!("does not encode: {e}"),
        })?;
        Ok(bytes)
    }

    /// Reads a shard from `bytes`, `origin` naming it in errors.
    pub fn from_bytes(bytes: &[u8], origin: &str) -> Result<Self, SimError> {
        let refuse = |message: String| SimError::Shard { shard: origin.to_owned(), message };
        let shard: Self = ciborium::from_reader(bytes).map_err(|e| {
            refuse(format!("is not a shard of `hya run`/`hya reproduce --shard` ({})", Clipped(&e.to_string(), 200)))
        })?;
        if shard.format != FORMAT {
            return Err(refuse(format!("has layout {}, this build reads {FORMAT}", shard.format)));
        }
        Ok(shard)
    }
}

/// The most bytes a shard file may have: the trace memory a run may hold
/// ([`crate::config::cost::MAX_TRACE_BYTES`]) and as much again for the metrics and the layout.
pub const MAX_SHARD_BYTES: u64 = 2 * crate::config::cost::MAX_TRACE_BYTES as u64;

/// Reads the [`SHARD_FILE`] of a shard folder, at most [`MAX_SHARD_BYTES`]. Where the folder's
/// manifest (written with the shard) lists the file, its bytes must have the listed SHA-256: a
/// flipped bit in a number would still decode. (A shard copied without its folder's manifest is
/// read on the strength of its layout alone.)
pub fn read(dir: &std::path::Path) -> Result<RunShard, SimError> {
    let path = dir.join(SHARD_FILE);
    let origin = path.display().to_string();
    let bytes = hya_urdf::file::read_bytes(&path, MAX_SHARD_BYTES)
        .map_err(|e| SimError::Shard { shard: origin.clone(), message: e.to_string() })?;
    if let Some(listed) = crate::io::output::listed_sha256(dir, SHARD_FILE) {
        if crate::io::output::sha256_hex(&bytes) != listed {
            return Err(SimError::Shard {
                shard: origin,
                message: format!(
                    "its SHA-256 differs from the one {} lists: the file changed since it was written",
                    crate::io::output::MANIFEST
                ),
            });
        }
    }
    RunShard::from_bytes(&bytes, &origin)
}

/// The cost of `shard` of the experiment's runs (no study: the merge runs those).
pub fn cost(scenarios: &[Scenario], seeds: usize, shard: Shard) -> Result<Cost, SimError> {
    Ok(shard_jobs(scenarios, seeds, shard)?
        .into_iter()
        .map(|(i, _, k)| Cost::of_runs(&scenarios[i], 1, usize::from(k == 0)))
        .fold(Cost::NONE, |a, b| a + b))
}

/// The experiment's runs in `shard` (checked: `0 ≤ index < count ≤ runs`).
fn shard_jobs(scenarios: &[Scenario], seeds: usize, shard: Shard) -> Result<Vec<seeds::Job>, SimError> {
    let jobs = seeds::jobs(scenarios, seeds);
    if shard.count == 0 || shard.index >= shard.count || shard.count > jobs.len() {
        return Err(SimError::Shard {
            shard: format!("{}/{}", shard.index, shard.count),
            message: format!("need 0 ≤ I < N ≤ {}, the experiment's runs", jobs.len()),
        });
    }
    Ok(jobs.into_iter().skip(shard.index).step_by(shard.count).collect())
}

/// Runs `shard` of the experiment (`key`'s) on `robot`, `build` naming the build.
pub fn run<const N: usize>(
    robot: &crate::robot::Robot<N>,
    scenarios: &[Scenario],
    (key, build): (&ExperimentKey, &str),
    shard: Shard,
    progress: &(dyn Fn(f64) + Sync),
) -> Result<RunShard, SimError> {
    let jobs = shard_jobs(scenarios, key.seeds, shard)?;
    let outcomes = seeds::run_jobs(robot, scenarios, &jobs, progress)?;
    let runs = jobs
        .iter()
        .zip(outcomes)
        .map(|(&(scenario, method, seed_index), outcome)| StoredRun {
            scenario,
            method,
            seed_index,
            bandwidth_rad_s: outcome.bandwidth_rad_s,
            metrics: outcome.metrics,
            trace: (seed_index == 0).then(|| StoredTrace::of(&outcome.trace)),
        })
        .collect();
    Ok(RunShard {
        format: FORMAT,
        experiment: key.clone(),
        build: build.to_owned(),
        index: shard.index,
        count: shard.count,
        runs,
    })
}

/// Checks that `shards` (each with where it came from) are every shard of the runs of one
/// experiment on `scenarios` over `seeds` seeds, shortened if `quick`, run by `build` on an arm
/// of `joints` joints: for a command to call before it takes its output folder.
pub fn check(
    scenarios: &[Scenario],
    (seeds, quick): (usize, bool),
    (build, joints): (&str, usize),
    shards: &[(String, RunShard)],
) -> Result<(), SimError> {
    let key = ExperimentKey::of(scenarios, seeds, quick)?;
    place(&seeds::jobs(scenarios, seeds), (&key, build, joints), shards).map(|_| ())
}

/// Each of `jobs`' run from `shards`, in the jobs' order; see [`merge`] for what is refused.
fn place<'s>(
    jobs: &[seeds::Job],
    (key, build, joints): (&ExperimentKey, &str, usize),
    shards: &'s [(String, RunShard)],
) -> Result<Vec<&'s StoredRun>, SimError> {
    let Some((_, first)) = shards.first() else { return Err(SimError::Nothing("no shards to merge")) };
    let count = first.count;
    let mut holder: Vec<Option<&str>> = Vec::new();
    let mut slots: Vec<Option<&StoredRun>> = vec![None; jobs.len()];
    for (origin, shard) in shards {
        let refuse = |message: String| SimError::Shard { shard: origin.clone(), message };
        if shard.experiment != *key {
            let describe = |k: &ExperimentKey| {
                format!(
                    "{} over {} seeds{} (settings and files' SHA-256 {})",
                    k.scenario_names.join(", "),
                    k.seeds,
                    if k.quick { ", quick" } else { "" },
                    Clipped(&k.scenarios_sha256, 12)
                )
            };
            return Err(refuse(format!(
                "comes from another experiment: {}, not {}",
                describe(&shard.experiment),
                describe(key)
            )));
        }
        if shard.build != build {
            return Err(refuse(format!(
                "was run by another build or machine ({}), not this one ({build}): its runs would not repeat bit for bit here",
                Clipped(&shard.build, 200)
            )));
        }
        if !(1..=jobs.len()).contains(&shard.count) {
            return Err(refuse(format!("claims {} shards; the experiment has {} runs", shard.count, jobs.len())));
        }
        if shard.count != count {
            return Err(refuse(format!(
                "is one of {} shards, where the first shard given is one of {count}",
                shard.count
            )));
        }
        holder.resize(count, None);
        let Some(slot) = holder.get_mut(shard.index) else {
            return Err(refuse(format!("names shard {}, beyond 0 to {}", shard.index, count - 1)));
        };
        if let Some(other) = slot.replace(origin) {
            return Err(refuse(format!("is shard {}/{count}, which {other} is too", shard.index)));
        }
        let expected: Vec<usize> = (shard.index..jobs.len()).step_by(count).collect();
        let matches = shard.runs.len() == expected.len()
            && shard.runs.iter().zip(&expected).all(|(run, &j)| (run.scenario, run.method, run.seed_index) == jobs[j]);
        if !matches {
            return Err(refuse(format!(
                "holds {} runs where shard {}/{count} has {} (runs missing, repeated or not of this experiment)",
                shard.runs.len(),
                shard.index,
                expected.len()
            )));
        }
        for (run, j) in shard.runs.iter().zip(expected) {
            if let Some((name, values)) = run.metrics.named().into_iter().find(|(_, v)| v.len() != joints) {
                return Err(refuse(format!(
                    "run {j}'s `{name}` has {} values, not one per joint ({joints})",
                    values.len()
                )));
            }
            slots[j] = Some(run);
        }
    }
    let missing: Vec<String> =
        holder.iter().enumerate().filter(|(_, h)| h.is_none()).map(|(i, _)| format!("{i}/{count}")).collect();
    if !missing.is_empty() {
        return Err(SimError::MissingShards(missing.join(", ")));
    }
    slots
        .into_iter()
        .map(|slot| slot.ok_or(SimError::MissingShards("a run (a bug: every shard was found)".into())))
        .collect()
}

/// The runs of every shard of one experiment (`key`'s, on `scenarios`, built as `build`), as
/// [`seeds::run_seeds`] returns them; each shard with where it came from. Refused: a shard of
/// another experiment, build or shard count, a shard named twice or missing, a shard whose runs
/// are not the ones its index names, a metric or trace not of `N` joints.
pub fn merge<const N: usize>(
    scenarios: &[Scenario],
    (key, build): (&ExperimentKey, &str),
    shards: &[(String, RunShard)],
) -> Result<(Vec<RunOutcome<N>>, MetricTable), SimError> {
    let jobs = seeds::jobs(scenarios, key.seeds);
    let slots = place(&jobs, (key, build, N), shards)?;
    let mut table = MetricTable::default();
    let mut first_seeds = Vec::new();
    for (&(i, method, k), run) in jobs.iter().zip(slots) {
        let scenario = &scenarios[i];
        table.push(&scenario.name, method, run.metrics.clone());
        if k == 0 {
            let trace = run.trace.as_ref().and_then(StoredTrace::trace::<N>).ok_or_else(|| SimError::Shard {
                shard: format!("run {} / {}", scenario.name, method.name()),
                message: format!("its first seed's trace is missing or not {N} joints per tick"),
            })?;
            first_seeds.push(RunOutcome {
                scenario: scenario.name.clone(),
                method,
                seed: scenario.seed,
                bandwidth_rad_s: run.bandwidth_rad_s.clone(),
                trace,
                metrics: run.metrics.clone(),
            });
        }
    }
    Ok((first_seeds, table))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_shard_outside_the_experiments_runs_is_refused_in_the_library() {
        let scenarios = [Scenario::builtin("goto_internal").unwrap_or_else(|e| panic!("{e}"))];
        let runs = seeds::jobs(&scenarios, 2).len();
        for (index, count) in [(0, 0), (2, 2), (0, runs + 1)] {
            assert!(cost(&scenarios, 2, Shard { index, count }).is_err(), "{index}/{count} accepted");
        }
        let whole = cost(&scenarios, 2, Shard { index: 0, count: 1 }).unwrap_or_else(|e| panic!("{e}"));
        let halves =
            [0, 1].map(|index| cost(&scenarios, 2, Shard { index, count: 2 }).unwrap_or_else(|e| panic!("{e}")));
        assert_eq!(whole.runs, runs);
        assert_eq!(halves[0].runs + halves[1].runs, runs);
    }

    #[test]
    fn a_trace_keeps_its_bits_and_a_misfit_is_refused() {
        let mut trace = Trace::<2> { stride: 3, time: vec![0.0, 0.5], ..Trace::default() };
        let v = |a: f64| vec![JointVector::<2>::new(a, f64::NAN), JointVector::<2>::new(-a, 1e-300)];
        (trace.q, trace.q_des, trace.d_true, trace.d_hat, trace.tau_cmd) = (v(1.0), v(2.0), v(3.0), v(4.0), v(5.0));
        let stored = StoredTrace::of(&trace);
        let mut bytes = Vec::new();
        ciborium::into_writer(&stored, &mut bytes).unwrap_or_else(|e| panic!("{e}"));
        let back: StoredTrace = ciborium::from_reader(bytes.as_slice()).unwrap_or_else(|e| panic!("{e}"));
        let again = back.trace::<2>().unwrap_or_else(|| panic!("a trace of two joints"));
        let bits =
            |t: &Trace<2>| t.q.iter().chain(&t.tau_cmd).flat_map(|x| x.iter().map(|v| v.to_bits())).collect::<Vec<_>>();
        assert_eq!(bits(&again), bits(&trace));
        assert!(back.trace::<3>().is_none(), "two joints read as three");
    }
}
