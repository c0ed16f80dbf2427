//! The HyA control tick (estimator update plus controller step on the generated model) and the
//! simulation throughput of `goto_internal`. `cargo bench -p hya-sim` (divan).

use divan::black_box;
use hya_core::{ComputedTorque, DisturbanceEstimator, Dynamics, FilterParams, Gains, JointVector, Reference};
use hya_robots::Hya;

fn main() {
    divan::main();
}

#[divan::bench(sample_count = 100, sample_size = 1000)]
fn hya_control_tick(bencher: divan::Bencher) {
    let q0 = JointVector::<6>::from(hya_robots::hya::HOME);
    let params = FilterParams::paper(1e-3).expect("the paper's filter is valid");
    let mut estimator = DisturbanceEstimator::new(Hya, params, q0, Hya.gravity(&q0)).expect("valid start");
    let controller = ComputedTorque::new(Hya, Gains::diagonal([300.0; 6], [30.0; 6]).expect("valid gains"));
    let reference = Reference::hold(q0);
    let mut k = 0u32;
    bencher.bench_local(|| {
        k = k.wrapping_add(1);
        let q = q0.add_scalar(f64::from(k % 1000) * 1e-5);
        let d_hat = estimator.update(black_box(&q), black_box(&q0)).unwrap_or_default();
        black_box(controller.command(&q, &q0, &reference, Some(&d_hat)).map(|c| c.torque).unwrap_or_default());
    });
}

/// Ten simulated seconds of `goto_internal` with the paper's method: divide 10 s by the time
/// shown for simulated seconds per wall-clock second.
#[divan::bench(sample_count = 3, sample_size = 1)]
fn goto_internal_ten_seconds() {
    let mut scenario = hya_sim::Scenario::builtin("goto_internal").expect("built in");
    scenario.duration_s = 10.0;
    black_box(hya_sim::run_method::<{ hya_sim::HYA_JOINTS }>(&scenario, hya_sim::Method::Lu).expect("runs"));
}
