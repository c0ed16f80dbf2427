//! `hya plant`: open-loop rollouts of the simulated arm under torque rows read from stdin, to
//! hold it against another simulator.

use std::io::{BufRead, Write};
use std::path::PathBuf;

use hya_core::model::TreeModel;
use hya_core::JointVector;
use hya_sim::rollout::{ideal_plant, open_loop, scenario_plant, TorqueCommand};
use hya_sim::Scenario;

use crate::{read_rows, rows, CliError};

/// Parameters of `hya plant`.
#[derive(Debug, clap::Args)]
#[command(allow_negative_numbers = true)]
pub struct PlantArgs {
    /// A shipped robot's name (see `hya robots`) or the path of a URDF file.
    #[arg(long)]
    robot: String,
    /// The plant of this scenario file (its perturbation, friction, actuators and loads);
    /// without it, the plant of the built-in `goto_internal`.
    #[arg(long, conflicts_with = "ideal")]
    scenario: Option<PathBuf>,
    /// The rigid body alone: nominal parameters, no friction, ideal actuators, no loads or
    /// noise, gravity 9.81 m/s² along −z.
    #[arg(long)]
    ideal: bool,
    /// Initial joint angles, rad, space-separated (default: the robot's home pose).
    #[arg(long)]
    q0: Option<String>,
    /// Output interval of simulated time, s.
    #[arg(long, default_value_t = 0.001)]
    dt: f64,
    /// Simulate until this time, s (default: the last row's time).
    #[arg(long)]
    until: Option<f64>,
}

fn input(message: impl Into<String>) -> CliError {
    CliError::Input(message.into())
}

fn sim(e: hya_sim::SimError) -> CliError {
    CliError::Input(e.to_string())
}

impl From<hya_sim::SimError> for CliError {
    fn from(e: hya_sim::SimError) -> Self {
        sim(e)
    }
}

/// The start pose: `--q0`, else the shipped robot's home pose, else zeros.
fn start_pose(args: &PlantArgs, robot: &str, dof: usize) -> Result<Vec<f64>, CliError> {
    match &args.q0 {
        Some(text) => {
            let values =
                rows::parse(text, 1).map_err(|e| input(format!("--q0: {e}")))?.map_or(Vec::new(), |r| r.values);
            if values.len() != dof {
                return Err(input(format!("--q0: expected {dof} angles, got {}", values.len())));
            }
            Ok(values)
        }
        None => Ok(hya_robots::find(robot).map_or_else(|| vec![0.0; dof], |r| r.home.to_vec())),
    }
}

/// The torque rows `t τ1 … τn`: times from 0, strictly increasing.
fn commands<const N: usize>(stdin: impl BufRead) -> Result<Vec<TorqueCommand<N>>, CliError> {
    let mut commands: Vec<TorqueCommand<N>> = Vec::new();
    for row in read_rows(stdin) {
        let row = row?;
        rows::expect_width(&row, N + 1, "t, then one torque per joint")?;
        let time = row.values[0];
        match commands.last() {
            None if time != 0.0 => {
                return Err(input(format!("line {}: the first row must be at t = 0, not {time}", row.line)))
            }
            Some(last) if time <= last.time => {
                return Err(input(format!("line {}: t = {time} does not come after {}", row.line, last.time)))
            }
            _ => {}
        }
        commands.push(TorqueCommand { time, torque: JointVector::from_column_slice(&row.values[1..]) });
    }
    Ok(commands)
}

/// The rollout for an `N`-joint robot.
fn rollout<const N: usize>(
    args: &PlantArgs,
    robot: &str,
    model: &TreeModel,
    stdin: impl BufRead,
    output: &mut impl Write,
) -> Result<(), CliError> {
    let q0 = JointVector::<N>::from_column_slice(&start_pose(args, robot, N)?);
    let commands = commands::<N>(stdin)?;
    let Some(last) = commands.last() else { return Err(input("no torque rows on stdin")) };
    let until = args.until.unwrap_or(last.time);
    if !(0.0..=1e6).contains(&until) {
        return Err(input(format!("--until {until}: must be between 0 and 1e6 s")));
    }
    if !(args.dt.is_finite() && args.dt > 0.0 && until / args.dt <= 1e8) {
        return Err(input(format!("--dt {}: must be > 0 and give at most 1e8 output rows", args.dt)));
    }
    let (mut plant, max_step) = if args.ideal {
        (ideal_plant(model, q0)?, 1e-4)
    } else {
        let scenario = match &args.scenario {
            Some(path) => {
                let text = std::fs::read_to_string(path)
                    .map_err(|e| input(format!("{}: cannot read: {e}", path.display())))?;
                Scenario::from_toml(&text, &path.display().to_string())?
            }
            None => Scenario::builtin("goto_internal")?,
        };
        scenario_plant(model, &scenario, q0, commands[0].torque)?
    };
    open_loop(&mut plant, &commands, max_step, args.dt, until, |t, state| {
        rows::write(output, std::iter::once(t).chain(state.q.iter().copied()).chain(state.qd.iter().copied()))
    })
}

/// `hya plant`.
pub fn run(args: &PlantArgs, stdin: impl BufRead, output: &mut impl Write) -> Result<(), CliError> {
    let model = crate::dynamics::model(&args.robot)?;
    let robot = args.robot.as_str();
    macro_rules! by_dof {
        ($($n:literal)*) => {
            match model.dof() {
                $($n => rollout::<$n>(args, robot, &model, stdin, output),)*
                n => Err(input(format!("hya plant runs arms of 1 to 12 joints; {robot} has {n}"))),
            }
        };
    }
    by_dof!(1 2 3 4 5 6 7 8 9 10 11 12)
}
