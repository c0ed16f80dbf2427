//! Every observer on the same footing: a constant disturbance is recovered, and on a linear plant
//! (a rotor, `I q̈ = τ + d`) the transfer from `d` to `d̂` is the observer's design.
#![allow(clippy::unwrap_used)] // test helpers: a failed unwrap is a failed test

mod common;

use common::{fit_sine, Plant};
use hya_core::test_arms::{PlanarTwoLink, Rotor};
use hya_core::{
    DisturbanceEstimator, DisturbanceObserver, Dynamics, ExtendedStateObserver, FilterParams, JointVector, Measurement,
    MomentumObserver, NonlinearDisturbanceObserver,
};
use nalgebra::{Complex, ComplexField};

const DT: f64 = 1e-3;
const BANDWIDTH: f64 = 50.0;

/// The four observers at 50 rad/s on a model `D`, with their design transfer functions `d̂/d`.
type Observer<const N: usize> = Box<dyn DisturbanceObserver<N>>;
/// An observer's design `d̂/d (jω)`.
type Design = Box<dyn Fn(f64) -> Complex<f64>>;

fn observers<const N: usize, D: Dynamics<N> + Copy + 'static>(
    dynamics: D,
    q0: JointVector<N>,
    ndob_gain: f64,
) -> Vec<(&'static str, Observer<N>, Design)> {
    let params = FilterParams::paper(DT).unwrap();
    let zero = JointVector::zeros();
    let lag = |k: f64| move |w: f64| Complex::new(k, 0.0) / Complex::new(k, w);
    vec![
        (
            "lu",
            Box::new(DisturbanceEstimator::new(dynamics, params, q0, dynamics.gravity(&q0)).unwrap()),
            Box::new(move |w| params.continuous_response(w)[0]),
        ),
        (
            "chen",
            Box::new(NonlinearDisturbanceObserver::new(dynamics, ndob_gain, DT, zero).unwrap()),
            Box::new(lag(BANDWIDTH)),
        ),
        (
            "momentum",
            Box::new(
                MomentumObserver::new(dynamics, JointVector::repeat(BANDWIDTH), DT, q0, zero, dynamics.gravity(&q0))
                    .unwrap(),
            ),
            Box::new(lag(BANDWIDTH)),
        ),
        (
            "eso",
            Box::new(ExtendedStateObserver::new(dynamics, BANDWIDTH, DT, q0).unwrap()),
            Box::new(|w: f64| {
                let pole = Complex::new(BANDWIDTH, w);
                Complex::new(BANDWIDTH.powi(3), 0.0) / (pole * pole * pole)
            }),
        ),
    ]
}

/// Holds the plant near `q0` with a PD law at 1 kHz under `disturbance(t)`; returns `(t, d, d̂)`
/// per tick for one observer. The actuator ramps to each new command over one tick, so the joint
/// torque is continuous and its samples are exact, as for a real actuator's torque sensor.
fn run<const N: usize, D: Dynamics<N> + Copy>(
    dynamics: D,
    q0: JointVector<N>,
    observer: &mut dyn DisturbanceObserver<N>,
    disturbance: impl Fn(f64) -> JointVector<N>,
    duration: f64,
) -> Vec<(f64, JointVector<N>, JointVector<N>)> {
    let mut plant = Plant::new(dynamics, q0);
    let mut trace = Vec::new();
    let mut previous = dynamics.gravity(&q0);
    while plant.time < duration {
        let tau = dynamics.gravity(&plant.q) - (plant.q - q0) * 40.0 - plant.qd * 8.0;
        let start = plant.time;
        for _ in 0..10 {
            plant.step(DT / 10.0, |t, _, _| previous + (tau - previous) * ((t - start) / DT) + disturbance(t));
        }
        previous = tau;
        let measurement = Measurement { position: plant.q, velocity: Some(plant.qd), torque: tau };
        let estimate = observer.update(&measurement).unwrap();
        trace.push((plant.time, disturbance(plant.time), estimate));
    }
    trace
}

#[test]
fn every_observer_recovers_a_constant_disturbance_on_the_two_link_arm() {
    let arm = PlanarTwoLink::default();
    let q0 = JointVector::from([0.4, 0.8]);
    // Chen's gain for convergence rate 50/s: y = β σ with σ ≥ λmax(M) over the motion.
    let sigma = arm.mass_matrix(&q0).symmetric_eigenvalues().max() * 1.2;
    let gain = hya_core::observers::mohammadi_gain(BANDWIDTH, sigma, 0.0).unwrap();
    let d = JointVector::from([3.0, -1.2]);
    for (name, mut observer, _) in observers(arm, q0, gain) {
        let trace = run(arm, q0, observer.as_mut(), |_| d, 3.0);
        let (_, _, last) = trace.last().unwrap();
        assert!((last - d).norm() < 1e-4 * d.norm(), "{name}: d̂ = {last}, d = {d}");
    }
}

#[test]
fn each_observer_follows_its_design_transfer_function_on_a_linear_plant() {
    let rotor = Rotor { inertia_kg_m2: 0.5 };
    let q0 = JointVector::from([0.0]);
    // Chen's L = y / I = 50/s.
    for omega in [5.0, 20.0, 50.0] {
        for (name, mut observer, design) in observers(rotor, q0, BANDWIDTH * rotor.inertia_kg_m2) {
            let trace = run(rotor, q0, observer.as_mut(), |t| JointVector::from([2.0 * (omega * t).sin()]), 4.0);
            let samples: Vec<(f64, f64)> =
                trace.iter().filter(|(t, ..)| *t > 2.0).map(|(t, _, e)| (*t, e[0])).collect();
            let measured = fit_sine(omega, &samples) / 2.0;
            let expected = design(omega);
            let gain_ratio = measured.modulus() / expected.modulus();
            let phase_deg = (measured / expected).argument().to_degrees();
            eprintln!("{name} at {omega} rad/s: gain ratio {gain_ratio:.4}, phase error {phase_deg:.2}°");
            assert!((gain_ratio - 1.0).abs() < 0.02, "{name} at {omega} rad/s: gain ratio {gain_ratio}");
            assert!(phase_deg.abs() < 2.0, "{name} at {omega} rad/s: phase error {phase_deg}°");
        }
    }
}

#[test]
fn velocity_based_observers_ask_for_the_velocity() {
    let rotor = Rotor { inertia_kg_m2: 0.5 };
    let zero = JointVector::from([0.0]);
    let without_velocity = Measurement { position: zero, velocity: None, torque: zero };
    let mut chen = NonlinearDisturbanceObserver::new(rotor, 25.0, DT, zero).unwrap();
    let mut momentum = MomentumObserver::new(rotor, JointVector::from([50.0]), DT, zero, zero, zero).unwrap();
    for result in [chen.update(&without_velocity), momentum.update(&without_velocity)] {
        assert!(matches!(result, Err(hya_core::Error::MissingMeasurement { signal: "qd_m" })));
    }
}

#[test]
fn the_inertia_shaped_gain_gives_equal_rates_at_the_design_pose() {
    let arm = PlanarTwoLink::default();
    let q0 = JointVector::from([0.4, 0.8]);
    let zero = JointVector::zeros();
    let shaped = NonlinearDisturbanceObserver::with_bandwidth(arm, BANDWIDTH, DT, &q0, zero).unwrap();
    for rate in shaped.rates(&q0).unwrap().iter() {
        assert!((rate - BANDWIDTH).abs() < 1e-9 * BANDWIDTH, "rates {:?}", shaped.rates(&q0).unwrap());
    }
    // Mohammadi's scalar gain spreads the rates by the inertia ratio: y / λ(M).
    let masses = arm.mass_matrix(&q0).symmetric_eigenvalues();
    let scalar = NonlinearDisturbanceObserver::new(arm, 10.0, DT, zero).unwrap();
    let rates = scalar.rates(&q0).unwrap();
    let expected = [10.0 / masses.max(), 10.0 / masses.min()];
    for (r, e) in rates.iter().zip(expected) {
        assert!((r - e).abs() < 1e-9 * e, "rates {rates:?}, expected {expected:?}");
    }
    // The shaped observer still recovers a constant disturbance away from q0's velocity.
    let d = JointVector::from([3.0, -1.2]);
    let mut observer = shaped;
    let trace = run(arm, q0, &mut observer, |_| d, 3.0);
    let (_, _, last) = trace.last().unwrap();
    assert!((last - d).norm() < 1e-4 * d.norm(), "d̂ = {last}, d = {d}");
    // A non-symmetric or indefinite gain is refused.
    let skew = hya_core::JointMatrix::<2>::new(1.0, 0.5, 0.0, 1.0);
    assert!(NonlinearDisturbanceObserver::with_gain_matrix(arm, skew, DT, zero).is_err());
}

#[test]
fn a_bandwidth_beyond_the_sample_rate_is_refused_by_name() {
    let arm = PlanarTwoLink::default();
    let (q0, zero) = (JointVector::from([0.4, 0.8]), JointVector::zeros());
    let at_limit = hya_core::MAX_RATE_TIMES_DT / DT;
    assert!(NonlinearDisturbanceObserver::with_bandwidth(arm, at_limit, DT, &q0, zero).is_ok());
    for bandwidth in [at_limit * 1.01, 1e9, 1e300, f64::INFINITY, f64::NAN, 0.0, -50.0] {
        let error = NonlinearDisturbanceObserver::with_bandwidth(arm, bandwidth, DT, &q0, zero).unwrap_err();
        assert!(error.to_string().contains("bandwidth"), "β = {bandwidth}: {error}");
    }
    let error =
        NonlinearDisturbanceObserver::with_bandwidth(arm, BANDWIDTH, DT, &JointVector::from([0.4, f64::NAN]), zero)
            .unwrap_err();
    assert!(error.to_string().contains("q0"), "{error}");
    // The scalar gain: its slowest rate at q = 0 is y / λmax(M(0)).
    let heaviest = arm.mass_matrix(&zero).symmetric_eigenvalues().max();
    let at_limit = hya_core::MAX_RATE_TIMES_DT / DT * heaviest;
    assert!(NonlinearDisturbanceObserver::new(arm, at_limit * 0.999, DT, zero).is_ok());
    for gain in [at_limit * 1.01, 1e300] {
        let error = NonlinearDisturbanceObserver::new(arm, gain, DT, zero).unwrap_err().to_string();
        assert!(error.contains("gain") && error.contains("slowest rate"), "y = {gain}: {error}");
    }
}
