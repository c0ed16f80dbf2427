//! Per-joint figures of one run, after the warm-up: the RMSEs of tracking and estimation, and
//! what a single RMSE hides (steady-state error, limit-cycle amplitude, recovery after a load
//! change, how the estimate moves with the task).

use serde::{Deserialize, Serialize};

use hya_core::JointVector;

use crate::analysis::running::{Correlation, Extremes, Mean, Recovery, Rms, Spread, StepNoise, Window};
use crate::analysis::shadow::{ShadowMetrics, ShadowRecorder};
use crate::config::settings::{Setup, TaskTimes, Timing};
use crate::run::trace::{Tick, SHADOWS};

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

/// The window a limit cycle is looked for in: the run's last this many seconds, once the task
/// has gone quiet (after the warm-up, a ramp or a move), s.
pub const CYCLE_WINDOW_S: f64 = 10.0;

/// The most samples of that window kept per joint (every k-th tick beyond).
const CYCLE_SAMPLES: usize = 10_000;

/// The highest frequency searched for a limit cycle, Hz.
pub const CYCLE_MAX_HZ: f64 = 10.0;

/// A joint counts as cycling where the largest spectral line of its detrended error
/// ([`Metrics::cycle_amplitude_q`]) reaches this amplitude, rad: a sine of 0.5 mrad peak to
/// peak, about 40 counts of HyA's encoders.
pub const CYCLE_AMPLITUDE_RAD: f64 = 2.5e-4;

/// Observers and filters need this long after the warm-up before a "before" window opens, s.
const SETTLE_AFTER_START_S: f64 = 1.0;

/// The earliest time a window that must precede `event_s` may open: after the warm-up and the
/// observers' settling, after a sine task's ramp, and after a goto move that ends before the
/// event (plus [`SETTLE_AFTER_START_S`]).
fn quiet_from(task: TaskTimes, event_s: f64) -> f64 {
    let start = WARM_UP_S + SETTLE_AFTER_START_S;
    match task {
        TaskTimes::Hold => start,
        TaskTimes::Sine { ramp_s } => start.max(ramp_s + SETTLE_AFTER_START_S),
        TaskTimes::Goto { start_s, transition_s } => {
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
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
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
    /// Peak-to-peak of `q − q_des` over the final window, rad (a limit cycle's amplitude, but
    /// drift and settling count too).
    pub limit_cycle_q: Vec<f64>,
    /// Amplitude of the largest spectral line of `q − q_des` once its straight-line trend is
    /// removed, over the last [`CYCLE_WINDOW_S`] after the task went quiet (bins from two periods
    /// per window to [`CYCLE_MAX_HZ`]), rad: an oscillation apart from drift; NaN where the window
    /// is too short.
    pub cycle_amplitude_q: Vec<f64>,
    /// That line's frequency, Hz.
    pub cycle_frequency_hz: Vec<f64>,
    /// The trend's change over that window, rad: creep (drift), apart from oscillation.
    pub creep_q: Vec<f64>,
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
    /// [`Self::estimate_shift`] over the joint's nominal Coulomb friction level
    /// (`plant.coulomb_nm`): a torque threshold scaled to each joint. Absent without friction.
    pub estimate_shift_over_coulomb: Option<Vec<f64>>,
    /// [`Self::estimate_mean_abs`] over the joint's nominal Coulomb friction level.
    pub estimate_mean_over_coulomb: Option<Vec<f64>>,
    /// Every shadow estimator's figures ([`crate::run::trace::SHADOWS`] order), on this run's
    /// measurements.
    pub shadow: [ShadowMetrics; 4],
}

/// A weight drop's windows: the error before it, while the weight rests, and the recoveries.
#[derive(Debug, Clone)]
struct DropWatch<const N: usize> {
    before: Window,
    error_before: Mean<N>,
    resting: Window,
    error_resting: Mean<N>,
    drop_recovery: Recovery<N>,
    removal_recovery: Option<Recovery<N>>,
}

/// The limit-cycle window of a run of `task` whose window ends at `end`, s.
fn cycle_window_ending(task: TaskTimes, end: f64) -> Window {
    Window::new((end - CYCLE_WINDOW_S).max(quiet_from(task, end)), end)
}

/// The window [`Metrics::cycle_amplitude_q`] looks in on a run of `task` on the clock `timing`,
/// s: its lowest frequency bin is two periods per window.
pub fn cycle_window(task: TaskTimes, timing: &Timing) -> Window {
    cycle_window_ending(task, timing.last_time_s() + 1e-9)
}

/// The tracking error's samples over the limit-cycle window, at most [`CYCLE_SAMPLES`] per joint.
#[derive(Debug, Clone)]
struct CycleWindow<const N: usize> {
    window: Window,
    stride: usize,
    seen: usize,
    step: f64,
    first: Option<f64>,
    samples: Vec<JointVector<N>>,
}

impl<const N: usize> CycleWindow<N> {
    /// The window of a run of `task` ending at `end`, s, ticking every `dt`.
    fn new(task: TaskTimes, end: f64, dt: f64) -> Self {
        let window = cycle_window_ending(task, end);
        let ticks = ((window.to - window.from) / dt).ceil().max(0.0) as usize;
        let stride = ticks.div_ceil(CYCLE_SAMPLES).max(1);
        let kept = ticks.div_ceil(stride);
        Self { window, stride, seen: 0, step: stride as f64 * dt, first: None, samples: Vec::with_capacity(kept) }
    }

    fn push(&mut self, t: f64, error: &JointVector<N>) {
        if !self.window.contains(t) {
            return;
        }
        if self.seen.is_multiple_of(self.stride) {
            self.first.get_or_insert(t);
            self.samples.push(*error);
        }
        self.seen += 1;
    }

    /// Per joint, the spectral line's amplitude and frequency and the drift (NaN where the
    /// window is too short).
    fn lines(&self) -> [Vec<f64>; 3] {
        let mut out = [Vec::with_capacity(N), Vec::with_capacity(N), Vec::with_capacity(N)];
        for j in 0..N {
            let x: Vec<f64> = self.samples.iter().map(|e| e[j]).collect();
            let line = crate::analysis::running::spectral_line(&x, self.first.unwrap_or(0.0), self.step, CYCLE_MAX_HZ);
            let values = line.map_or([f64::NAN; 3], |l| [l.amplitude, l.frequency_hz, l.drift]);
            for (series, value) in out.iter_mut().zip(values) {
                series.push(value);
            }
        }
        out
    }
}

/// A goto task's mean estimate before the move and after the setpoint.
#[derive(Debug, Clone)]
struct EstimateShift<const N: usize> {
    before: Window,
    mean_before: Mean<N>,
    after: Window,
    mean_after: Mean<N>,
}

/// The correlation of `d̂` with the velocity from the true angles by central differences
/// (one-sided at the ends), `(q_{k+1} − q_{k−1}) / (t_{k+1} − t_{k−1})`: each tick is paired
/// once the next one is known.
#[derive(Debug, Clone, Default)]
struct VelocityCorrelation<const N: usize> {
    previous: Option<(f64, JointVector<N>)>,
    pending: Option<PendingTick<N>>,
    correlation: Correlation<N>,
}

#[derive(Debug, Clone, Copy)]
struct PendingTick<const N: usize> {
    t: f64,
    q: JointVector<N>,
    d_hat: JointVector<N>,
    counted: bool,
}

impl<const N: usize> VelocityCorrelation<N> {
    fn push(&mut self, tick: &Tick<N>, counted: bool) {
        self.settle(Some((tick.t, tick.q)));
        self.pending = Some(PendingTick { t: tick.t, q: tick.q, d_hat: tick.d_hat, counted });
    }

    /// Pairs the pending tick with its velocity, from the tick before it to `next` (or to
    /// itself at the end of the run).
    fn settle(&mut self, next: Option<(f64, JointVector<N>)>) {
        let Some(p) = self.pending.take() else { return };
        let (t_before, q_before) = self.previous.unwrap_or((p.t, p.q));
        let (t_after, q_after) = next.unwrap_or((p.t, p.q));
        if p.counted {
            self.correlation.push(&p.d_hat, &((q_after - q_before) / (t_after - t_before).max(1e-12)));
        }
        self.previous = Some((p.t, p.q));
    }

    fn value(mut self) -> Vec<f64> {
        self.settle(None);
        self.correlation.value()
    }
}

/// A run's [`Metrics`], accumulated tick by tick as the run goes: memory does not grow with
/// the run's duration.
#[derive(Debug, Clone)]
pub struct MetricsRecorder<const N: usize> {
    has_estimate: bool,
    tracking: Rms<N>,
    error_extremes: Extremes<N>,
    settled: Window,
    settled_error: Mean<N>,
    settled_extremes: Extremes<N>,
    cycle: CycleWindow<N>,
    command_noise: StepNoise<N>,
    estimate_error: Rms<N>,
    disturbance_spread: Spread<N>,
    estimate_mean: Mean<N>,
    velocity: VelocityCorrelation<N>,
    drop: Option<DropWatch<N>>,
    shift: Option<EstimateShift<N>>,
    shadows: [ShadowRecorder<N>; 4],
    /// The joints' nominal Coulomb levels, N·m, where the plant has friction.
    coulomb: Option<Vec<f64>>,
}

impl<const N: usize> MetricsRecorder<N> {
    /// The recorder of a run set up by `setup` (its task, loads and clock set the windows) whose
    /// last tick is at `last_time` (s); `has_estimate` for methods with a disturbance estimate.
    pub fn new(setup: &Setup<N>, has_estimate: bool, last_time: f64) -> Self {
        let end = last_time + 1e-9;
        let window = SETTLED_WINDOW_S.min(0.2 * (end - WARM_UP_S).max(0.0));
        let task = setup.task.times();
        let drop = setup.plant.loads.weight_drop.as_ref().map(|d| {
            let resting_until = d.remove_s.unwrap_or(end).min(end);
            let before_from = (d.drop_s - SETTLED_WINDOW_S).max(quiet_from(task, d.drop_s));
            DropWatch {
                before: Window::new(before_from, d.drop_s),
                error_before: Mean::default(),
                resting: Window::new(d.drop_s + 0.5, resting_until),
                error_resting: Mean::default(),
                drop_recovery: Recovery::new(Window::new(d.drop_s, resting_until), RECOVERY_HOLD_S),
                removal_recovery: d
                    .remove_s
                    .filter(|r| *r < end)
                    .map(|r| Recovery::new(Window::new(r, end), RECOVERY_HOLD_S)),
            }
        });
        let shift = match (task, has_estimate) {
            (TaskTimes::Goto { start_s, transition_s }, true) => Some(EstimateShift {
                before: Window::new((start_s - SETTLED_WINDOW_S).max(quiet_from(task, start_s)), start_s),
                mean_before: Mean::default(),
                after: Window::new((start_s + transition_s).max(end - window), end),
                mean_after: Mean::default(),
            }),
            _ => None,
        };
        Self {
            has_estimate,
            tracking: Rms::default(),
            error_extremes: Extremes::default(),
            settled: Window::new(end - window, end),
            settled_error: Mean::default(),
            settled_extremes: Extremes::default(),
            cycle: CycleWindow::new(task, end, setup.timing.dt_s),
            command_noise: StepNoise::default(),
            estimate_error: Rms::default(),
            disturbance_spread: Spread::default(),
            estimate_mean: Mean::default(),
            velocity: VelocityCorrelation::default(),
            drop,
            shift,
            shadows: SHADOWS.map(|method| {
                ShadowRecorder::new(
                    method,
                    (setup.control.observer_bandwidth_rad_s, setup.timing.dt_s),
                    setup.plant.loads.sinusoid.as_ref(),
                    last_time,
                )
            }),
            coulomb: setup.plant.friction.levels().map(|levels| levels.coulomb.iter().copied().collect()),
        }
    }

    /// Adds one control tick.
    pub fn push(&mut self, tick: &Tick<N>) {
        let (t, error) = (tick.t, tick.q - tick.q_des);
        let after_warm_up = t >= WARM_UP_S;
        for (recorder, d_hat) in self.shadows.iter_mut().zip(&tick.shadow) {
            recorder.push(t, &tick.d_true, d_hat, after_warm_up);
        }
        if self.has_estimate {
            self.velocity.push(tick, after_warm_up);
        }
        self.cycle.push(t, &error);
        if self.settled.contains(t) {
            self.settled_error.push(&error.abs());
            self.settled_extremes.push(&error);
        }
        if let Some(drop) = self.drop.as_mut() {
            if drop.before.contains(t) {
                drop.error_before.push(&error.abs());
            }
            if drop.resting.contains(t) {
                drop.error_resting.push(&error.abs());
            }
            let band = || drop.error_before.value().map(|e| (RECOVERY_FACTOR * e).max(RECOVERY_FLOOR_RAD));
            drop.drop_recovery.push(t, &error, || band().as_slice().to_vec());
            if let Some(removal) = drop.removal_recovery.as_mut() {
                removal.push(t, &error, || band().as_slice().to_vec());
            }
        }
        if let Some(shift) = self.shift.as_mut() {
            if shift.before.contains(t) {
                shift.mean_before.push(&tick.d_hat);
            }
            if shift.after.contains(t) {
                shift.mean_after.push(&tick.d_hat);
            }
        }
        if !after_warm_up {
            return;
        }
        self.tracking.push(&error);
        self.error_extremes.push(&error);
        self.command_noise.push(&tick.tau_cmd);
        self.estimate_error.push(&(tick.d_hat - tick.d_true));
        self.disturbance_spread.push(&tick.d_true);
        self.estimate_mean.push(&tick.d_hat);
    }

    /// The metrics of the ticks pushed.
    pub fn finish(self) -> Metrics {
        let estimated = |v: Vec<f64>| self.has_estimate.then_some(v);
        let vec = |v: JointVector<N>| v.as_slice().to_vec();
        let rmse_d = estimated(self.estimate_error.value());
        let spread = self.disturbance_spread.value();
        let [cycle_amplitude_q, cycle_frequency_hz, creep_q] = self.cycle.lines();
        let estimate_shift =
            self.shift.as_ref().map(|s| (s.mean_after.value() - s.mean_before.value()).abs().as_slice().to_vec());
        let estimate_mean_abs = estimated(vec(self.estimate_mean.value().abs()));
        let over_coulomb = |v: &Option<Vec<f64>>| match (v, &self.coulomb) {
            (Some(v), Some(c)) => Some(v.iter().zip(c).map(|(x, c)| x / c).collect()),
            _ => None,
        };
        Metrics {
            estimate_shift_over_coulomb: over_coulomb(&estimate_shift),
            estimate_mean_over_coulomb: over_coulomb(&estimate_mean_abs),
            cycle_amplitude_q,
            cycle_frequency_hz,
            creep_q,
            rmse_q: self.tracking.value(),
            relative_rmse_d: rmse_d.as_ref().map(|r| r.iter().zip(&spread).map(|(e, s)| e / s.max(1e-12)).collect()),
            rmse_d,
            tau_cmd_noise: self.command_noise.value(),
            max_abs_error_q: self.error_extremes.max_abs(),
            steady_error_q: vec(self.settled_error.value()),
            limit_cycle_q: self.settled_extremes.peak_to_peak(),
            weight_error_q: self.drop.as_ref().map(|d| vec(d.error_resting.value())),
            drop_recovery_s: self.drop.as_ref().map(|d| d.drop_recovery.value()),
            removal_recovery_s: self.drop.as_ref().and_then(|d| d.removal_recovery.as_ref().map(Recovery::value)),
            pre_drop_error_q: self.drop.as_ref().map(|d| vec(d.error_before.value())),
            estimate_shift,
            estimate_mean_abs,
            estimate_velocity_correlation: estimated(self.velocity.value()),
            shadow: self.shadows.each_ref().map(ShadowRecorder::finish),
        }
    }
}

impl Metrics {
    /// Every per-joint metric by name (those the run has), for tables and rules.
    pub fn named(&self) -> Vec<(&'static str, &[f64])> {
        let mut all: Vec<(&'static str, &[f64])> = vec![
            ("rmse_q", &self.rmse_q),
            ("tau_cmd_noise", &self.tau_cmd_noise),
            ("max_abs_error_q", &self.max_abs_error_q),
            ("steady_error_q", &self.steady_error_q),
            ("limit_cycle_q", &self.limit_cycle_q),
            ("cycle_amplitude_q", &self.cycle_amplitude_q),
            ("cycle_frequency_hz", &self.cycle_frequency_hz),
            ("creep_q", &self.creep_q),
        ];
        let optional: [(&'static str, &Option<Vec<f64>>); 11] = [
            ("rmse_d", &self.rmse_d),
            ("relative_rmse_d", &self.relative_rmse_d),
            ("weight_error_q", &self.weight_error_q),
            ("pre_drop_error_q", &self.pre_drop_error_q),
            ("drop_recovery_s", &self.drop_recovery_s),
            ("removal_recovery_s", &self.removal_recovery_s),
            ("estimate_shift", &self.estimate_shift),
            ("estimate_velocity_correlation", &self.estimate_velocity_correlation),
            ("estimate_mean_abs", &self.estimate_mean_abs),
            ("estimate_shift_over_coulomb", &self.estimate_shift_over_coulomb),
            ("estimate_mean_over_coulomb", &self.estimate_mean_over_coulomb),
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::scenario::{FrictionKind, Scenario};

    /// The settings of `scenario` on six joints.
    fn setup(scenario: &Scenario) -> Setup<6> {
        Setup::of(scenario).unwrap_or_else(|e| panic!("{e}"))
    }

    #[test]
    fn torque_metrics_are_scaled_by_each_joints_coulomb_level() {
        let scenario = Scenario::builtin("sine_internal").unwrap_or_else(|e| panic!("{e}"));
        let coulomb = scenario.plant.coulomb_nm.clone();
        let mut recorder = MetricsRecorder::<6>::new(&setup(&scenario), true, 3.0);
        let d_hat = JointVector::<6>::from([1.0, -1.0, 0.6, -0.6, 0.4, 0.2]);
        for k in 0..=3000 {
            let zero = JointVector::zeros();
            recorder.push(&crate::run::trace::Tick {
                t: k as f64 * 1e-3,
                q: zero,
                q_des: zero,
                d_true: zero,
                d_hat,
                tau_cmd: zero,
                shadow: [zero; 4],
            });
        }
        let metrics = recorder.finish();
        let (Some(mean), Some(scaled)) = (metrics.estimate_mean_abs, metrics.estimate_mean_over_coulomb) else {
            panic!("an estimating run has both")
        };
        for j in 0..6 {
            assert!((mean[j] - d_hat[j].abs()).abs() < 1e-12 && (scaled[j] - mean[j] / coulomb[j]).abs() < 1e-12);
        }
        let mut frictionless = scenario.clone();
        frictionless.plant.friction = FrictionKind::Off;
        let none = MetricsRecorder::<6>::new(&setup(&frictionless), true, 3.0).finish();
        assert!(none.estimate_mean_over_coulomb.is_none(), "no friction, no friction scale");
    }
}
