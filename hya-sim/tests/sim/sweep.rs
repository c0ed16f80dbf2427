//! Sweeps split into shards and merge back into exactly the unsharded result; a merge refuses
//! every set of shards that is not exactly one sweep's grid.

use hya_sim::report::pareto_figure;
use hya_sim::sweep::{
    dominates, front_points, merge, pareto_optimal, run, scenarios, Entry, FrontPoint, Measure, Plan, Shard, Sweep,
};
use hya_sim::{Method, Scenario};

fn tiny_plan() -> Plan {
    let mut scenario = Scenario::builtin("goto_internal").unwrap();
    scenario.duration_s = 0.8;
    Plan {
        scenarios: vec![scenario],
        methods: vec![Method::Lu, Method::Pid],
        bandwidths_rad_s: vec![30.0, 60.0],
        seeds: 2,
    }
}

/// Shards named as a merge names them, by where they came from.
fn named(shards: &[Sweep]) -> Vec<(String, Sweep)> {
    shards.iter().enumerate().map(|(i, s)| (format!("s{i}"), s.clone())).collect()
}

fn refusal(plan: &Plan, shards: &[Sweep]) -> String {
    merge(plan, &named(shards)).unwrap_err().to_string()
}

#[test]
fn merged_shards_equal_the_unsharded_sweep() {
    let plan = tiny_plan();
    let whole = run(&plan, Shard::ALL, false, &|_| {}).unwrap();
    assert_eq!(whole.entries.len(), 8);
    let shards: Vec<_> = (0..3).map(|i| run(&plan, Shard { index: i, count: 3 }, false, &|_| {}).unwrap()).collect();
    assert!(shards.iter().all(|s| s.entries.len() < 8), "each shard runs a part");
    let merged = merge(&plan, &named(&shards)).unwrap();
    assert_eq!(merged.entries, whole.entries);
    // pid runs, with a tracking error and no estimate.
    let pid: Vec<_> = whole.entries.iter().filter(|e| e.method == "pid").collect();
    assert_eq!(pid.len(), 4);
    assert!(pid.iter().all(|e| e.rmse_d.is_none() && e.rmse_q.is_finite() && e.rmse_q > 0.0));
    assert!(whole.entries.iter().filter(|e| e.method == "lu").all(|e| e.rmse_d.is_some()));
    assert_eq!(merged.plan, whole.plan);
    // Through JSON and back, as `hya sweep --merge` reads them: still bit for bit.
    let reread: Vec<Sweep> =
        shards.iter().map(|s| serde_json::from_str(&serde_json::to_string_pretty(s).unwrap()).unwrap()).collect();
    assert_eq!(merge(&plan, &named(&reread)).unwrap().entries, whole.entries);
    // A shard named twice, a tampered or incomplete shard, a missing shard, a shard of another
    // sweep: all refused, naming the shard.
    let mut twice = shards.clone();
    twice.push(shards[0].clone());
    assert!(refusal(&plan, &twice).contains("s0 holds too"));
    let mut dropped = shards.clone();
    dropped[1].entries.pop();
    assert!(refusal(&plan, &dropped).contains("shard s1: holds"));
    let mut moved = shards.clone();
    moved[2].entries[0].bandwidth_rad_s = -30.0;
    assert!(refusal(&plan, &moved).contains("shard s2"));
    let mut huge = shards.clone();
    huge[0].entries[0].rmse_q = f64::INFINITY;
    assert!(refusal(&plan, &huge).contains("not a finite number"));
    assert!(refusal(&plan, &shards[..2]).contains("missing shards: 2/3"));
    let mut foreign = shards.clone();
    foreign[1].plan.push_str(" (another)");
    assert!(refusal(&plan, &foreign).contains("another sweep"));
}

#[test]
fn shard_headers_out_of_range_are_refused() {
    let plan = tiny_plan();
    let shard = run(&plan, Shard { index: 0, count: 2 }, false, &|_| {}).unwrap();
    let mut both = shard.clone();
    both.shard_indices = vec![0, 1]; // half the grid claiming both indices
    assert!(refusal(&plan, &[both]).contains("holds 4 points where its shards have 8"));
    let mut beyond = shard.clone();
    beyond.shard_indices = vec![5];
    assert!(refusal(&plan, &[beyond]).contains("beyond 0 to 1"));
    for count in [0, 1_000_000, usize::MAX] {
        let mut absurd = shard.clone();
        absurd.shards = count;
        assert!(refusal(&plan, &[absurd]).contains("so 1 to 8"), "{count} shards accepted");
    }
}

#[test]
fn shards_parse_and_refuse_nonsense() {
    assert_eq!(Shard::parse("2/8", 8).unwrap(), Shard { index: 2, count: 8 });
    for bad in ["8/8", "1/0", "x/2", "3", "-1/2", "0/9", "0/18446744073709551615"] {
        assert!(Shard::parse(bad, 8).is_err(), "{bad} accepted");
    }
}

/// pid's `K_I` per joint at the point of `plan` with swept value `omega`.
fn integral_gain_at(plan: &Plan, omega: f64) -> Vec<f64> {
    use hya_core::Dynamics;
    let scenario = plan.scenario_at(0, Method::Pid, omega, 0).unwrap();
    let robot = hya_sim::Robot::<6>::load(&scenario.robot).unwrap();
    let joints = hya_sim::settings::Setup::<6>::of(&scenario).unwrap();
    let gains = hya_sim::run::gains(robot.nominal.as_ref(), &joints).unwrap();
    let inertia = robot.nominal.mass_matrix(&joints.initial_position).diagonal();
    hya_sim::run::pid_gains(&gains, &inertia, &joints).1.iter().copied().collect()
}

#[test]
fn pid_integral_gain_follows_the_swept_value() {
    let mut plan = tiny_plan();
    // Even a scenario set to another rule is swept by the estimator-matching rule.
    plan.scenarios[0].controller.integral_rule = hya_sim::scenario::IntegralRule::ZeroRatio;
    let (slow, fast) = (integral_gain_at(&plan, 5.0), integral_gain_at(&plan, 10.0));
    // K_I = K_P ω / (1 + 2ζ): doubling ω doubles K_I where the Routh cap does not bind.
    assert!(slow.iter().zip(&fast).any(|(s, f)| (f / s - 2.0).abs() < 1e-9), "{slow:?} {fast:?}");
    assert!(slow.iter().zip(&fast).all(|(s, f)| f >= s && *s > 0.0));
    let capped = integral_gain_at(&plan, 1e4);
    assert!(capped.iter().zip(&integral_gain_at(&plan, 2e4)).all(|(a, b)| a == b), "capped at half the Routh bound");
}

#[test]
fn the_report_grid_holds_every_method_and_pid() {
    let plan = Plan::report(true).unwrap();
    assert!(plan.methods.contains(&Method::Pid) && plan.methods.len() == 5);
    assert_eq!(plan.seeds, 1);
    assert_eq!(Plan::report(false).unwrap().runs(), 2 * 5 * 4 * hya_sim::sweep::REPORT_SEEDS);
    assert!(Plan::standard(false).unwrap().methods.contains(&Method::Pid));
}

fn point(method: &str, noise: (f64, f64), error: (f64, f64)) -> FrontPoint {
    FrontPoint { method: method.into(), bandwidth_rad_s: 50.0, noise, error }
}

#[test]
fn the_pareto_set_of_a_small_table() {
    let table = [
        point("lu", (1.0, 0.1), (10.0, 0.5)),
        point("lu", (2.0, 0.1), (5.0, 0.5)),
        point("chen", (2.0, 0.1), (8.0, 0.5)), // as noisy as lu's second, worse beyond the intervals
        point("chen", (3.0, 0.1), (5.2, 0.5)), // errors overlap lu's second, noisier beyond them
        point("eso", (0.5, 0.1), (20.0, 1.0)), // the quietest
        point("pid", (5.0, 0.1), (1.0, 0.1)),  // the most accurate
        point("eso", (1.02, 0.1), (10.3, 0.5)), // within lu's first intervals: not beaten
    ];
    assert_eq!(pareto_optimal(&table), [0, 1, 4, 5, 6]);
    assert!(dominates(&table[1], &table[2]) && !dominates(&table[2], &table[1]));
    assert!(!dominates(&table[0], &table[6]) && !dominates(&table[6], &table[0]));
    // Quieter beyond the intervals but four times the error in mean, its interval wide enough to
    // reach the other's: not a dominating point.
    let (quiet_but_worse, accurate) = (point("pid", (1.0, 0.01), (4.0, 3.0)), point("lu", (1.5, 0.01), (1.0, 0.5)));
    assert!(!dominates(&quiet_but_worse, &accurate) && !dominates(&accurate, &quiet_but_worse));
    // One seed: no interval, the means decide.
    let single: Vec<FrontPoint> = table
        .iter()
        .map(|p| FrontPoint { noise: (p.noise.0, f64::INFINITY), error: (p.error.0, f64::INFINITY), ..p.clone() })
        .collect();
    assert_eq!(pareto_optimal(&single), [0, 1, 4, 5]);
}

/// A hand-made sweep: lu and pid at three bandwidths, two seeds, noise spanning decades.
fn table_sweep() -> Sweep {
    let mut entries = Vec::new();
    for (method, scale) in [("lu", 1.0), ("pid", 2.0)] {
        for (k, bandwidth) in [20.0, 50.0, 200.0].into_iter().enumerate() {
            for seed in 0..2u64 {
                let wobble = 1.0 + 0.01 * seed as f64;
                entries.push(Entry {
                    scenario: "s".into(),
                    method: method.into(),
                    bandwidth_rad_s: bandwidth,
                    seed,
                    rmse_d: (method == "lu").then_some(0.3 * wobble / (k + 1) as f64),
                    tau_cmd_noise: 0.5 * 10f64.powi(k as i32) * scale * wobble,
                    rmse_q: 0.004 * wobble / (k + 1) as f64,
                });
            }
        }
    }
    Sweep { plan: "table".into(), quick: false, shards: 1, shard_indices: vec![0], entries }
}

/// The tick labels along the bottom of the first panel.
fn x_tick_labels(svg: &str) -> Vec<String> {
    svg.split(r##"stroke="#eee"/><text"##)
        .skip(1)
        .filter_map(|t| t.split_once("</text>").map(|(tick, _)| tick))
        .filter_map(|t| t.split_once(r#"text-anchor="middle">"#).map(|(_, label)| label.to_owned()))
        .collect()
}

#[test]
fn the_figure_marks_and_labels_every_point_on_log_axes() {
    let sweep = table_sweep();
    let svg = pareto_figure(&sweep);
    // Tracking: lu and pid, 3 points each; estimate: lu's 3. The front's points are ringed.
    assert_eq!(svg.matches("<circle cx").count(), 9);
    let fronts: usize =
        Measure::ALL.iter().map(|&m| pareto_optimal(&front_points(&sweep, scenarios(&sweep)[0], m)).len()).sum();
    assert!(fronts > 0);
    assert_eq!(svg.matches(r#"<circle class="front""#).count(), fronts);
    assert_eq!(svg.matches(r#"class="mark""#).count(), 9);
    assert_eq!(svg.matches(">200</text>").count(), 3);
    assert!(!svg.contains("NaN") && !svg.contains("inf"), "{svg}");
    assert!(svg.matches("<path").count() >= 9, "whiskers of two seeds' intervals");
    // Noise from 0.5 to 101 N·m: a log axis with a tick at each decade.
    let ticks = x_tick_labels(&svg);
    assert!(!ticks.is_empty());
    for t in &ticks {
        assert!(["0.1", "1", "10", "100", "1000"].contains(&t.as_str()), "{t} is not a decade: {ticks:?}");
    }
    assert!(ticks.contains(&"1".to_owned()) && ticks.contains(&"100".to_owned()));
    // A point beyond the drawable and a single seed: no marker for it, still no NaN or inf.
    let mut wild = sweep.clone();
    wild.entries.retain(|e| e.seed == 0);
    wild.entries[0].rmse_q = 1e300;
    let svg = pareto_figure(&wild);
    assert_eq!(svg.matches("<circle cx").count(), 8);
    assert!(!svg.contains("NaN") && !svg.contains("inf"), "{svg}");
}

/// The pole-placement rule gives `M s³ + K_D s² + K_P s + K_I = M (s + ω)³` on every joint, with
/// the common `K_P`: `K_D² = 3 M K_P` and `K_I = K_D K_P / 9M`.
#[test]
fn pole_placement_puts_the_pid_poles_together() {
    use hya_core::Dynamics;
    let mut scenario = hya_sim::Scenario::builtin("goto_internal").unwrap();
    scenario.controller.integral_rule = hya_sim::scenario::IntegralRule::PolePlacement;
    let robot = hya_sim::Robot::<6>::load(&scenario.robot).unwrap();
    let joints = hya_sim::settings::Setup::<6>::of(&scenario).unwrap();
    let gains = hya_sim::run::gains(robot.nominal.as_ref(), &joints).unwrap();
    let m = robot.nominal.mass_matrix(&joints.initial_position).diagonal();
    let (kd, ki, capped) = hya_sim::run::pid_gains(&gains, &m, &joints);
    let kp = gains.kp().diagonal();
    for j in 0..6 {
        // M (s + ω)³ = M s³ + 3Mω s² + 3Mω² s + Mω³ with K_P = 3Mω² given: its other two
        // coefficients in terms of K_P, without the rule's ω.
        let (kd_placed, ki_placed) = ((3.0 * m[j] * kp[j]).sqrt(), (kp[j] / 3.0).powf(1.5) / m[j].sqrt());
        for (ours, placed) in [(kd[j], kd_placed), (ki[j], ki_placed)] {
            assert!((ours - placed).abs() <= 1e-12 * placed, "joint {}: {ours} against {placed}", j + 1);
        }
        assert!(ki[j] < kd[j] * kp[j] / m[j], "joint {}: within the Routh bound", j + 1);
    }
    assert_eq!(capped, [false; 6]);
}

/// Chen's scalar design: `Y = β λmax(M(q0)) I`, so the slowest rate at the start pose is `β` and
/// the light joints' are faster; the inertia design gives `β` on every joint.
#[test]
fn chen_designs_set_their_rates() {
    use hya_core::{Dynamics, JointVector, Measurement};
    let scenario = hya_sim::Scenario::builtin("goto_internal").unwrap();
    let robot = hya_sim::Robot::<6>::load(&scenario.robot).unwrap();
    let q0 = JointVector::<6>::from_column_slice(&hya_sim::settings::initial_position(&scenario, 6));
    let first = Measurement { position: q0, velocity: Some(JointVector::zeros()), torque: robot.nominal.gravity(&q0) };
    let rates = |chen| {
        let design = (50.0, 1e-3, chen);
        hya_sim::run::observer_designed(Method::Chen, robot.nominal.as_ref(), design, &first).unwrap().unwrap().1
    };
    let inertia = rates(hya_sim::scenario::ChenGain::Inertia);
    assert!(inertia.iter().all(|r| (r - 50.0).abs() < 1e-9), "{inertia:?}");
    let scalar = rates(hya_sim::scenario::ChenGain::Scalar);
    assert!((scalar[0] - 50.0).abs() < 1e-6, "slowest {scalar:?}");
    assert!(scalar[5] > 10.0 * 50.0, "the light joints are faster: {scalar:?}");
}
