//! hya's rigid-body plant against MuJoCo: the same URDF, the same recorded torque sequence, the
//! same start, friction, actuators and noise off (`tools/mujoco_rollout.py` wrote the reference,
//! with MuJoCo's RK4 at 0.1 ms, gravity 9.81 m/s² along −z, limits, contacts, damping and
//! armature off; its own error against a 0.01 ms step is below 2e-12 rad).
//!
//! Tolerance: both integrate with RK4 at 0.1 ms, so the two differ by rounding and by the
//! different order of floating-point operations in two dynamics implementations (≈ 1e-15 per
//! step); both start poses are unstable equilibria, along which a difference grows ≈ 1,250-fold
//! (HyA) and 300-fold (iiwa14) within the second, as the reference's header measures. 1e-8 rad
//! leaves that growth three orders of margin and still catches any modelling difference
//! (a wrong inertia, axis or gravity gives millradians).
#![allow(clippy::unwrap_used)] // test helpers: a failed unwrap is a failed test

use std::path::PathBuf;

use hya_core::JointVector;
use hya_sim::rollout::{ideal_plant, open_loop, TorqueCommand};
use hya_sim::SimError;

/// The numeric rows of a reference CSV (comment lines start with `#`).
pub fn rows(file: &str) -> Vec<Vec<f64>> {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data").join(file);
    std::fs::read_to_string(&path)
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .map(|l| l.split(',').map(|x| x.trim().parse().unwrap()).collect())
        .collect()
}

/// Worst `|q_hya − q_mujoco|` and `|q̇_hya − q̇_mujoco|` over the second.
fn worst_difference<const N: usize>(robot: &str) -> (f64, f64) {
    let model = hya_codegen::load_str(hya_robots::find(robot).unwrap().urdf, robot).unwrap().model;
    let commands: Vec<TorqueCommand<N>> = rows(&format!("mujoco_{robot}_torque.csv"))
        .iter()
        .map(|r| TorqueCommand { time: r[0], torque: JointVector::from_column_slice(&r[1..]) })
        .collect();
    let reference = rows(&format!("mujoco_{robot}_rollout.csv"));
    let q0 = JointVector::<N>::from_column_slice(&reference[0][1..=N]);
    let mut plant = ideal_plant(&model, q0).unwrap();
    let mut ours: Vec<(f64, JointVector<N>, JointVector<N>)> = Vec::new();
    open_loop(&mut plant, &commands, 1e-4, 1e-3, 1.0, |t, s| {
        ours.push((t, s.q, s.qd));
        Ok::<(), SimError>(())
    })
    .unwrap();
    assert_eq!(ours.len(), reference.len(), "one sample per reference row");
    let (mut q_worst, mut qd_worst) = (0.0_f64, 0.0_f64);
    for ((t, q, qd), row) in ours.iter().zip(&reference) {
        assert!((t - row[0]).abs() < 1e-12, "sample times differ: {t} against {}", row[0]);
        q_worst = q_worst.max((q - JointVector::<N>::from_column_slice(&row[1..=N])).amax());
        qd_worst = qd_worst.max((qd - JointVector::<N>::from_column_slice(&row[N + 1..])).amax());
    }
    let travel = (reference.last().unwrap()[1..=N].iter().zip(&reference[0][1..=N]))
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    eprintln!(
        "{robot}: worst |Δq| {q_worst:.2e} rad, |Δq̇| {qd_worst:.2e} rad/s over 1 s (largest travel {travel:.2} rad)"
    );
    (q_worst, qd_worst)
}

#[test]
fn hya_follows_mujoco() {
    let (q, qd) = worst_difference::<6>("hya");
    assert!(q < 1e-8 && qd < 1e-6, "HyA departs from MuJoCo by {q} rad, {qd} rad/s");
}

#[test]
fn iiwa14_follows_mujoco() {
    let (q, qd) = worst_difference::<7>("iiwa14");
    assert!(q < 1e-8 && qd < 1e-6, "iiwa14 departs from MuJoCo by {q} rad, {qd} rad/s");
}
