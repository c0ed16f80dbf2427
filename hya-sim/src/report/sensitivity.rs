//! Whether the headline comparisons survive the modelling choices behind them: the paper's
//! estimator against `none`, `pid` and `chen` on the goto and sine tasks, rerun with one
//! structural choice changed at a time (the torque sensors' transducers, the PID's tuning rule,
//! Chen's gain design, the friction's Stribeck peak, the command delay), every variant on the
//! same seeds.
//!
//! Each comparison is a paired ratio: per seed and joint `r = RMSE_baseline / RMSE_lu`, then the
//! geometric mean over seeds with the 95 % interval of `ln r` (Student's t). The verdict is
//! "lu lower" where the interval lies above 1, "baseline lower" where it lies below, and
//! "inconclusive" where it straddles 1. A choice's effect is paired too: per seed the variant's
//! `r` over the report's, with its interval; the section lists the comparisons a choice moves
//! (interval excluding 1) and those it moves across 1, computed from the table. The report's own
//! row is its first seeds' runs, not a rerun; a variant reruns only the methods it changes (the
//! others' runs are the report's, bit for bit).

use std::fmt::Write as _;

use crate::analysis::seeds::{per_joint_paired_ratio, PairedRatio};
use crate::config::scenario::Method;
use crate::studies::sensitivity::{Sensitivity, VariantRuns, BASELINES};

use super::text::table_row;

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

/// Per joint, the paired ratio of `baseline` to `lu` in `runs` of `scenario`.
fn ratios(runs: &VariantRuns, scenario: &str, baseline: Method) -> Vec<PairedRatio> {
    per_joint_paired_ratio(runs.rmse(scenario, baseline), runs.rmse(scenario, Method::Lu))
}

/// What one variant does to one comparison, where its paired effect is beyond the interval.
#[derive(Debug, Clone)]
pub struct Effect {
    /// The variant.
    pub variant: String,
    /// `scenario joint, baseline / lu: as run → variant (× effect [interval])`.
    pub line: String,
    /// Whether the ratio's geometric mean moves across 1 (lu's advantage to the baseline's, or
    /// back).
    pub crosses: bool,
}

/// Every comparison a variant moves: per seed, the variant's ratio over the report's (same
/// seeds), whose interval excludes 1.
#[derive(Debug, Clone, Default)]
pub struct Changes {
    /// Comparisons per variant (scenario, baseline, joint).
    pub compared: usize,
    /// Per variant (after the report's own row), the comparisons it can move: those whose
    /// baseline or lu it reran.
    pub movable: Vec<usize>,
    /// The moves, variant by variant.
    pub moved: Vec<Effect>,
    /// The comparisons whose mean ratio changes side under a variant though the change is not
    /// beyond the seeds' spread: `scenario jN, baseline / lu under variant`.
    pub crossed_within: Vec<String>,
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

/// Per seed, `baseline / lu` at joint `j` of `scenario` in `runs`.
fn seed_ratios(runs: &VariantRuns, scenario: &str, baseline: Method, j: usize) -> Vec<f64> {
    runs.rmse(scenario, baseline).iter().zip(runs.rmse(scenario, Method::Lu)).map(|(b, l)| b[j] / l[j]).collect()
}

/// The comparisons each variant moves beyond its interval.
pub fn changes(sensitivity: &Sensitivity) -> Changes {
    let mut changes = Changes::default();
    let Some((reported, variants)) = sensitivity.variants.split_first() else { return changes };
    changes.movable = vec![0; variants.len()];
    for (scenario, baseline, rows) in comparisons(sensitivity) {
        let joints = rows.first().map_or(0, Vec::len);
        changes.compared += joints;
        for (k, v) in variants.iter().enumerate() {
            if v.reran.iter().any(|m| *m == baseline.name() || *m == Method::Lu.name()) {
                changes.movable[k] += joints;
            }
        }
        for (v, row) in variants.iter().zip(&rows[1..]) {
            for (j, ratio) in row.iter().enumerate() {
                let own = seed_ratios(reported, &scenario, baseline, j);
                let effect = PairedRatio::of(&seed_ratios(v, &scenario, baseline, j), &own);
                let before = rows[0][j].ratio;
                if !effect.above_one() && !effect.below_one() {
                    if (before > 1.0) != (ratio.ratio > 1.0) {
                        let name = format!("`{scenario}` j{}, {} / lu", j + 1, baseline.name());
                        changes
                            .crossed_within
                            .push(format!("{name} under {} ({before:.2} → {:.2})", v.variant, ratio.ratio));
                    }
                    continue;
                }
                changes.moved.push(Effect {
                    variant: v.variant.clone(),
                    line: format!(
                        "`{scenario}` j{}, {} / lu: {before:.2} → {:.2} (× {:.2} [{:.2}, {:.2}])",
                        j + 1,
                        baseline.name(),
                        ratio.ratio,
                        effect.ratio,
                        effect.low,
                        effect.high
                    ),
                    crosses: (before > 1.0) != (ratio.ratio > 1.0),
                });
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
        "\n## Sensitivity to the modelling choices\n\nThe headline comparisons rerun with one structural choice changed at a time, {} seeds each (the same seeds in every row, so the rows are paired too):\n\n",
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
    let _ = writeln!(
        md,
        "\nWhat each choice does, paired by seed: per seed the variant's ratio over the report's, then the geometric mean with its 95 % interval; listed where the interval excludes 1 (a move beyond the seeds' spread), out of {} comparisons per variant (no correction for the number of comparisons). \"across 1\" marks a comparison whose mean ratio moves from one side of 1 to the other.",
        changes.compared
    );
    for (v, movable) in sensitivity.variants.iter().skip(1).zip(&changes.movable) {
        let moved: Vec<&Effect> = changes.moved.iter().filter(|e| e.variant == v.variant).collect();
        let _ = writeln!(
            md,
            "\n**{}** moves {} of the {movable} comparisons it reruns a side of:\n",
            v.variant,
            moved.len()
        );
        for e in moved {
            let _ = writeln!(md, "- {}{}", e.line, if e.crosses { ", across 1" } else { "" });
        }
    }
    md
}

/// The headline's sentence on the section, computed from its moves, or nothing without one.
pub fn headline(sensitivity: Option<&Sensitivity>) -> String {
    let Some(sensitivity) = sensitivity else { return String::new() };
    let changes = changes(sensitivity);
    let per_variant: Vec<String> = sensitivity
        .variants
        .iter()
        .skip(1)
        .zip(&changes.movable)
        .map(|(v, movable)| {
            let moved = changes.moved.iter().filter(|e| e.variant == v.variant).count();
            format!("{}: {moved} of {movable}", v.variant)
        })
        .collect();
    let across: Vec<String> = changes
        .moved
        .iter()
        .filter(|e| e.crosses)
        .map(|e| format!("{} under {}", e.line.split(':').next().unwrap_or_default(), e.variant))
        .collect();
    let mut sides = match across.is_empty() {
        true => "among these moves no mean ratio changes side".to_owned(),
        false => format!("among these moves the mean ratio changes side on {} only", across.join("; ")),
    };
    if !changes.crossed_within.is_empty() {
        let _ =
            write!(sides, "; within the seeds' spread it also changes side on {}", changes.crossed_within.join("; "));
    }
    format!(
        "\nRerun with one modelling choice changed at a time ({} seeds, paired by seed), the tracking comparisons with {} that each choice moves beyond the seeds' spread (of those it reruns a side of): {}; {sides} (no correction for the number of comparisons). See \"Sensitivity to the modelling choices\".\n",
        sensitivity.seeds,
        BASELINES.map(|m| m.name()).join(", "),
        per_variant.join("; ")
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
