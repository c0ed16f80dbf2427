//! The cost `hya reproduce` prints before it runs counts the studies' runs: each closed-loop
//! study, run on shortened scenarios, reports as many runs and simulated seconds as its cost
//! said beforehand.

use std::sync::Mutex;

use hya_sim::analysis::seeds::run_seeds;
use hya_sim::cost::Cost;
use hya_sim::studies::{chen_designs, gain_rule, limit_cycles, sensitivity};
use hya_sim::{Method, Robot, Scenario, SimError};

/// The runs and simulated seconds `study` tells its progress.
fn counted(study: impl FnOnce(&(dyn Fn(f64) + Sync)) -> Result<(), SimError>) -> (usize, f64) {
    let told = Mutex::new((0, 0.0));
    study(&|seconds| {
        let mut told = told.lock().unwrap();
        *told = (told.0 + 1, told.1 + seconds);
    })
    .unwrap();
    told.into_inner().unwrap()
}

fn assert_counts(study: &str, cost: Cost, (runs, seconds): (usize, f64)) {
    assert!(runs > 0, "{study} ran nothing");
    assert_eq!(cost.runs, runs, "{study}: runs counted against runs made");
    assert!(
        (cost.simulated_s - seconds).abs() < 1e-9 * seconds,
        "{study}: {} s counted, {seconds} s run",
        cost.simulated_s
    );
}

#[test]
fn each_closed_loop_study_costs_what_it_runs() {
    let robot = Robot::<6>::load("hya").unwrap();
    let scenarios: Vec<Scenario> = ["goto_internal", "sine_internal", "estimator_noise_low", "estimator_noise_high"]
        .iter()
        .map(|name| {
            let mut s = Scenario::builtin(name).unwrap();
            s.duration_s = 0.6;
            s
        })
        .collect();
    let seeds = 2;
    let (_, table) = run_seeds(&robot, &scenarios, seeds, &|_| {}).unwrap();
    let goto = &scenarios[0];
    assert_counts(
        "sensitivity",
        sensitivity::cost(&scenarios, seeds),
        counted(|p| sensitivity::run(&robot, &scenarios, &table, p).map(drop)),
    );
    assert_counts(
        "chen designs",
        chen_designs::cost(&scenarios, seeds),
        counted(|p| chen_designs::run(&robot, &scenarios, &table, p).map(drop)),
    );
    assert_counts("limit cycles", limit_cycles::cost(goto), counted(|p| limit_cycles::run(&robot, goto, p).map(drop)));
    assert_counts("gain rule", gain_rule::cost(goto), counted(|p| gain_rule::run(&robot, goto, p).map(drop)));
    // Where the report ran no lu, the sensitivity study takes no seeds: nothing run, nothing costed.
    let mut without_lu = scenarios.clone();
    without_lu.iter_mut().for_each(|s| s.methods.retain(|m| *m != Method::Lu));
    let (_, table) = run_seeds(&robot, &without_lu[..1], 1, &|_| {}).unwrap();
    assert_eq!(sensitivity::cost(&without_lu, 1), Cost::NONE);
    assert_eq!(counted(|p| sensitivity::run(&robot, &without_lu, &table, p).map(drop)), (0, 0.0));
}

#[test]
fn a_sweeps_shards_cost_the_whole_grid_between_them() {
    let plan = hya_sim::sweep::Plan::standard(true).unwrap();
    let whole = plan.cost(hya_sim::sweep::Shard::ALL);
    assert_eq!(whole.runs, plan.runs());
    let shards: Vec<Cost> =
        (0..3).map(|i| plan.cost(hya_sim::sweep::Shard::parse(&format!("{i}/3"), plan.runs()).unwrap())).collect();
    assert_eq!(shards.iter().map(|c| c.runs).sum::<usize>(), whole.runs);
    let seconds: f64 = shards.iter().map(|c| c.simulated_s).sum();
    assert!((seconds - whole.simulated_s).abs() < 1e-9 * whole.simulated_s);
    assert!(shards.iter().all(|c| c.runs > 0 && c.runs < whole.runs));
}
