//! Limit cycles measured: each method's peak-to-peak error after settling on the goto task, and
//! the paper's estimator at bandwidths from 20 to 200 rad/s. No bandwidth is recommended here:
//! the measurements show amplitudes, not a rule.

use std::fmt::Write as _;

use crate::analysis::seeds::{median, per_joint_mean_ci95, run_seeds, MetricTable};
use crate::config::scenario::{Method, Scenario};
use crate::error::SimError;

use super::text::table_row;

/// The bandwidths swept, rad/s (`ω1 = ω2`, `ζ = 0.8`).
pub const BANDWIDTHS_RAD_S: [f64; 7] = [20.0, 35.0, 50.0, 75.0, 100.0, 150.0, 200.0];

/// A joint counts as still when its peak-to-peak error over the final 5 s stays below this, rad
/// (about 80 counts of HyA's encoders); the measure counts drift and settling as well as cycles.
pub const LIMIT_CYCLE_RAD: f64 = 1e-3;

use crate::metrics::CYCLE_AMPLITUDE_RAD;

/// Seeds per bandwidth.
const SEEDS: usize = 3;

/// The methods measured, in the table's order.
const METHODS: [Method; 6] = [Method::None, Method::Pid, Method::Lu, Method::Chen, Method::Momentum, Method::Eso];

/// Oscillation apart from drift, per method and joint of `scenario` in `table`: the share of
/// seeds whose detrended error holds a spectral line of [`CYCLE_AMPLITUDE_RAD`] or more, with
/// those seeds' median frequency and amplitude, and every seed's median drift.
fn cycles_apart_from_drift<const N: usize>(table: &MetricTable, base: &Scenario) -> String {
    let scenario = base.name.as_str();
    let window = crate::metrics::cycle_window(base);
    let span = window.to - window.from;
    let lowest_hz = 2.0 / span;
    let mut md = format!(
        "\nThe same runs with oscillation told apart from drift: over the last {:.1} s once the task is quiet (at most {} s; here {:.1} to {:.1} s), the straight-line trend of each joint's error is removed (its change over the window is the creep) and the largest spectral line of what is left is found (bins from two periods per window, {:.2} Hz, to {} Hz). A joint counts as cycling where that line reaches {} mrad (a sine of {} mrad peak to peak). A line in the lowest bin cannot be told from drift that is not straight; cells whose median frequency lies there are marked \"lowest bin\". Per method and joint: seeds cycling / seeds, then the cycling seeds' median frequency and amplitude; and the median creep over every seed, mrad:\n\n",
        span,
        crate::metrics::CYCLE_WINDOW_S,
        window.from,
        window.to,
        lowest_hz,
        crate::metrics::CYCLE_MAX_HZ,
        CYCLE_AMPLITUDE_RAD * 1e3,
        2.0 * CYCLE_AMPLITUDE_RAD * 1e3
    );
    md.push_str(&table_row(["method".to_owned()].into_iter().chain((1..=N).map(|j| format!("j{j}")))));
    md.push_str(&table_row(std::iter::repeat_n("---".to_owned(), N + 1)));
    let mut never = Vec::new();
    for method in METHODS {
        let get = |metric: &str| table.values(scenario, method, metric).filter(|v| !v.is_empty());
        let (Some(amplitude), Some(frequency), Some(creep)) =
            (get("cycle_amplitude_q"), get("cycle_frequency_hz"), get("creep_q"))
        else {
            continue;
        };
        let mut cells = Vec::new();
        let mut cycling_anywhere = false;
        for j in 0..N {
            let cycling: Vec<usize> =
                (0..amplitude.len()).filter(|&s| amplitude[s][j] >= CYCLE_AMPLITUDE_RAD).collect();
            cycling_anywhere |= !cycling.is_empty();
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
    md
}

/// Whether joint `j` is still by [`LIMIT_CYCLE_RAD`] at the `k`-th bandwidth.
fn is_still(amplitude: &[Vec<f64>], k: usize, j: usize) -> bool {
    amplitude[k].get(j).is_some_and(|a| *a < LIMIT_CYCLE_RAD)
}

/// The section, from `methods` (the report's runs, for the per-method table) and runs of `base`
/// (the goto task) with the paper's estimator at every bandwidth.
pub fn section<const N: usize>(
    robot: &crate::robot::Robot<N>,
    base: &Scenario,
    methods: &MetricTable,
) -> Result<String, SimError> {
    let scenarios: Vec<Scenario> = BANDWIDTHS_RAD_S
        .iter()
        .map(|w| base.variant(&format!("w{w}"), Method::Lu, |s| s.controller.observer_bandwidth_rad_s = *w))
        .collect();
    let (_, table) = run_seeds(robot, &scenarios, SEEDS, &|_| {})?;
    let mut amplitude = Vec::new();
    for s in &scenarios {
        let values = table.values(&s.name, Method::Lu, "limit_cycle_q").unwrap_or_default();
        amplitude.push(per_joint_mean_ci95(&values).0);
    }
    let mut md = format!(
        "\n### Limit cycles and residual motion\n\nOne candidate mechanism is stick-slip hunting: a joint with stiction and integral action sticks, the integral winds the torque up until the joint breaks away, it overshoots, sticks on the other side, and the cycle repeats. The PID's integral could do this, and so could every estimator, which at low frequency acts as an integral of the error (gain about `K_P / τ_d` for the paper's); `none` (a PD) has no integral to wind up, so whatever it shows is not hunting. The rows without stiction rerun the scenario with the `tanh` law, which has no breakaway but is steep at rest (slope F_c/ε, far above F_v): they remove stiction, not every nonlinearity at rest, so they narrow the mechanism down without settling it. Measured on `{}` (peak-to-peak tracking error over the final window, mean over seeds, mrad; peak-to-peak counts slow drift and settling as well as oscillation):\n\n",
        base.name
    );
    md.push_str(&table_row(["method".to_owned()].into_iter().chain((1..=N).map(|j| format!("j{j}")))));
    md.push_str(&table_row(std::iter::repeat_n("---".to_owned(), N + 1)));
    // The same loops without stiction: smooth friction (Coulomb through tanh, no breakaway).
    let mut smooth = base.clone();
    smooth.name = format!("{}_smooth", base.name);
    smooth.plant.friction = crate::config::scenario::FrictionKind::Smooth;
    smooth.methods = METHODS.to_vec();
    let (_, without_stiction) = run_seeds(robot, std::slice::from_ref(&smooth), SEEDS, &|_| {})?;
    let mut cycling = Vec::new();
    for method in METHODS {
        for (label, table, scenario) in [("", methods, &base.name), (" (no stiction)", &without_stiction, &smooth.name)]
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
        "\nRows marked \"no stiction\" rerun the same scenario with smooth friction (the same Coulomb and viscous levels through `tanh`, no breakaway; {SEEDS} seeds): {}",
        if cycling.is_empty() {
            format!("no method keeps a joint at {} mrad or more, so the cycles above need stiction.", LIMIT_CYCLE_RAD * 1e3)
        } else {
            format!(
                "{} still keep a joint at {} mrad or more without stiction: what this measure shows is not all stiction's.",
                cycling.join(", "),
                LIMIT_CYCLE_RAD * 1e3
            )
        }
    );
    md.push_str(&cycles_apart_from_drift::<N>(methods, base));
    let _ = writeln!(
        md,
        "\nThe paper's estimator at ω1 = ω2 from {} to {} rad/s ({SEEDS} seeds each), same measure (mrad); below {} mrad a joint counts as still (peak-to-peak counts drift and settling as well as cycles):\n",
        BANDWIDTHS_RAD_S[0],
        BANDWIDTHS_RAD_S[BANDWIDTHS_RAD_S.len() - 1],
        LIMIT_CYCLE_RAD * 1e3
    );
    md.push_str(&table_row(
        ["joint".to_owned()].into_iter().chain(BANDWIDTHS_RAD_S.iter().map(|w| format!("{w} rad/s"))),
    ));
    md.push_str(&table_row(std::iter::repeat_n("---".to_owned(), BANDWIDTHS_RAD_S.len() + 1)));
    for j in 0..N {
        let cells = amplitude.iter().map(|a| a.get(j).map_or("-".to_owned(), |v| format!("{:.2}", v * 1e3)));
        md.push_str(&table_row([format!("{}", j + 1)].into_iter().chain(cells)));
    }
    let free_everywhere: Vec<String> = (0..N)
        .filter(|&j| (0..BANDWIDTHS_RAD_S.len()).all(|k| is_still(&amplitude, k, j)))
        .map(|j| format!("{}", j + 1))
        .collect();
    let _ = writeln!(
        md,
        "\n{} A faster filter passes more sensor noise into `d̂` (see the sweep).",
        if free_everywhere.len() == N {
            "Every joint stays still by this measure at every bandwidth swept.".to_owned()
        } else if free_everywhere.is_empty() {
            "No joint stays still by this measure at every bandwidth swept.".to_owned()
        } else {
            format!(
                "Joints {} stay still by this measure at every bandwidth swept; the others exceed it at one or more (which may be drift or settling, not a cycle).",
                free_everywhere.join(", ")
            )
        }
    );
    Ok(md)
}
