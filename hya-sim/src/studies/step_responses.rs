//! The hydraulic actuators on the arm, open loop: each joint's actuator torque after a step of
//! its own command, and the rigid body against MuJoCo's rollout of the same URDF.
//! [`crate::report`]'s Plant section draws and tabulates them.

use hya_core::JointVector;

use crate::config::cost::Cost;
use crate::config::scenario::Scenario;
use crate::error::SimError;
use crate::plant::{Actuators, PlantState};
use crate::run::rollout::{open_loop, reference_gap, scenario_plant, TorqueCommand, MUJOCO_HYA};

/// The command steps of the step test, N·m: one small enough that no light joint reaches its
/// valve's flow limit within the window, and a large one.
pub const STEPS_NM: [f64; 2] = [0.05, 2.0];

/// When the step comes, s after the release.
const STEP_AT_S: f64 = 0.05;

/// How long the response is followed after the step, s.
const WINDOW_S: f64 = 0.1;

/// The interval between the response's samples, s.
const SAMPLE_S: f64 = 2e-4;

/// One step size's responses.
#[derive(Debug, Clone)]
pub struct StepResponse {
    /// The step, N·m.
    pub step_nm: f64,
    /// Per joint, `(ms after the step, Δτ_act / step)`.
    pub points: Vec<Vec<(f64, f64)>>,
    /// Per joint, the 10–90 % rise time, ms (NaN where it does not reach 90 %).
    pub rise_ms: Vec<f64>,
}

/// What the Plant section shows of the open-loop arm.
#[derive(Debug, Clone)]
pub struct OpenLoop {
    /// Per step of [`STEPS_NM`], on hydraulic actuators only.
    pub steps: Vec<StepResponse>,
    /// The worst difference from MuJoCo's rollout of HyA, `(rad, rad/s)`, for HyA only.
    pub mujoco_gap: Option<(f64, f64)>,
}

/// Each joint's actuator torque after a step of `step_nm` in its command, the arm at the start
/// pose with every actuator holding the nominal gravity torque; and each joint's 10–90 % rise
/// time.
fn step_response<const N: usize>(
    scenario: &Scenario,
    robot: &crate::robot::Robot<N>,
    step_nm: f64,
) -> Result<StepResponse, SimError> {
    // Friction off: the steps are below every joint's static friction, and a sticking joint
    // would show the locked loop; free, each joint's load shapes its response. Pressure noise
    // and offsets off too: a 0.05 N·m step is the size of one reading's noise.
    let free = crate::config::settings::Setup::<N>::of(&crate::torque_response::clean(scenario))?;
    let q0 = free.initial_position;
    let hold: JointVector<N> = robot.nominal.gravity(&q0);
    let (mut all_points, mut rise_ms) = (Vec::new(), Vec::new());
    for j in 0..N {
        let (mut plant, max_step) = scenario_plant(&robot.model, &free, q0, hold)?;
        let Actuators::Hydraulic(actuators) = plant.actuators().clone() else {
            return Err(SimError::Nothing("the step response needs hydraulic actuators"));
        };
        let mut stepped = hold;
        stepped[j] += step_nm;
        let commands = [TorqueCommand { time: 0.0, torque: hold }, TorqueCommand { time: STEP_AT_S, torque: stepped }];
        let mut points = Vec::new();
        let mut before = hold[j];
        open_loop(&mut plant, &commands, max_step, SAMPLE_S, STEP_AT_S + WINDOW_S, |t, s: &PlantState<N>| {
            let torque = actuators.torque(&s.hydraulic.pressure_a, &s.hydraulic.pressure_b)[j];
            if t < STEP_AT_S {
                before = torque;
            } else {
                points.push(((t - STEP_AT_S) * 1e3, (torque - before) / step_nm));
            }
            Ok::<(), SimError>(())
        })?;
        let crossing = |level: f64| points.iter().find(|(_, y)| *y >= level).map(|(t, _)| *t);
        rise_ms.push(match (crossing(0.1), crossing(0.9)) {
            (Some(a), Some(b)) => b - a,
            _ => f64::NAN,
        });
        all_points.push(points);
    }
    Ok(StepResponse { step_nm, points: all_points, rise_ms })
}

/// What [`run`]'s step test costs on `first` for an arm of `joints` joints: one open-loop run
/// per step and joint, each sample interval in as many equal steps as keep to the plant's step
/// (the rigid body's 1 s rollout against MuJoCo, on HyA, not counted).
pub fn cost(first: &Scenario, joints: usize) -> Cost {
    match first.plant.actuator {
        crate::config::scenario::ActuatorKind::Hydraulic => {
            let plant_step = first.controller.dt_s / first.plant.substeps() as f64;
            let step = SAMPLE_S / (SAMPLE_S / plant_step).ceil();
            Cost::open_loop(STEPS_NM.len() * joints, STEP_AT_S + WINDOW_S, step)
        }
        _ => Cost::NONE,
    }
}

/// Runs the step test on `first`'s plant (the report's first scenario) where its actuators are
/// hydraulic, and the comparison with MuJoCo where it is HyA.
pub fn run<const N: usize>(robot: &crate::robot::Robot<N>, first: &Scenario) -> Result<OpenLoop, SimError> {
    let steps = match first.plant.actuator {
        crate::config::scenario::ActuatorKind::Hydraulic => {
            STEPS_NM.iter().map(|&step| step_response(first, robot, step)).collect::<Result<_, _>>()?
        }
        _ => Vec::new(),
    };
    let mujoco_gap = match first.robot == "hya" {
        true => Some(reference_gap::<N>(&robot.model, MUJOCO_HYA.0, MUJOCO_HYA.1)?),
        false => None,
    };
    Ok(OpenLoop { steps, mujoco_gap })
}
