//! The report's first section, "In short": what was run and what the paper's estimator (`lu`)
//! achieves against each baseline, every figure computed from the metric table it summarises.
//!
//! For a baseline `b` and a metric (tracking RMSE, estimate RMSE, command noise), each entry is a
//! scenario's joint where both ran: the ratio of `b`'s mean over seeds to `lu`'s. Above 1, `lu`
//! does better. The section gives the entries' range and geometric mean, and counts the entries
//! where `b` does better (ratio below 1): where the paper's method does not win.

use std::fmt::Write as _;

use super::summary::aggregate;
use crate::analysis::seeds::MetricTable;
use crate::config::scenario::{Method, Scenario};

/// The baselines held against `lu`, in the order the section lists them.
const BASELINES: [Method; 5] = [Method::None, Method::Pid, Method::Chen, Method::Momentum, Method::Eso];

/// The metrics summarised: `(metric, what it measures, unit)`.
const METRICS: [(&str, &str, &str); 3] = [
    ("rmse_q", "tracking error (RMSE of q − q_des)", "rad"),
    ("rmse_d", "estimate error (RMSE of d̂ − d)", "N·m"),
    ("tau_cmd_noise", "command noise (RMS of the command's step over √2)", "N·m"),
];

/// Ratios `b / lu` of `metric`'s means over seeds, one per scenario and joint where both ran,
/// and how many of those entries have no ratio (a zero, infinite or NaN mean on either side).
fn ratios(scenarios: &[Scenario], table: &MetricTable, baseline: Method, metric: &str) -> (Vec<f64>, usize) {
    let all: Vec<f64> = scenarios
        .iter()
        .filter_map(|s| {
            let (theirs, _) = aggregate(table, &s.name, baseline, metric)?;
            let (ours, _) = aggregate(table, &s.name, Method::Lu, metric)?;
            Some(theirs.into_iter().zip(ours).map(|(b, l)| b / l).collect::<Vec<_>>())
        })
        .flatten()
        .collect();
    let valid: Vec<f64> = all.iter().copied().filter(|r| r.is_finite() && *r > 0.0).collect();
    let dropped = all.len() - valid.len();
    (valid, dropped)
}

/// `lo–hi×, geometric mean g×` of `ratios`.
fn spread(ratios: &[f64]) -> String {
    let lo = ratios.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = ratios.iter().copied().fold(0.0, f64::max);
    let geometric = (ratios.iter().map(|r| r.ln()).sum::<f64>() / ratios.len() as f64).exp();
    format!("{}–{}× (geometric mean {}×)", short(lo), short(hi), short(geometric))
}

/// A ratio in two significant digits.
fn short(x: f64) -> String {
    hya_core::Short(format!("{x:.1e}").parse().unwrap_or(x)).to_string()
}

/// The section, from the runs of `scenarios` in `table` over `seeds` seeds.
pub(super) fn in_short(
    scenarios: &[Scenario],
    table: &MetricTable,
    seeds: usize,
    (arm, quick): (&str, bool),
    (sensitivity, chen_designs): (
        Option<&crate::studies::sensitivity::Sensitivity>,
        Option<&crate::studies::chen_designs::ChenDesigns>,
    ),
) -> String {
    let methods: std::collections::BTreeSet<&str> =
        scenarios.iter().flat_map(|s| s.methods.iter().map(|m| m.name())).collect();
    let mut md = String::from("## In short\n\n");
    let _ = writeln!(
        md,
        "{} scenarios on a simulated {arm}{}, each method ({}) over {seeds} seeds. Below, for each \
         baseline, `baseline / lu` of each metric's mean over seeds, one entry per scenario and joint where both \
         ran: above 1× the paper's estimator (`lu`) does better on the means, below 1× the baseline does (lower \
         is better for all three metrics; the counts compare means only, not their intervals). Every figure is \
         computed from the tables further down.\n",
        scenarios.len(),
        if quick { " (quick mode: shortened scenarios)" } else { "" },
        methods.into_iter().collect::<Vec<_>>().join(", "),
    );
    for baseline in BASELINES {
        let mut parts = Vec::new();
        for (metric, what, unit) in METRICS {
            let (found, dropped) = ratios(scenarios, table, baseline, metric);
            if found.is_empty() {
                continue;
            }
            let dropped = match dropped {
                0 => String::new(),
                d => format!(" ({d} more without a ratio: a zero or non-finite mean)"),
            };
            let worse = found.iter().filter(|r| **r < 1.0).count();
            let better = found.iter().filter(|r| **r > 1.0).count();
            let ties = found.len() - worse - better;
            let verdict = match (worse, ties) {
                (0, 0) => "lu's mean lower on every entry".to_string(),
                (w, 0) if w == found.len() => format!("{}'s mean lower on every entry", baseline.name()),
                (w, 0) => format!("{}'s mean lower on {w} of {}", baseline.name(), found.len()),
                (w, t) => format!("{}'s mean lower on {w} of {}, equal on {t}", baseline.name(), found.len()),
            };
            parts.push(format!("{what} [{unit}]: {} over {} entries{dropped}, {verdict}", spread(&found), found.len()));
        }
        if !parts.is_empty() {
            let _ = writeln!(md, "- **against {}**: {}.", baseline.name(), parts.join("; "));
        }
    }
    md.push_str(
        "\nThe observers (lu, chen, momentum, eso) are all designed with their poles at one magnitude, the \
         scenario's observer bandwidth, so the comparisons with chen, momentum and eso above hold for that matching; \
         the Pareto section compares chen and momentum with lu at about equal delay too (on the sweep's seeds, stated there).\n",
    );
    md.push_str(&super::chen_designs::headline(chen_designs));
    md.push_str(&super::sensitivity::headline(sensitivity));
    md.push_str(
        "\nHow the report was made follows; then the claims' verdicts, and the joints where a baseline's tracking or \
         estimate error is lower than lu's by the paired per-seed ratio's 95 % interval (a stricter test than the means above).\n\n",
    );
    md
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;

    #[test]
    fn the_spread_is_computed_from_the_ratios() {
        assert_eq!(spread(&[0.5, 2.0, 8.0]), "0.5–8× (geometric mean 2×)");
        assert_eq!(short(26.37), "26");
        assert_eq!(short(0.8149), "0.81");
    }
}
