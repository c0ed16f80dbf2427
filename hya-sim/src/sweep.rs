//! Observer bandwidth sweeps: every observer from 10 to 200 rad/s on chosen scenarios, the
//! estimate error against the noise it puts in the command and the tracking error it buys. The
//! grid splits into shards (`i/n`: every n-th run from the i-th) that a batch scheduler runs on
//! separate machines; [`merge`] joins their `sweep.json` files into the same result as one run.

use serde::{Deserialize, Serialize};

use crate::scenario::{Method, Scenario};
use crate::svg::{line_grid, Panel, Series, PALETTE};
use crate::{run_method, SimError, HYA_JOINTS};

/// What a sweep runs.
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    /// The scenarios (already shortened where wanted).
    pub scenarios: Vec<Scenario>,
    /// The observers.
    pub methods: Vec<Method>,
    /// Their bandwidths, rad/s.
    pub bandwidths_rad_s: Vec<f64>,
    /// Seeds per point (the scenario's seed and the next ones).
    pub seeds: usize,
}

impl Plan {
    /// The default grid: every observer at 10 to 200 rad/s on the high-noise estimator
    /// comparison and the goto task; `quick` shortens the scenarios.
    pub fn standard(quick: bool) -> Result<Self, SimError> {
        let scenarios = ["estimator_noise_high", "goto_internal"]
            .iter()
            .map(|name| Scenario::builtin(name).map(|s| if quick { s.quick() } else { s }))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Self {
            scenarios,
            methods: vec![Method::Lu, Method::Chen, Method::Momentum, Method::Eso],
            bandwidths_rad_s: vec![10.0, 20.0, 35.0, 50.0, 75.0, 100.0, 150.0, 200.0],
            seeds: if quick { 1 } else { 3 },
        })
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

    /// Parses `I/N` with `0 ≤ I < N`.
    pub fn parse(text: &str) -> Result<Self, String> {
        let (i, n) = text.split_once('/').ok_or_else(|| format!("--shard {text:?}: expected I/N, e.g. 0/4"))?;
        let parse = |x: &str| x.trim().parse::<usize>().map_err(|e| format!("--shard {text:?}: {x:?}: {e}"));
        let (index, count) = (parse(i)?, parse(n)?);
        if count == 0 || index >= count {
            return Err(format!("--shard {text:?}: need 0 ≤ I < N"));
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
    /// Mean over joints of the RMSE of `d̂ − d`, N·m.
    pub rmse_d: f64,
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
    /// Into how many shards the sweep was split.
    pub shards: usize,
    /// Which of them this file holds.
    pub shard_indices: Vec<usize>,
    /// Every point, sorted by scenario, method, bandwidth and seed.
    pub entries: Vec<Entry>,
}

fn key(e: &Entry) -> (String, String, u64, u64) {
    (e.scenario.clone(), e.method.clone(), e.bandwidth_rad_s.to_bits(), e.seed)
}

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

/// Runs the shard `shard` of `plan`, telling `progress` each finished run's simulated seconds.
pub fn run(plan: &Plan, shard: Shard, progress: &(dyn Fn(f64) + Sync)) -> Result<Sweep, SimError> {
    let jobs: Vec<_> =
        plan.jobs().into_iter().enumerate().filter(|(k, _)| k % shard.count == shard.index).map(|(_, j)| j).collect();
    let entries = crate::seeds::parallel_map(&jobs, |&(i, method, bandwidth, k)| {
        let mut scenario = plan.scenarios[i].clone();
        scenario.seed = scenario.seed.wrapping_add(k as u64);
        scenario.controller.observer_bandwidth_rad_s = bandwidth;
        let entry = run_method::<HYA_JOINTS>(&scenario, method).map(|o| Entry {
            scenario: scenario.name.clone(),
            method: method.name().to_owned(),
            bandwidth_rad_s: bandwidth,
            seed: scenario.seed,
            rmse_d: o.metrics.rmse_d.as_deref().map_or(f64::NAN, mean),
            tau_cmd_noise: mean(&o.metrics.tau_cmd_noise),
            rmse_q: mean(&o.metrics.rmse_q),
        });
        progress(scenario.duration_s);
        entry
    })
    .into_iter()
    .collect::<Result<Vec<_>, _>>()?;
    Ok(Sweep {
        plan: plan.fingerprint(),
        shards: shard.count,
        shard_indices: vec![shard.index],
        entries: Sweep::sorted(entries),
    })
}

/// Joins shards of one sweep: every entry once (an entry present in several shards must agree).
/// Shards of different sweeps, or a set missing a shard, are refused.
pub fn merge(shards: &[Sweep]) -> Result<Sweep, SimError> {
    let Some(first) = shards.first() else { return Err(SimError::Config("no shards to merge".into())) };
    if let Some(other) = shards.iter().find(|s| s.plan != first.plan || s.shards != first.shards) {
        return Err(SimError::Config(format!(
            "shards come from different sweeps: {:?} in {} shards against {:?} in {}",
            first.plan, first.shards, other.plan, other.shards
        )));
    }
    let missing: Vec<String> = (0..first.shards)
        .filter(|i| !shards.iter().any(|s| s.shard_indices.contains(i)))
        .map(|i| format!("{i}/{}", first.shards))
        .collect();
    if !missing.is_empty() {
        return Err(SimError::Config(format!("missing shards: {}", missing.join(", "))));
    }
    let mut all: Vec<Entry> = shards.iter().flat_map(|s| s.entries.iter().cloned()).collect();
    all.sort_by_key(key);
    let mut merged: Vec<Entry> = Vec::with_capacity(all.len());
    for entry in all {
        match merged.last() {
            Some(last) if key(last) == key(&entry) => {
                if *last != entry {
                    return Err(SimError::Config(format!(
                        "shards disagree on {} / {} at {} rad/s, seed {}",
                        entry.scenario, entry.method, entry.bandwidth_rad_s, entry.seed
                    )));
                }
            }
            _ => merged.push(entry),
        }
    }
    Ok(Sweep {
        plan: first.plan.clone(),
        shards: first.shards,
        shard_indices: (0..first.shards).collect(),
        entries: Sweep::sorted(merged),
    })
}

/// The Pareto figure: per scenario, estimate error and tracking RMSE against command noise, one
/// line per method through its bandwidths (means over seeds).
pub fn pareto_figure(sweep: &Sweep) -> String {
    let mut scenarios: Vec<&str> = sweep.entries.iter().map(|e| e.scenario.as_str()).collect();
    scenarios.dedup();
    let mut panels = Vec::new();
    for scenario in scenarios {
        let estimate: fn(&Entry) -> f64 = |e| e.rmse_d;
        let tracking: fn(&Entry) -> f64 = |e| e.rmse_q;
        for (y_label, value) in [("RMSE d̂ − d [N·m]", estimate), ("RMSE q [rad]", tracking)] {
            let mut methods: Vec<&str> =
                sweep.entries.iter().filter(|e| e.scenario == scenario).map(|e| e.method.as_str()).collect();
            methods.sort_unstable();
            methods.dedup();
            let series = methods
                .iter()
                .enumerate()
                .map(|(k, method)| {
                    let mut bandwidths: Vec<f64> = sweep
                        .entries
                        .iter()
                        .filter(|e| e.scenario == scenario && e.method == *method)
                        .map(|e| e.bandwidth_rad_s)
                        .collect();
                    bandwidths.sort_by(f64::total_cmp);
                    bandwidths.dedup();
                    let points = bandwidths
                        .iter()
                        .map(|b| {
                            let at: Vec<&Entry> = sweep
                                .entries
                                .iter()
                                .filter(|e| e.scenario == scenario && e.method == *method && e.bandwidth_rad_s == *b)
                                .collect();
                            let avg =
                                |f: &dyn Fn(&Entry) -> f64| at.iter().map(|e| f(e)).sum::<f64>() / at.len() as f64;
                            (avg(&|e| e.tau_cmd_noise), avg(&value))
                        })
                        .collect();
                    Series {
                        label: format!(
                            "{method} ({}–{} rad/s)",
                            bandwidths.first().copied().unwrap_or(0.0),
                            bandwidths.last().copied().unwrap_or(0.0)
                        ),
                        points,
                        color: PALETTE[(k + 1) % PALETTE.len()],
                        dashed: false,
                        markers: false,
                    }
                })
                .collect();
            panels.push(Panel { title: scenario.to_owned(), y_label: y_label.into(), series });
        }
    }
    line_grid("observer bandwidth sweep: error against command noise", "command-torque noise [N·m]", &panels, 2)
}
