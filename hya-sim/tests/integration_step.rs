//! The plant's step is chosen by measurement: the plant, driven open loop by the torque commands
//! of a closed-loop run, at the default sub-step against the same at a ten times finer one. (In
//! closed loop, a difference below one encoder count can flip a count and change every later
//! command, so the loop's own sensitivity, not the integrator, would be measured.)
#![allow(clippy::unwrap_used)] // test helpers: a failed unwrap is a failed test

use hya_core::JointVector;
use hya_sim::rollout::{open_loop, scenario_plant, TorqueCommand};
use hya_sim::{run_method, Method, Scenario, SimError};

/// Largest joint-angle difference, rad, between open-loop rollouts of `scenario`'s plant under
/// `commands` with `substeps` and with `10 × substeps` sub-steps per tick.
fn step_error(scenario: &Scenario, commands: &[TorqueCommand<6>], substeps: usize) -> f64 {
    let robot = hya_robots::find("hya").unwrap();
    let model = hya_codegen::load_str(robot.urdf, "hya").unwrap().model;
    let q0 = JointVector::from_column_slice(&hya_sim::HYA_HOME);
    let rollout = |substeps: usize| {
        let mut s = scenario.clone();
        s.plant.substeps = substeps;
        let (mut plant, step) = scenario_plant(&model, &s, q0, commands[0].torque).unwrap();
        let mut q = Vec::new();
        let until = commands.last().unwrap().time;
        open_loop(&mut plant, commands, step, 1e-3, until, |_, state| {
            q.push(state.q);
            Ok::<(), SimError>(())
        })
        .unwrap();
        q
    };
    let (rough, fine) = (rollout(substeps), rollout(10 * substeps));
    rough.iter().zip(&fine).map(|(a, b)| (a - b).amax()).fold(0.0, f64::max)
}

#[test]
fn the_default_step_is_within_tolerance_of_a_ten_times_finer_one() {
    // The goto move of the quick scenario (start at 3 s), with the new plant's stiffest parts
    // (bristles, valves, oil) all active.
    let mut scenario = Scenario::builtin("goto_internal").unwrap().quick();
    scenario.duration_s = 4.5;
    let trace = run_method(&scenario, Method::Lu).unwrap().trace;
    let commands: Vec<TorqueCommand<6>> =
        trace.time.iter().zip(&trace.tau_cmd).map(|(t, tau)| TorqueCommand { time: *t, torque: *tau }).collect();
    let default = scenario.plant.substeps;
    let error = step_error(&scenario, &commands, default);
    eprintln!("{default} sub-steps per tick: {error:.2e} rad from the rollout at {}", 10 * default);
    assert!(error < 1e-6, "the default step leaves {error} rad of integration error");
}
