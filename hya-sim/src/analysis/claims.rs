//! The paper's claims as data: each a rule on the metrics over seeds, fixed here before any run,
//! with a threshold and a margin. A claim's verdict is an output of the report; no test asserts
//! one (tests check that the rules evaluate correctly on tables built to pass or fail them).
//!
//! A rule's value is computed per seed and joint (a metric, the ratio of two metrics of the same
//! seed, or whether a metric is within a limit). A metric's centre is its mean over seeds with
//! Student's t 95 % interval; a ratio's is its geometric mean, the interval taken on the
//! logarithms (`exp(m̄ ± t s/√n)` of `m = ln ratio`): ratios of noisy positive figures are
//! skewed and heavy-tailed, their logarithms much less so, and the interval then never reaches
//! below zero. Ratios are paired: both runs of a seed share its plant, noise and model error. A
//! share of seeds (for a metric that is censored or bimodal, such as a recovery time that is the
//! window's length where a joint never recovers) has Wilson's 95 % score interval.
//!
//! At a joint the rule's bound is the threshold moved by the margin toward the claim's side
//! (`threshold − margin` below, `threshold + margin` above). The rule **holds** there when the
//! whole interval lies on the claim's side of the bound, **fails** when the whole interval lies
//! on the other, and is **inconclusive** when the interval straddles it: more seeds could settle
//! it. The claim is reproduced when it holds on every joint it names (or on the number it needs)
//! and every joint it needs quiet stays on the other side; inconclusive when it could still be,
//! were the inconclusive joints to hold; partly when it holds on some joints and cannot be
//! reproduced; not reproduced when it holds on none and cannot be. A claim that rests on a
//! fact of the real robot the simulation does not have is "not testable here", with the reason;
//! its figures are still shown.

use serde::Serialize;

use crate::analysis::metrics::CYCLE_AMPLITUDE_RAD;
use crate::analysis::seeds::{mean_ci95, MetricTable};
use crate::config::scenario::Method;

/// One metric of one method's runs of one scenario.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Source {
    /// The scenario.
    pub scenario: &'static str,
    /// The method.
    pub method: Method,
    /// The metric's name (see [`crate::analysis::metrics::Metrics::named`]).
    pub metric: &'static str,
}

/// What a rule measures, per seed and joint.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Quantity {
    /// The metric itself.
    Metric(Source),
    /// The first over the second, seed by seed.
    Ratio(Source, Source),
    /// Whether the metric is on that side of the limit, seed by seed (1 or 0): the share of
    /// seeds.
    Share(Source, Side, f64),
}

/// Which side of the threshold the claim needs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    /// Below the threshold.
    Below,
    /// Above it.
    Above,
}

/// On how many of the named joints the rule must hold.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Need {
    /// Every one.
    All,
    /// At least this many.
    AtLeast(usize),
}

/// A claim of the paper and the rule that judges it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rule {
    /// Short identifier.
    pub id: &'static str,
    /// The claim, in the paper's sense.
    pub statement: &'static str,
    /// The paper's section.
    pub section: &'static str,
    /// What the paper shows for it.
    pub paper: &'static str,
    /// What is measured.
    pub quantity: Quantity,
    /// The joints it is judged on (0-based).
    pub joints: &'static [usize],
    /// The side of the threshold the claim needs.
    pub side: Side,
    /// The threshold.
    pub threshold: f64,
    /// The margin the 95 % interval must clear the threshold by.
    pub margin: f64,
    /// On how many joints it must hold.
    pub need: Need,
    /// Joints that must stay on the other side of the threshold (by the margin) for the claim to
    /// hold: a claim about some joints that says the others do not do the same.
    pub quiet: &'static [usize],
    /// Why the simulation cannot test the claim, where it cannot.
    pub untestable: Option<&'static str>,
}

/// A rule's verdict.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Verdict {
    /// It holds wherever the claim needs it.
    #[serde(rename = "reproduced")]
    Reproduced,
    /// A claim about every joint it names holds on some of them and fails on others.
    #[serde(rename = "partly")]
    Partly,
    /// It could hold as the claim needs, but joints whose interval straddles the bound leave it
    /// open: more seeds could settle it.
    #[serde(rename = "inconclusive")]
    Inconclusive,
    /// It holds on none.
    #[serde(rename = "not reproduced")]
    NotReproduced,
    /// A run it needs is missing.
    #[serde(rename = "not run")]
    NotRun,
    /// It rests on a fact of the real robot that the simulation does not have.
    #[serde(rename = "not testable here")]
    NotTestable,
}

impl Verdict {
    /// The verdict as `summary.json` and the report write it.
    pub fn name(self) -> &'static str {
        match self {
            Verdict::Reproduced => "reproduced",
            Verdict::Partly => "partly",
            Verdict::Inconclusive => "inconclusive",
            Verdict::NotReproduced => "not reproduced",
            Verdict::NotRun => "not run",
            Verdict::NotTestable => "not testable here",
        }
    }
}

/// The figures behind a verdict at one joint.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct JointFigure {
    /// The joint, from 1.
    pub joint: usize,
    /// Mean over seeds (a geometric mean for a ratio, the share for a share of seeds).
    pub mean: f64,
    /// Lower end of its 95 % interval.
    pub low: f64,
    /// Upper end of its 95 % interval.
    pub high: f64,
    /// Whether the rule holds there (for a joint that must stay quiet: whether it does).
    pub holds: bool,
    /// Whether the interval straddles the rule's bound (neither holds nor fails).
    pub inconclusive: bool,
    /// Whether this joint is one that must stay quiet.
    pub quiet: bool,
}

/// A judged claim, as `summary.json` holds it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Judgement {
    /// The rule's identifier.
    pub id: &'static str,
    /// The claim.
    pub statement: &'static str,
    /// The paper's section.
    pub section: &'static str,
    /// The verdict.
    pub verdict: Verdict,
    /// Per judged joint: mean, interval, whether it holds.
    pub numbers: Vec<JointFigure>,
    /// Seeds the figures rest on.
    pub seeds: usize,
    /// Why the claim is not testable here, where it is not.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub untestable: Option<&'static str>,
}

const ALL: &[usize] = &[0, 1, 2, 3, 4, 5];

/// Where a joint stands against a rule's bound.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Standing {
    Holds,
    Fails,
    Inconclusive,
}

/// Where the interval `low..high` stands against `bound` for a claim that needs the value below
/// it (`below`) or above it.
fn standing(low: f64, high: f64, bound: f64, below: bool) -> Standing {
    let (clear, crossed) = if below { (high < bound, low >= bound) } else { (low > bound, high <= bound) };
    match (clear, crossed) {
        (true, _) => Standing::Holds,
        (_, true) => Standing::Fails,
        _ => Standing::Inconclusive,
    }
}

const fn source(scenario: &'static str, method: Method, metric: &'static str) -> Source {
    Source { scenario, method, metric }
}

const fn compensation_lowers_rmse(id: &'static str, scenario: &'static str, section: &'static str) -> Rule {
    Rule {
        id,
        statement: "compensation lowers the tracking RMSE on every joint (RMSE(lu) / RMSE(none) below 0.9)",
        section,
        paper: "lower RMSE on all six joints",
        quantity: Quantity::Ratio(source(scenario, Method::Lu, "rmse_q"), source(scenario, Method::None, "rmse_q")),
        joints: ALL,
        side: Side::Below,
        threshold: 1.0,
        margin: 0.1,
        need: Need::All,
        quiet: &[],
        untestable: None,
    }
}

const fn weight_kept_near(id: &'static str, scenario: &'static str, section: &'static str) -> Rule {
    Rule {
        id,
        statement: "with the weight on, compensation keeps joints 2 and 4 nearer their reference (mean |e| of lu / none below 0.9)",
        section,
        paper: "joints 2 and 4 recover and keep tracking; without compensation they drop",
        quantity: Quantity::Ratio(
            source(scenario, Method::Lu, "weight_error_q"),
            source(scenario, Method::None, "weight_error_q"),
        ),
        joints: &[1, 3],
        side: Side::Below,
        threshold: 1.0,
        margin: 0.1,
        need: Need::All,
        quiet: &[],
        untestable: None,
    }
}

/// The paper's estimate more accurate than Chen's on `scenario`: RMSE(d̂ − d) of lu over chen's
/// below 0.9 on every joint.
const fn lu_beats_chen(id: &'static str, scenario: &'static str, statement: &'static str, paper: &'static str) -> Rule {
    Rule {
        id,
        statement,
        section: "V",
        paper,
        quantity: Quantity::Ratio(source(scenario, Method::Lu, "rmse_d"), source(scenario, Method::Chen, "rmse_d")),
        joints: ALL,
        side: Side::Below,
        threshold: 1.0,
        margin: 0.1,
        need: Need::All,
        quiet: &[],
        untestable: None,
    }
}

/// Every claim the report judges.
pub const RULES: &[Rule] = &[
    compensation_lowers_rmse("goto_internal_rmse", "goto_internal", "VI-A"),
    compensation_lowers_rmse("sine_internal_rmse", "sine_internal", "VI-B"),
    compensation_lowers_rmse("goto_weight_rmse", "goto_weight", "VI-C"),
    compensation_lowers_rmse("sine_weight_rmse", "sine_weight", "VI-D"),
    weight_kept_near("goto_weight_joints_2_4", "goto_weight", "VI-C"),
    weight_kept_near("sine_weight_joints_2_4", "sine_weight", "VI-D"),
    Rule {
        id: "goto_weight_recovery",
        statement: "after the drop, the compensated joints 2 and 4 recover within 1 s in most seeds (|e| back within twice its pre-drop level, and at least 1 mrad, for 0.5 s; the share of seeds, whose interval must lie above one half: a joint that never recovers has no time to average)",
        section: "VI-C",
        paper: "the joints deviate, then quickly recover",
        quantity: Quantity::Share(source("goto_weight", Method::Lu, "drop_recovery_s"), Side::Below, 1.0),
        joints: &[1, 3],
        side: Side::Above,
        threshold: 0.5,
        margin: 0.0,
        need: Need::All,
        quiet: &[],
        untestable: None,
    },
    Rule {
        id: "lu_noise_insensitive",
        statement: "the paper's estimate is hardly affected by velocity-sensor noise (RMSE(d̂ − d) grows by less than 25 % from σ_q̇ = 0.01 to 0.1 rad/s); lu reads no velocity, so the noise reaches it only through the closed loop, whose controller reads the sensor",
        section: "V",
        paper: "robust to noise; the estimate is accurate despite the higher noise",
        quantity: Quantity::Ratio(
            source("estimator_noise_high", Method::Lu, "rmse_d"),
            source("estimator_noise_low", Method::Lu, "rmse_d"),
        ),
        joints: ALL,
        side: Side::Below,
        threshold: 1.25,
        margin: 0.0,
        need: Need::All,
        quiet: &[],
        untestable: None,
    },
    Rule {
        id: "chen_noise_sensitive",
        statement: "Chen's observer is sensitive to velocity noise (RMSE(d̂ − d) at least doubles from σ_q̇ = 0.01 to 0.1 rad/s)",
        section: "V",
        paper: "sensitive to noise",
        quantity: Quantity::Ratio(
            source("estimator_noise_high", Method::Chen, "rmse_d"),
            source("estimator_noise_low", Method::Chen, "rmse_d"),
        ),
        joints: ALL,
        side: Side::Above,
        threshold: 2.0,
        margin: 0.0,
        need: Need::All,
        quiet: &[],
        untestable: None,
    },
    lu_beats_chen(
        "lu_beats_chen_high_noise",
        "estimator_noise_high",
        "under high velocity noise the paper's estimate is more accurate than Chen's (RMSE ratio lu / chen below 0.9)",
        "more accurate under noise",
    ),
    lu_beats_chen(
        "lu_beats_chen_low_noise",
        "estimator_noise_low",
        "at σ_q̇ = 0.01 rad/s the paper's estimate is more accurate than Chen's (RMSE ratio lu / chen below 0.9); the observers run at equal pole magnitude, where Chen's lags less (20 ms against 52 ms)",
        "accurate estimates, where several of Chen's cannot track",
    ),
    Rule {
        id: "chen_cannot_track_low_noise",
        statement: "at σ_q̇ = 0.01 rad/s Chen's estimate cannot track the disturbance on several joints (RMSE(d̂ − d) above half the disturbance's RMS on at least two joints)",
        section: "V",
        paper: "several estimates can not track the real disturbances",
        quantity: Quantity::Metric(source("estimator_noise_low", Method::Chen, "relative_rmse_d")),
        joints: ALL,
        side: Side::Above,
        threshold: 0.5,
        margin: 0.0,
        need: Need::AtLeast(2),
        quiet: &[],
        untestable: None,
    },
    Rule {
        id: "disturbance_changes_after_setpoint",
        statement: "the estimated disturbance changes after the setpoint is reached: |Δ mean d̂| above a tenth of the joint's nominal Coulomb friction F_c on at least two joints; the figures are |Δ mean d̂| / F_c (the paper reads this as static friction varying with position; here the model error's change with pose and where a joint sticks can contribute too)",
        section: "VI-A",
        paper: "the internal disturbances change significantly after the setpoint",
        quantity: Quantity::Metric(source("goto_internal", Method::Lu, "estimate_shift_over_coulomb")),
        joints: ALL,
        side: Side::Above,
        threshold: 0.1,
        margin: 0.0,
        need: Need::AtLeast(2),
        quiet: &[],
        untestable: None,
    },
    Rule {
        id: "none_misses_reference",
        statement: "without compensation no joint reaches its reference (steady error above 2 mrad = 0.002 rad on every joint)",
        section: "VI-A",
        paper: "none of the joints reached the desired reference",
        quantity: Quantity::Metric(source("goto_internal", Method::None, "steady_error_q")),
        joints: ALL,
        side: Side::Above,
        threshold: 2e-3,
        margin: 0.0,
        need: Need::All,
        quiet: &[],
        untestable: None,
    },
    Rule {
        id: "weight_helps_uncompensated_joint_2",
        statement: "with the weight on, the uncompensated joint 2 tracks better than before the drop (internal and external disturbances cancel; mean |e| with the weight over mean |e| before the drop below 1). The weight, 2 kg at the end effector, is this study's choice, not the paper's: its torque on joint 2 can outweigh the joint's own bias, whose sign the seeded model error and friction set",
        section: "VI-C",
        paper: "joint 2 tracks better after the weight is dropped",
        quantity: Quantity::Ratio(
            source("goto_weight", Method::None, "weight_error_q"),
            source("goto_weight", Method::None, "pre_drop_error_q"),
        ),
        joints: &[1],
        side: Side::Below,
        threshold: 1.0,
        margin: 0.0,
        need: Need::All,
        quiet: &[],
        untestable: None,
    },
    Rule {
        id: "friction_opposes_motion",
        statement: "the estimated disturbance opposes the joint velocity (correlation of d̂ with q̇ below −0.3 on every joint)",
        section: "VI-B",
        paper: "all the disturbances show opposite direction to the joint motion",
        quantity: Quantity::Metric(source("sine_internal", Method::Lu, "estimate_velocity_correlation")),
        joints: ALL,
        side: Side::Below,
        threshold: -0.3,
        margin: 0.0,
        need: Need::All,
        quiet: &[],
        untestable: None,
    },
    Rule {
        id: "friction_has_a_bias",
        statement: "the estimated disturbance has a non-zero mean over the sine task: |mean d̂| above a tenth of the joint's nominal Coulomb friction F_c on at least four joints; the figures are |mean d̂| / F_c. The paper reads the mean as static friction; but friction is odd in the velocity and averages to about zero over whole periods of a symmetric sine (this task's window after the warm-up need not hold whole periods, so friction leaves some mean too): a mean can come from friction over a part period, the model's error in gravity and inertia and the torque sensors' offsets (not measured apart here)",
        section: "VI-B",
        paper: "the mean of the disturbance is not zero (read as static friction)",
        quantity: Quantity::Metric(source("sine_internal", Method::Lu, "estimate_mean_over_coulomb")),
        joints: ALL,
        side: Side::Above,
        threshold: 0.1,
        margin: 0.0,
        need: Need::AtLeast(4),
        quiet: &[],
        untestable: None,
    },
    Rule {
        id: "oscillations_joints_3_5_6",
        statement: "joints 3, 5 and 6 keep slight oscillations with compensation, and the others do not: in most seeds (the share's interval above one half) the error's largest spectral line reaches 0.25 mrad (a sine of 0.5 mrad peak to peak) on joints 3, 5 and 6, and in few (below one half) on joints 1, 2 and 4; the line is taken over the last 10 s once the task is quiet (less in quick mode: the limit-cycle section gives the window), after the straight-line trend (creep) is removed, so drift does not count, though a line in the lowest bin may be drift that is not straight",
        section: "VI-A",
        paper: "slight oscillations in joints 3, 5 and 6",
        quantity: Quantity::Share(source("goto_internal", Method::Lu, "cycle_amplitude_q"), Side::Above, CYCLE_AMPLITUDE_RAD),
        joints: &[2, 4, 5],
        side: Side::Above,
        threshold: 0.5,
        margin: 0.0,
        need: Need::All,
        quiet: &[0, 1, 3],
        untestable: None,
    },
];

/// The per-seed, per-joint values of `quantity`, or `None` where a run is missing.
fn values(quantity: &Quantity, table: &MetricTable) -> Option<Vec<Vec<f64>>> {
    let get = |s: &Source| table.values(s.scenario, s.method, s.metric);
    match quantity {
        Quantity::Metric(s) => get(s),
        Quantity::Ratio(a, b) => {
            let (a, b) = (get(a)?, get(b)?);
            Some(a.iter().zip(&b).map(|(x, y)| x.iter().zip(y).map(|(p, q)| p / q).collect()).collect())
        }
        Quantity::Share(s, side, limit) => {
            let on_side = |x: f64| match side {
                Side::Below => x < *limit,
                Side::Above => x >= *limit,
            };
            Some(get(s)?.iter().map(|v| v.iter().map(|&x| f64::from(u8::from(on_side(x)))).collect()).collect())
        }
    }
}

/// Wilson's 95 % score interval of a share `p` of `n` trials: `(p + z²/2n ± z √(p(1 − p)/n +
/// z²/4n²)) / (1 + z²/n)`, which stays within 0 and 1 and is not empty at a share of 0 or 1.
pub fn wilson_ci95(p: f64, n: usize) -> (f64, f64) {
    const Z: f64 = 1.959_963_984_540_054;
    if n == 0 {
        return (0.0, 1.0);
    }
    let n = n as f64;
    let z2 = Z * Z;
    let centre = (p + z2 / (2.0 * n)) / (1.0 + z2 / n);
    let half = Z * (p * (1.0 - p) / n + z2 / (4.0 * n * n)).sqrt() / (1.0 + z2 / n);
    ((centre - half).max(0.0), (centre + half).min(1.0))
}

/// The centre of `samples` of `quantity` and its 95 % interval `(low, high)`: the mean with
/// Student's t for a metric, the geometric mean with the interval on the logarithms for a ratio,
/// the share with Wilson's interval for a share of seeds.
fn interval(samples: &[f64], quantity: &Quantity) -> (f64, f64, f64) {
    match quantity {
        Quantity::Ratio(..) => {
            let logs: Vec<f64> = samples.iter().map(|x| x.ln()).collect();
            let (mean, half) = mean_ci95(&logs);
            (mean.exp(), (mean - half).exp(), (mean + half).exp())
        }
        Quantity::Metric(..) => {
            let (mean, half) = mean_ci95(samples);
            (mean, mean - half, mean + half)
        }
        Quantity::Share(..) => {
            let share = samples.iter().sum::<f64>() / samples.len().max(1) as f64;
            let (low, high) = wilson_ci95(share, samples.len());
            (share, low, high)
        }
    }
}

/// Judges `rule` on `table`.
pub fn judge(rule: &Rule, table: &MetricTable) -> Judgement {
    let mut judgement = Judgement {
        id: rule.id,
        statement: rule.statement,
        section: rule.section,
        verdict: Verdict::NotRun,
        numbers: Vec::new(),
        seeds: 0,
        untestable: rule.untestable,
    };
    let Some(per_seed) = values(&rule.quantity, table).filter(|v| !v.is_empty()) else { return judgement };
    judgement.seeds = per_seed.len();
    let named = rule.joints.iter().map(|&j| (j, false));
    let mut standings = Vec::new();
    for (j, quiet) in named.chain(rule.quiet.iter().map(|&j| (j, true))) {
        let samples: Vec<f64> = per_seed.iter().filter_map(|v| v.get(j).copied()).collect();
        let (mean, low, high) = interval(&samples, &rule.quantity);
        // A quiet joint must stay on the other side of the threshold, by the margin.
        let below = (rule.side == Side::Below) != quiet;
        let bound = if below { rule.threshold - rule.margin } else { rule.threshold + rule.margin };
        let standing = standing(low, high, bound, below);
        standings.push((standing, quiet));
        let (holds, inconclusive) = (standing == Standing::Holds, standing == Standing::Inconclusive);
        judgement.numbers.push(JointFigure { joint: j + 1, mean, low, high, holds, inconclusive, quiet });
    }
    let count = |wanted: Standing, quiet: bool| standings.iter().filter(|&&s| s == (wanted, quiet)).count();
    let (holding, open) = (count(Standing::Holds, false), count(Standing::Inconclusive, false));
    let (quiet_crossed, quiet_open) = (count(Standing::Fails, true), count(Standing::Inconclusive, true));
    let needed = match rule.need {
        Need::All => rule.joints.len(),
        Need::AtLeast(k) => k,
    };
    judgement.verdict = match holding {
        _ if rule.untestable.is_some() => Verdict::NotTestable,
        h if h >= needed && quiet_crossed + quiet_open == 0 => Verdict::Reproduced,
        h if h + open >= needed && quiet_crossed == 0 => Verdict::Inconclusive,
        // "Partly" for a claim about every joint it names; one that needs only some of them and
        // cannot reach that many is not reproduced, whatever it holds on.
        h if h > 0 && rule.need == Need::All => Verdict::Partly,
        _ => Verdict::NotReproduced,
    };
    judgement
}

/// Every rule of [`RULES`] judged on `table`.
pub fn judge_all(table: &MetricTable) -> Vec<Judgement> {
    RULES.iter().map(|r| judge(r, table)).collect()
}
