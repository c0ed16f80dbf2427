//! The disturbance estimator on the closed-form two-link arm, driven by a trajectory integrated
//! from the true dynamics with a known disturbance.
#![allow(clippy::unwrap_used)] // test helpers: a failed unwrap is a failed test

mod common;

use common::{fit_sine, Plant};
use hya_core::test_arms::PlanarTwoLink;
use hya_core::{ComputedTorque, DisturbanceEstimator, Dynamics, FilterParams, Gains, JointVector, Reference};
use nalgebra::ComplexField;

const CONTROL_DT: f64 = 1e-3;
const SUBSTEPS: usize = 10;

/// Closed loop at 1 kHz: an uncompensated PD computed-torque law tracks `reference(t)` while the
/// plant feels `disturbance(t)`; returns `(t, d(t), d̂(t))` per tick.
fn closed_loop(
    duration: f64,
    reference: impl Fn(f64) -> Reference<2>,
    disturbance: impl Fn(f64) -> JointVector<2>,
) -> Vec<(f64, JointVector<2>, JointVector<2>)> {
    let arm = PlanarTwoLink::default();
    let controller = ComputedTorque::new(&arm, Gains::diagonal([200.0, 120.0], [30.0, 18.0]).unwrap());
    let start = reference(0.0).position;
    let mut plant = Plant::new(&arm, start);
    let mut estimator =
        DisturbanceEstimator::new(&arm, FilterParams::paper(CONTROL_DT).unwrap(), start, arm.gravity(&start)).unwrap();
    let mut trace = Vec::new();
    let mut previous = arm.gravity(&start);
    while plant.time < duration {
        let t0 = plant.time;
        let tau = controller.command(&plant.q, &plant.qd, &reference(t0), None).unwrap().torque;
        // The actuator ramps from the previous command to the new one over one tick, so the
        // joint torque is continuous and τ_m, its sample at the tick's end, is exact.
        for _ in 0..SUBSTEPS {
            plant.step(CONTROL_DT / SUBSTEPS as f64, |s, _, _| {
                previous + (tau - previous) * ((s - t0) / CONTROL_DT) + disturbance(s)
            });
        }
        previous = tau;
        let estimate = estimator.update(&plant.q, &tau).unwrap();
        trace.push((plant.time, disturbance(plant.time), estimate));
    }
    trace
}

/// A slow, smooth motion of both joints (0.2 Hz, 0.3 rad).
fn slow_sine(t: f64) -> Reference<2> {
    let w = 2.0 * std::f64::consts::PI * 0.2;
    let base = JointVector::from([0.4, 0.8]);
    let shape = JointVector::from([0.3, -0.3]);
    Reference {
        position: base + shape * (w * t).sin(),
        velocity: shape * (w * (w * t).cos()),
        acceleration: shape * (-w * w * (w * t).sin()),
    }
}

#[test]
fn constant_disturbance_is_recovered_while_the_arm_moves() {
    let d = JointVector::from([2.5, -1.5]);
    let trace = closed_loop(8.0, slow_sine, |_| d);
    // After the filter has settled (≈ 10 group delays), every tick is within 0.1 %.
    let worst = trace
        .iter()
        .filter(|(t, ..)| *t > 2.0)
        .map(|(_, d, estimate)| (estimate - d).abs().component_div(&d.abs()).max())
        .fold(0.0, f64::max);
    eprintln!("constant disturbance: worst relative error of d̂ after 2 s: {worst:.3e}");
    assert!(worst < 1e-3, "worst relative error {worst}");
}

#[test]
fn sinusoidal_disturbance_leaves_the_predicted_residual() {
    let frequency = 2.0 * std::f64::consts::PI; // 1 Hz
    let amplitude = JointVector::from([3.0, 1.5]);
    let trace =
        closed_loop(6.0, |_| Reference::hold(JointVector::from([0.4, 0.8])), |t| amplitude * (frequency * t).sin());
    // Residual d̂ − d ≈ (H(jω) − 1) d for a slowly varying configuration: |1 − H(j2π)| = 0.32.
    let params = FilterParams::paper(CONTROL_DT).unwrap();
    let predicted = (params.continuous_response(frequency)[0] - 1.0).modulus();
    for joint in 0..2 {
        let residual: Vec<(f64, f64)> =
            trace.iter().filter(|(t, ..)| *t > 3.0).map(|(t, d, e)| (*t, e[joint] - d[joint])).collect();
        let ratio = fit_sine(frequency, &residual).modulus() / amplitude[joint];
        eprintln!("1 Hz disturbance, joint {joint}: residual {ratio:.4} of the amplitude, predicted {predicted:.4}");
        assert!((ratio / predicted - 1.0).abs() < 0.1, "joint {joint}: residual ratio {ratio}, predicted {predicted}");
    }
}

#[test]
fn bad_measurement_is_rejected_and_the_estimate_kept() {
    let arm = PlanarTwoLink::default();
    let q0 = JointVector::from([0.1, 0.2]);
    let mut estimator =
        DisturbanceEstimator::new(&arm, FilterParams::paper(1e-3).unwrap(), q0, arm.gravity(&q0)).unwrap();
    estimator.update(&q0, &JointVector::from([10.0, 3.0])).unwrap();
    let before = (*estimator.disturbance(), *estimator.joint_estimate(), *estimator.torque_estimate());
    let error = estimator.update(&JointVector::from([0.1, f64::INFINITY]), &JointVector::zeros()).unwrap_err();
    assert!(matches!(error, hya_core::Error::NonFinite { signal: "q_m", index: 1, .. }), "{error}");
    let error = estimator.update(&q0, &JointVector::from([f64::NAN, 0.0])).unwrap_err();
    assert!(matches!(error, hya_core::Error::NonFinite { signal: "tau_m", index: 0, .. }), "{error}");
    assert_eq!(before, (*estimator.disturbance(), *estimator.joint_estimate(), *estimator.torque_estimate()));
}
