//! Chen's observer per gain design and per matching: `Y = β M(q0)` (ours, well conditioned) and
//! the scalar gain of Chen et al. (2000) in Mohammadi's form, each at the three meanings of
//! "equal bandwidth" with the paper's filter (equal pole magnitude, equal −3 dB bandwidth, equal
//! low-frequency delay), with the section V claims that name Chen's observer judged on each row.
//!
//! Each row reruns chen alone on the noise scenarios over the report's first seeds, with its `β`
//! from [`crate::linear::ObserverDesign::matched_to`]; lu's runs are the report's (the same seeds,
//! so every ratio stays paired), and the row of the report's own design at equal pole magnitude
//! is the report's runs, not a rerun. Each claim is judged by its rule in
//! [`crate::analysis::claims::RULES`], unchanged; only the table it reads differs.
//! [`crate::report`] renders what this returns.

use std::collections::BTreeMap;

use serde::Serialize;

use crate::analysis::claims::{judge, Judgement, RULES};
use crate::analysis::seeds::{run_seeds, MetricTable};
use crate::config::cost::Cost;
use crate::config::scenario::{ChenGain, Method, Scenario};
use crate::error::SimError;
use crate::linear::{Matching, ObserverDesign};

/// The noise scenarios of section V the claims read.
pub const SCENARIOS: [&str; 2] = ["estimator_noise_low", "estimator_noise_high"];

/// The claims that name Chen's observer, with the table's short name for each.
pub const CLAIMS: [(&str, &str); 4] = [
    ("chen_noise_sensitive", "chen's error at least doubles with the noise"),
    ("lu_beats_chen_high_noise", "lu more accurate at σ_q̇ = 0.1"),
    ("lu_beats_chen_low_noise", "lu more accurate at σ_q̇ = 0.01"),
    ("chen_cannot_track_low_noise", "chen cannot track at σ_q̇ = 0.01"),
];

/// Seeds per row: the report's first ones, at most this many.
pub const SEEDS: usize = 6;

/// Chen's two gain designs, in the table's order.
pub const DESIGNS: [ChenGain; 2] = [ChenGain::Inertia, ChenGain::Scalar];

/// One design at one matching: its `β`, chen's estimate error per seed, and the claims' verdicts.
#[derive(Debug, Clone, Serialize)]
pub struct DesignRow {
    /// Chen's gain design.
    pub design: ChenGain,
    /// How its `β` was matched to the paper's filter.
    pub matching: Matching,
    /// Chen's `β`, rad/s.
    pub beta_rad_s: f64,
    /// The fastest rate of `L = Y M⁻¹(q0)` at the start pose, rad/s, as the observer's design
    /// gives it (`ObserverDesign::build`): `β` for `Y = β M(q0)`, `β λmax / λmin` of `M(q0)` for
    /// the scalar gain.
    pub fastest_rate_rad_s: f64,
    /// Whether the row is the report's own runs (not a rerun).
    pub as_run: bool,
    /// Per scenario, chen's `rmse_d[seed][joint]`, N·m.
    pub rmse_d: BTreeMap<String, Vec<Vec<f64>>>,
    /// The claims, judged on these runs and lu's.
    pub claims: Vec<Judgement>,
}

/// Every row, in the order design by design, matching by matching.
#[derive(Debug, Clone, Serialize)]
pub struct ChenDesigns {
    /// Seeds per row (the report's first ones).
    pub seeds: usize,
    /// The paper's filter's parameter the matchings refer to, rad/s.
    pub lu_bandwidth_rad_s: f64,
    /// The control period, s: rates beyond `π/T` are not the continuous design's.
    pub period_s: f64,
    /// The rows.
    pub rows: Vec<DesignRow>,
}

/// Chen's `β` matched to the paper's filter at `omega` by `matching`.
fn matched_beta(omega: f64, matching: Matching) -> f64 {
    let lu = ObserverDesign::of(Method::Lu, omega);
    let chen = ObserverDesign::of(Method::Chen, omega);
    match (lu, chen) {
        (Some(lu), Some(chen)) => chen.matched_to(&lu, matching).parameter_rad_s(),
        _ => omega,
    }
}

/// Whether the row of `design` at `matching` is the report's own runs on `bases`, and else the
/// runs it adds: chen alone, at its design and `β` matched to the first base's bandwidth.
fn reruns(bases: &[&Scenario], design: ChenGain, matching: Matching) -> (bool, Vec<Scenario>) {
    let Some(first) = bases.first() else { return (false, Vec::new()) };
    if matching == Matching::PoleMagnitude && bases.iter().all(|s| s.controller.chen_gain == design) {
        return (true, Vec::new());
    }
    let beta = matched_beta(first.controller.observer_bandwidth_rad_s, matching);
    let variants = bases
        .iter()
        .map(|base| {
            let mut s = (*base).clone();
            s.methods = vec![Method::Chen];
            s.controller.chen_gain = design;
            s.controller.observer_bandwidth_rad_s = beta;
            s
        })
        .collect();
    (false, variants)
}

/// What [`run`] costs where the report runs `seeds` seeds of each method (none where the first
/// base scenario does not run chen, whose seeds [`run`] takes).
pub fn cost(scenarios: &[Scenario], seeds: usize) -> Cost {
    let bases = super::hya_scenarios(scenarios, &SCENARIOS);
    let seeds = bases.first().filter(|s| s.methods.contains(&Method::Chen)).map_or(0, |_| seeds.min(SEEDS));
    DESIGNS
        .iter()
        .flat_map(|&design| Matching::ALL.map(|matching| reruns(&bases, design, matching).1))
        .map(|runs| Cost::of(&runs, seeds))
        .fold(Cost::NONE, Cost::then)
}

/// Runs every row on the noise scenarios among `scenarios` (HyA's; `table` holds the report's
/// runs), telling `progress` each run's simulated seconds; `None` where they are not there.
pub fn run<const N: usize>(
    robot: &crate::robot::Robot<N>,
    scenarios: &[Scenario],
    table: &MetricTable,
    progress: &(dyn Fn(f64) + Sync),
) -> Result<Option<ChenDesigns>, SimError> {
    let bases = super::hya_scenarios(scenarios, &SCENARIOS);
    let Some(first) = bases.first() else { return Ok(None) };
    let omega = first.controller.observer_bandwidth_rad_s;
    let q0 = crate::config::settings::Setup::<N>::of(first)?.initial_position;
    // Chen's observer at rest at the start pose, for its rates there (its design's).
    let at_rest = hya_core::Measurement {
        position: q0,
        velocity: Some(hya_core::JointVector::zeros()),
        torque: robot.nominal.gravity(&q0),
    };
    let seeds = table.seeds(&first.name, Method::Chen).min(SEEDS);
    let reported = table.first_seeds(seeds);
    let mut rows = Vec::new();
    for design in DESIGNS {
        for matching in Matching::ALL {
            let beta = matched_beta(omega, matching);
            let (as_run, variants) = reruns(&bases, design, matching);
            let runs = match as_run {
                true => reported.clone(),
                false => reported.clone().overlaid(run_seeds(robot, &variants, seeds, progress)?.1),
            };
            let rmse_d = bases
                .iter()
                .map(|s| (s.name.clone(), runs.values(&s.name, Method::Chen, "rmse_d").unwrap_or_default()))
                .collect();
            let claims = CLAIMS
                .iter()
                .filter_map(|(id, _)| RULES.iter().find(|r| r.id == *id))
                .map(|rule| judge(rule, &runs))
                .collect();
            let design_at = (beta, first.controller.dt_s, design);
            let rates = crate::run::observer_designed(Method::Chen, robot.nominal.as_ref(), design_at, &at_rest)?;
            let fastest_rate_rad_s = rates.map_or(f64::NAN, |(_, rates)| rates.iter().fold(0.0, |a: f64, r| a.max(*r)));
            rows.push(DesignRow { design, matching, beta_rad_s: beta, fastest_rate_rad_s, as_run, rmse_d, claims });
        }
    }
    Ok(Some(ChenDesigns { seeds, lu_bandwidth_rad_s: omega, period_s: first.controller.dt_s, rows }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matched_betas_follow_the_equal_bandwidth_table() {
        // At ω = 50 rad/s: lu's −3 dB bandwidth 32.4 rad/s, its delay 1/50 + 1.6/50 = 52 ms.
        assert_eq!(matched_beta(50.0, Matching::PoleMagnitude), 50.0);
        assert!((matched_beta(50.0, Matching::Bandwidth3Db) - 32.4).abs() < 0.05);
        assert!((matched_beta(50.0, Matching::LowFrequencyDelay) - 1.0 / 0.052).abs() < 1e-9);
    }
}
