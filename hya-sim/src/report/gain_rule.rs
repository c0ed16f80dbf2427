//! How the uncompensated baseline moves with the gain rule ([`crate::studies::gain_rule`] runs
//! it): `none` on the goto task at several `e_f`, the error at which the PD's torque reaches the joint's static friction
//! (`K_P = clamp(F_s / e_f, M_ii ω_n², M_ii ω_max²)`). A stiffer PD holds a sticking joint
//! closer to its reference; `none`'s figures in the report are those of one `e_f`.

use std::fmt::Write as _;

use crate::analysis::seeds::per_joint_mean_ci95;
use crate::config::scenario::{Method, Scenario};
use crate::studies::gain_rule::{GainRuleRuns, FRICTION_ERRORS_RAD, SEEDS};

use super::text::table_row;

/// The section, from `runs` of `none` on `base` at every `e_f` ([`crate::studies::gain_rule`]).
pub fn section<const N: usize>(base: &Scenario, runs: &GainRuleRuns) -> String {
    let (scenarios, table) = (&runs.scenarios, &runs.table);
    let mut md = format!(
        "\n### The uncompensated baseline and the gain rule\n\n`none`'s steady error depends on how stiff the PD is: the gain rule stiffens each joint until its torque at the error `e_f` reaches the joint's static friction (`K_P = clamp(F_s / e_f, M_ii ω_n², M_ii ω_max²)`), so a joint that sticks stays within about `e_f` of its reference where `K_P` reaches `F_s / e_f`; where the ceiling `M_ii ω_max²` binds (the light wrist joints here), its error can exceed `e_f`, by as much as the table shows. The report's runs use e_f = {} rad. `none` on `{}` at other e_f ({SEEDS} seeds each), mean |e| over the final window per joint, mrad:\n\n",
        base.controller.friction_error_rad, base.name
    );
    md.push_str(&table_row(["e_f [rad]".to_owned()].into_iter().chain((1..=N).map(|j| format!("j{j}")))));
    md.push_str(&table_row(std::iter::repeat_n("---".to_owned(), N + 1)));
    for (s, e) in scenarios.iter().zip(FRICTION_ERRORS_RAD) {
        let values = table.values(&s.name, Method::None, "steady_error_q").unwrap_or_default();
        let mean = per_joint_mean_ci95(&values).0;
        md.push_str(&table_row([format!("{e}")].into_iter().chain(mean.iter().map(|v| format!("{:.2}", v * 1e3)))));
    }
    let _ = writeln!(
        md,
        "\nThe claims comparing with `none` (its RMSE ratios, its steady error) are judged at the report's e_f only."
    );
    md
}
