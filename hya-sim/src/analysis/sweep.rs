//! Observer bandwidth sweeps: every observer from 10 to 200 rad/s on chosen scenarios, the
//! estimate error against the noise it puts in the command and the tracking error it buys. The PID
//! baseline is swept the same way: its swept value is the equivalent bandwidth `ω` of its integral,
//! `K_I = K_P / τ_d(ω)` with `τ_d(ω) = 1/ω + 2ζ/ω` (the paper's estimator's low-frequency delay at
//! that bandwidth, [`IntegralRule::MatchEstimator`]), still capped at half the Routh bound
//! `½ K_D K_P / M_ii` ([`crate::run::pid_gains`]). The grid splits into shards (`i/n`: every n-th run from the i-th) that a batch scheduler runs on
//! separate machines; [`merge`] joins their `sweep.json` files into the same result as one run.

use serde::{Deserialize, Serialize};

use crate::analysis::seeds::{lockstep_groups, mean_ci95};
use crate::config::scenario::{IntegralRule, Method, Scenario};
use crate::error::SimError;
use hya_core::{Clipped, Short};

/// What a sweep runs.
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    /// The scenarios (already shortened where wanted).
    pub scenarios: Vec<Scenario>,
    /// The observers, and `pid` (its integral's equivalent bandwidth swept).
    pub methods: Vec<Method>,
    /// Their bandwidths, rad/s (for `pid`, the bandwidth its `K_I` is matched to).
    pub bandwidths_rad_s: Vec<f64>,
    /// Seeds per point (the scenario's seed and the next ones).
    pub seeds: usize,
}

impl Plan {
    /// The default grid: every observer and pid at 10 to 200 rad/s on the high-noise estimator
    /// comparison and the goto task; `quick` shortens the scenarios.
    pub fn standard(quick: bool) -> Result<Self, SimError> {
        Ok(Self {
            scenarios: builtin_scenarios(quick)?,
            methods: SWEPT_METHODS.to_vec(),
            bandwidths_rad_s: vec![10.0, 20.0, 35.0, 50.0, 75.0, 100.0, 150.0, 200.0],
            seeds: if quick { 1 } else { 3 },
        })
    }

    /// The reduced grid `hya reproduce` runs: the same scenarios and methods at
    /// [`REPORT_BANDWIDTHS_RAD_S`], [`REPORT_SEEDS`] seeds (1 with `quick`, which also shortens the
    /// scenarios).
    pub fn report(quick: bool) -> Result<Self, SimError> {
        Ok(Self {
            scenarios: builtin_scenarios(quick)?,
            methods: SWEPT_METHODS.to_vec(),
            bandwidths_rad_s: REPORT_BANDWIDTHS_RAD_S.to_vec(),
            seeds: if quick { 1 } else { REPORT_SEEDS },
        })
    }

    /// The scenario one run of the grid simulates: the `scenario`-th at `bandwidth_rad_s` (for
    /// every method: the observers read it as their bandwidth, pid's `K_I` rule
    /// [`IntegralRule::MatchEstimator`] as its equivalent bandwidth), seed offset by `seed_offset`,
    /// its methods just `method` (so pid's settings are checked when pid runs). `None` past the
    /// plan's scenarios.
    pub fn scenario_at(
        &self,
        scenario: usize,
        method: Method,
        bandwidth_rad_s: f64,
        seed_offset: usize,
    ) -> Option<Scenario> {
        let mut s = self.scenarios.get(scenario)?.clone();
        s.seed = s.seed.wrapping_add(seed_offset as u64);
        s.controller.observer_bandwidth_rad_s = bandwidth_rad_s;
        if method == Method::Pid {
            s.controller.integral_rule = IntegralRule::MatchEstimator;
        }
        s.methods = vec![method];
        Some(s)
    }

    /// How many runs the grid holds (the most shards it splits into).
    pub fn runs(&self) -> usize {
        self.scenarios.len() * self.methods.len() * self.bandwidths_rad_s.len() * self.seeds
    }

    /// What running `shard`'s points of the grid costs (no run keeps a trace).
    pub fn cost(&self, shard: Shard) -> crate::config::cost::Cost {
        self.shard_jobs(shard)
            .into_iter()
            .filter_map(|(i, method, bandwidth, k)| self.scenario_at(i, method, bandwidth, k))
            .map(|s| crate::config::cost::Cost::of_runs(&s, 1, 0))
            .sum()
    }

    /// The point run `job` gives, as [`key`] names entries.
    fn point(&self, &(i, method, bandwidth, k): &(usize, Method, f64, usize)) -> Key {
        let scenario = &self.scenarios[i];
        (scenario.name.clone(), method.name().to_owned(), bandwidth.to_bits(), scenario.seed.wrapping_add(k as u64))
    }

    /// The runs of `shard`: every `count`-th of [`Self::jobs`] from the `index`-th.
    fn shard_jobs(&self, shard: Shard) -> Vec<(usize, Method, f64, usize)> {
        self.jobs().into_iter().enumerate().filter(|(k, _)| k % shard.count == shard.index).map(|(_, j)| j).collect()
    }

    /// Every run of the grid, in one fixed order: `(scenario index, method, bandwidth, seed offset)`.
    fn jobs(&self) -> Vec<(usize, Method, f64, usize)> {
        let mut jobs = Vec::new();
        for (i, _) in self.scenarios.iter().enumerate() {
            for &method in &self.methods {
                for &bandwidth in &self.bandwidths_rad_s {
                    for k in 0..self.seeds {
                        jobs.push((i, method, bandwidth, k));
                    }
                }
            }
        }
        jobs
    }
}

/// The methods a sweep compares.
const SWEPT_METHODS: [Method; 5] = [Method::Lu, Method::Chen, Method::Momentum, Method::Eso, Method::Pid];

/// The bandwidths of the report's reduced grid, rad/s.
pub const REPORT_BANDWIDTHS_RAD_S: [f64; 4] = [20.0, 50.0, 100.0, 200.0];

/// Seeds per point of the report's reduced grid (without `--quick`).
pub const REPORT_SEEDS: usize = 3;

/// The swept scenarios, shortened with `quick`.
fn builtin_scenarios(quick: bool) -> Result<Vec<Scenario>, SimError> {
    ["estimator_noise_high", "goto_internal"]
        .iter()
        .map(|name| Scenario::builtin(name).map(|s| if quick { s.quick() } else { s }))
        .collect()
}

/// One shard of a sweep: the `index`-th of `count` (from 0).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    /// Which shard.
    pub index: usize,
    /// How many shards.
    pub count: usize,
}

impl Shard {
    /// The whole sweep.
    pub const ALL: Shard = Shard { index: 0, count: 1 };

    /// Parses `I/N` with `0 ≤ I < N ≤ runs` (a shard beyond the grid's `runs` would be empty).
    pub fn parse(text: &str, runs: usize) -> Result<Self, String> {
        let shown = Clipped(text, 40);
        let (i, n) = text.split_once('/').ok_or_else(|| format!("--shard {shown}: expected I/N, e.g. 0/4"))?;
        let parse =
            |x: &str| x.trim().parse::<usize>().map_err(|e| format!("--shard {shown}: {}: {e}", Clipped(x, 20)));
        let (index, count) = (parse(i)?, parse(n)?);
        if count == 0 || index >= count {
            return Err(format!("--shard {shown}: need 0 ≤ I < N"));
        }
        if count > runs {
            return Err(format!("--shard {shown}: there are {runs} runs, so N can be at most {runs}"));
        }
        Ok(Self { index, count })
    }
}

/// One point of a sweep: means over joints of one run's metrics.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Entry {
    /// Scenario name.
    pub scenario: String,
    /// Method name.
    pub method: String,
    /// The observer's bandwidth, rad/s.
    pub bandwidth_rad_s: f64,
    /// The run's seed.
    pub seed: u64,
    /// Mean over joints of the RMSE of `d̂ − d`, N·m; `None` for pid, which estimates nothing.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rmse_d: Option<f64>,
    /// Mean over joints of the command-torque noise, N·m.
    pub tau_cmd_noise: f64,
    /// Mean over joints of the tracking RMSE, rad.
    pub rmse_q: f64,
}

/// `sweep.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
pub struct Sweep {
    /// What was swept (scenarios and durations, methods, bandwidths, seeds): shards of different
    /// sweeps do not merge.
    pub plan: String,
    /// Whether the scenarios were shortened (`--quick`), so the merge can rebuild the plan.
    pub quick: bool,
    /// Into how many shards the sweep was split.
    pub shards: usize,
    /// Which of them this file holds.
    pub shard_indices: Vec<usize>,
    /// Every point, sorted by scenario, method, bandwidth and seed.
    pub entries: Vec<Entry>,
}

/// A point of the grid: scenario, method, bandwidth's bits, seed.
type Key = (String, String, u64, u64);

fn key(e: &Entry) -> Key {
    (e.scenario.clone(), e.method.clone(), e.bandwidth_rad_s.to_bits(), e.seed)
}

/// The largest `sweep.json` read, bytes (the full grid's is about 60 kB).
pub const MAX_SWEEP_BYTES: u64 = 16 << 20;

impl Plan {
    /// A description of the grid that identifies it.
    fn fingerprint(&self) -> String {
        let scenarios: Vec<String> =
            self.scenarios.iter().map(|s| format!("{} ({} s, seed {})", s.name, s.duration_s, s.seed)).collect();
        let methods: Vec<&str> = self.methods.iter().map(|m| m.name()).collect();
        format!(
            "{}; {}; {:?} rad/s; {} seeds",
            scenarios.join(", "),
            methods.join(", "),
            self.bandwidths_rad_s,
            self.seeds
        )
    }
}

impl Sweep {
    fn sorted(mut entries: Vec<Entry>) -> Vec<Entry> {
        entries.sort_by(|a, b| {
            (a.scenario.as_str(), a.method.as_str(), a.seed)
                .cmp(&(b.scenario.as_str(), b.method.as_str(), b.seed))
                .then(a.bandwidth_rad_s.total_cmp(&b.bandwidth_rad_s))
        });
        entries
    }
}

fn mean(values: &[f64]) -> f64 {
    values.iter().sum::<f64>() / values.len().max(1) as f64
}

/// Runs the shard `shard` of `plan` on its scenarios' robot, telling `progress` each finished
/// run's simulated seconds; `quick` is recorded for the merge.
pub fn run(plan: &Plan, shard: Shard, quick: bool, progress: &(dyn Fn(f64) + Sync)) -> Result<Sweep, SimError> {
    let Some(first) = plan.scenarios.first() else { return Err(SimError::Nothing("a sweep of no scenario")) };
    crate::robot::with_robot(&first.robot.clone(), ShardRun { plan, shard, quick, progress })
}

/// One shard of a sweep, for the robot [`with_robot`](crate::robot::with_robot) finds.
struct ShardRun<'a> {
    plan: &'a Plan,
    shard: Shard,
    quick: bool,
    progress: &'a (dyn Fn(f64) + Sync),
}

impl crate::robot::ForRobot for ShardRun<'_> {
    type Output = Sweep;
    fn call<const N: usize>(self, robot: crate::robot::Robot<N>) -> Result<Sweep, SimError> {
        run_on(&robot, self.plan, self.shard, self.quick, self.progress)
    }
}

/// [`run`] on a robot already loaded (the plan's scenarios must name it).
pub fn run_on<const N: usize>(
    robot: &crate::robot::Robot<N>,
    plan: &Plan,
    shard: Shard,
    quick: bool,
    progress: &(dyn Fn(f64) + Sync),
) -> Result<Sweep, SimError> {
    let jobs = plan.shard_jobs(shard);
    // A point's seeds step together (`RunSetup::run_together`): they differ by seed alone.
    let groups = lockstep_groups(&jobs, |&(i, method, bandwidth, _)| (i, method, bandwidth.to_bits()));
    let entries = crate::analysis::seeds::parallel_map(&groups, |group| {
        let beyond = || SimError::Nothing("a sweep point beyond its scenarios");
        let point = |k: usize| plan.scenario_at(group[0].0, group[0].1, group[0].2, k).ok_or_else(beyond);
        let (scenario, method, bandwidth) = (point(group[0].3)?, group[0].1, group[0].2);
        let seeds = group
            .iter()
            .map(|&(.., k)| Ok((point(k)?.seed, crate::run::trace::Recording::Off)))
            .collect::<Result<Vec<_>, SimError>>()?;
        let setup = crate::analysis::simulate::run_setup(&scenario, method, robot)?;
        let entries = setup.run_together(&seeds).into_iter().zip(&seeds).map(|(run, &(seed, _))| {
            progress(scenario.duration_s);
            run.map(|run| Entry {
                scenario: scenario.name.clone(),
                method: method.name().to_owned(),
                bandwidth_rad_s: bandwidth,
                seed,
                rmse_d: run.metrics.rmse_d.as_deref().map(mean),
                tau_cmd_noise: mean(&run.metrics.tau_cmd_noise),
                rmse_q: mean(&run.metrics.rmse_q),
            })
        });
        entries.collect::<Result<Vec<_>, SimError>>()
    })
    .into_iter()
    .collect::<Result<Vec<Vec<_>>, _>>()?
    .into_iter()
    .flatten()
    .collect();
    Ok(Sweep {
        plan: plan.fingerprint(),
        quick,
        shards: shard.count,
        shard_indices: vec![shard.index],
        entries: Sweep::sorted(entries),
    })
}

/// Reads the `sweep.json` of a shard folder, at most [`MAX_SWEEP_BYTES`].
pub fn read(dir: &std::path::Path) -> Result<Sweep, SimError> {
    let path = dir.join("sweep.json");
    let origin = path.display().to_string();
    let text = crate::io::input::read_text(&path, MAX_SWEEP_BYTES)
        .map_err(|message| SimError::Shard { shard: origin.clone(), message })?;
    serde_json::from_str(&text).map_err(|e| SimError::Shard { shard: origin, message: format!("not a sweep: {e}") })
}

/// Joins the shards of one sweep of `plan`, each named by where it came from. Every shard must
/// come from `plan` split the same way, name shard indices in range that no other shard names,
/// and hold exactly the grid's points of those indices, each value finite and ≥ 0; together they
/// must cover every index. Anything else is refused, naming the shard.
pub fn merge(plan: &Plan, shards: &[(String, Sweep)]) -> Result<Sweep, SimError> {
    let Some((_, first)) = shards.first() else { return Err(SimError::Nothing("no shards to merge")) };
    let runs = plan.runs();
    let count = first.shards;
    let fingerprint = plan.fingerprint();
    let jobs = plan.jobs();
    let mut claimed: Vec<Option<&str>> = Vec::new();
    let mut all = Vec::with_capacity(runs);
    for (origin, shard) in shards {
        let refuse = |message: String| SimError::Shard { shard: origin.clone(), message };
        if shard.plan != fingerprint || shard.quick != first.quick {
            return Err(refuse(format!(
                "comes from another sweep: {} against {}",
                Clipped(&shard.plan, 200),
                Clipped(&fingerprint, 200)
            )));
        }
        if shard.shards != count {
            return Err(refuse(format!("is one of {} shards, the first of {count}", shard.shards)));
        }
        if !(1..=runs).contains(&count) {
            return Err(refuse(format!("claims {count} shards; the sweep has {runs} runs, so 1 to {runs}")));
        }
        claimed.resize(count, None);
        let mut expected = Vec::new();
        for &index in &shard.shard_indices {
            let Some(slot) = claimed.get_mut(index) else {
                return Err(refuse(format!("names shard {index}, beyond 0 to {}", count - 1)));
            };
            if let Some(other) = slot.replace(origin) {
                return Err(refuse(format!("names shard {index}/{count}, which {other} holds too")));
            }
            expected.extend(jobs.iter().skip(index).step_by(count).map(|job| plan.point(job)));
        }
        expected.sort();
        let mut found: Vec<Key> = shard.entries.iter().map(key).collect();
        found.sort();
        if found != expected {
            return Err(refuse(format!(
                "holds {} points where its shards have {} of the grid (points missing, repeated or not in the plan)",
                found.len(),
                expected.len()
            )));
        }
        if let Some(e) = shard
            .entries
            .iter()
            .find(|e| ![e.rmse_d.unwrap_or(0.0), e.tau_cmd_noise, e.rmse_q].iter().all(|v| v.is_finite() && *v >= 0.0))
        {
            return Err(refuse(format!(
                "{} / {} at {} rad/s, seed {}: a value is not a finite number ≥ 0",
                e.scenario,
                e.method,
                Short(e.bandwidth_rad_s),
                e.seed
            )));
        }
        all.extend(shard.entries.iter().cloned());
    }
    let missing: Vec<String> =
        claimed.iter().enumerate().filter(|(_, c)| c.is_none()).take(10).map(|(i, _)| format!("{i}/{count}")).collect();
    if !missing.is_empty() {
        let more = claimed.iter().filter(|c| c.is_none()).count() - missing.len();
        let more = if more > 0 { format!(" and {more} more") } else { String::new() };
        return Err(SimError::MissingShards(format!("{}{more}", missing.join(", "))));
    }
    Ok(Sweep {
        plan: fingerprint,
        quick: first.quick,
        shards: count,
        shard_indices: (0..count).collect(),
        entries: Sweep::sorted(all),
    })
}

/// What a front plots against command noise.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Measure {
    /// The tracking RMSE, rad.
    Tracking,
    /// The estimate's RMSE `d̂ − d`, N·m (not pid's: it estimates nothing).
    Estimate,
}

impl Measure {
    /// Both, tracking first.
    pub const ALL: [Measure; 2] = [Measure::Tracking, Measure::Estimate];

    /// Its value in one run.
    pub fn of(self, e: &Entry) -> Option<f64> {
        match self {
            Measure::Tracking => Some(e.rmse_q),
            Measure::Estimate => e.rmse_d,
        }
    }

    /// Its name and unit, for axes and text.
    pub fn label(self) -> &'static str {
        match self {
            Measure::Tracking => "tracking RMSE [rad]",
            Measure::Estimate => "estimate RMSE d̂ − d [N·m]",
        }
    }
}

/// One point of a front: a method at one swept value, means over seeds with the half-widths of
/// their 95 % intervals (infinite with one seed).
#[derive(Debug, Clone, PartialEq)]
pub struct FrontPoint {
    /// Method name.
    pub method: String,
    /// The swept value, rad/s.
    pub bandwidth_rad_s: f64,
    /// Command-torque noise, N·m: mean and half-width.
    pub noise: (f64, f64),
    /// The measure: mean and half-width.
    pub error: (f64, f64),
}

/// The scenarios of a sweep, in its entries' order.
pub fn scenarios(sweep: &Sweep) -> Vec<&str> {
    let mut names: Vec<&str> = sweep.entries.iter().map(|e| e.scenario.as_str()).collect();
    names.dedup();
    names
}

/// Every point of `scenario` with `measure`, by method and swept value (methods without the
/// measure, like pid's estimate, have none).
pub fn front_points(sweep: &Sweep, scenario: &str, measure: Measure) -> Vec<FrontPoint> {
    let mut keys: Vec<(&str, f64)> = sweep
        .entries
        .iter()
        .filter(|e| e.scenario == scenario && measure.of(e).is_some())
        .map(|e| (e.method.as_str(), e.bandwidth_rad_s))
        .collect();
    keys.sort_by(|a, b| a.0.cmp(b.0).then(a.1.total_cmp(&b.1)));
    keys.dedup();
    keys.into_iter()
        .map(|(method, bandwidth)| {
            let at: Vec<&Entry> = sweep
                .entries
                .iter()
                .filter(|e| e.scenario == scenario && e.method == method && e.bandwidth_rad_s == bandwidth)
                .collect();
            let noise: Vec<f64> = at.iter().map(|e| e.tau_cmd_noise).collect();
            let error: Vec<f64> = at.iter().filter_map(|e| measure.of(e)).collect();
            FrontPoint {
                method: method.to_owned(),
                bandwidth_rad_s: bandwidth,
                noise: mean_ci95(&noise),
                error: mean_ci95(&error),
            }
        })
        .collect()
}

/// `mean ± half`'s ends; an interval that is not finite (one seed) is taken as the mean alone.
fn ends((mean, half): (f64, f64)) -> (f64, f64) {
    let half = if half.is_finite() { half } else { 0.0 };
    (mean - half, mean + half)
}

/// Whether `a` dominates `b`: in command noise and in error `a`'s mean is no worse than `b`'s,
/// and in at least one it is better beyond the intervals (its upper end below `b`'s lower end).
/// With one seed the means are compared. (A rule that let `a` be worse in mean wherever the
/// intervals overlap once called the three slowest points of a sweep its front: with three seeds
/// an error interval can span most of the axis.)
pub fn dominates(a: &FrontPoint, b: &FrontPoint) -> bool {
    let pairs = [(a.noise, b.noise), (a.error, b.error)];
    pairs.iter().all(|(a, b)| a.0 <= b.0) && pairs.iter().any(|(a, b)| ends(*a).1 < ends(*b).0)
}

/// The indices of the points no other point dominates (the Pareto-optimal set), in order.
pub fn pareto_optimal(points: &[FrontPoint]) -> Vec<usize> {
    (0..points.len()).filter(|&i| !points.iter().enumerate().any(|(j, p)| j != i && dominates(p, &points[i]))).collect()
}
