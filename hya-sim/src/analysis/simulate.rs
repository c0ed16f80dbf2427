//! A finished run: its metrics and what was kept of its trace.

use crate::analysis::metrics::Metrics;
use crate::config::scenario::{Method, Scenario};
use crate::config::settings::Setup;
use crate::error::SimError;
use crate::robot::Robot;
use crate::run::trace::{Recording, Trace};
use crate::run::RunSetup;

/// A finished run.
#[derive(Debug, Clone)]
pub struct RunOutcome<const N: usize> {
    /// The scenario's name.
    pub scenario: String,
    /// The method.
    pub method: Method,
    /// The seed of the plant's perturbation, friction profile and noise.
    pub seed: u64,
    /// The observer's rates at the start pose, 1/s, from its design (ascending eigenvalues of
    /// `L` for Chen's observer); `None` without an observer.
    pub bandwidth_rad_s: Option<Vec<f64>>,
    /// Its time series, as far as they were kept ([`Recording`]).
    pub trace: Trace<N>,
    /// Its metrics.
    pub metrics: Metrics,
}

/// Runs `scenario` with `method` on `robot` from its seed ([`crate::run::closed_loop`]), its trace bounded
/// ([`Recording::Bounded`]).
pub fn simulate<const N: usize>(
    scenario: &Scenario,
    method: Method,
    robot: &Robot<N>,
) -> Result<RunOutcome<N>, SimError> {
    simulate_recording(scenario, method, robot, Recording::Bounded)
}

/// [`simulate`], keeping its trace as `recording` says.
pub fn simulate_recording<const N: usize>(
    scenario: &Scenario,
    method: Method,
    robot: &Robot<N>,
    recording: Recording,
) -> Result<RunOutcome<N>, SimError> {
    let run = crate::run::closed_loop(Setup::for_run(scenario, method, &robot.model)?, method, robot, recording)?;
    Ok(RunOutcome::of(&scenario.name, method, scenario.seed, run))
}

/// The loop of `scenario` under `method` on `robot`, set up once for its seeds: its settings
/// checked for the run ([`Setup::for_run`]), then [`RunSetup::new`].
pub fn run_setup<'a, const N: usize>(
    scenario: &Scenario,
    method: Method,
    robot: &'a Robot<N>,
) -> Result<RunSetup<'a, N>, SimError> {
    RunSetup::new(Setup::for_run(scenario, method, &robot.model)?, method, robot)
}

impl<const N: usize> RunOutcome<N> {
    /// The outcome of `run`, a run of the scenario named `scenario` with `method` from `seed`.
    pub fn of(scenario: &str, method: Method, seed: u64, run: crate::run::ClosedLoop<N>) -> Self {
        Self {
            scenario: scenario.to_owned(),
            method,
            seed,
            bandwidth_rad_s: run.bandwidth_rad_s,
            trace: run.trace,
            metrics: run.metrics,
        }
    }
}
