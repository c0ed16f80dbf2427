//! The claim rules evaluate correctly on metric tables built to pass, fail or split them: the
//! machinery, never a verdict on the simulation.

use hya_sim::claims::{judge, Need, Quantity, Rule, Side, Source, Verdict, RULES};
use hya_sim::seeds::MetricTable;
use hya_sim::{Method, Metrics};

/// Metrics whose `rmse_q` is `values` (every other metric zero or absent).
fn with_rmse(values: [f64; 6]) -> Metrics {
    Metrics {
        rmse_q: values.to_vec(),
        rmse_d: None,
        relative_rmse_d: None,
        tau_cmd_noise: vec![0.0; 6],
        max_abs_error_q: vec![0.0; 6],
        steady_error_q: vec![0.0; 6],
        limit_cycle_q: vec![0.0; 6],
        cycle_amplitude_q: vec![0.0; 6],
        cycle_frequency_hz: vec![0.0; 6],
        creep_q: vec![0.0; 6],
        weight_error_q: None,
        pre_drop_error_q: None,
        drop_recovery_s: None,
        removal_recovery_s: None,
        estimate_shift: None,
        estimate_velocity_correlation: None,
        estimate_mean_abs: None,
        estimate_shift_over_coulomb: None,
        estimate_mean_over_coulomb: None,
        shadow: Default::default(),
    }
}

/// 20 seeds of `none` at RMSE 1 (± a little) and `lu` at `ratio` × that, per joint.
fn table(ratio: [f64; 6], spread: f64) -> MetricTable {
    let mut table = MetricTable::default();
    for seed in 0..20 {
        let wobble = spread * if seed % 2 == 0 { 1.0 } else { -1.0 };
        let none = [1.0 + wobble; 6];
        table.push("goto_internal", Method::None, with_rmse(none));
        table.push("goto_internal", Method::Lu, with_rmse(std::array::from_fn(|j| none[j] * ratio[j])));
    }
    table
}

fn rmse_rule() -> &'static Rule {
    RULES.iter().find(|r| r.id == "goto_internal_rmse").unwrap()
}

#[test]
fn a_table_built_to_pass_passes() {
    let judged = judge(rmse_rule(), &table([0.5; 6], 0.05));
    assert_eq!(judged.verdict, Verdict::Reproduced);
    assert_eq!(judged.seeds, 20);
    assert!(judged.numbers.iter().all(|f| f.holds && (f.mean - 0.5).abs() < 1e-12));
}

#[test]
fn a_table_built_to_fail_fails_and_the_margin_counts() {
    // Lower, but not by the 10 % margin.
    let judged = judge(rmse_rule(), &table([0.95; 6], 0.05));
    assert_eq!(judged.verdict, Verdict::NotReproduced);
    // Worse.
    assert_eq!(judge(rmse_rule(), &table([1.2; 6], 0.05)).verdict, Verdict::NotReproduced);
}

#[test]
fn a_split_table_is_partly_reproduced_and_names_the_joints() {
    let judged = judge(rmse_rule(), &table([0.5, 0.5, 0.5, 1.1, 1.1, 1.1], 0.05));
    assert_eq!(judged.verdict, Verdict::Partly);
    let holding: Vec<usize> = judged.numbers.iter().filter(|f| f.holds).map(|f| f.joint).collect();
    assert_eq!(holding, [1, 2, 3]);
}

/// 20 seeds of `none` at RMSE 1 and `lu` at `lu(w)`, with `w` 0.1 and 3.0 on alternate seeds:
/// where `lu` takes `w`, a ratio of geometric mean 0.55 whose seeds disagree wildly about it.
fn wobbling(lu: impl Fn(f64) -> [f64; 6]) -> MetricTable {
    let mut table = MetricTable::default();
    for seed in 0..20 {
        let w = if seed % 2 == 0 { 0.1 } else { 3.0 };
        table.push("goto_internal", Method::None, with_rmse([1.0; 6]));
        table.push("goto_internal", Method::Lu, with_rmse(lu(w)));
    }
    table
}

#[test]
fn a_wide_interval_does_not_hold() {
    let judged = judge(rmse_rule(), &wobbling(|w| [w; 6]));
    // A ratio's centre is the geometric mean, √(0.1 · 3), its interval taken on the logarithms.
    assert!((judged.numbers[0].mean - (0.1f64 * 3.0).sqrt()).abs() < 1e-12);
    assert!(judged.numbers[0].low > 0.0, "a ratio's interval stays above zero");
    // The interval straddles the bound 0.9: neither holds nor fails.
    assert!(judged.numbers.iter().all(|f| !f.holds && f.inconclusive), "{judged:?}");
    assert_eq!(judged.verdict, Verdict::Inconclusive, "{judged:?}");
}

#[test]
fn one_failing_joint_closes_a_claim_and_one_open_joint_leaves_it_open() {
    // Joints 1-5 straddle the bound; joint 6 is clearly worse: the claim cannot hold on all six.
    let judged = judge(rmse_rule(), &wobbling(|w| [w, w, w, w, w, 1.5]));
    assert_eq!(judged.verdict, Verdict::NotReproduced, "none holds, one fails: {judged:?}");
    assert_eq!(judge(rmse_rule(), &table([0.5, 0.5, 0.5, 0.5, 0.5, 1.5], 0.05)).verdict, Verdict::Partly);
    // Joints 1-5 hold and joint 6 straddles: the claim is open.
    let judged = judge(rmse_rule(), &wobbling(|w| [0.5, 0.5, 0.5, 0.5, 0.5, w]));
    assert!(judged.numbers[..5].iter().all(|f| f.holds) && judged.numbers[5].inconclusive, "{judged:?}");
    assert_eq!(judged.verdict, Verdict::Inconclusive);
}

#[test]
fn a_share_of_seeds_has_wilsons_interval() {
    // Wilson's interval at 12 of 20: 0.387 to 0.781 (statsmodels' `proportion_confint(12, 20,
    // method="wilson")`, an independent implementation, gives the same to 1e-4).
    let (low, high) = hya_sim::claims::wilson_ci95(0.6, 20);
    assert!((low - 0.3866).abs() < 1e-3 && (high - 0.7812).abs() < 1e-3, "{low} {high}");
    // Never outside 0..1, and not empty at a share of 1.
    let (low, high) = hya_sim::claims::wilson_ci95(1.0, 20);
    assert!(low > 0.8 && low < 1.0 && high == 1.0, "{low} {high}");
    // A recovery rule: 20 of 20 seeds within the limit holds, 12 of 20 is open.
    let rule = Rule {
        quantity: Quantity::Share(
            Source { scenario: "goto_internal", method: Method::Lu, metric: "rmse_q" },
            Side::Below,
            1.0,
        ),
        side: Side::Above,
        threshold: 0.5,
        margin: 0.0,
        ..*rmse_rule()
    };
    let recovered = |within: usize| {
        let mut table = MetricTable::default();
        for seed in 0..20 {
            table.push("goto_internal", Method::Lu, with_rmse([if seed < within { 0.5 } else { 4.0 }; 6]));
        }
        judge(&rule, &table)
    };
    assert_eq!(recovered(20).verdict, Verdict::Reproduced);
    assert!((recovered(12).numbers[0].mean - 0.6).abs() < 1e-12);
    assert_eq!(recovered(12).verdict, Verdict::Inconclusive);
    assert_eq!(recovered(2).verdict, Verdict::NotReproduced);
}

#[test]
fn missing_runs_are_not_run_and_at_least_counts() {
    assert_eq!(judge(rmse_rule(), &MetricTable::default()).verdict, Verdict::NotRun);
    let two_of_six = Rule {
        id: "test",
        statement: "at least two joints above 0.5",
        section: "-",
        paper: "-",
        quantity: Quantity::Metric(Source { scenario: "goto_internal", method: Method::Lu, metric: "rmse_q" }),
        joints: &[0, 1, 2, 3, 4, 5],
        side: Side::Above,
        threshold: 0.5,
        margin: 0.0,
        need: Need::AtLeast(2),
        quiet: &[],
        untestable: None,
    };
    let table = table([1.0, 1.0, 0.1, 0.1, 0.1, 0.1], 0.01);
    assert_eq!(judge(&two_of_six, &table).verdict, Verdict::Reproduced);
    let table_one = self::table([1.0, 0.1, 0.1, 0.1, 0.1, 0.1], 0.01);
    // One of the two it needs: a claim about "at least two" is not partly true of one.
    assert_eq!(judge(&two_of_six, &table_one).verdict, Verdict::NotReproduced);
}

#[test]
fn every_rule_names_metrics_the_runs_have() {
    let names: Vec<&str> = with_rmse([0.0; 6]).named().iter().map(|(n, _)| *n).collect();
    let optional = [
        "rmse_d",
        "relative_rmse_d",
        "weight_error_q",
        "pre_drop_error_q",
        "drop_recovery_s",
        "removal_recovery_s",
        "estimate_shift",
        "estimate_velocity_correlation",
        "estimate_mean_abs",
        "estimate_shift_over_coulomb",
        "estimate_mean_over_coulomb",
    ];
    for rule in RULES {
        let sources = match rule.quantity {
            Quantity::Metric(s) => vec![s],
            Quantity::Ratio(a, b) => vec![a, b],
            Quantity::Share(s, _, _) => vec![s],
        };
        for s in sources {
            assert!(
                names.contains(&s.metric) || optional.contains(&s.metric),
                "{}: unknown metric {}",
                rule.id,
                s.metric
            );
            assert!(hya_sim::Scenario::builtin(s.scenario).is_ok(), "{}: unknown scenario {}", rule.id, s.scenario);
        }
    }
}

#[test]
fn quiet_joints_and_untestable_claims_are_judged_as_such() {
    let oscillating = Rule {
        id: "test",
        statement: "joints 1 and 2 above 0.5, the others below",
        section: "-",
        paper: "-",
        quantity: Quantity::Metric(Source { scenario: "goto_internal", method: Method::Lu, metric: "rmse_q" }),
        joints: &[0, 1],
        side: Side::Above,
        threshold: 0.5,
        margin: 0.0,
        need: Need::All,
        quiet: &[2, 3, 4, 5],
        untestable: None,
    };
    let judged = judge(&oscillating, &table([1.0, 1.0, 0.1, 0.1, 0.1, 0.1], 0.01));
    assert_eq!(judged.verdict, Verdict::Reproduced);
    assert_eq!(judged.numbers.iter().filter(|f| f.quiet).count(), 4);
    // Every joint oscillating: the named ones hold, the quiet ones do not stay quiet.
    let loud = judge(&oscillating, &table([1.0; 6], 0.01));
    assert_eq!(loud.verdict, Verdict::Partly);
    assert!(loud.numbers.iter().filter(|f| f.quiet).all(|f| !f.holds));
    let untestable = Rule { untestable: Some("a fact of the real robot"), ..oscillating };
    let judged = judge(&untestable, &table([1.0, 1.0, 0.1, 0.1, 0.1, 0.1], 0.01));
    assert_eq!(judged.verdict, Verdict::NotTestable);
    assert_eq!(judged.numbers.len(), 6, "the figures are still shown");
}

#[test]
fn a_heavy_tailed_ratio_is_not_carried_by_one_seed() {
    // Nineteen seeds near 0.9 and one at 0.05: the arithmetic mean (0.86) with a symmetric
    // interval would sit below 0.9; on the logarithms the outlier widens the interval instead.
    let mut table = MetricTable::default();
    for seed in 0..20 {
        let lu = if seed == 0 { 0.05 } else { 0.9 };
        table.push("goto_internal", Method::None, with_rmse([1.0; 6]));
        table.push("goto_internal", Method::Lu, with_rmse([lu; 6]));
    }
    let judged = judge(rmse_rule(), &table);
    let figure = &judged.numbers[0];
    assert!(figure.low > 0.0 && figure.high > 0.9, "{figure:?}");
    // The interval reaches past the bound: the outlier leaves the claim open, never reproduced.
    assert_eq!(judged.verdict, Verdict::Inconclusive);
}
