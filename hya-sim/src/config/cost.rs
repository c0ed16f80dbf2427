//! What a run will cost, known before it starts: the integration steps it takes and the trace
//! memory it holds, checked against documented caps so that an absurd setting is refused with
//! its figure instead of running for weeks or until memory runs out.
//!
//! Metrics are accumulated tick by tick; only the first seed's runs keep a trace (time, `q`,
//! `q_des`, `d`, `d̂`, `τ_cmd`), for the figures and CSV files, of at most
//! [`MAX_TRACE_SAMPLES`] ticks each (a longer run keeps every k-th tick). So memory grows with
//! the number of scenarios and methods, not with the duration or the number of seeds.

use std::fmt;

use hya_core::Short;

use crate::config::scenario::Scenario;
use crate::error::SimError;
use crate::run::trace::{bytes_per_sample, MAX_TRACE_SAMPLES};
use hya_core::dispatch::MAX_JOINTS;

/// The most plant integration steps (control ticks × sub-steps, summed over every run) a
/// command runs without `--no-cost-limit`: 47 times the default `hya reproduce` (6.4e7 steps,
/// about 2.5 minutes on 2 cores), so about two hours.
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
    /// The cost of `scenarios` (checked) over `seeds` seeds each, on every core of this machine.
    pub fn of(scenarios: &[Scenario], seeds: usize) -> Self {
        let ticks = |s: &Scenario| (s.duration_s / s.controller.dt_s).ceil();
        let kept: f64 = scenarios.iter().map(|s| ticks(s).min(MAX_TRACE_SAMPLES as f64) * s.methods.len() as f64).sum();
        let runs: usize = scenarios.iter().map(|s| s.methods.len() * seeds).sum();
        Self {
            runs,
            simulated_s: scenarios.iter().map(|s| s.duration_s * (s.methods.len() * seeds) as f64).sum(),
            physics_steps: scenarios
                .iter()
                .map(|s| ticks(s) * s.plant.substeps() as f64 * (s.methods.len() * seeds) as f64)
                .sum(),
            trace_bytes: kept * TRACE_BYTES_PER_TICK,
        }
    }

    /// The cost of one method of each of `scenarios` (checked) over `seeds` seeds each, every
    /// run keeping its trace: a batch of rollouts handed back whole (Python's `hya.rollouts`).
    pub fn of_rollouts(scenarios: &[Scenario], seeds: usize) -> Self {
        let ticks = |s: &Scenario| (s.duration_s / s.controller.dt_s).ceil();
        let each = |f: &dyn Fn(&Scenario) -> f64| scenarios.iter().map(f).sum::<f64>() * seeds as f64;
        Self {
            runs: scenarios.len() * seeds,
            simulated_s: each(&|s| s.duration_s),
            physics_steps: each(&|s| ticks(s) * s.plant.substeps() as f64),
            trace_bytes: each(&|s| ticks(s).min(MAX_TRACE_SAMPLES as f64)) * TRACE_BYTES_PER_TICK,
        }
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
        assert_eq!(base.physics_steps, ticks * scenario.plant.substeps() as f64 * methods);
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
