//! Per-joint figures of one run, after the warm-up: the RMSEs of tracking and estimation, and
//! what a single RMSE hides (steady-state error, limit-cycle amplitude, recovery after a load
//! change, how the estimate moves with the task).

use serde::Serialize;

use hya_core::JointVector;

use crate::analysis::shadow::{rms, shadow_metrics, ShadowMetrics};
use crate::config::scenario::{Scenario, Task};
use crate::run::trace::Trace;

pub use crate::config::scenario::WARM_UP_S;

/// The final window in which a settled run is judged, s (or the last fifth of a shorter run).
pub const SETTLED_WINDOW_S: f64 = 5.0;

/// A joint counts as recovered once `|e|` stays within this many times its error before the
/// load change (and at least [`RECOVERY_FLOOR_RAD`]) for [`RECOVERY_HOLD_S`].
pub const RECOVERY_FACTOR: f64 = 2.0;
/// See [`RECOVERY_FACTOR`], rad.
pub const RECOVERY_FLOOR_RAD: f64 = 1e-3;
/// See [`RECOVERY_FACTOR`], s.
pub const RECOVERY_HOLD_S: f64 = 0.5;

/// Observers and filters need this long after the warm-up before a "before" window opens, s.
const SETTLE_AFTER_START_S: f64 = 1.0;

/// The earliest time a window that must precede `event_s` may open: after the warm-up and the
/// observers' settling, after a sine task's ramp, and after a goto move that ends before the
/// event (plus [`SETTLE_AFTER_START_S`]).
fn quiet_from(scenario: &Scenario, event_s: f64) -> f64 {
    let start = WARM_UP_S + SETTLE_AFTER_START_S;
    match &scenario.task {
        Task::Hold {} => start,
        Task::Sine { ramp_s, .. } => start.max(ramp_s + SETTLE_AFTER_START_S),
        Task::Goto { start_s, transition_s, .. } => {
            let moved = start_s + transition_s + SETTLE_AFTER_START_S;
            if moved < event_s {
                start.max(moved)
            } else {
                start
            }
        }
    }
}

/// The names [`Metrics::named`] gives the shadow estimators' figures: per estimator of
/// [`crate::run::trace::SHADOWS`], its RMSE against `d`, against its design, its noise, its error
/// in the load's band.
pub const SHADOW_METRIC_NAMES: [[&str; 4]; 4] = [
    ["shadow_lu_rmse_d", "shadow_lu_rmse_design", "shadow_lu_noise", "shadow_lu_band_error"],
    ["shadow_chen_rmse_d", "shadow_chen_rmse_design", "shadow_chen_noise", "shadow_chen_band_error"],
    ["shadow_momentum_rmse_d", "shadow_momentum_rmse_design", "shadow_momentum_noise", "shadow_momentum_band_error"],
    ["shadow_eso_rmse_d", "shadow_eso_rmse_design", "shadow_eso_noise", "shadow_eso_band_error"],
];

/// Per-joint figures of one run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Metrics {
    /// RMSE of tracking, `q − q_des`, rad.
    pub rmse_q: Vec<f64>,
    /// RMSE of `d̂ − d`, N·m; `None` without an estimator.
    pub rmse_d: Option<Vec<f64>>,
    /// `rmse_d` over the RMS of `d` about its mean: above about 0.5 the estimate does not track.
    pub relative_rmse_d: Option<Vec<f64>>,
    /// Noise in the commanded torque: RMS of its first difference over √2, N·m (white noise of
    /// standard deviation σ gives σ; a smooth command gives nearly 0).
    pub tau_cmd_noise: Vec<f64>,
    /// Largest `|q − q_des|`, rad.
    pub max_abs_error_q: Vec<f64>,
    /// Mean `|q − q_des|` over the final window, rad (the steady-state error of a hold).
    pub steady_error_q: Vec<f64>,
    /// Peak-to-peak of `q − q_des` over the final window, rad (a limit cycle's amplitude).
    pub limit_cycle_q: Vec<f64>,
    /// Mean `|q − q_des|` while a dropped weight rests on the arm (from 0.5 s after the drop), rad.
    pub weight_error_q: Option<Vec<f64>>,
    /// Mean `|q − q_des|` over the 5 s before the drop (from the end of any earlier move or ramp,
    /// and never within the first 1.5 s), rad; NaN where no such window exists.
    pub pre_drop_error_q: Option<Vec<f64>>,
    /// Time from the drop until `|e|` is back within its band ([`RECOVERY_FACTOR`]), s; the
    /// whole remaining run where it never is.
    pub drop_recovery_s: Option<Vec<f64>>,
    /// The same after the weight's removal, s.
    pub removal_recovery_s: Option<Vec<f64>>,
    /// `|mean d̂ after the setpoint − mean d̂ before the move|` of a goto task, each over 5 s, N·m.
    pub estimate_shift: Option<Vec<f64>>,
    /// Correlation of `d̂` with the joint velocity (`q̇` from the true angles): −1 when the
    /// estimate opposes the motion like friction.
    pub estimate_velocity_correlation: Option<Vec<f64>>,
    /// `|mean d̂|`, N·m (a static-friction bias).
    pub estimate_mean_abs: Option<Vec<f64>>,
    /// Every shadow estimator's figures ([`crate::run::trace::SHADOWS`] order), on this run's
    /// measurements.
    pub shadow: [ShadowMetrics; 4],
}

/// Per-joint mean of `f(k)[j]` over the ticks `k` in `range`.
fn mean_over<const N: usize>(range: std::ops::Range<usize>, f: impl Fn(usize) -> JointVector<N>) -> Vec<f64> {
    let count = range.len() as f64; // an empty window gives NaN
    let sum = range.fold(JointVector::<N>::zeros(), |s, k| s + f(k));
    (sum / count).as_slice().to_vec()
}

/// The tick range of `[from, to)` seconds.
fn ticks<const N: usize>(trace: &Trace<N>, from: f64, to: f64) -> std::ops::Range<usize> {
    let start = trace.time.partition_point(|t| *t < from);
    let end = trace.time.partition_point(|t| *t < to);
    start..end.max(start)
}

/// Per joint, the time from `from_s` until `|e|`, having left `band[j]`, stays back within it
/// for [`RECOVERY_HOLD_S`]; 0 where it never leaves the band, the rest of the run where it
/// never returns.
fn recovery<const N: usize>(trace: &Trace<N>, from_s: f64, to_s: f64, band: &[f64]) -> Vec<f64> {
    let range = ticks(trace, from_s, to_s);
    (0..N)
        .map(|j| {
            let outside = |k: &usize| (trace.q[*k][j] - trace.q_des[*k][j]).abs() > band[j];
            let Some(left) = range.clone().find(outside) else { return 0.0 };
            let mut inside_since: Option<f64> = None;
            for k in left..range.end {
                let t = trace.time[k];
                if (trace.q[k][j] - trace.q_des[k][j]).abs() <= band[j] {
                    let since = *inside_since.get_or_insert(t);
                    if t - since >= RECOVERY_HOLD_S {
                        return since - from_s;
                    }
                } else {
                    inside_since = None;
                }
            }
            to_s - from_s
        })
        .collect()
}

/// Per-joint Pearson correlation of `a` and `b` over the samples.
fn correlation(pairs: &[(f64, f64)]) -> f64 {
    let n = pairs.len().max(1) as f64;
    let (ma, mb) = pairs.iter().fold((0.0, 0.0), |(x, y), (a, b)| (x + a / n, y + b / n));
    let (mut sab, mut saa, mut sbb) = (0.0, 0.0, 0.0);
    for (a, b) in pairs {
        sab += (a - ma) * (b - mb);
        saa += (a - ma) * (a - ma);
        sbb += (b - mb) * (b - mb);
    }
    if saa > 0.0 && sbb > 0.0 {
        sab / (saa * sbb).sqrt()
    } else {
        0.0
    }
}

impl Metrics {
    /// The metrics of `trace`, a run of `scenario` (which sets the windows), after the warm-up;
    /// `has_estimate` for methods with a disturbance estimate.
    pub fn of<const N: usize>(trace: &Trace<N>, scenario: &Scenario, has_estimate: bool) -> Self {
        let end = trace.time.last().copied().unwrap_or(0.0) + 1e-9;
        let start = trace.time.partition_point(|t| *t < WARM_UP_S);
        let error = |k: usize| trace.q[k] - trace.q_des[k];
        let errors = || (start..trace.time.len()).map(error);
        let estimate_errors = (start..trace.time.len()).map(|k| trace.d_hat[k] - trace.d_true[k]);
        let command_steps = trace.tau_cmd[start..].windows(2).map(|w| (w[1] - w[0]) / std::f64::consts::SQRT_2);
        let window = SETTLED_WINDOW_S.min(0.2 * (end - WARM_UP_S).max(0.0));
        let settled = ticks(trace, end - window, end);
        let rmse_d = has_estimate.then(|| rms(estimate_errors));
        let d_mean = mean_over(start..trace.time.len(), |k| trace.d_true[k]);
        let d_spread =
            rms((start..trace.time.len()).map(|k| trace.d_true[k] - JointVector::from_column_slice(&d_mean)));
        let drop = scenario.loads.weight_drop.as_ref();
        let pre_drop = drop.map(|d| {
            let from = (d.drop_s - SETTLED_WINDOW_S).max(quiet_from(scenario, d.drop_s));
            mean_over(ticks(trace, from, d.drop_s), |k| error(k).abs())
        });
        let band = |pre: &[f64]| pre.iter().map(|e| (RECOVERY_FACTOR * e).max(RECOVERY_FLOOR_RAD)).collect::<Vec<_>>();
        let removal = drop.and_then(|d| d.remove_s).filter(|r| *r < end);
        let velocity = |k: usize, j: usize| {
            let (a, b) = (k.saturating_sub(1), (k + 1).min(trace.time.len() - 1));
            (trace.q[b][j] - trace.q[a][j]) / (trace.time[b] - trace.time[a]).max(1e-12)
        };
        Metrics {
            rmse_q: rms(errors()),
            relative_rmse_d: rmse_d.as_ref().map(|r| r.iter().zip(&d_spread).map(|(e, s)| e / s.max(1e-12)).collect()),
            rmse_d,
            tau_cmd_noise: rms(command_steps),
            max_abs_error_q: (0..N).map(|i| errors().map(|e| e[i].abs()).fold(0.0, f64::max)).collect(),
            steady_error_q: mean_over(settled.clone(), |k| error(k).abs()),
            limit_cycle_q: (0..N)
                .map(|j| {
                    let values = settled.clone().map(|k| error(k)[j]);
                    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| (l.min(v), h.max(v)));
                    if hi >= lo {
                        hi - lo
                    } else {
                        0.0
                    }
                })
                .collect(),
            weight_error_q: drop.map(|d| {
                mean_over(ticks(trace, d.drop_s + 0.5, d.remove_s.unwrap_or(end).min(end)), |k| error(k).abs())
            }),
            drop_recovery_s: drop
                .zip(pre_drop.as_ref())
                .map(|(d, pre)| recovery(trace, d.drop_s, d.remove_s.unwrap_or(end).min(end), &band(pre))),
            removal_recovery_s: removal.zip(pre_drop.as_ref()).map(|(r, pre)| recovery(trace, r, end, &band(pre))),
            pre_drop_error_q: pre_drop,
            estimate_shift: match (&scenario.task, has_estimate) {
                (Task::Goto { start_s, transition_s, .. }, true) => {
                    let from = (start_s - SETTLED_WINDOW_S).max(quiet_from(scenario, *start_s));
                    let before = mean_over(ticks(trace, from, *start_s), |k| trace.d_hat[k]);
                    let after =
                        mean_over(ticks(trace, (start_s + transition_s).max(end - window), end), |k| trace.d_hat[k]);
                    Some(before.iter().zip(&after).map(|(b, a)| (a - b).abs()).collect())
                }
                _ => None,
            },
            estimate_velocity_correlation: has_estimate.then(|| {
                (0..N)
                    .map(|j| {
                        let pairs: Vec<(f64, f64)> =
                            (start..trace.time.len()).map(|k| (trace.d_hat[k][j], velocity(k, j))).collect();
                        correlation(&pairs)
                    })
                    .collect()
            }),
            estimate_mean_abs: has_estimate
                .then(|| mean_over(start..trace.time.len(), |k| trace.d_hat[k]).iter().map(|m| m.abs()).collect()),
            shadow: shadow_metrics(trace, scenario, start),
        }
    }

    /// Every per-joint metric by name (those the run has), for tables and rules.
    pub fn named(&self) -> Vec<(&'static str, &[f64])> {
        let mut all: Vec<(&'static str, &[f64])> = vec![
            ("rmse_q", &self.rmse_q),
            ("tau_cmd_noise", &self.tau_cmd_noise),
            ("max_abs_error_q", &self.max_abs_error_q),
            ("steady_error_q", &self.steady_error_q),
            ("limit_cycle_q", &self.limit_cycle_q),
        ];
        let optional: [(&'static str, &Option<Vec<f64>>); 9] = [
            ("rmse_d", &self.rmse_d),
            ("relative_rmse_d", &self.relative_rmse_d),
            ("weight_error_q", &self.weight_error_q),
            ("pre_drop_error_q", &self.pre_drop_error_q),
            ("drop_recovery_s", &self.drop_recovery_s),
            ("removal_recovery_s", &self.removal_recovery_s),
            ("estimate_shift", &self.estimate_shift),
            ("estimate_velocity_correlation", &self.estimate_velocity_correlation),
            ("estimate_mean_abs", &self.estimate_mean_abs),
        ];
        all.extend(optional.into_iter().filter_map(|(n, v)| v.as_deref().map(|v| (n, v))));
        for (names, shadow) in SHADOW_METRIC_NAMES.iter().zip(&self.shadow) {
            let values =
                [Some(&shadow.rmse_d), Some(&shadow.rmse_design), Some(&shadow.noise), shadow.band_error.as_ref()];
            all.extend(
                names.iter().zip(values).filter_map(|(n, v)| v.filter(|v| !v.is_empty()).map(|v| (*n, v.as_slice()))),
            );
        }
        all
    }
}
