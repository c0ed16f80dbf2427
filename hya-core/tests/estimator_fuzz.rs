//! Fuzzing the disturbance estimator with proptest: random filter parameters in the accepted
//! range, random sequences mixing ordinary, huge, tiny and non-finite samples. Laws: a refused
//! update changes nothing; an accepted one leaves every state finite; after any sample,
//! ordinary samples are accepted again; a constant disturbance is recovered after settling.
//!
//! The default run is a few hundred cases per law. A long run:
//! `PROPTEST_CASES=1000000 cargo test --release -p hya-core --test estimator_fuzz`.
#![allow(clippy::unwrap_used)] // test helpers: a failed unwrap is a failed test

use hya_core::test_arms::PlanarTwoLink;
use hya_core::{DisturbanceEstimator, Dynamics, FilterParams, JointVector};
use proptest::prelude::*;

/// 512 cases per law, or `PROPTEST_CASES` for a long run.
fn cases() -> u32 {
    std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(512)
}

/// Accepted parameters: `ζ ∈ [0.2, 3]`, `ω ∈ [1, 2000]` rad/s, `dt ∈ [1e-4, 1e-2]` s, with
/// `ω dt` within the accepted bound.
fn parameters() -> impl Strategy<Value = FilterParams> {
    (0.2..=3.0f64, 1.0..=2000.0f64, 1.0..=2000.0f64, 1e-4..=1e-2f64)
        .prop_filter_map("ω dt beyond the bound", |(zeta, w1, w2, dt)| FilterParams::new(zeta, w1, w2, dt).ok())
}

/// Parameters whose slowest mode settles within seconds: `ζ ∈ [0.3, 1.5]`, `ω ∈ [10, 2000]`.
fn settling_parameters() -> impl Strategy<Value = FilterParams> {
    (0.3..=1.5f64, 10.0..=2000.0f64, 10.0..=2000.0f64, 1e-4..=1e-2f64)
        .prop_filter_map("ω dt beyond the bound", |(zeta, w1, w2, dt)| FilterParams::new(zeta, w1, w2, dt).ok())
}

/// The decay rate of the second-order factor's slowest mode: `ζ ω2` when underdamped,
/// `ω2 (ζ − √(ζ² − 1))` when overdamped.
fn slowest_second_order_rate(params: &FilterParams) -> f64 {
    let (zeta, w) = (params.zeta(), params.omega2_rad_s());
    if zeta < 1.0 {
        zeta * w
    } else {
        w * (zeta - (zeta * zeta - 1.0).sqrt())
    }
}

/// One sample: mostly ordinary, sometimes huge, tiny (subnormal) or non-finite.
fn sample() -> impl Strategy<Value = f64> {
    prop_oneof![
        6 => -10.0..10.0f64,
        // Log-uniform from 1e6 to the largest finite value, either sign.
        1 => (6.0..=308.25f64, any::<bool>()).prop_map(|(e, negative)| {
            let x = 10f64.powf(e).min(f64::MAX);
            if negative { -x } else { x }
        }),
        1 => 1e-320..1e-300f64,
        1 => prop_oneof![Just(f64::NAN), Just(f64::INFINITY), Just(f64::NEG_INFINITY)],
    ]
}

/// `(q_m, τ_m)` for the two-link arm.
fn measurement() -> impl Strategy<Value = (JointVector<2>, JointVector<2>)> {
    [sample(), sample(), sample(), sample()]
        .prop_map(|[a, b, c, d]| (JointVector::from([a, b]), JointVector::from([c, d])))
}

/// Everything the estimator holds that a caller can see.
fn snapshot(e: &DisturbanceEstimator<2, PlanarTwoLink>) -> [f64; 10] {
    let j = e.joint_estimate();
    let (t, d) = (e.torque_estimate(), e.disturbance());
    [j.x1[0], j.x1[1], j.x2[0], j.x2[1], j.x3[0], j.x3[1], t[0], t[1], d[0], d[1]]
}

fn finite(values: &[f64]) -> bool {
    values.iter().all(|v| v.is_finite())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(), ..ProptestConfig::default() })]

    #[test]
    fn no_sample_poisons_the_estimator(params in parameters(), samples in proptest::collection::vec(measurement(), 1..40)) {
        let arm = PlanarTwoLink::default();
        let q0 = JointVector::from([0.3, -0.2]);
        let mut estimator = DisturbanceEstimator::new(arm, params, q0, arm.gravity(&q0)).unwrap();
        for (q, tau) in samples {
            let before = snapshot(&estimator);
            match estimator.update(&q, &tau) {
                Ok(d) => {
                    prop_assert!(finite(&snapshot(&estimator)), "an accepted sample left a non-finite state");
                    prop_assert!(finite(d.as_slice()));
                }
                Err(_) => prop_assert_eq!(snapshot(&estimator).map(f64::to_bits), before.map(f64::to_bits), "a refused sample changed the state"),
            }
            // An ordinary sample after anything is accepted again.
            let mut probe = estimator.clone();
            prop_assert!(probe.update(&q0, &arm.gravity(&q0)).is_ok(), "an ordinary sample was refused after {q:?}, {tau:?}");
        }
    }

    #[test]
    fn a_constant_disturbance_is_recovered(params in settling_parameters(), d in proptest::array::uniform2(-20.0..20.0f64), q in proptest::array::uniform2(-2.0..2.0f64)) {
        // Held still at q with τ_m = G(q) − d: then ID(q, 0, 0) − τ̂ → d.
        let arm = PlanarTwoLink::default();
        let (q, d) = (JointVector::from(q), JointVector::from(d));
        let tau = arm.gravity(&q) - d;
        let mut estimator = DisturbanceEstimator::new(arm, params, q, arm.gravity(&q)).unwrap();
        // Settle for 40 time constants of the slowest mode.
        let slowest = params.omega1_rad_s().min(slowest_second_order_rate(&params));
        let ticks = ((40.0 / slowest) / params.dt_s()).ceil() as usize;
        for _ in 0..ticks.max(10) {
            estimator.update(&q, &tau).unwrap();
        }
        let error = (estimator.disturbance() - d).amax();
        prop_assert!(error < 1e-6 * (1.0 + d.amax()), "error {error} after {ticks} ticks");
    }
}
