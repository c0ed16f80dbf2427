//! Sweeps split into shards and merge back into exactly the unsharded result.

use hya_sim::sweep::{merge, run, Plan, Shard};
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

#[test]
fn merged_shards_equal_the_unsharded_sweep() {
    let plan = tiny_plan();
    let whole = run(&plan, Shard::ALL, &|_| {}).unwrap();
    assert_eq!(whole.entries.len(), 8);
    let shards: Vec<_> = (0..3).map(|i| run(&plan, Shard { index: i, count: 3 }, &|_| {}).unwrap()).collect();
    assert!(shards.iter().all(|s| s.entries.len() < 8), "each shard runs a part");
    let merged = merge(&shards).unwrap();
    assert_eq!(merged.entries, whole.entries);
    assert_eq!(merged.plan, whole.plan);
    // Merging a shard twice changes nothing; a shard that disagrees, a missing shard or a
    // shard of another sweep is refused.
    let mut twice = shards.clone();
    twice.push(shards[0].clone());
    assert_eq!(merge(&twice).unwrap().entries, whole.entries);
    let mut tampered = shards[0].clone();
    tampered.entries[0].rmse_q *= 2.0;
    let mut with_tampered = shards.clone();
    with_tampered.push(tampered);
    assert!(merge(&with_tampered).unwrap_err().to_string().contains("disagree"));
    assert!(merge(&shards[..2]).unwrap_err().to_string().contains("missing shards: 2/3"));
    let mut foreign = shards.clone();
    foreign[1].plan.push_str(" (another)");
    assert!(merge(&foreign).unwrap_err().to_string().contains("different sweeps"));
}

#[test]
fn shards_parse_and_refuse_nonsense() {
    assert_eq!(Shard::parse("2/8").unwrap(), Shard { index: 2, count: 8 });
    for bad in ["8/8", "1/0", "x/2", "3", "-1/2"] {
        assert!(Shard::parse(bad).is_err(), "{bad} accepted");
    }
}
