//! `robot!` on a URDF of its own (the messages of bad input: the crate's unit tests).
#![allow(clippy::unwrap_used)] // test helpers: a failed unwrap is a failed test

use hya_core::{Dynamics, JointVector};

hya_macros::robot!(Arm, "tests/urdf/arm.urdf");

#[test]
fn macro_generated_dynamics_work() {
    assert_eq!(Arm::DOF, 2);
    assert_eq!(Arm::JOINT_NAMES, ["shoulder", "elbow"]);
    // Stretched out horizontally, gravity pulls with m g r on each joint:
    // shoulder: 9.81 (3 · 0.25 + 2 · 0.7), elbow: 9.81 · 2 · 0.2, against +y rotation.
    let g = Arm.gravity(&JointVector::zeros());
    assert!((g[0] + 9.81 * (3.0 * 0.25 + 2.0 * 0.7)).abs() < 1e-12, "{g}");
    assert!((g[1] + 9.81 * 2.0 * 0.2).abs() < 1e-12, "{g}");
}
