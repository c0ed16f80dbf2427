//! `summary.json`: per scenario and method, per-joint means over the seeds with their 95 %
//! intervals, and the claims' verdicts.

use serde::Serialize;

use crate::analysis::claims::Judgement;
use crate::analysis::seeds::{per_joint_mean_ci95, MetricTable};
use crate::config::scenario::Method;

/// One scenario and method's line in `summary.json`: per-joint means over the seeds, each with
/// the half-width of its 95 % interval (`…_ci95`).
#[derive(Debug, Clone, Serialize)]
pub struct RunSummary {
    /// Scenario name.
    pub scenario: String,
    /// Method name.
    pub method: &'static str,
    /// How many seeds.
    pub seeds: usize,
    /// Tracking RMSE per joint, rad.
    pub rmse_q: Vec<f64>,
    /// Its 95 % half-width.
    pub rmse_q_ci95: Vec<f64>,
    /// Estimate RMSE per joint, N·m; `null` without an estimator.
    pub rmse_d: Option<Vec<f64>>,
    /// Its 95 % half-width.
    pub rmse_d_ci95: Option<Vec<f64>>,
    /// Command-torque noise per joint, N·m.
    pub tau_cmd_noise: Vec<f64>,
    /// Its 95 % half-width.
    pub tau_cmd_noise_ci95: Vec<f64>,
    /// Largest tracking error per joint, rad.
    pub max_abs_error_q: Vec<f64>,
    /// Its 95 % half-width.
    pub max_abs_error_q_ci95: Vec<f64>,
    /// Mean |e| over the final 5 s, rad.
    pub steady_error_q: Vec<f64>,
    /// Its 95 % half-width.
    pub steady_error_q_ci95: Vec<f64>,
    /// Peak-to-peak error over the final 5 s, rad.
    pub limit_cycle_q: Vec<f64>,
    /// Its 95 % half-width.
    pub limit_cycle_q_ci95: Vec<f64>,
    /// The observer's rates at the start pose from its design, 1/s; absent without an observer.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bandwidth_rad_s: Option<Vec<f64>>,
    /// Every metric of every seed, `[seed][joint]`, seeds in order from the scenario's: the
    /// numbers every mean, interval and verdict above is computed from.
    pub per_seed: std::collections::BTreeMap<&'static str, Vec<Vec<f64>>>,
}

/// `summary.json`.
#[derive(Debug, Clone, Serialize)]
pub struct Summary {
    /// The robot.
    pub robot: String,
    /// Whether scenarios were shortened (`--quick`).
    pub quick: bool,
    /// Seeds per scenario and method.
    pub seeds: usize,
    /// Every scenario and method.
    pub runs: Vec<RunSummary>,
    /// The paper's claims, judged over the seeds.
    pub claims: Vec<Judgement>,
    /// What produced the report.
    pub provenance: super::Provenance,
    /// The bandwidth sweep behind the report's Pareto fronts, every seed's point (the format of
    /// `hya sweep`'s `sweep.json`); absent where the report ran none.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sweep: Option<serde_json::Value>,
    /// The headline comparisons under other modelling choices, every seed's RMSE; absent where
    /// the report ran none.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sensitivity: Option<crate::studies::sensitivity::Sensitivity>,
    /// The claims that name Chen's observer per gain design and matching, every seed's estimate
    /// error; absent where the report ran none.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub chen_designs: Option<crate::studies::chen_designs::ChenDesigns>,
    /// The hydraulic actuators' measured torque frequency responses and the fitted models;
    /// absent where the report measured none.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub torque_responses: Option<crate::torque_response::TorqueResponses>,
}

pub(super) fn mean(values: &[f64]) -> f64 {
    values.iter().sum::<f64>() / values.len().max(1) as f64
}

/// The mean and 95 % half-width over seeds of `metric` for one scenario and method.
pub(super) fn aggregate(
    table: &MetricTable,
    scenario: &str,
    method: Method,
    metric: &str,
) -> Option<(Vec<f64>, Vec<f64>)> {
    table.values(scenario, method, metric).filter(|v| !v.is_empty()).map(|v| per_joint_mean_ci95(&v))
}

pub(super) fn run_summary(
    table: &MetricTable,
    scenario: &str,
    method: Method,
    bandwidth: Option<Vec<f64>>,
) -> RunSummary {
    let get = |metric: &str| aggregate(table, scenario, method, metric).unwrap_or_default();
    let (rmse_q, rmse_q_ci95) = get("rmse_q");
    let rmse_d = aggregate(table, scenario, method, "rmse_d");
    let (tau_cmd_noise, tau_cmd_noise_ci95) = get("tau_cmd_noise");
    let (max_abs_error_q, max_abs_error_q_ci95) = get("max_abs_error_q");
    let (steady_error_q, steady_error_q_ci95) = get("steady_error_q");
    let (limit_cycle_q, limit_cycle_q_ci95) = get("limit_cycle_q");
    RunSummary {
        scenario: scenario.to_owned(),
        method: method.name(),
        seeds: table.seeds(scenario, method),
        rmse_q,
        rmse_q_ci95,
        rmse_d_ci95: rmse_d.as_ref().map(|(_, ci)| ci.clone()),
        rmse_d: rmse_d.map(|(m, _)| m),
        tau_cmd_noise,
        tau_cmd_noise_ci95,
        max_abs_error_q,
        max_abs_error_q_ci95,
        steady_error_q,
        steady_error_q_ci95,
        limit_cycle_q,
        limit_cycle_q_ci95,
        bandwidth_rad_s: bandwidth,
        per_seed: table.per_seed(scenario, method),
    }
}
