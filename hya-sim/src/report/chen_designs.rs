//! The section V claims that name Chen's observer, judged again per gain design and per
//! matching ([`crate::studies::chen_designs`] runs them): the rows' verdicts and figures, and
//! what each claim's verdicts depend on, computed from the rows.

use std::fmt::Write as _;

use crate::analysis::claims::{Judgement, Verdict};
use crate::config::scenario::ChenGain;
use crate::linear::Matching;
use crate::studies::chen_designs::{ChenDesigns, DesignRow, CLAIMS, DESIGNS};

use super::text::table_row;

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
            "\nIn {} of the {} rows ({}) the fastest rate at the start pose is beyond the {} ms tick's Nyquist rate `π/T` = {:.0} rad/s. The observer, stepped implicitly, has its pole at that rate at `1/(1 + rate·T)`, at most {largest_pole:.3}: each tick keeps at most that share of the previous estimate, so on that joint `d̂` is close to a one-step difference of the measured velocity, not the continuous design; those rows hold lu against that, not against a matched observer.",
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
    use std::collections::BTreeMap;

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
}
