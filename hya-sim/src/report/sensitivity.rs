//! Whether the headline comparisons survive the modelling choices behind them: the paper's
//! estimator against `none`, `pid` and `chen` on the goto and sine tasks, rerun with one
//! structural choice changed at a time (the torque sensors' transducers, the PID's tuning rule,
//! the friction's Stribeck peak, the command delay), every variant on the same seeds.
//!
//! Each comparison is a paired ratio: per seed and joint `r = RMSE_baseline / RMSE_lu`, then the
//! geometric mean over seeds with the 95 % interval of `ln r` (Student's t). The verdict is
//! "lu lower" where the interval lies above 1, "baseline lower" where it lies below, and
//! "inconclusive" where it straddles 1. A comparison whose verdict differs between the rows
//! depends on that choice, and the section says so, computed from the table.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use serde::Serialize;

use crate::analysis::seeds::{per_joint_paired_ratio, run_seeds, PairedRatio};
use crate::config::scenario::{IntegralRule, Method, Scenario, Transducers};
use crate::error::SimError;

use super::text::table_row;

/// The scenarios varied (HyA's goto and sine tasks under internal disturbances).
const SCENARIOS: [&str; 2] = ["goto_internal", "sine_internal"];

/// The methods run in every variant: the paper's estimator and the baselines it is held against.
const METHODS: [Method; 4] = [Method::None, Method::Pid, Method::Lu, Method::Chen];

/// The baselines each compared with `lu`.
const BASELINES: [Method; 3] = [Method::None, Method::Pid, Method::Chen];

/// Seeds per variant, scenario and method (the full report; `--quick`: [`QUICK_SEEDS`]).
const SEEDS: usize = 6;
/// See [`SEEDS`].
const QUICK_SEEDS: usize = 3;

/// One structural choice changed from the report's runs.
struct Variant {
    /// Its name in the table.
    name: &'static str,
    /// What it changes, for the text.
    change: &'static str,
    apply: fn(&mut Scenario),
}

/// The report's runs first, then one change each.
const VARIANTS: [Variant; 5] = [
    Variant { name: "as run", change: "the report's settings", apply: |_| {} },
    Variant {
        name: "independent transducers",
        change: "the controller reads pressure transducers of its own, with offsets of their own (`sensors.transducers = \"independent\"`), instead of the torque loops' (one set per joint, as on HyA)",
        apply: |s| s.sensors.transducers = Transducers::Independent,
    },
    Variant {
        name: "pid by pole placement",
        change: "pid tuned on its own terms instead of matched to lu's low-frequency rejection and capped at half the Routh bound: the same `K_P`, `K_D` and `K_I` placing the rigid joint's three poles at one point, `M (s + ω)³` with `ω = √(K_P / 3M)` (`controller.integral_rule = \"pole_placement\"`); only pid's rows move",
        apply: |s| s.controller.integral_rule = IntegralRule::PolePlacement,
    },
    Variant {
        name: "no Stribeck peak",
        change: "LuGre with its static level at the Coulomb level (`static_nm = coulomb_nm`): no breakaway peak",
        apply: |s| s.plant.static_nm = s.plant.coulomb_nm.clone(),
    },
    Variant {
        name: "command delay 6 ms",
        change: "six control ticks between the command and the valves instead of one",
        apply: |s| s.sensors.command_delay_ticks = 6,
    },
];

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
    /// Per scenario, per method, `rmse_q[seed][joint]`, rad.
    pub rmse_q: BTreeMap<String, BTreeMap<String, Vec<Vec<f64>>>>,
}

/// One comparison: a scenario, a baseline, and per variant the paired ratio of each joint.
type Comparison = (String, Method, Vec<Vec<PairedRatio>>);

/// A paired comparison's verdict.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    /// The interval of the ratio lies above 1: `lu` tracks better.
    LuLower,
    /// It lies below 1: the baseline tracks better.
    BaselineLower,
    /// It straddles 1.
    Inconclusive,
}

impl Verdict {
    fn mark(self) -> &'static str {
        match self {
            Verdict::LuLower => "+",
            Verdict::BaselineLower => "−",
            Verdict::Inconclusive => "?",
        }
    }

    fn words(self, baseline: Method) -> String {
        match self {
            Verdict::LuLower => "lu lower".into(),
            Verdict::BaselineLower => format!("{} lower", baseline.name()),
            Verdict::Inconclusive => "inconclusive".into(),
        }
    }
}

impl Verdict {
    /// The verdict of `baseline / lu`'s paired ratio on 1.
    fn of(ratio: &PairedRatio) -> Self {
        if ratio.above_one() {
            Verdict::LuLower
        } else if ratio.below_one() {
            Verdict::BaselineLower
        } else {
            Verdict::Inconclusive
        }
    }
}

/// Runs every variant of the scenarios among `scenarios` that it varies (HyA's only); `None`
/// where none is there.
pub fn run<const N: usize>(
    robot: &crate::robot::Robot<N>,
    scenarios: &[Scenario],
    quick: bool,
) -> Result<Option<Sensitivity>, SimError> {
    let bases: Vec<&Scenario> =
        scenarios.iter().filter(|s| s.robot == "hya" && SCENARIOS.contains(&s.name.as_str())).collect();
    if bases.is_empty() {
        return Ok(None);
    }
    let seeds = if quick { QUICK_SEEDS } else { SEEDS };
    let mut variants = Vec::new();
    for variant in &VARIANTS {
        let runs: Vec<Scenario> = bases
            .iter()
            .map(|base| {
                let mut s = (*base).clone();
                s.methods = METHODS.to_vec();
                (variant.apply)(&mut s);
                s
            })
            .collect();
        let (_, table) = run_seeds(robot, &runs, seeds, &|_| {})?;
        let rmse_q = runs
            .iter()
            .map(|s| {
                let methods = METHODS
                    .iter()
                    .map(|m| (m.name().to_owned(), table.values(&s.name, *m, "rmse_q").unwrap_or_default()))
                    .collect();
                (s.name.clone(), methods)
            })
            .collect();
        variants.push(VariantRuns { variant: variant.name.into(), change: variant.change.into(), rmse_q });
    }
    Ok(Some(Sensitivity { seeds, variants }))
}

/// Per joint, the paired ratio of `baseline` to `lu` in `runs` of `scenario`.
fn ratios(runs: &VariantRuns, scenario: &str, baseline: Method) -> Vec<PairedRatio> {
    let methods = runs.rmse_q.get(scenario);
    let of = |m: Method| methods.and_then(|by| by.get(m.name())).cloned().unwrap_or_default();
    per_joint_paired_ratio(&of(baseline), &of(Method::Lu))
}

/// The comparisons whose verdict changes between the variants.
#[derive(Debug, Clone, Default)]
pub struct Changes {
    /// Comparisons made per variant (scenario, baseline, joint).
    pub compared: usize,
    /// Those where one variant finds lu lower and another the baseline, one line each.
    pub reversed: Vec<String>,
    /// Those conclusive in some variants and inconclusive in others, one line each.
    pub significance: Vec<String>,
}

/// Every comparison of `sensitivity`: per scenario and baseline, the rows of paired ratios
/// (one per variant, one entry per joint).
fn comparisons(sensitivity: &Sensitivity) -> Vec<Comparison> {
    let scenarios: Vec<String> =
        sensitivity.variants.first().map(|v| v.rmse_q.keys().cloned().collect()).unwrap_or_default();
    scenarios
        .into_iter()
        .flat_map(|scenario| {
            BASELINES.map(|baseline| {
                let rows = sensitivity.variants.iter().map(|v| ratios(v, &scenario, baseline)).collect();
                (scenario.clone(), baseline, rows)
            })
        })
        .collect()
}

/// The comparisons that change verdict between the variants.
pub fn changes(sensitivity: &Sensitivity) -> Changes {
    let mut changes = Changes::default();
    for (scenario, baseline, rows) in comparisons(sensitivity) {
        let joints = rows.first().map_or(0, Vec::len);
        changes.compared += joints;
        for j in 0..joints {
            let verdicts: Vec<Verdict> = rows.iter().map(|row| Verdict::of(&row[j])).collect();
            if verdicts.iter().all(|v| *v == verdicts[0]) {
                continue;
            }
            let by_row: Vec<String> = sensitivity
                .variants
                .iter()
                .zip(&verdicts)
                .map(|(v, verdict)| format!("{}: {}", v.variant, verdict.words(baseline)))
                .collect();
            let line = format!("`{scenario}` joint {}, {} / lu ({})", j + 1, baseline.name(), by_row.join("; "));
            match verdicts.contains(&Verdict::LuLower) && verdicts.contains(&Verdict::BaselineLower) {
                true => changes.reversed.push(line),
                false => changes.significance.push(line),
            }
        }
    }
    changes
}

/// The report's section: the table per scenario and baseline, then every comparison whose
/// verdict changes between the rows: reversals (lu lower in one row, the baseline in another)
/// apart from changes of significance.
pub fn section(sensitivity: &Sensitivity) -> String {
    let mut md = format!(
        "\n### Sensitivity to the modelling choices\n\nThe headline comparisons rerun with one structural choice changed at a time, {} seeds each (the same seeds in every row, so the rows are paired too):\n\n",
        sensitivity.seeds
    );
    for v in &sensitivity.variants {
        let _ = writeln!(md, "- **{}**: {}.", v.variant, v.change);
    }
    md.push_str("\nEach cell is the ratio of the baseline's tracking RMSE to lu's, paired by seed: the geometric mean over seeds with its 95 % interval (Student's t on the logarithms), then `+` where the interval lies above 1 (lu tracks better), `−` below 1 (the baseline does), `?` where it straddles 1 (inconclusive at these seeds).\n");
    for (scenario, baseline, rows) in comparisons(sensitivity) {
        let joints = rows.first().map_or(0, Vec::len);
        let _ = writeln!(md, "\n`{scenario}`, {} / lu:\n", baseline.name());
        md.push_str(&table_row(["variant".to_owned()].into_iter().chain((1..=joints).map(|j| format!("j{j}")))));
        md.push_str(&table_row(std::iter::repeat_n("---".to_owned(), joints + 1)));
        for (v, row) in sensitivity.variants.iter().zip(&rows) {
            md.push_str(&table_row([v.variant.clone()].into_iter().chain(
                row.iter().map(|r| format!("{:.2} [{:.2}, {:.2}] {}", r.ratio, r.low, r.high, Verdict::of(r).mark())),
            )));
        }
    }
    let changes = changes(sensitivity);
    let list = |lines: &[String]| lines.iter().map(|l| format!("- {l}\n")).collect::<String>();
    let _ = writeln!(
        md,
        "\nOf {} comparisons (scenario, baseline, joint), {} reverse between the rows (one variant finds lu lower, another the baseline){}",
        changes.compared,
        changes.reversed.len(),
        if changes.reversed.is_empty() { ".".to_owned() } else { format!(":\n\n{}", list(&changes.reversed)) }
    );
    let _ = writeln!(
        md,
        "\n{} are conclusive in some rows and inconclusive in others: they depend on the choice, or need more seeds than these {} to tell{}",
        changes.significance.len(),
        sensitivity.seeds,
        if changes.significance.is_empty() { ".".to_owned() } else { format!(":\n\n{}", list(&changes.significance)) }
    );
    md
}

/// The headline's sentence on the section, or nothing without one.
pub fn headline(sensitivity: Option<&Sensitivity>) -> String {
    let Some(sensitivity) = sensitivity else { return String::new() };
    let changes = changes(sensitivity);
    let others: Vec<&str> = sensitivity.variants.iter().skip(1).map(|v| v.variant.as_str()).collect();
    format!(
        "\nRerun under {} other modelling choices ({}; {} seeds each), {} of the {} paired tracking comparisons with {} reverse their verdict and {} change significance: see \"Sensitivity to the modelling choices\".\n",
        others.len(),
        others.join(", "),
        sensitivity.seeds,
        changes.reversed.len(),
        changes.compared,
        BASELINES.map(|m| m.name()).join(", "),
        changes.significance.len()
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paired_ratios_give_their_verdicts() {
        // Every seed's ratio 2: no spread, lu lower.
        let r = PairedRatio::of(&[2.0, 4.0, 6.0], &[1.0, 2.0, 3.0]);
        assert!((r.ratio - 2.0).abs() < 1e-12 && (r.low - 2.0).abs() < 1e-12 && (r.high - 2.0).abs() < 1e-12);
        assert_eq!(Verdict::of(&r), Verdict::LuLower);
        // Ratios 1/2 every seed: the baseline lower.
        assert_eq!(Verdict::of(&PairedRatio::of(&[1.0, 1.0], &[2.0, 2.0])), Verdict::BaselineLower);
        // Ratios 2 and 1/2: geometric mean 1, interval straddling it.
        let r = PairedRatio::of(&[2.0, 1.0], &[1.0, 2.0]);
        assert!((r.ratio - 1.0).abs() < 1e-12 && r.low < 1.0 && r.high > 1.0);
        assert_eq!(Verdict::of(&r), Verdict::Inconclusive);
        // Pairing matters: seed-to-seed spread that both share cancels in the ratio.
        let lu = [1.0, 10.0, 100.0];
        let base: Vec<f64> = lu.iter().map(|x| 1.1 * x).collect();
        assert_eq!(Verdict::of(&PairedRatio::of(&base, &lu)), Verdict::LuLower);
    }
}
