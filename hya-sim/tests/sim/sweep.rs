//! Sweeps split into shards and merge back into exactly the unsharded result; a merge refuses
//! every set of shards that is not exactly one sweep's grid.

use hya_sim::sweep::{merge, run, Plan, Shard, Sweep};
use hya_sim::{Method, Scenario};

fn tiny_plan() -> Plan {
    let mut scenario = Scenario::builtin("goto_internal").unwrap();
    scenario.duration_s = 0.8;
    Plan {
        scenarios: vec![scenario],
        methods: vec![Method::Lu, Method::Momentum],
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
