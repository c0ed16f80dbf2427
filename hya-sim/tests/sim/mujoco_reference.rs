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
//! (a wrong inertia, axis or gravity gives milliradians).

use hya_sim::rollout::{reference_gap, MUJOCO_HYA};

fn model(robot: &str) -> hya_core::model::TreeModel {
    hya_urdf::load_str(hya_robots::find(robot).unwrap().urdf, robot).unwrap().model
}

#[test]
fn hya_follows_mujoco() {
    let (q, qd) = reference_gap::<6>(&model("hya"), MUJOCO_HYA.0, MUJOCO_HYA.1).unwrap();
    eprintln!("hya: worst |Δq| {q:.2e} rad, |Δq̇| {qd:.2e} rad/s over 1 s");
    assert!(q < 1e-8 && qd < 1e-6, "HyA departs from MuJoCo by {q} rad, {qd} rad/s");
}

#[test]
fn iiwa14_follows_mujoco() {
    let torque = include_str!("../data/mujoco_iiwa14_torque.csv");
    let states = include_str!("../data/mujoco_iiwa14_rollout.csv");
    let (q, qd) = reference_gap::<7>(&model("iiwa14"), torque, states).unwrap();
    eprintln!("iiwa14: worst |Δq| {q:.2e} rad, |Δq̇| {qd:.2e} rad/s over 1 s");
    assert!(q < 1e-8 && qd < 1e-6, "iiwa14 departs from MuJoCo by {q} rad, {qd} rad/s");
}

#[test]
fn a_wrong_model_is_caught() {
    // The same comparison on a perturbed HyA: the tolerance is far below a modelling error.
    let mut rng = <rand_chacha::ChaCha8Rng as rand::SeedableRng>::seed_from_u64(5);
    let wrong = hya_sim::plant::perturbed(&model("hya"), 0.01, &mut rng);
    let (q, _) = reference_gap::<6>(&wrong, MUJOCO_HYA.0, MUJOCO_HYA.1).unwrap();
    assert!(q > 1e-4, "a 1 % inertia error moved the rollout by only {q} rad");
}
