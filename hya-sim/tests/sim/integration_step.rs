//! The plant's step is chosen by measurement: along the torque commands of a closed-loop run,
//! each 1 ms control tick is integrated from the same state at the default sub-step and at a
//! ten times finer one; the largest difference after a tick is the integrator's error per tick.
//! (Whole open-loop rollouts are no measure: replayed without feedback, a held arm drifts away
//! and stick-slip events amplify any difference, as they would in any simulator. In closed loop
//! the controller sees the state again every tick.)

use hya_core::JointVector;
use hya_sim::rollout::scenario_plant;
use hya_sim::scenario::ActuatorKind;
use hya_sim::{run_method, Method, Scenario};

/// Largest per-tick joint-angle difference, rad, between `substeps` and `10 × substeps`
/// sub-steps per tick along `commands` (one per 1 ms tick).
fn tick_error(scenario: &Scenario, commands: &[JointVector<6>], substeps: usize) -> f64 {
    let robot = hya_robots::find("hya").unwrap();
    let model = hya_urdf::load_str(robot.urdf, "hya").unwrap().model;
    let q0 = JointVector::from_column_slice(&hya_robots::hya::HOME);
    let settings = hya_sim::settings::Setup::<6>::of(scenario).unwrap();
    let (mut fine, _) = scenario_plant(&model, &settings, q0, commands[0]).unwrap();
    let (mut coarse, _) = scenario_plant(&model, &settings, q0, commands[0]).unwrap();
    let dt = scenario.controller.dt_s;
    let mut worst: f64 = 0.0;
    for command in commands {
        coarse.state = fine.state;
        coarse.time = fine.time;
        for _ in 0..substeps {
            coarse.step(dt / substeps as f64, command).unwrap();
        }
        for _ in 0..10 * substeps {
            fine.step(dt / (10 * substeps) as f64, command).unwrap();
        }
        worst = worst.max((coarse.state.q - fine.state.q).amax());
    }
    worst
}

/// The goto move of the quick scenario (start at 3 s), with the plant's stiffest parts
/// (bristles, valves, oil) all active, on `actuator`, and the commands of its closed-loop run.
fn goto_move(actuator: ActuatorKind) -> (Scenario, Vec<JointVector<6>>) {
    let mut scenario = Scenario::builtin("goto_internal").unwrap().quick();
    scenario.duration_s = 4.5;
    scenario.plant.actuator = actuator;
    let commands = run_method::<6>(&scenario, Method::Lu).unwrap().trace.tau_cmd;
    (scenario, commands)
}

const ACTUATORS: [ActuatorKind; 3] = [ActuatorKind::Hydraulic, ActuatorKind::Lag, ActuatorKind::Ideal];

#[test]
fn the_default_step_is_within_tolerance_of_a_ten_times_finer_one() {
    for actuator in ACTUATORS {
        let (scenario, commands) = goto_move(actuator);
        let default = scenario.plant.substeps();
        let error = tick_error(&scenario, &commands, default);
        eprintln!("{actuator:?}: {default} sub-steps per tick: {error:.2e} rad per tick from {}", 10 * default);
        assert!(error < 1e-7, "{actuator:?}: the default step leaves {error} rad of integration error per tick");
    }
}

/// The table behind `PlantConfig::substeps`: `cargo test --release -p hya-sim --test sim
/// integration_step -- --ignored --nocapture`.
#[test]
#[ignore = "prints the error of 1, 2 and 4 sub-steps per actuator (release build: 10 s)"]
fn error_per_tick_for_one_two_and_four_sub_steps() {
    for actuator in ACTUATORS {
        let (scenario, commands) = goto_move(actuator);
        for substeps in [1, 2, 4] {
            let error = tick_error(&scenario, &commands, substeps);
            eprintln!("{actuator:?}: {substeps} sub-steps per tick: {error:.2e} rad per tick from {}", 10 * substeps);
            assert!(error.is_finite());
        }
    }
}
