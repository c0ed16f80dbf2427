//! The paired control tick ([`DisturbanceAttenuation::tick`]) on every shipped arm's generated
//! dynamics, where its two inverse dynamics run as one batch, against the estimator's update
//! followed by the controller's command: equal bit for bit, and on bad input the same error,
//! with nothing committed.
#![allow(clippy::unwrap_used)] // test helpers: a failed unwrap is a failed test

use hya_core::control::{PdPlacement, Reference};
use hya_core::{ComputedTorque, DisturbanceAttenuation, DisturbanceEstimator, Dynamics, FilterParams, Gains};
use hya_core::{Error, JointVector};
use proptest::prelude::*;

/// Runs `ticks` (measured angle offset, velocity, torque; a `NaN` marks a bad sample) through
/// the paired tick and through `update` then `command` on the same model, and compares every
/// command and estimate exactly.
fn check_tick<const N: usize, D: Dynamics<N> + Clone>(
    dynamics: D,
    placement: PdPlacement,
    home: JointVector<N>,
    ticks: &[(JointVector<N>, JointVector<N>, JointVector<N>)],
) -> Result<(), TestCaseError> {
    let params = FilterParams::paper(1e-3).unwrap();
    let gains = Gains::diagonal([150.0; N], [15.0; N]).unwrap();
    let limit = JointVector::from_element(80.0);
    let tau0 = dynamics.gravity(&home);
    let mut paired = DisturbanceAttenuation::new(dynamics.clone(), params, gains, home, tau0)
        .unwrap()
        .with_placement(placement)
        .with_torque_limit(limit)
        .unwrap();
    let mut estimator = DisturbanceEstimator::new(dynamics.clone(), params, home, tau0).unwrap();
    let controller = ComputedTorque::new(dynamics, gains).with_placement(placement).with_torque_limit(limit).unwrap();
    let reference = Reference { position: home, velocity: JointVector::from_element(0.1), acceleration: home * 0.5 };
    for (k, (offset, qd, tau)) in ticks.iter().enumerate() {
        let q = home + offset;
        let state = |p: &DisturbanceAttenuation<N, D>| {
            (*p.disturbance(), *p.estimator().joint_estimate(), *p.estimator().torque_estimate())
        };
        let before = state(&paired);
        let got = paired.tick(&q, qd, tau, &reference);
        let expected = estimator.update(&q, tau).and_then(|d_hat| controller.command(&q, qd, &reference, Some(&d_hat)));
        match (got, expected) {
            (Ok(got), Ok(expected)) => {
                prop_assert_eq!(got, expected, "command, tick {}", k);
                prop_assert_eq!(paired.disturbance(), estimator.disturbance(), "d̂, tick {}", k);
            }
            (Err(got), Err(expected)) => {
                // The same refusal, naming the same signal, entry and value (compared as text:
                // a NaN value is not equal to itself).
                prop_assert_eq!(format!("{got:?}"), format!("{expected:?}"), "error, tick {}", k);
                prop_assert!(matches!(got, Error::NonFinite { .. }), "tick {}: {:?}", k, got);
                prop_assert_eq!(state(&paired), before, "a refused tick changes nothing, tick {}", k);
                // The two-call reference may have committed its update before the command failed;
                // restart it from the paired tick's state so the next ticks compare again.
                estimator = paired.estimator().clone();
            }
            (got, expected) => prop_assert!(false, "tick {}: paired {:?}, in sequence {:?}", k, got, expected),
        }
    }
    Ok(())
}

fn ticks<const N: usize>() -> impl Strategy<Value = Vec<(JointVector<N>, JointVector<N>, JointVector<N>)>> {
    let vector = |bound: f64| proptest::array::uniform::<_, N>(-bound..bound).prop_map(JointVector::from);
    let tick = (vector(0.3), vector(2.0), vector(60.0), 0..20u8).prop_map(|(q, mut qd, tau, bad)| {
        // One tick in twenty has a non-finite velocity: refused by the controller's law.
        if bad == 0 {
            qd[0] = f64::NAN;
        }
        (q, qd, tau)
    });
    proptest::collection::vec(tick, 1..40)
}

macro_rules! robot_tests {
    ($($module:ident $type:ident $parametric:ident $dof:literal [$($home:expr),*] $doc:literal;)*) => {$(
        mod $module {
            use super::*;
            use hya_robots::$module::{$type, HOME};

            proptest! {
                #![proptest_config(ProptestConfig { cases: 16, ..ProptestConfig::default() })]

                #[test]
                fn the_paired_tick_equals_update_then_command(ticks in ticks::<$dof>(), inside in any::<bool>()) {
                    let placement = if inside { PdPlacement::InsideMassMatrix } else { PdPlacement::OutsideMassMatrix };
                    check_tick(&$type, placement, JointVector::from(HOME), &ticks)?;
                }
            }
        }
    )*};
}

hya_robots::for_each_robot!(robot_tests);

/// A model without batch entry points of its own runs the tick through the default loop.
#[test]
fn the_paired_tick_on_a_looping_model_equals_update_then_command() {
    let arm = hya_core::test_arms::PlanarTwoLink::default();
    let ticks: Vec<_> = (0..200)
        .map(|k| {
            let t = k as f64 * 1e-3;
            let q = JointVector::from([0.1 * t.sin(), -0.2 * t.cos()]);
            (q, q * 3.0, JointVector::from([5.0 * t.cos(), if k == 77 { f64::INFINITY } else { 1.0 }]))
        })
        .collect();
    let home = JointVector::from([0.3, -0.2]);
    for placement in [PdPlacement::OutsideMassMatrix, PdPlacement::InsideMassMatrix] {
        check_tick(&arm, placement, home, &ticks).unwrap();
    }
}
