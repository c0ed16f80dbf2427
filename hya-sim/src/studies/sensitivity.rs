//! The sensitivity study: the headline comparisons (the paper's estimator against `none`, `pid`
//! and `chen` on the goto and sine tasks) rerun with one structural choice changed at a time
//! (the torque sensors' transducers, the PID's tuning rule, Chen's gain design, the friction's
//! Stribeck peak, the command delay), every variant on the same seeds. The report's own row is
//! its first seeds' runs, not a rerun; a variant reruns only the methods it changes (the others'
//! runs are the report's, bit for bit). [`crate::report`] judges and renders what this returns.

use std::collections::BTreeMap;

use serde::Serialize;

use crate::analysis::seeds::{run_seeds, MetricTable};
use crate::config::cost::Cost;
use crate::config::scenario::{ChenGain, IntegralRule, Method, Scenario, Transducers};
use crate::error::SimError;

/// The scenarios varied (HyA's goto and sine tasks under internal disturbances).
pub const SCENARIOS: [&str; 2] = ["goto_internal", "sine_internal"];

/// The methods run in every variant: the paper's estimator and the baselines it is held against.
pub const METHODS: [Method; 4] = [Method::None, Method::Pid, Method::Lu, Method::Chen];

/// The baselines each compared with `lu`.
pub const BASELINES: [Method; 3] = [Method::None, Method::Pid, Method::Chen];

/// Seeds per variant, scenario and method: the report's first ones, at most this many.
pub const SEEDS: usize = 6;

/// One structural choice changed from the report's runs.
struct Variant {
    /// Its name in the table.
    name: &'static str,
    /// What it changes, for the text.
    change: &'static str,
    apply: fn(&mut Scenario),
    /// The methods whose runs it changes (the others read nothing it touches).
    changes: &'static [Method],
}

/// The report's runs first, then one change each.
const VARIANTS: [Variant; 6] = [
    Variant { name: "as run", change: "the report's settings (its runs of these seeds)", apply: |_| {}, changes: &[] },
    Variant {
        name: "independent transducers",
        change: "the controller reads pressure transducers of its own, with offsets of their own (`sensors.transducers = \"independent\"`), instead of the torque loops' (one set per joint, as on HyA); none and pid read no torque, so only lu's and chen's runs change",
        apply: |s| s.sensors.transducers = Transducers::Independent,
        changes: &[Method::Lu, Method::Chen],
    },
    Variant {
        name: "pid by pole placement",
        change: "pid by another stated rule: the same `K_P`, and `K_D`, `K_I` placing the rigid joint's three poles at one point, `M (s + ω)³` with `ω = √(K_P / 3M)` (`controller.integral_rule = \"pole_placement\"`), stable without a cap; the rows show whether it is the stronger PID here",
        apply: |s| s.controller.integral_rule = IntegralRule::PolePlacement,
        changes: &[Method::Pid],
    },
    Variant {
        name: "chen scalar gain",
        change: "Chen's observer with the scalar gain of Chen et al. (2000) in Mohammadi's form, `Y = y I`, `y = β λmax(M(q0))` (`controller.chen_gain = \"scalar\"`), instead of `Y = β M(q0)`: the slowest rate at the start pose stays β, the light joints' rates grow by the inertia ratio, and velocity noise reaches `d̂` through `y`",
        apply: |s| s.controller.chen_gain = ChenGain::Scalar,
        changes: &[Method::Chen],
    },
    Variant {
        name: "no Stribeck peak",
        change: "LuGre with its static level at the Coulomb level (`static_nm = coulomb_nm`): no breakaway peak",
        apply: |s| s.plant.static_nm = s.plant.coulomb_nm.clone(),
        changes: &METHODS,
    },
    Variant {
        name: "command delay 6 ms",
        change: "six control ticks between the command and the valves instead of one",
        apply: |s| s.sensors.command_delay_ticks = 6,
        changes: &METHODS,
    },
];

impl Variant {
    /// The runs it adds on `bases`: each with the methods it changes, changed.
    fn reruns(&self, bases: &[&Scenario]) -> Vec<Scenario> {
        bases
            .iter()
            .filter(|_| !self.changes.is_empty())
            .map(|base| {
                let mut s = (*base).clone();
                s.methods = self.changes.to_vec();
                (self.apply)(&mut s);
                s
            })
            .collect()
    }
}

/// What [`run`] costs where the report runs `seeds` seeds of each method (none where the first
/// base scenario does not run lu, whose seeds [`run`] takes).
pub fn cost(scenarios: &[Scenario], seeds: usize) -> Cost {
    let bases = super::hya_scenarios(scenarios, &SCENARIOS);
    let seeds = bases.first().filter(|s| s.methods.contains(&Method::Lu)).map_or(0, |_| seeds.min(SEEDS));
    VARIANTS.iter().map(|v| Cost::of(&v.reruns(&bases), seeds)).fold(Cost::NONE, Cost::then)
}

/// Every variant's runs: per variant and scenario, each method's tracking RMSE per seed and
/// joint, rad (in `summary.json`).
#[derive(Debug, Clone, Serialize)]
pub struct Sensitivity {
    /// Seeds per variant, scenario and method (the scenarios' own seeds and the next ones).
    pub seeds: usize,
    /// The variants, the report's own settings first.
    pub variants: Vec<VariantRuns>,
}

/// One variant's runs.
#[derive(Debug, Clone, Serialize)]
pub struct VariantRuns {
    /// Its name.
    pub variant: String,
    /// What it changes.
    pub change: String,
    /// The methods it reran (the others' runs are the report's).
    pub reran: Vec<&'static str>,
    /// Per scenario, per method, `rmse_q[seed][joint]`, rad.
    pub rmse_q: BTreeMap<String, BTreeMap<String, Vec<Vec<f64>>>>,
}

impl VariantRuns {
    /// `method`'s `rmse_q[seed][joint]` on `scenario` (empty where it did not run).
    pub fn rmse(&self, scenario: &str, method: Method) -> &[Vec<f64>] {
        self.rmse_q.get(scenario).and_then(|by| by.get(method.name())).map_or(&[], Vec::as_slice)
    }
}

/// Runs every variant of the scenarios among `scenarios` that it varies (HyA's only) over the
/// report's first seeds (at most [`SEEDS`]; `table` holds the report's runs), telling `progress`
/// each run's simulated seconds; `None` where none is there.
pub fn run<const N: usize>(
    robot: &crate::robot::Robot<N>,
    scenarios: &[Scenario],
    table: &MetricTable,
    progress: &(dyn Fn(f64) + Sync),
) -> Result<Option<Sensitivity>, SimError> {
    let bases = super::hya_scenarios(scenarios, &SCENARIOS);
    let Some(first) = bases.first() else { return Ok(None) };
    let seeds = table.seeds(&first.name, Method::Lu).min(SEEDS);
    let reported = |scenario: &str, method: Method| -> Vec<Vec<f64>> {
        let mut values = table.values(scenario, method, "rmse_q").unwrap_or_default();
        values.truncate(seeds);
        values
    };
    let mut variants = Vec::new();
    for variant in &VARIANTS {
        let (_, rerun) = run_seeds(robot, &variant.reruns(&bases), seeds, progress)?;
        let rmse_q = bases
            .iter()
            .map(|s| {
                let methods = METHODS
                    .iter()
                    .map(|m| {
                        let values = match variant.changes.contains(m) {
                            true => rerun.values(&s.name, *m, "rmse_q").unwrap_or_default(),
                            false => reported(&s.name, *m),
                        };
                        (m.name().to_owned(), values)
                    })
                    .collect();
                (s.name.clone(), methods)
            })
            .collect();
        variants.push(VariantRuns {
            variant: variant.name.into(),
            change: variant.change.into(),
            reran: variant.changes.iter().map(|m| m.name()).collect(),
            rmse_q,
        });
    }
    Ok(Some(Sensitivity { seeds, variants }))
}
