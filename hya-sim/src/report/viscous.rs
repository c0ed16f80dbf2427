//! The lagged-cancellation mechanism measured: the paper's estimator on the goto task at
//! bandwidths from 20 to 200 rad/s, each joint's limit-cycle amplitude after settling, and per
//! joint the largest filter delay that keeps it free of a limit cycle.

use std::fmt::Write as _;

use crate::analysis::seeds::{per_joint_mean_ci95, run_seeds};
use crate::config::scenario::{Method, Scenario};
use crate::error::SimError;

use super::text::table_row;

/// The bandwidths swept, rad/s (`ω1 = ω2`, `ζ = 0.8`).
pub const BANDWIDTHS_RAD_S: [f64; 7] = [20.0, 35.0, 50.0, 75.0, 100.0, 150.0, 200.0];

/// A joint is free of a limit cycle when its peak-to-peak error over the final 5 s stays below
/// this, rad (about 80 counts of HyA's encoders).
pub const LIMIT_CYCLE_RAD: f64 = 1e-3;

/// Seeds per bandwidth.
const SEEDS: usize = 3;

/// Whether joint `j` is free of a limit cycle at the `k`-th bandwidth.
fn is_free(amplitude: &[Vec<f64>], k: usize, j: usize) -> bool {
    amplitude[k].get(j).is_some_and(|a| *a < LIMIT_CYCLE_RAD)
}

/// The section, from runs of `base` (the goto task) at every bandwidth.
pub fn section<const N: usize>(robot: &crate::robot::Robot<N>, base: &Scenario) -> Result<String, SimError> {
    let scenarios: Vec<Scenario> = BANDWIDTHS_RAD_S
        .iter()
        .map(|w| {
            let mut s = base.clone();
            s.name = format!("{}_w{w}", base.name);
            s.controller.observer_bandwidth_rad_s = *w;
            s.methods = vec![Method::Lu];
            s
        })
        .collect();
    let (_, table) = run_seeds(robot, &scenarios, SEEDS, &|_| {})?;
    let mut amplitude = Vec::new();
    for s in &scenarios {
        let values = table.values(&s.name, Method::Lu, "limit_cycle_q").unwrap_or_default();
        amplitude.push(per_joint_mean_ci95(&values).0);
    }
    let delay = |w: f64| 1.0 / w + 2.0 * hya_core::filter::PAPER_ZETA / w;
    let mut md = format!(
        "\nMeasured: `lu` on `{}` at ω1 = ω2 from {} to {} rad/s ({SEEDS} seeds each), the peak-to-peak tracking error over the final window (5 s, or the last fifth of a shorter run), mean over seeds (mrad); a joint counts as free of a limit cycle below {} mrad. Per joint, the slowest bandwidth from which on every faster one in the sweep is free of a limit cycle, and the delay `τ_d = 1/ω + 2ζ/ω` it allows:\n\n",
        base.name,
        BANDWIDTHS_RAD_S[0],
        BANDWIDTHS_RAD_S[BANDWIDTHS_RAD_S.len() - 1],
        LIMIT_CYCLE_RAD * 1e3
    );
    md.push_str(&table_row(
        ["joint".to_owned()]
            .into_iter()
            .chain(BANDWIDTHS_RAD_S.iter().map(|w| format!("{w} rad/s")))
            .chain(["largest τ_d free of a limit cycle [ms]".to_owned(), "recommended ω1 = ω2 [rad/s]".to_owned()]),
    ));
    md.push_str(&table_row(std::iter::repeat_n("---".to_owned(), BANDWIDTHS_RAD_S.len() + 3)));
    for j in 0..N {
        // The slowest bandwidth from which on every faster one is free too.
        let free = |k: usize| is_free(&amplitude, k, j);
        let slowest_free = (0..BANDWIDTHS_RAD_S.len())
            .find(|&k| (k..BANDWIDTHS_RAD_S.len()).all(free))
            .map_or(f64::INFINITY, |k| BANDWIDTHS_RAD_S[k]);
        let (largest_delay, recommended) = if slowest_free.is_finite() {
            (format!("{:.0}", delay(slowest_free) * 1e3), format!("{slowest_free}"))
        } else {
            ("none in the sweep".to_owned(), format!("above {}", BANDWIDTHS_RAD_S[BANDWIDTHS_RAD_S.len() - 1]))
        };
        let cells = amplitude.iter().map(|a| a.get(j).map_or("-".to_owned(), |v| format!("{:.2}", v * 1e3)));
        md.push_str(&table_row([format!("{}", j + 1)].into_iter().chain(cells).chain([largest_delay, recommended])));
    }
    // Joints where a longer delay is free of a limit cycle while a shorter one is not: there the
    // measurement contradicts the simple `F_v τ_d > M_ii` rule.
    let contradicting: Vec<String> = (0..N)
        .filter(|&j| {
            let free = |k: usize| is_free(&amplitude, k, j);
            (0..BANDWIDTHS_RAD_S.len())
                .any(|slow| free(slow) && (slow + 1..BANDWIDTHS_RAD_S.len()).any(|fast| !free(fast)))
        })
        .map(|j| format!("{}", j + 1))
        .collect();
    if !contradicting.is_empty() {
        let _ = writeln!(
            md,
            "\nOn joints {} a slower filter (a longer delay) is free of a limit cycle while a faster one is not: there the measurement does not follow the `F_v τ_d > M_ii` rule above, which ignores friction's nonlinearity and the actuators.",
            contradicting.join(", ")
        );
    }
    let _ = writeln!(
        md,
        "\nThe filters share one `Φ` for all joints, so one bandwidth serves the arm: by this table's definition the largest per-joint value keeps every joint free of a limit cycle in the sweep; a faster filter passes more sensor noise into `d̂` (see `hya sweep`)."
    );
    Ok(md)
}
