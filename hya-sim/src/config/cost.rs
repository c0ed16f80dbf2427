//! What a run will cost, known before it starts: the integration steps it takes and the trace
//! memory it holds, checked against documented caps so that an absurd setting is refused with
//! its figure instead of running for weeks or until memory runs out.
//!
//! `hya reproduce` and `hya run` count their studies too (`hya_sim::studies::cost`): by default
//! 1307 runs and 24,895 simulated seconds where the scenarios alone are 720 runs and 16,800 s.
//!
//! Metrics are accumulated tick by tick; only the first seed's runs keep a trace (time, `q`,
//! `q_des`, `d`, `d̂`, `τ_cmd`), for the figures and CSV files, of at most
//! [`MAX_TRACE_SAMPLES`] ticks each (a longer run keeps every k-th tick). So memory grows with
//! the number of scenarios and methods, not with the duration or the number of seeds.

use std::fmt;

use hya_core::Short;

use crate::config::scenario::{ActuatorKind, Scenario};
use crate::error::SimError;
use crate::run::trace::{bytes_per_sample, MAX_TRACE_SAMPLES};
use hya_core::dispatch::MAX_JOINTS;

/// The most plant integration steps (control ticks × [`steps_per_tick`], summed over every run
/// and study) a command runs without `--no-cost-limit`: 32 times the default `hya reproduce`
/// (9.4e7 steps with its studies, about two to five minutes on 2 cores), so one to three hours.
pub const MAX_PHYSICS_STEPS: f64 = 3e9;

/// The most trace memory a command holds without `--no-cost-limit`, bytes (4 GiB).
pub const MAX_TRACE_BYTES: f64 = 4.0 * (1u64 << 30) as f64;

/// Bytes of trace per kept tick for the largest arm.
const TRACE_BYTES_PER_TICK: f64 = bytes_per_sample(MAX_JOINTS) as f64;

/// The cost of running every method of every scenario over some seeds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cost {
    /// Closed-loop runs.
    pub runs: usize,
    /// Simulated time over every run, s.
    pub simulated_s: f64,
    /// Plant integration steps over every run.
    pub physics_steps: f64,
    /// The largest trace memory held at once, bytes (an upper bound: the largest arm's size).
    pub trace_bytes: f64,
}

impl Cost {
    /// Nothing run.
    pub const NONE: Self = Self { runs: 0, simulated_s: 0.0, physics_steps: 0.0, trace_bytes: 0.0 };

    /// `runs` closed-loop runs of `scenario` (checked), `traced` of them keeping a trace, all
    /// held at once.
    pub fn of_runs(scenario: &Scenario, runs: usize, traced: usize) -> Self {
        let ticks = (scenario.duration_s / scenario.controller.dt_s).ceil();
        Self {
            runs,
            simulated_s: scenario.duration_s * runs as f64,
            physics_steps: ticks * steps_per_tick(scenario) * runs as f64,
            trace_bytes: ticks.min(MAX_TRACE_SAMPLES as f64) * traced as f64 * TRACE_BYTES_PER_TICK,
        }
    }

    /// `runs` runs without a controller of `simulated_s` each, in steps of `step_s` (a plant
    /// stepped open loop, an actuator alone), keeping no trace.
    pub fn open_loop(runs: usize, simulated_s: f64, step_s: f64) -> Self {
        Self {
            runs,
            simulated_s: simulated_s * runs as f64,
            physics_steps: (simulated_s / step_s).ceil() * runs as f64,
            trace_bytes: 0.0,
        }
    }

    /// The cost of `scenarios` (checked) over `seeds` seeds each, on every core of this machine:
    /// every method's first seed keeps its trace.
    pub fn of(scenarios: &[Scenario], seeds: usize) -> Self {
        let traced = |s: &Scenario| if seeds > 0 { s.methods.len() } else { 0 };
        scenarios.iter().map(|s| Self::of_runs(s, s.methods.len() * seeds, traced(s))).sum()
    }

    /// The cost of one method of each of `scenarios` (checked) over `seeds` seeds each, every
    /// run keeping its trace: a batch of rollouts handed back whole (Python's `hya.rollouts`).
    pub fn of_rollouts(scenarios: &[Scenario], seeds: usize) -> Self {
        scenarios.iter().map(|s| Self::of_runs(s, seeds, seeds)).sum()
    }

    /// This, then `next` once this is done: runs, simulated time and steps add, and the traces
    /// held at once are the larger of the two (each part drops its traces when it ends).
    pub fn then(self, next: Self) -> Self {
        Self { trace_bytes: self.trace_bytes.max(next.trace_bytes), ..self + next }
    }

    /// `Ok` within [`MAX_PHYSICS_STEPS`] and [`MAX_TRACE_BYTES`]; the error gives the figure,
    /// the cap, what to shorten and, where the command has one (`lifted_by`), the flag that lifts
    /// the cap.
    pub fn check(&self, shorten: &str, lifted_by: Option<&str>) -> Result<(), SimError> {
        let lift = lifted_by.map(|flag| format!(", or pass {flag} if you mean it")).unwrap_or_default();
        let over = |what: &str, figure: String, cap: String| {
            Err(SimError::Cost(format!("{what} {figure}, beyond the cap of {cap}; {shorten}{lift}")))
        };
        if self.physics_steps > MAX_PHYSICS_STEPS {
            return over(
                "the run would take",
                format!("{} integration steps", Short(self.physics_steps)),
                Short(MAX_PHYSICS_STEPS).to_string(),
            );
        }
        if self.trace_bytes > MAX_TRACE_BYTES {
            return over(
                "the traces would hold",
                format!("{} GiB of memory", Short(self.trace_bytes / (1u64 << 30) as f64)),
                format!("{} GiB", Short(MAX_TRACE_BYTES / (1u64 << 30) as f64)),
            );
        }
        Ok(())
    }
}

/// Both held at once: everything adds, traces included.
impl core::ops::Add for Cost {
    type Output = Self;
    fn add(self, other: Self) -> Self {
        Self {
            runs: self.runs + other.runs,
            simulated_s: self.simulated_s + other.simulated_s,
            physics_steps: self.physics_steps + other.physics_steps,
            trace_bytes: self.trace_bytes + other.trace_bytes,
        }
    }
}

impl core::iter::Sum for Cost {
    fn sum<I: Iterator<Item = Self>>(parts: I) -> Self {
        parts.fold(Self::NONE, |a, b| a + b)
    }
}

/// Plant integration steps per control tick: the sub-steps, each cut into as many equal cycles
/// as the fastest spool needs ([`crate::plant::cycles_for`] on
/// [`crate::plant::hydraulic::spool_pole`]), and on hydraulic actuators one more for each
/// sample instant of their inner torque loops that falls inside a cycle, which the plant splits
/// there ([`crate::plant::Plant::step`]; both clocks start at 0). The stiff cycles that depend
/// on the motion (bristles sliding fast, a valve wide open onto a chamber near zero drop) are
/// not counted.
pub fn steps_per_tick(scenario: &Scenario) -> f64 {
    let substeps = scenario.plant.substeps();
    if scenario.plant.actuator != ActuatorKind::Hydraulic {
        return substeps as f64;
    }
    let hydraulic = &scenario.plant.hydraulic;
    let damping = hydraulic.valve_damping_ratio;
    let spool = hydraulic.valve_natural_frequency_hz.iter().fold(0.0, |fastest: f64, &hz| {
        fastest.max(crate::plant::hydraulic::spool_pole(std::f64::consts::TAU * hz, damping))
    });
    let h = scenario.controller.dt_s / substeps as f64;
    let steps = substeps * crate::plant::cycles_for(h, spool);
    let samples = scenario.controller.dt_s * hydraulic.torque_loop_rate_hz;
    let whole = samples.round();
    if (samples - whole).abs() > 1e-9 * whole || !(1.0..=1e6).contains(&whole) {
        // The instants drift across the ticks: at most every one splits a cycle.
        return steps as f64 + samples.ceil();
    }
    // Sample m of a tick at m/k of it lies on a cycle's boundary where m n / k is whole.
    let (k, n) = (whole as u64, steps as u64);
    steps as f64 + (1..=k).filter(|m| (m * n) % k != 0).count() as f64
}

impl fmt::Display for Cost {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} runs, {} s simulated, {} integration steps, at most {} MiB of traces in memory",
            self.runs,
            Short(self.simulated_s),
            Short(self.physics_steps),
            Short(self.trace_bytes / (1u64 << 20) as f64)
        )
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;

    #[test]
    fn cost_grows_with_duration_substeps_methods_and_seeds_and_is_capped() {
        let mut scenario = Scenario::builtin("goto_internal").unwrap();
        let base = Cost::of(std::slice::from_ref(&scenario), 1);
        let ticks = scenario.duration_s / scenario.controller.dt_s;
        let methods = scenario.methods.len() as f64;
        assert_eq!(base.physics_steps, ticks * steps_per_tick(&scenario) * methods);
        // The inner loops sample at the ticks (1 kHz, 1 ms): no sub-step is split; at 6 kHz
        // over 2 sub-steps, the samples at 1/6, 2/6, 4/6 and 5/6 of a tick split one each (the
        // one at 3/6 falls on the sub-steps' boundary).
        assert_eq!(steps_per_tick(&scenario), 2.0);
        scenario.plant.hydraulic.torque_loop_rate_hz = 6000.0;
        assert_eq!(steps_per_tick(&scenario), 6.0);
        // One sub-step a tick: HyA's spools (ω_v = 2π 255 Hz) cut it into two cycles, the
        // samples at 1/6, 2/6, 4/6 and 5/6 split them as before.
        scenario.plant.substeps = Some(1);
        assert_eq!(steps_per_tick(&scenario), 6.0);
        // Overdamped spools (ζ = 3: the faster pole 5.83 ω_v) cut each of two sub-steps in five.
        scenario.plant.substeps = None;
        scenario.plant.hydraulic.valve_damping_ratio = 3.0;
        assert_eq!(steps_per_tick(&scenario), 10.0 + 4.0);
        scenario.plant.hydraulic.valve_damping_ratio = 0.5;
        scenario.plant.hydraulic.torque_loop_rate_hz = 1000.0;
        assert!(
            Cost::of(std::slice::from_ref(&scenario), 20).check("", None).is_ok(),
            "the default run is within the caps"
        );
        scenario.duration_s = 3600.0;
        scenario.plant.substeps = Some(1000);
        let cost = Cost::of(std::slice::from_ref(&scenario), 20);
        let error = cost.check("shorten it", Some("--no-cost-limit")).unwrap_err().to_string();
        assert!(
            error.contains("integration steps, beyond the cap of 3e9; shorten it, or pass --no-cost-limit"),
            "{error}"
        );
        let error = cost.check("shorten it", None).unwrap_err().to_string();
        assert!(error.ends_with("shorten it"), "a command without the flag does not name it: {error}");
        // Memory depends neither on the seeds nor, beyond the trace's bound, on the duration.
        scenario.plant.substeps = Some(1);
        let ten = Cost::of(std::slice::from_ref(&scenario), 10);
        assert_eq!(ten.trace_bytes, Cost::of(std::slice::from_ref(&scenario), 20).trace_bytes);
        scenario.methods.truncate(1);
        let bounded = MAX_TRACE_SAMPLES as f64 * TRACE_BYTES_PER_TICK;
        assert_eq!(Cost::of(std::slice::from_ref(&scenario), 1).trace_bytes, bounded);
        scenario.duration_s = 20.0;
        let ticks = (scenario.duration_s / scenario.controller.dt_s).ceil();
        assert_eq!(Cost::of(std::slice::from_ref(&scenario), 1).trace_bytes, ticks * TRACE_BYTES_PER_TICK);
    }
}
