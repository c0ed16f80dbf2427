//! The testbed's own laws: seeded runs repeat bit for bit, the free rigid body conserves energy.
//! (The paper's claims are the report's output, never asserted here.)

use hya_core::JointVector;
use hya_sim::plant::Plant;
use hya_sim::scenario::{ActuatorKind, FrictionKind, LoadConfig, PlantConfig};
use hya_sim::{run_method, Method, Scenario};
use rand::SeedableRng;

#[test]
fn seeded_runs_are_bit_identical() {
    let mut scenario = Scenario::builtin("goto_weight").unwrap().quick();
    scenario.duration_s = 9.0; // through the weight drop at 7.4 s
    let first = run_method::<6>(&scenario, Method::Lu).unwrap();
    let second = run_method::<6>(&scenario, Method::Lu).unwrap();
    assert_eq!(first.trace.q, second.trace.q);
    assert_eq!(first.trace.d_hat, second.trace.d_hat);
    assert_eq!(first.trace.tau_cmd, second.trace.tau_cmd);
    assert_eq!(first.metrics, second.metrics);
    // A different seed draws a different plant and different noise.
    scenario.seed += 1;
    assert_ne!(run_method::<6>(&scenario, Method::Lu).unwrap().trace.q, first.trace.q);
}

#[test]
fn the_free_plant_conserves_energy() {
    let robot = hya_robots::find("hya").unwrap();
    let model = hya_urdf::load_str(robot.urdf, "hya").unwrap().model;
    let config = PlantConfig { friction: FrictionKind::Off, actuator: ActuatorKind::Ideal, ..PlantConfig::default() };
    let q0 = JointVector::<6>::from([0.3, -0.4, -0.7, 0.8, 0.5, -0.2]);
    let zero = JointVector::zeros();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
    let mut plant = Plant::new(
        model.clone(),
        &hya_sim::plant::generic_dynamics,
        &hya_sim::config::plant::PlantSetup::of(&config, &LoadConfig::default()).unwrap(),
        (q0, zero),
        &mut rng,
    )
    .unwrap();
    // E = ½ q̇ᵀ M q̇ + V(q), V = −Σ m_i g·c_i with c_i each body's centre of mass in the base.
    let energy = |plant: &Plant<6>| {
        let s = &plant.state;
        let dynamics = plant.dynamics(0.0);
        let kinetic = 0.5 * s.qd.dot(&(dynamics.mass_matrix(&s.q) * s.qd));
        let potential: f64 = model
            .bodies()
            .iter()
            .map(|b| {
                let pose = model.frame_pose(&b.link, s.q.as_slice()).unwrap();
                let (_, com, _) = b.inertia.centre_of_mass_form().unwrap();
                let com = pose.point_to_parent(&com);
                b.inertia.mass * 9.81 * com.z
            })
            .sum();
        kinetic + potential
    };
    let start = energy(&plant);
    let mut worst: f64 = 0.0;
    for _ in 0..50_000 {
        plant.step(2e-4, &zero).unwrap();
        worst = worst.max((energy(&plant) - start).abs());
    }
    let scale = start.abs().max(1.0);
    eprintln!("energy drift over 10 s: {:.2e} of {start:.3} J", worst / scale);
    assert!(worst / scale < 1e-6, "energy drifted by {worst} J of {start} J over 10 s");
    assert!(plant.state.qd.norm() > 0.5, "the arm should be swinging, not resting");
}

#[test]
fn every_observer_runs_at_the_same_bandwidth() {
    let mut scenario = Scenario::builtin("goto_internal").unwrap();
    scenario.duration_s = 0.6;
    let target = scenario.controller.observer_bandwidth_rad_s;
    for method in [Method::Lu, Method::Chen, Method::Momentum, Method::Eso] {
        let rates = run_method::<6>(&scenario, method).unwrap().bandwidth_rad_s.unwrap();
        assert_eq!(rates.len(), 6);
        for rate in rates {
            assert!((rate - target).abs() < 1e-6 * target, "{}: rate {rate} rad/s, target {target}", method.name());
        }
    }
    for method in [Method::None, Method::Pid] {
        assert!(run_method::<6>(&scenario, method).unwrap().bandwidth_rad_s.is_none());
    }
}

/// Section V in the paper's setting (no friction to absorb the load): the injected 1 Hz load
/// reaches the true disturbance, its 1 Hz component at least 80 % of the injected amplitude on
/// every joint, at both noise levels.
#[test]
fn the_section_v_load_reaches_the_true_disturbance() {
    for name in ["estimator_noise_low", "estimator_noise_high"] {
        let scenario = Scenario::builtin(name).unwrap().quick();
        let amplitude = scenario.loads.sinusoid.as_ref().unwrap().amplitude_nm.clone();
        let trace = run_method::<6>(&scenario, Method::Lu).unwrap().trace;
        // Whole periods after the first second.
        let start = trace.time.partition_point(|t| *t < 1.0);
        let end = trace.time.partition_point(|t| *t < scenario.duration_s.floor() - 1e-9);
        for (j, injected) in amplitude.iter().enumerate() {
            let samples: Vec<(f64, f64)> = (start..end).map(|k| (trace.time[k], trace.d_true[k][j])).collect();
            let reached = hya_sim::frequency::phasor(&samples, std::f64::consts::TAU).norm();
            assert!(reached >= 0.8 * injected, "{name} joint {}: {reached:.3} of {injected} N·m at 1 Hz", j + 1);
        }
    }
}

/// Shadow mode: every estimator reads the loop's own measurements. The shadow of the method
/// that compensates therefore equals the loop's estimate bit for bit (its error sums to the
/// same RMSE, to the last bit, over thousands of ticks), and the others differ.
#[test]
fn shadow_estimators_see_the_loops_measurements() {
    let scenario = Scenario::builtin("estimator_noise_high").unwrap().quick();
    for (i, method) in hya_sim::run::trace::SHADOWS.into_iter().enumerate() {
        let metrics = run_method::<6>(&scenario, method).unwrap().metrics;
        let own = metrics.rmse_d.clone().unwrap();
        assert_eq!(metrics.shadow[i].rmse_d, own, "{method:?}'s shadow is not the loop's own estimate");
        let other = (i + 1) % 4;
        assert_ne!(metrics.shadow[other].rmse_d, own, "{method:?}: another estimator matched it exactly");
        assert!(metrics.shadow.iter().all(|s| s.rmse_d.len() == 6 && s.noise.len() == 6));
    }
}
