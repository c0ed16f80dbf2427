//! The section V claims that name Chen's observer, judged again per gain design and per
//! matching: Chen's observer with `Y = β M(q0)` (ours, well conditioned) and with the scalar gain
//! of Chen et al. (2000) in Mohammadi's form, each at the three meanings of "equal bandwidth" with
//! the paper's filter (equal pole magnitude, equal −3 dB bandwidth, equal low-frequency delay).
//!
//! Each row reruns chen alone on the noise scenarios over the report's first seeds, with its `β`
//! from [`crate::linear::ObserverDesign::matched_to`]; lu's runs are the report's (the same seeds,
//! so every ratio stays paired), and the row of the report's own design at equal pole magnitude
//! is the report's runs, not a rerun. Each claim is judged by its rule in
//! [`crate::analysis::claims::RULES`], unchanged; only the table it reads differs.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use serde::Serialize;

use crate::analysis::claims::{judge, Judgement, Verdict, RULES};
use crate::analysis::seeds::{run_seeds, MetricTable};
use crate::config::scenario::{ChenGain, Method, Scenario};
use crate::error::SimError;
use crate::linear::{Matching, ObserverDesign};

use super::text::table_row;

/// The noise scenarios of section V the claims read.
const SCENARIOS: [&str; 2] = ["estimator_noise_low", "estimator_noise_high"];

/// The claims that name Chen's observer, with the table's short name for each.
const CLAIMS: [(&str, &str); 4] = [
    ("chen_noise_sensitive", "chen's error at least doubles with the noise"),
    ("lu_beats_chen_high_noise", "lu more accurate at σ_q̇ = 0.1"),
    ("lu_beats_chen_low_noise", "lu more accurate at σ_q̇ = 0.01"),
    ("chen_cannot_track_low_noise", "chen cannot track at σ_q̇ = 0.01"),
];

/// Seeds per row: the report's first ones, at most this many.
const SEEDS: usize = 6;

/// Chen's two gain designs, in the table's order.
const DESIGNS: [ChenGain; 2] = [ChenGain::Inertia, ChenGain::Scalar];

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

/// Runs every row on the noise scenarios among `scenarios` (HyA's; `table` holds the report's
/// runs); `None` where they are not there.
pub fn run<const N: usize>(
    robot: &crate::robot::Robot<N>,
    scenarios: &[Scenario],
    table: &MetricTable,
) -> Result<Option<ChenDesigns>, SimError> {
    let bases: Vec<&Scenario> =
        scenarios.iter().filter(|s| s.robot == "hya" && SCENARIOS.contains(&s.name.as_str())).collect();
    let Some(first) = bases.first() else { return Ok(None) };
    let omega = first.controller.observer_bandwidth_rad_s;
    let q0 = crate::config::settings::JointSettings::<N>::of(first)?.initial_position;
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
            let as_run = matching == Matching::PoleMagnitude && bases.iter().all(|s| s.controller.chen_gain == design);
            let runs = match as_run {
                true => reported.clone(),
                false => {
                    let variants: Vec<Scenario> = bases
                        .iter()
                        .map(|base| {
                            let mut s = (*base).clone();
                            s.methods = vec![Method::Chen];
                            s.controller.chen_gain = design;
                            s.controller.observer_bandwidth_rad_s = beta;
                            s
                        })
                        .collect();
                    reported.clone().overlaid(run_seeds(robot, &variants, seeds, &|_| {})?.1)
                }
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

/// The design's name in the text.
fn design_name(design: ChenGain) -> &'static str {
    match design {
        ChenGain::Inertia => "`Y = β M(q0)`",
        ChenGain::Scalar => "scalar `y = β λmax(M(q0))`",
    }
}

/// A judged claim as a table cell: the verdict, then each joint's centre, marked where it fails
/// (✗) or is open (?).
fn cell(judgement: &Judgement) -> String {
    let verdict = match judgement.verdict {
        Verdict::Reproduced => judgement.verdict.name().to_owned(),
        other => format!("**{}**", other.name()),
    };
    let figures: Vec<String> = judgement
        .numbers
        .iter()
        .map(|f| {
            let mark = match (f.holds, f.inconclusive) {
                (true, _) => "",
                (false, true) => " ?",
                (false, false) => " ✗",
            };
            format!("{:.2}{mark}", f.mean)
        })
        .collect();
    format!("{verdict}: {}", figures.join(", "))
}

/// What one claim's verdicts across the rows depend on, computed from them: whether it is
/// reproduced in every row, in none (then where it holds in part), or in some, and then whether
/// the gain design or the matching alone tells which.
fn dependence(rows: &[DesignRow], claim: usize) -> String {
    let verdict = |r: &DesignRow| r.claims.get(claim).map_or(Verdict::NotRun, |c| c.verdict);
    let reproduced = |r: &DesignRow| verdict(r) == Verdict::Reproduced;
    // The rows `keep` picks, each design once with its matchings ("at every matching" for all).
    let listed = |keep: &dyn Fn(&DesignRow) -> bool| -> Vec<String> {
        DESIGNS
            .iter()
            .filter_map(|&d| {
                let at: Vec<&str> =
                    rows.iter().filter(|r| r.design == d && keep(r)).map(|r| r.matching.short()).collect();
                match at.len() {
                    0 => None,
                    n if n == Matching::ALL.len() => Some(format!("{} at every matching", design_name(d))),
                    _ => Some(format!("{} at {}", design_name(d), at.join(", "))),
                }
            })
            .collect()
    };
    if rows.iter().all(|r| matches!(verdict(r), Verdict::NotRun | Verdict::NotTestable)) {
        return "not judged in any row (its runs are missing)".to_owned();
    }
    if rows.iter().all(reproduced) {
        return "reproduced in every row".to_owned();
    }
    if !rows.iter().any(reproduced) {
        let partly = listed(&|r| matches!(verdict(r), Verdict::Partly | Verdict::Inconclusive));
        return match partly.is_empty() {
            true => "reproduced in no row".to_owned(),
            false => {
                format!("reproduced in no row; partly or inconclusive (some joints only) with {}", partly.join("; "))
            }
        };
    }
    // Whether rows that share a design (or a matching) share whether the claim is reproduced.
    let decided_by = |same: &dyn Fn(&DesignRow, &DesignRow) -> bool| {
        rows.iter().all(|a| rows.iter().filter(|b| same(a, b)).all(|b| reproduced(a) == reproduced(b)))
    };
    let which = if decided_by(&|a, b| a.design == b.design) {
        "depends on the gain design"
    } else if decided_by(&|a, b| a.matching == b.matching) {
        "depends on the matching"
    } else {
        "depends on both the design and the matching"
    };
    format!(
        "{which}: reproduced with {}; not reproduced (or open) with {}",
        listed(&reproduced).join("; "),
        listed(&|r| !reproduced(r)).join("; ")
    )
}

/// The report's section: the rows' verdicts and figures, then what each claim depends on.
pub fn section(designs: &ChenDesigns) -> String {
    let mut md = format!(
        "\n### Chen's observer by gain design and matching\n\nThe claims above that name Chen's observer are judged at one design (the report's: {}) and one matching (equal pole magnitude, β = {} rad/s). Here they are judged again, each by its own rule unchanged, with both of Chen's gain designs at each meaning of \"equal bandwidth\" with the paper's filter at ω = {} rad/s (see \"What equal bandwidth means\"), on the report's first {} seeds: chen alone is rerun, lu's runs are the report's, so every ratio stays paired by seed; the row marked (as run) is the report's own runs. The scalar design keeps the slowest rate at the start pose at β and makes the light joints faster by the inertia ratio. A cell gives the verdict and each joint's centre (lu / chen for the ratios; chen's RMSE(d̂ − d) over RMS(d) for \"cannot track\"; chen's σ_q̇ = 0.1 over 0.01 for \"doubles\"), ✗ where the joint fails, ? where it is open.\n\n",
        design_name(designs.rows.iter().find(|r| r.as_run).map_or(ChenGain::Inertia, |r| r.design)),
        hya_core::Short(designs.lu_bandwidth_rad_s),
        hya_core::Short(designs.lu_bandwidth_rad_s),
        designs.seeds
    );
    md.push_str(&table_row(
        ["design".to_owned(), "matching".into(), "β [rad/s]".into(), "fastest rate at q0 [rad/s]".into()]
            .into_iter()
            .chain(CLAIMS.map(|(_, s)| s.to_owned())),
    ));
    md.push_str(&table_row(std::iter::repeat_n("---".to_owned(), CLAIMS.len() + 4)));
    for r in &designs.rows {
        let matching = if r.as_run { format!("{} (as run)", r.matching.name()) } else { r.matching.name().to_owned() };
        md.push_str(&table_row(
            [
                design_name(r.design).to_owned(),
                matching,
                format!("{:.1}", r.beta_rad_s),
                format!("{:.0}", r.fastest_rate_rad_s),
            ]
            .into_iter()
            .chain(r.claims.iter().map(cell)),
        ));
    }
    let nyquist = std::f64::consts::PI / designs.period_s;
    let beyond = beyond_nyquist(designs);
    if !beyond.is_empty() {
        // The implicit step's pole at the rate `r`, `1/(1 + r T)`: what each tick keeps of the
        // previous estimate (hya-core's `observers.rs` derives the one-step differentiator).
        let pole = |r: &DesignRow| 1.0 / (1.0 + r.fastest_rate_rad_s * designs.period_s);
        let largest_pole = designs.rows.iter().filter(|r| r.fastest_rate_rad_s > nyquist).map(pole).fold(0.0, f64::max);
        let _ = writeln!(
            md,
            "\nIn {} of the {} rows ({}) the fastest rate at the start pose is beyond the {} ms tick's Nyquist rate `π/T` = {:.0} rad/s. The stepped observer's pole at that rate, `1/(1 + rate·T)`, is at most {largest_pole:.2}: each tick keeps at most that share of the previous estimate, so on that joint `d̂` is close to a one-step difference of the measured velocity, not the continuous design; those rows hold lu against that, not against a matched observer.",
            beyond.len(),
            designs.rows.len(),
            beyond.join("; "),
            hya_core::Short(designs.period_s * 1e3),
            nyquist
        );
    }
    md.push_str("\nAcross the rows, computed from the verdicts above:\n\n");
    for (k, (_, name)) in CLAIMS.iter().enumerate() {
        let _ = writeln!(md, "- {name}: {}.", dependence(&designs.rows, k));
    }
    md
}

/// The rows whose fastest rate at the start pose is beyond the tick's Nyquist rate `π/T`.
fn beyond_nyquist(designs: &ChenDesigns) -> Vec<String> {
    let nyquist = std::f64::consts::PI / designs.period_s;
    designs
        .rows
        .iter()
        .filter(|r| r.fastest_rate_rad_s > nyquist)
        .map(|r| format!("{} at {}", design_name(r.design), r.matching.short()))
        .collect()
}

/// The headline's sentence on the section, or nothing without one.
pub fn headline(designs: Option<&ChenDesigns>) -> String {
    let Some(designs) = designs else { return String::new() };
    let claims: Vec<String> =
        CLAIMS.iter().enumerate().map(|(k, (_, name))| format!("{name}: {}", dependence(&designs.rows, k))).collect();
    let beyond = beyond_nyquist(designs);
    let caveat = match beyond.is_empty() {
        true => String::new(),
        false => format!(
            " In {} of the rows ({}) chen's fastest rate is beyond the tick's Nyquist rate, where it is not the continuous design: what holds there holds against that.",
            beyond.len(),
            beyond.join("; ")
        ),
    };
    format!(
        "\nThe claims that name chen, judged again with both of its gain designs at all three matchings ({} seeds, \"Chen's observer by gain design and matching\"): {}.{caveat}\n",
        designs.seeds,
        claims.join("; ")
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(design: ChenGain, matching: Matching, verdict: Verdict) -> DesignRow {
        let judgement = Judgement {
            id: "x",
            statement: "x",
            section: "V",
            verdict,
            numbers: Vec::new(),
            seeds: 3,
            untestable: None,
        };
        DesignRow {
            design,
            matching,
            beta_rad_s: 1.0,
            fastest_rate_rad_s: 1.0,
            as_run: false,
            rmse_d: BTreeMap::new(),
            claims: vec![judgement],
        }
    }

    fn rows(verdict: impl Fn(ChenGain, Matching) -> Verdict) -> Vec<DesignRow> {
        DESIGNS.iter().flat_map(|&d| Matching::ALL.map(|m| row(d, m, verdict(d, m)))).collect()
    }

    #[test]
    fn dependence_names_the_choice_that_moves_a_verdict() {
        let same = rows(|_, _| Verdict::Reproduced);
        assert_eq!(dependence(&same, 0), "reproduced in every row");
        let by_design = rows(|d, _| if d == ChenGain::Scalar { Verdict::Reproduced } else { Verdict::NotReproduced });
        let text = dependence(&by_design, 0);
        assert!(text.starts_with("depends on the gain design: reproduced with scalar"), "{text}");
        assert!(text.contains("not reproduced (or open) with `Y = β M(q0)` at every matching"), "{text}");
        let by_matching =
            rows(|_, m| if m == Matching::LowFrequencyDelay { Verdict::Reproduced } else { Verdict::NotReproduced });
        assert!(dependence(&by_matching, 0).starts_with("depends on the matching"));
        let both = rows(|d, m| match (d, m) {
            (ChenGain::Scalar, Matching::PoleMagnitude) => Verdict::Reproduced,
            _ => Verdict::NotReproduced,
        });
        let text = dependence(&both, 0);
        assert!(text.starts_with("depends on both"), "{text}");
        assert!(
            text.contains("reproduced with scalar `y = β λmax(M(q0))` at equal poles; not reproduced (or open) with"),
            "{text}"
        );
        // Never reproduced: "partly" in one row is not a dependence.
        let one_partly = rows(|d, m| match (d, m) {
            (ChenGain::Scalar, Matching::PoleMagnitude) => Verdict::Partly,
            _ => Verdict::NotReproduced,
        });
        let text = dependence(&one_partly, 0);
        assert!(text.starts_with("reproduced in no row; partly or inconclusive"), "{text}");
    }

    #[test]
    fn matched_betas_follow_the_equal_bandwidth_table() {
        // At ω = 50 rad/s: lu's −3 dB bandwidth 32.4 rad/s, its delay 1/50 + 1.6/50 = 52 ms.
        assert_eq!(matched_beta(50.0, Matching::PoleMagnitude), 50.0);
        assert!((matched_beta(50.0, Matching::Bandwidth3Db) - 32.4).abs() < 0.05);
        assert!((matched_beta(50.0, Matching::LowFrequencyDelay) - 1.0 / 0.052).abs() < 1e-9);
    }
}
