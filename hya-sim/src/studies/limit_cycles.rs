//! The runs behind the limit-cycle tables: the paper's estimator on the goto task at bandwidths
//! from 20 to 200 rad/s, and every method on the same task without the friction's Stribeck peak
//! (LuGre at `F_s = F_c`). [`crate::report`] measures the cycles in them and renders the tables.

use crate::analysis::seeds::{run_seeds, MetricTable};
use crate::config::cost::Cost;
use crate::config::scenario::{Method, Scenario};
use crate::error::SimError;

/// The bandwidths swept, rad/s (`ω1 = ω2`, `ζ = 0.8`).
pub const BANDWIDTHS_RAD_S: [f64; 7] = [20.0, 35.0, 50.0, 75.0, 100.0, 150.0, 200.0];

/// Seeds per bandwidth, and of the runs without the peak.
pub const SEEDS: usize = 3;

/// The methods measured, in the table's order.
pub const METHODS: [Method; 6] = [Method::None, Method::Pid, Method::Lu, Method::Chen, Method::Momentum, Method::Eso];

/// The runs, each with the scenarios it ran.
#[derive(Debug, Clone)]
pub struct LimitCycleRuns {
    /// The goto task at each of [`BANDWIDTHS_RAD_S`], the paper's estimator alone.
    pub bandwidths: Vec<Scenario>,
    /// Their metrics.
    pub by_bandwidth: MetricTable,
    /// The goto task without the Stribeck peak, every method of [`METHODS`].
    pub no_peak: Scenario,
    /// Its metrics.
    pub without_peak: MetricTable,
}

/// The goto task `base` at every bandwidth, and without the Stribeck peak.
fn scenarios(base: &Scenario) -> (Vec<Scenario>, Scenario) {
    let bandwidths = BANDWIDTHS_RAD_S
        .iter()
        .map(|w| base.variant(&format!("w{w}"), Method::Lu, |s| s.controller.observer_bandwidth_rad_s = *w))
        .collect();
    // The same loops without the Stribeck peak: LuGre at F_s = F_c.
    let mut no_peak = base.clone();
    no_peak.name = format!("{}_no_peak", base.name);
    no_peak.plant.static_nm = no_peak.plant.coulomb_nm.clone();
    no_peak.methods = METHODS.to_vec();
    (bandwidths, no_peak)
}

/// What [`run`] costs on `base`.
pub fn cost(base: &Scenario) -> Cost {
    let (bandwidths, no_peak) = scenarios(base);
    Cost::of(&bandwidths, SEEDS).then(Cost::of(std::slice::from_ref(&no_peak), SEEDS))
}

/// Runs both on `base` (the goto task), telling `progress` each run's simulated seconds.
pub fn run<const N: usize>(
    robot: &crate::robot::Robot<N>,
    base: &Scenario,
    progress: &(dyn Fn(f64) + Sync),
) -> Result<LimitCycleRuns, SimError> {
    let (bandwidths, no_peak) = scenarios(base);
    let (_, by_bandwidth) = run_seeds(robot, &bandwidths, SEEDS, progress)?;
    let (_, without_peak) = run_seeds(robot, std::slice::from_ref(&no_peak), SEEDS, progress)?;
    Ok(LimitCycleRuns { bandwidths, by_bandwidth, no_peak, without_peak })
}
