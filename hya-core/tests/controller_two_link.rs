//! Computed-torque control of the closed-form two-link arm.
#![allow(clippy::unwrap_used)] // test helpers: a failed unwrap is a failed test

mod common;

use common::Plant;
use hya_core::test_arms::PlanarTwoLink;
use hya_core::{
    ComputedTorque, DisturbanceEstimator, Dynamics, FilterParams, Gains, JointVector, PdPlacement, Reference,
};

fn smooth_reference(t: f64) -> Reference<2> {
    let w = JointVector::from([2.0, 3.1]);
    let amplitude = JointVector::from([0.5, -0.7]);
    let base = JointVector::from([0.3, 1.0]);
    let phase = w * t;
    let sin = phase.map(f64::sin);
    let cos = phase.map(f64::cos);
    Reference {
        position: base + amplitude.component_mul(&sin),
        velocity: amplitude.component_mul(&w).component_mul(&cos),
        acceleration: -amplitude.component_mul(&w).component_mul(&w).component_mul(&sin),
    }
}

#[test]
fn exact_model_tracks_a_smooth_reference_to_numerical_precision() {
    let arm = PlanarTwoLink::default();
    for placement in [PdPlacement::OutsideMassMatrix, PdPlacement::InsideMassMatrix] {
        let controller =
            ComputedTorque::new(&arm, Gains::diagonal([100.0, 100.0], [20.0, 20.0]).unwrap()).with_placement(placement);
        let mut plant = Plant::new(&arm, smooth_reference(0.0).position);
        plant.qd = smooth_reference(0.0).velocity;
        let mut worst: f64 = 0.0;
        // The law is evaluated inside every RK4 stage: continuous-time computed torque, so the
        // error obeys a homogeneous linear ODE from zero and only integration error remains.
        for _ in 0..5000 {
            plant.step(1e-3, |t, q, qd| controller.command(q, qd, &smooth_reference(t), None).unwrap().torque);
            worst = worst.max((plant.q - smooth_reference(plant.time).position).abs().max());
        }
        assert!(worst < 1e-9, "{placement:?}: worst tracking error {worst} rad");
    }
}

/// Holds a pose for 6 s at 1 kHz under a constant disturbance; the final error, rad.
fn final_error_under_constant_disturbance(compensate: bool) -> JointVector<2> {
    let arm = PlanarTwoLink::default();
    let d = JointVector::from([4.0, -2.0]);
    let target = Reference::hold(JointVector::from([0.5, 0.5]));
    let controller = ComputedTorque::new(&arm, Gains::diagonal([150.0, 80.0], [25.0, 15.0]).unwrap());
    let start = JointVector::from([0.3, 0.6]);
    let mut plant = Plant::new(&arm, start);
    let mut estimator =
        DisturbanceEstimator::new(&arm, FilterParams::paper(1e-3).unwrap(), start, arm.gravity(&start)).unwrap();
    for _ in 0..6000 {
        let estimate = compensate.then_some(estimator.disturbance());
        let tau = controller.command(&plant.q, &plant.qd, &target, estimate).unwrap().torque;
        for _ in 0..10 {
            plant.step(1e-4, |_, _, _| tau + d);
        }
        estimator.update(&plant.q, &tau).unwrap();
    }
    plant.q - target.position
}

#[test]
fn compensation_removes_the_steady_error_of_a_constant_disturbance() {
    let without = final_error_under_constant_disturbance(false);
    let with = final_error_under_constant_disturbance(true);
    // Uncompensated, the paper's law settles where K_P e = d: e = (4/150, −2/80) rad.
    assert!((without - JointVector::from([4.0 / 150.0, -2.0 / 80.0])).abs().max() < 1e-6, "{without}");
    assert!(with.abs().max() < 1e-3 * without.abs().min(), "with compensation: {with}");
}

#[test]
fn torque_limits_saturate_and_report() {
    let arm = PlanarTwoLink::default();
    let controller = ComputedTorque::new(&arm, Gains::diagonal([1000.0, 1000.0], [0.0, 0.0]).unwrap())
        .with_torque_limit(JointVector::from([5.0, 50.0]))
        .unwrap();
    let q = JointVector::from([0.0, 0.0]);
    let command =
        controller.command(&q, &JointVector::zeros(), &Reference::hold(JointVector::from([0.1, 0.001])), None).unwrap();
    let unlimited = arm.gravity(&q) + JointVector::from([100.0, 1.0]);
    assert_eq!(command.saturated, [true, false]);
    assert_eq!(command.torque[0], 5.0);
    assert!((command.torque[1] - unlimited[1]).abs() < 1e-12);
}

#[test]
fn bad_inputs_are_errors_never_non_finite_commands() {
    let arm = PlanarTwoLink::default();
    let controller = ComputedTorque::new(&arm, Gains::diagonal([10.0, 10.0], [1.0, 1.0]).unwrap());
    let q = JointVector::from([0.1, 0.2]);
    let mut reference = Reference::hold(q);
    reference.acceleration[1] = f64::NAN;
    let error = controller.command(&q, &JointVector::zeros(), &reference, None).unwrap_err();
    assert!(matches!(error, hya_core::Error::NonFinite { signal: "qdd_des", index: 1, .. }));
    let bad_estimate = JointVector::from([f64::INFINITY, 0.0]);
    let error = controller.command(&q, &JointVector::zeros(), &Reference::hold(q), Some(&bad_estimate)).unwrap_err();
    assert!(matches!(error, hya_core::Error::NonFinite { signal: "d_hat", index: 0, .. }));
    assert!(matches!(
        Gains::diagonal([-1.0, 1.0], [1.0, 1.0]),
        Err(hya_core::Error::InvalidParameter { name: "kp", .. })
    ));
}
