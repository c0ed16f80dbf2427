//! The Cartesian impedance controller on the shipped Panda (generated dynamics, the run-time
//! model's frame kinematics): its posture term exerts no force at the tool, and on a simulated
//! arm pushed by a constant joint-torque disturbance it holds the tool's pose when given that
//! disturbance as `d̂`, which checks the compensation's sign and place in the law.
#![allow(clippy::unwrap_used)] // test helpers: a failed unwrap is a failed test

use hya_core::cartesian::Vector6;
use hya_core::model::TreeModel;
use hya_core::{CartesianImpedance, CartesianReference, Dynamics, FrameState, Impedance, JointVector};
use hya_robots::Panda;

const READY: [f64; 7] = [0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785];

fn panda_tree() -> (TreeModel, String) {
    let robot = hya_robots::find("panda").unwrap();
    let model = hya_urdf::load_str(robot.urdf, robot.name).unwrap().model;
    let tool = model.frames().last().unwrap().name.clone();
    (model, tool)
}

fn impedance() -> Impedance<7> {
    Impedance::new([600.0, 600.0, 600.0, 40.0, 40.0, 40.0], [60.0, 60.0, 60.0, 4.0, 4.0, 4.0])
        .unwrap()
        .with_posture(READY, [5.0; 7], [2.0; 7])
        .unwrap()
}

#[test]
fn the_posture_term_exerts_no_force_at_the_tool() {
    let (model, tool) = panda_tree();
    let q = JointVector::<7>::from([0.3, -0.5, 0.2, -2.0, 0.1, 1.8, 0.4]);
    let qd = JointVector::<7>::from([0.2, -0.1, 0.3, 0.1, -0.2, 0.05, 0.4]);
    let frame = FrameState::of_tree(&model, &tool, &q).unwrap();
    let reference = CartesianReference::hold(frame.position, frame.orientation);
    let task_only = Impedance::new([300.0; 6], [30.0; 6]).unwrap().with_regularisation(0.0).unwrap();
    let with_posture = task_only.with_posture(READY, [50.0; 7], [5.0; 7]).unwrap();
    let command = |gains| CartesianImpedance::new(Panda, gains).command(&q, &qd, &frame, &reference, None).unwrap();
    let posture = command(with_posture).torque - command(task_only).torque;
    assert!(posture.norm() > 1.0, "the posture term acts: {posture}");
    // J P = J − J Jᵀ (J Jᵀ)⁻¹ J = 0: no wrench at the tool.
    let at_tool = frame.jacobian * posture;
    assert!(at_tool.norm() < 1e-9 * posture.norm(), "{at_tool}");
}

/// Simulates the Panda under the controller for `seconds` (semi-implicit Euler at 1 ms) from
/// rest at `READY`, the tool's target moved from there by `offset` (2 cm and 0.1 rad), with a
/// constant joint-torque disturbance `d` acting on the arm, `d̂` given or not; returns the final
/// pose error, joint speed and the tool's final kinematics.
fn hold_against(
    offset: bool,
    d: JointVector<7>,
    d_hat: Option<JointVector<7>>,
    seconds: f64,
) -> (Vector6, f64, FrameState<7>) {
    let (model, tool) = panda_tree();
    let controller = CartesianImpedance::new(Panda, impedance());
    let (mut q, mut qd) = (JointVector::<7>::from(READY), JointVector::<7>::zeros());
    let start = FrameState::of_tree(&model, &tool, &q).unwrap();
    let mut reference = CartesianReference::hold(start.position, start.orientation);
    if offset {
        reference.position += start.orientation * vector(0.02, -0.01, 0.015);
        let turn = CartesianImpedance::<7, Panda>::pose_error(&start, &reference);
        assert!(turn.norm() > 0.02, "the target is away from the start");
        reference.orientation = small_turn(0.1) * start.orientation;
    }
    let dt = 1e-3;
    for _ in 0..(seconds / dt) as usize {
        let frame = FrameState::of_tree(&model, &tool, &q).unwrap();
        let tau = controller.command(&q, &qd, &frame, &reference, d_hat.as_ref()).unwrap().torque;
        let qdd = Panda.forward_dynamics(&q, &qd, &(tau + d)).unwrap();
        qd += qdd * dt;
        q += qd * dt;
    }
    let frame = FrameState::of_tree(&model, &tool, &q).unwrap();
    (CartesianImpedance::<7, Panda>::pose_error(&frame, &reference), qd.norm(), frame)
}

/// `(x, y, z)` as the controller's vector type (the test crate does not depend on nalgebra).
fn vector(x: f64, y: f64, z: f64) -> hya_core::cartesian::Vector3 {
    hya_core::cartesian::Vector3::new(x, y, z)
}

/// A rotation by `angle` about the base's `(1, 1, 1)/√3`.
fn small_turn(angle: f64) -> hya_core::cartesian::Matrix3 {
    let k = 1.0 / 3f64.sqrt();
    let (s, c) = (angle.sin(), angle.cos());
    let skew = hya_core::cartesian::Matrix3::new(0.0, -k, k, k, 0.0, -k, -k, k, 0.0);
    hya_core::cartesian::Matrix3::identity() + skew * s + skew * skew * (1.0 - c)
}

#[test]
fn the_tool_reaches_a_moved_target_and_compensation_cancels_a_known_disturbance() {
    let d = JointVector::<7>::from([2.0, -6.0, 1.5, 4.0, -1.0, 2.0, 0.5]);
    // From 2 cm and 0.1 rad away, with the disturbance cancelled: the spring and damper bring
    // the tool onto the target (a sign error in e, in log(R_des Rᵀ) or in D_x would not).
    let (reached, speed, _) = hold_against(true, d, Some(d), 3.0);
    assert!(reached.norm() < 1e-4 && speed < 1e-3, "error {reached}, speed {speed}");
    // Without d̂ the spring yields until K e balances the disturbance's wrench at the tool:
    // K e = −(J Jᵀ)⁻¹ J d at rest (the posture term exerts none).
    let (yielded, speed, frame) = hold_against(false, d, None, 3.0);
    assert!(speed < 1e-3, "at rest: {speed}");
    let stiffness = Vector6::new(600.0, 600.0, 600.0, 40.0, 40.0, 40.0);
    let j = frame.jacobian;
    let wrench = -(j * j.transpose()).cholesky().unwrap().solve(&(j * d));
    let predicted = wrench.component_div(&stiffness);
    assert!((yielded - predicted).norm() < 0.05 * predicted.norm(), "yielded {yielded}, predicted {predicted}");
    assert!(predicted.norm() > 1e-2, "a disturbance the test can see: {predicted}");
}

#[test]
fn bad_gains_and_a_reference_that_is_no_rotation_are_refused() {
    assert!(Impedance::<7>::new([f64::NAN; 6], [1.0; 6]).is_err());
    assert!(Impedance::<7>::new([1.0; 6], [-1.0; 6]).is_err());
    assert!(impedance().with_regularisation(-1.0).is_err());
    let (model, tool) = panda_tree();
    let q = JointVector::<7>::from(READY);
    let frame = FrameState::of_tree(&model, &tool, &q).unwrap();
    let skewed = CartesianReference::hold(frame.position, frame.orientation * 1.1);
    let refused = CartesianImpedance::new(Panda, impedance()).command(&q, &JointVector::zeros(), &frame, &skewed, None);
    assert!(matches!(refused, Err(hya_core::Error::InvalidParameter { name: "orientation_des", .. })), "{refused:?}");
    assert!(FrameState::<7>::of_tree(&model, "no_such_link", &q).is_err());
}
