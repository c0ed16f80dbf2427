//! The testbed's own laws (determinism, energy conservation) and the paper's claims on the
//! `--quick` durations.
#![allow(clippy::unwrap_used)] // test helpers: a failed unwrap is a failed test

use hya_core::JointVector;
use hya_sim::plant::Plant;
use hya_sim::scenario::{LoadConfig, PlantConfig};
use hya_sim::{run_method, Method, Scenario};

#[test]
fn seeded_runs_are_bit_identical() {
    let mut scenario = Scenario::builtin("goto_weight").unwrap().quick();
    scenario.duration_s = 9.0; // through the weight drop at 7.4 s
    let first = run_method(&scenario, Method::Lu).unwrap();
    let second = run_method(&scenario, Method::Lu).unwrap();
    assert_eq!(first.trace.q, second.trace.q);
    assert_eq!(first.trace.d_hat, second.trace.d_hat);
    assert_eq!(first.trace.tau_cmd, second.trace.tau_cmd);
    assert_eq!(first.metrics, second.metrics);
    // A different seed draws a different plant and different noise.
    scenario.seed += 1;
    assert_ne!(run_method(&scenario, Method::Lu).unwrap().trace.q, first.trace.q);
}

#[test]
fn compensation_lowers_tracking_error_on_every_joint_in_all_four_experiments() {
    for name in ["goto_internal", "sine_internal", "goto_weight", "sine_weight"] {
        let scenario = Scenario::builtin(name).unwrap().quick();
        let none = run_method(&scenario, Method::None).unwrap().metrics.rmse_q;
        let lu = run_method(&scenario, Method::Lu).unwrap().metrics.rmse_q;
        for joint in 0..6 {
            assert!(
                lu[joint] < none[joint],
                "{name}, joint {}: RMSE lu {} ≥ none {}",
                joint + 1,
                lu[joint],
                none[joint]
            );
        }
    }
}

#[test]
fn velocity_noise_leaves_the_paper_estimate_alone_and_degrades_chen() {
    let mean_error = |scenario: &str, method| {
        let outcome = run_method(&Scenario::builtin(scenario).unwrap().quick(), method).unwrap();
        let errors = outcome.metrics.rmse_d.unwrap();
        errors.iter().sum::<f64>() / errors.len() as f64
    };
    let lu = (mean_error("estimator_noise_low", Method::Lu), mean_error("estimator_noise_high", Method::Lu));
    let chen = (mean_error("estimator_noise_low", Method::Chen), mean_error("estimator_noise_high", Method::Chen));
    assert!(lu.1 / lu.0 < 1.25, "lu's estimate error grew from {} to {} N·m", lu.0, lu.1);
    assert!(chen.1 / chen.0 > 2.0, "chen's estimate error only went from {} to {} N·m", chen.0, chen.1);
}

#[test]
fn the_free_plant_conserves_energy() {
    let robot = hya_robots::find("hya").unwrap();
    let model = hya_codegen::load_str(robot.urdf, "hya").unwrap().model;
    let config = PlantConfig { friction: false, ..PlantConfig::default() };
    let q0 = JointVector::<6>::from([0.3, -0.4, -0.7, 0.8, 0.5, -0.2]);
    let zero = JointVector::zeros();
    let mut plant =
        Plant::new(model.clone(), &hya_sim::plant::generic_dynamics, &config, &LoadConfig::default(), q0, zero)
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
