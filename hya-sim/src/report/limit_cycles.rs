//! Limit cycles measured: each method's peak-to-peak error after settling on the goto task and
//! its spectral cycles, with and without the friction's Stribeck peak, and the paper's estimator
//! at bandwidths from 20 to 200 rad/s. No bandwidth is recommended here: the measurements show
//! amplitudes, not a rule.

use std::fmt::Write as _;

use crate::analysis::seeds::{median, per_joint_mean_ci95, MetricTable};
use crate::config::scenario::{Method, Scenario};
use crate::studies::limit_cycles::{LimitCycleRuns, BANDWIDTHS_RAD_S, METHODS, SEEDS};

use super::text::{joints_text, table_row};

/// A joint counts as still when its peak-to-peak error over the final 5 s stays below this, rad
/// (about 80 counts of HyA's encoders); the measure counts drift and settling as well as cycles.
pub const LIMIT_CYCLE_RAD: f64 = 1e-3;

use crate::metrics::CYCLE_AMPLITUDE_RAD;

/// [`crate::metrics::cycle_window`] of a run of `base`.
fn cycle_window_of(base: &Scenario) -> crate::analysis::running::Window {
    let task = crate::config::settings::TaskTimes::of(&base.task);
    crate::metrics::cycle_window(task, &crate::config::settings::Timing::of(base))
}

/// How [`cycle_table`] measures, for `base`'s window.
fn cycles_text(base: &Scenario) -> String {
    let window = cycle_window_of(base);
    let span = window.to - window.from;
    let lowest_hz = 2.0 / span;
    format!(
        "\nThe same runs with oscillation told apart from drift: over the last {:.1} s once the task is quiet (at most {} s; here {:.1} to {:.1} s), the straight-line trend of each joint's error is removed (its change over the window is the creep) and the largest spectral line of what is left is found (bins from two periods per window, {:.2} Hz, to {} Hz). A joint counts as cycling where that line reaches {} mrad (a sine of {} mrad peak to peak). A line in the lowest bin cannot be told from drift that is not straight; cells whose median frequency lies there are marked \"lowest bin\". Per method and joint: seeds cycling / seeds, then the cycling seeds' median frequency and amplitude; and the median creep over every seed, mrad:\n\n",
        span,
        crate::metrics::CYCLE_WINDOW_S,
        window.from,
        window.to,
        lowest_hz,
        crate::metrics::CYCLE_MAX_HZ,
        CYCLE_AMPLITUDE_RAD * 1e3,
        2.0 * CYCLE_AMPLITUDE_RAD * 1e3
    )
}

/// Per method, the joints (from 1) where at least half the seeds cycle at a median frequency
/// above the lowest bin, and where no seed cycles.
type CycleCounts = Vec<(Method, Vec<usize>, Vec<usize>)>;

/// Oscillation apart from drift, per method and joint of `scenario` (its window that of `base`)
/// in `table`: the share of seeds whose detrended error holds a spectral line of
/// [`CYCLE_AMPLITUDE_RAD`] or more, with those seeds' median frequency and amplitude, and every
/// seed's median drift; and per method the joints where most and where no seeds cycle.
fn cycle_table<const N: usize>(table: &MetricTable, base: &Scenario, scenario: &str) -> (String, CycleCounts) {
    let window = cycle_window_of(base);
    let lowest_hz = 2.0 / (window.to - window.from);
    let mut md = table_row(["method".to_owned()].into_iter().chain((1..=N).map(|j| format!("j{j}"))));
    md.push_str(&table_row(std::iter::repeat_n("---".to_owned(), N + 1)));
    let mut never = Vec::new();
    let mut counts = Vec::new();
    for method in METHODS {
        let get = |metric: &str| table.values(scenario, method, metric).filter(|v| !v.is_empty());
        let (Some(amplitude), Some(frequency), Some(creep)) =
            (get("cycle_amplitude_q"), get("cycle_frequency_hz"), get("creep_q"))
        else {
            continue;
        };
        let mut cells = Vec::new();
        let mut cycling_anywhere = false;
        let (mut most, mut none) = (Vec::new(), Vec::new());
        for j in 0..N {
            let cycling: Vec<usize> =
                (0..amplitude.len()).filter(|&s| amplitude[s][j] >= CYCLE_AMPLITUDE_RAD).collect();
            cycling_anywhere |= !cycling.is_empty();
            if 2 * cycling.len() >= amplitude.len()
                && median(cycling.iter().map(|&s| frequency[s][j]).collect()) >= 1.25 * lowest_hz
            {
                most.push(j + 1);
            }
            if cycling.is_empty() {
                none.push(j + 1);
            }
            let creep = median(creep.iter().map(|c| c[j].abs()).collect()) * 1e3;
            cells.push(match cycling.is_empty() {
                true => format!("0/{}; creep {creep:.2}", amplitude.len()),
                false => {
                    let hz = median(cycling.iter().map(|&s| frequency[s][j]).collect());
                    format!(
                        "{}/{} at {hz:.2} Hz{}, {:.2}; creep {creep:.2}",
                        cycling.len(),
                        amplitude.len(),
                        if hz < 1.25 * lowest_hz { " (lowest bin)" } else { "" },
                        median(cycling.iter().map(|&s| amplitude[s][j]).collect()) * 1e3
                    )
                }
            });
        }
        if !cycling_anywhere {
            never.push(method.name());
        }
        counts.push((method, most, none));
        md.push_str(&table_row([method.name().to_owned()].into_iter().chain(cells)));
    }
    let _ = writeln!(
        md,
        "\n{}",
        match never.len() {
            0 => "Every method cycles on some joint in some seeds by this measure.".to_owned(),
            _ => format!("{} cycle on no joint in any seed by this measure.", never.join(", ")),
        }
    );
    (md, counts)
}

/// Per method, what the control without the Stribeck peak does to the joints whose cycles in
/// the report's runs are above the lowest bin in at least half the seeds, and the joints that
/// cycle so only without the peak; computed from both tables' counts.
fn peak_comparison(with_peak: &CycleCounts, without: &CycleCounts, seeds: (usize, usize)) -> String {
    let lines: Vec<String> = with_peak
        .iter()
        .filter_map(|(method, most, _)| {
            let (_, still, quiet) = without.iter().find(|(m, ..)| m == method)?;
            let gone: Vec<usize> = most.iter().copied().filter(|j| quiet.contains(j)).collect();
            let kept: Vec<usize> = most.iter().copied().filter(|j| still.contains(j)).collect();
            let new: Vec<usize> = still.iter().copied().filter(|j| !most.contains(j)).collect();
            (!most.is_empty() || !new.is_empty()).then(|| {
                format!(
                    "{}: cycling with the peak on {}; of those, in no seed without it on {}, in half or more still on {}; cycling only without the peak on {}",
                    method.name(),
                    joints_text(most),
                    joints_text(&gone),
                    joints_text(&kept),
                    joints_text(&new)
                )
            })
        })
        .collect();
    match lines.is_empty() {
        true => "\nNo method cycles above the lowest bin in half the seeds or more, with the peak or without it.\n".to_owned(),
        false => format!(
            "\nComputed from the two tables, counting a joint as cycling where half its seeds or more have a line above the lowest bin ({} seeds with the peak, {} without): {}. A cycle that stops without the peak is consistent with stick-slip hunting; with so few seeds without the peak, a single seed moves these counts.\n",
            seeds.0,
            seeds.1,
            lines.join("; ")
        ),
    }
}

/// The section, from `methods` (the report's runs, for the per-method table) and `runs` of `base`
/// (the goto task; [`crate::studies::limit_cycles`]).
pub fn section<const N: usize>(base: &Scenario, methods: &MetricTable, runs: &LimitCycleRuns) -> String {
    let LimitCycleRuns { bandwidths: scenarios, by_bandwidth: table, no_peak, without_peak } = runs;
    // Per bandwidth, per joint: the seeds whose spectral line reaches the cycle amplitude.
    let cycling_seeds: Vec<Vec<usize>> = scenarios
        .iter()
        .map(|s| {
            let values = table.values(&s.name, Method::Lu, "cycle_amplitude_q").unwrap_or_default();
            (0..N)
                .map(|j| values.iter().filter(|v| v.get(j).is_some_and(|a| *a >= CYCLE_AMPLITUDE_RAD)).count())
                .collect()
        })
        .collect();
    let mut md = format!(
        "\n### Limit cycles and residual motion\n\nOne candidate mechanism is stick-slip hunting: a joint with stiction and integral action sticks, the integral winds the torque up until the joint breaks away, it overshoots, sticks on the other side, and the cycle repeats. The PID's integral could do this, and so could every estimator, which at low frequency acts as an integral of the error (gain about `K_P / τ_d` for the paper's); `none` (a PD) has no integral to wind up, so whatever it shows is not hunting. The rows \"no Stribeck peak\" rerun the scenario with LuGre at its static level equal to its Coulomb level (`static_nm = coulomb_nm`): the same bristles, Coulomb and viscous levels, no breakaway peak. A joint still sticks below the Coulomb level, so these rows remove the breakaway peak, not sticking; with integral action, hunting needs static friction above the Coulomb level (Olsson & Åström, IEEE TCST 9(4), 2001), which this model's peak is. Measured on `{}` (peak-to-peak tracking error over the final window, mean over seeds, mrad; peak-to-peak counts slow drift and settling as well as oscillation):\n\n",
        base.name
    );
    md.push_str(&table_row(["method".to_owned()].into_iter().chain((1..=N).map(|j| format!("j{j}")))));
    md.push_str(&table_row(std::iter::repeat_n("---".to_owned(), N + 1)));
    let mut cycling = Vec::new();
    for method in METHODS {
        for (label, table, scenario) in
            [("", methods, &base.name), (" (no Stribeck peak)", without_peak, &no_peak.name)]
        {
            let Some(values) = table.values(scenario, method, "limit_cycle_q").filter(|v| !v.is_empty()) else {
                continue;
            };
            let mean = per_joint_mean_ci95(&values).0;
            if !label.is_empty() && mean.iter().any(|a| *a >= LIMIT_CYCLE_RAD) {
                cycling.push(method.name());
            }
            md.push_str(&table_row(
                [format!("{}{label}", method.name())].into_iter().chain(mean.iter().map(|v| format!("{:.2}", v * 1e3))),
            ));
        }
    }
    let _ = writeln!(
        md,
        "\nRows marked \"no Stribeck peak\" rerun the same scenario with LuGre at F_s = F_c ({SEEDS} seeds): {}",
        if cycling.is_empty() {
            format!("no method keeps a joint at {} mrad or more peak to peak without the peak.", LIMIT_CYCLE_RAD * 1e3)
        } else {
            format!(
                "{} still keep a joint at {} mrad or more peak to peak without the peak (peak to peak counts drift too: the spectral tables below tell cycles apart).",
                cycling.join(", "),
                LIMIT_CYCLE_RAD * 1e3
            )
        }
    );
    md.push_str(&cycles_text(base));
    let (with_table, with_counts) = cycle_table::<N>(methods, base, &base.name);
    md.push_str(&with_table);
    let _ = writeln!(md, "\nThe same measure on the runs without the Stribeck peak ({SEEDS} seeds):\n");
    let (without_table, without_counts) = cycle_table::<N>(without_peak, base, &no_peak.name);
    md.push_str(&without_table);
    let with_seeds = methods.seeds(&base.name, Method::Lu);
    md.push_str(&peak_comparison(&with_counts, &without_counts, (with_seeds, SEEDS)));
    let _ = writeln!(
        md,
        "\nThe paper's estimator at ω1 = ω2 from {} to {} rad/s, seeds cycling of {SEEDS} by the spectral measure above (a line of {} mrad or more over the detrended error):\n",
        BANDWIDTHS_RAD_S[0],
        BANDWIDTHS_RAD_S[BANDWIDTHS_RAD_S.len() - 1],
        CYCLE_AMPLITUDE_RAD * 1e3
    );
    md.push_str(&table_row(
        ["joint".to_owned()].into_iter().chain(BANDWIDTHS_RAD_S.iter().map(|w| format!("{w} rad/s"))),
    ));
    md.push_str(&table_row(std::iter::repeat_n("---".to_owned(), BANDWIDTHS_RAD_S.len() + 1)));
    for j in 0..N {
        let cells = cycling_seeds.iter().map(|c| format!("{}/{SEEDS}", c[j]));
        md.push_str(&table_row([format!("{}", j + 1)].into_iter().chain(cells)));
    }
    let free_everywhere: Vec<String> =
        (0..N).filter(|&j| cycling_seeds.iter().all(|c| c[j] == 0)).map(|j| format!("{}", j + 1)).collect();
    let _ = writeln!(
        md,
        "\n{}",
        if free_everywhere.len() == N {
            "No joint cycles in any seed at any bandwidth swept.".to_owned()
        } else if free_everywhere.is_empty() {
            "Every joint cycles in some seed at some bandwidth swept.".to_owned()
        } else {
            format!(
                "Joints {} cycle in no seed at any bandwidth swept; the others do in some seeds at one bandwidth or more (the lowest-bin caveat above applies).",
                free_everywhere.join(", ")
            )
        }
    );
    md
}
