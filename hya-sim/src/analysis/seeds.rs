//! Every method of every scenario over many seeds, spread over the machine's cores, and the
//! per-joint means and 95 % intervals of their metrics.

use std::collections::BTreeMap;

use crate::analysis::metrics::Metrics;
use crate::analysis::simulate::RunOutcome;
use crate::config::scenario::{Method, Scenario};
use crate::error::SimError;
use crate::run::trace::Recording;

/// The metrics of every run, by scenario and method, one entry per seed in seed order.
#[derive(Debug, Clone, Default)]
pub struct MetricTable {
    runs: BTreeMap<(String, Method), Vec<Metrics>>,
}

impl MetricTable {
    /// Adds one seed's metrics of `method` on `scenario` (seeds in order).
    pub fn push(&mut self, scenario: &str, method: Method, metrics: Metrics) {
        self.runs.entry((scenario.to_owned(), method)).or_default().push(metrics);
    }

    /// Per seed, the per-joint values of `metric`; `None` where the run or the metric is missing.
    pub fn values(&self, scenario: &str, method: Method, metric: &str) -> Option<Vec<Vec<f64>>> {
        let runs = self.runs.get(&(scenario.to_owned(), method))?;
        runs.iter().map(|m| m.named().into_iter().find(|(name, _)| *name == metric).map(|(_, v)| v.to_vec())).collect()
    }

    /// Every metric of `method` on `scenario` by name, `[seed][joint]` (empty where it did not run).
    pub fn per_seed(&self, scenario: &str, method: Method) -> BTreeMap<&'static str, Vec<Vec<f64>>> {
        let mut all: BTreeMap<&'static str, Vec<Vec<f64>>> = BTreeMap::new();
        for metrics in self.runs.get(&(scenario.to_owned(), method)).into_iter().flatten() {
            for (name, values) in metrics.named() {
                all.entry(name).or_default().push(values.to_vec());
            }
        }
        all
    }

    /// How many seeds `method` ran on `scenario`.
    pub fn seeds(&self, scenario: &str, method: Method) -> usize {
        self.runs.get(&(scenario.to_owned(), method)).map_or(0, Vec::len)
    }

    /// The same table with every run cut to its first `seeds` seeds.
    pub fn first_seeds(&self, seeds: usize) -> MetricTable {
        let runs = self.runs.iter().map(|(key, runs)| (key.clone(), runs[..runs.len().min(seeds)].to_vec())).collect();
        MetricTable { runs }
    }

    /// This table with `other`'s runs in place of its own where both ran a scenario and method.
    pub fn overlaid(mut self, other: MetricTable) -> MetricTable {
        self.runs.extend(other.runs);
        self
    }
}

/// Two-sided 95 % quantile of Student's t with `df` degrees of freedom (its 0.975 quantile,
/// statrs' inverse distribution function; infinite for `df = 0`).
fn student_t_975(df: usize) -> f64 {
    use statrs::distribution::{ContinuousCDF, StudentsT};
    match StudentsT::new(0.0, 1.0, df as f64) {
        Ok(t) if df > 0 => t.inverse_cdf(0.975),
        _ => f64::INFINITY,
    }
}

/// The mean of `samples` and the half-width of its 95 % confidence interval (Student's t; an
/// infinite half-width for a single sample).
pub fn mean_ci95(samples: &[f64]) -> (f64, f64) {
    let n = samples.len();
    if n == 0 {
        return (f64::NAN, f64::INFINITY);
    }
    let mean = samples.iter().sum::<f64>() / n as f64;
    if n == 1 {
        return (mean, f64::INFINITY);
    }
    let variance = samples.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / (n - 1) as f64;
    (mean, student_t_975(n - 1) * (variance / n as f64).sqrt())
}

/// The median of `values` (NaN when empty): for metrics whose seeds split into groups (a joint
/// that recovers or sticks), where a mean and a t interval mislead.
pub fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    match values.len() {
        0 => f64::NAN,
        n if n % 2 == 1 => values[n / 2],
        n => 0.5 * (values[n / 2 - 1] + values[n / 2]),
    }
}

/// The ratio of two paired samples (the same seeds), `a[s] / b[s]`: the geometric mean over
/// seeds and its 95 % interval, from the Student-t interval of `ln(a/b)`. Seed-to-seed spread
/// that both share cancels in each ratio, which unpaired intervals cannot use.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairedRatio {
    /// The geometric mean of the ratios.
    pub ratio: f64,
    /// The interval's lower end.
    pub low: f64,
    /// The interval's upper end.
    pub high: f64,
}

impl PairedRatio {
    /// The ratio of `a` to `b`, paired by index.
    pub fn of(a: &[f64], b: &[f64]) -> Self {
        let logs: Vec<f64> = a.iter().zip(b).map(|(x, y)| (x / y).ln()).collect();
        let (mean, half) = mean_ci95(&logs);
        Self { ratio: mean.exp(), low: (mean - half).exp(), high: (mean + half).exp() }
    }

    /// Whether the whole interval lies above 1.
    pub fn above_one(&self) -> bool {
        self.low > 1.0
    }

    /// Whether the whole interval lies below 1.
    pub fn below_one(&self) -> bool {
        self.high < 1.0
    }
}

/// Per joint, the paired ratio of `a[seed][joint]` to `b[seed][joint]` ([`PairedRatio`]).
pub fn per_joint_paired_ratio(a: &[Vec<f64>], b: &[Vec<f64>]) -> Vec<PairedRatio> {
    let joints = a.first().map_or(0, Vec::len).min(b.first().map_or(0, Vec::len));
    let column = |rows: &[Vec<f64>], j: usize| rows.iter().map(|r| r[j]).collect::<Vec<f64>>();
    (0..joints).map(|j| PairedRatio::of(&column(a, j), &column(b, j))).collect()
}

/// Per joint, the mean and 95 % half-width over seeds of `values[seed][joint]`.
pub fn per_joint_mean_ci95(values: &[Vec<f64>]) -> (Vec<f64>, Vec<f64>) {
    let joints = values.first().map_or(0, Vec::len);
    (0..joints).map(|j| mean_ci95(&values.iter().map(|v| v[j]).collect::<Vec<_>>())).unzip()
}

/// `f` applied to every job on every core (rayon's pool), the results in the jobs' order (so the
/// outcome does not depend on which thread ran what).
///
/// A job is a whole closed-loop run (0.1 s to seconds of computing), so the pool's scheduling
/// costs nothing measurable: `hya reproduce --quick` (README build, 2 cores, the two builds run
/// in turn, three times each) took a median of 30.3 s wall on the hand-written scoped pool this
/// replaced and 28.0 s on rayon's, within the machine's noise (27.6-34.8 s), with the same
/// `summary.json`. Rayon is kept as the well-kept pool, with work stealing for jobs of unequal
/// length.
pub fn parallel_map<J: Sync, R: Send>(jobs: &[J], f: impl Fn(&J) -> R + Sync) -> Vec<R> {
    use rayon::prelude::*;
    jobs.par_iter().map(&f).collect()
}

/// How many seeds of one scenario and method [`run_jobs`] steps together
/// ([`RunSetup::run_together`](crate::run::RunSetup::run_together)): the lanes of the batch its plants' forward dynamics runs on.
pub const LOCKSTEP_SEEDS: usize = hya_core::lanes::BATCH_LANES;

/// `items` in the groups that step together: consecutive items of one `key` (a scenario and a
/// method: runs that differ by seed alone), [`LOCKSTEP_SEEDS`] at a time, in order.
pub fn lockstep_groups<T, K: PartialEq>(items: &[T], key: impl Fn(&T) -> K) -> Vec<&[T]> {
    items.chunk_by(|a, b| key(a) == key(b)).flat_map(|group| group.chunks(LOCKSTEP_SEEDS)).collect()
}

/// One run of an experiment: which scenario, the method, which seed (0: the scenario's own).
pub type Job = (usize, Method, usize);

/// Every run of every scenario and method over `seeds` seeds, scenario by scenario, method by
/// method, seed by seed: the order runs are reported, stored and sharded in.
pub fn jobs(scenarios: &[Scenario], seeds: usize) -> Vec<Job> {
    scenarios
        .iter()
        .enumerate()
        .flat_map(|(i, s)| s.methods.iter().flat_map(move |&m| (0..seeds).map(move |k| (i, m, k))))
        .collect()
}

/// Runs `jobs` on every core, each seed's offset added to its scenario's seed, the first seed's
/// traces kept (for figures); `progress` is told each finished run's simulated seconds. Each
/// scenario and method is set up once ([`RunSetup`](crate::run::RunSetup)) for all its seeds, which run
/// [`LOCKSTEP_SEEDS`] at a time in lockstep ([`RunSetup::run_together`](crate::run::RunSetup::run_together): the same results).
pub fn run_jobs<const N: usize>(
    robot: &crate::robot::Robot<N>,
    scenarios: &[Scenario],
    jobs: &[Job],
    progress: &(dyn Fn(f64) + Sync),
) -> Result<Vec<RunOutcome<N>>, SimError> {
    let seed = |i: usize, k: usize| scenarios[i].seed.wrapping_add(k as u64);
    let failed = |(i, method, k): Job| {
        move |e: SimError| SimError::Run {
            run: format!("{} / {} / seed {}", scenarios[i].name, method.name(), seed(i, k)),
            source: Box::new(e),
        }
    };
    // A setup's error is every seed's: it names none.
    let mut setups = BTreeMap::new();
    for &(i, method, _) in jobs {
        if let std::collections::btree_map::Entry::Vacant(slot) = setups.entry((i, method)) {
            let setup = crate::analysis::simulate::run_setup(&scenarios[i], method, robot).map_err(|e| {
                SimError::Run { run: format!("{} / {}", scenarios[i].name, method.name()), source: Box::new(e) }
            })?;
            slot.insert(setup);
        }
    }
    let groups = lockstep_groups(jobs, |&(i, method, _)| (i, method));
    let results = parallel_map(&groups, |group| {
        let (i, method, _) = group[0];
        // Only the first seed's traces are kept (for the figures and CSV files).
        let seeds: Vec<(u64, Recording)> = group
            .iter()
            .map(|&(_, _, k)| (seed(i, k), if k == 0 { Recording::Bounded } else { Recording::Off }))
            .collect();
        let runs = setups[&(i, method)].run_together(&seeds);
        for _ in group.iter() {
            progress(scenarios[i].duration_s);
        }
        group
            .iter()
            .zip(runs)
            .map(|(&(_, _, k), run)| run.map(|run| RunOutcome::of(&scenarios[i].name, method, seed(i, k), run)))
            .collect::<Vec<_>>()
    });
    let results = results.into_iter().flatten();
    jobs.iter().zip(results).map(|(&job, outcome)| outcome.map_err(failed(job))).collect()
}

/// The runs of every scenario and method over `seeds` seeds (the scenario's seed and the next
/// ones): the first seed's runs with their traces (for figures), and every run's metrics.
/// `progress` is told each finished run's simulated seconds.
pub fn run_seeds<const N: usize>(
    robot: &crate::robot::Robot<N>,
    scenarios: &[Scenario],
    seeds: usize,
    progress: &(dyn Fn(f64) + Sync),
) -> Result<(Vec<RunOutcome<N>>, MetricTable), SimError> {
    let jobs = jobs(scenarios, seeds);
    let outcomes = run_jobs(robot, scenarios, &jobs, progress)?;
    let mut table = MetricTable::default();
    let mut first = Vec::new();
    for (&(_, method, k), outcome) in jobs.iter().zip(outcomes) {
        table.push(&outcome.scenario, method, outcome.metrics.clone());
        if k == 0 {
            first.push(outcome);
        }
    }
    Ok((first, table))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn intervals_follow_student_t() {
        // Samples 1..=5: mean 3, s = √2.5, t(4) = 2.7764451 (tables' 2.776).
        let (mean, half) = mean_ci95(&[1.0, 2.0, 3.0, 4.0, 5.0]);
        assert!((mean - 3.0).abs() < 1e-15);
        assert!((half - 2.776_445_105 * (2.5f64 / 5.0).sqrt()).abs() < 1e-8);
        // Published quantiles (Abramowitz & Stegun, table 26.10), beyond the old table's 30 too.
        for (df, t) in [(1, 12.706_204_7), (19, 2.093_024_1), (40, 2.021_075_4), (120, 1.979_930_4)] {
            assert!((student_t_975(df) - t).abs() < 1e-6, "t({df}) = {}", student_t_975(df));
        }
        assert!(mean_ci95(&[1.0]).1.is_infinite(), "one sample has no interval");
    }
}
