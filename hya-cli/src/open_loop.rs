//! `hya plant`: open-loop rollouts of the simulated arm under torque rows read from stdin, to
//! hold it against another simulator.

use std::io::{BufRead, Write};
use std::path::PathBuf;

use hya_core::model::TreeModel;
use hya_core::{JointVector, Short};
use hya_sim::config::plant::PlantSetup;
use hya_sim::rollout::{ideal_plant, open_loop, seeded_plant, TorqueCommand};
use hya_sim::settings::Timing;

use crate::table::names::{self, Joints, Unit};
use crate::table::{self, ColumnsArg, HeaderArg, RowWriter, Table};
use crate::CliError;

/// Parameters of `hya plant`.
#[derive(Debug, clap::Args)]
#[command(allow_negative_numbers = true)]
pub struct PlantArgs {
    /// A shipped robot's name (see `hya robots`) or the path of a URDF file.
    #[arg(long)]
    robot: String,
    /// The plant of this scenario file (its perturbation, friction, actuators and loads);
    /// without it, the plant of the shipped arm's built-in scenario (`goto_internal` for
    /// `hya`, `<arm>_goto` for the others; a URDF file needs `--scenario` or `--ideal`).
    #[arg(long, conflicts_with = "ideal")]
    scenario: Option<PathBuf>,
    /// The rigid body alone: nominal parameters, no friction, ideal actuators, no loads or
    /// noise, gravity 9.81 m/s² along −z.
    #[arg(long)]
    ideal: bool,
    /// Initial joint angles, rad, space-separated (default: the robot's home pose); within the
    /// joints' limits and at most 100 in magnitude.
    #[arg(long)]
    q0: Option<String>,
    /// Output interval of simulated time, s (1e-6 to 1).
    #[arg(long, default_value_t = 0.001)]
    dt: f64,
    /// Simulate until this time, s (default: the last row's time; at most 1e6, and at most
    /// 1e7 integration steps in all).
    #[arg(long)]
    until: Option<f64>,
    /// (--columns) Read in the order t, τ.
    #[command(flatten)]
    columns: ColumnsArg,
    #[command(flatten)]
    header: HeaderArg,
}

/// The latest `--until` (or last row's time) `hya plant` accepts, s.
pub const MAX_UNTIL_S: f64 = 1e6;

/// The most integration steps one `hya plant` run takes (1e7, about a minute of computing for
/// HyA): with steps of at most 0.1 ms (`--ideal`) or the scenario's physics step, and one more
/// per output row and per torque row, it bounds the run's time (`--until 1e6 --dt 1` would take
/// 1e10). The LuGre friction of a scenario may split a step further, by a bounded factor.
pub const MAX_STEPS: f64 = 1e7;

/// The most torque rows `hya plant` reads (1e6, 1000 s at 1 kHz): they are held in memory.
pub const MAX_TORQUE_ROWS: usize = 1_000_000;

/// The largest start position `--q0` accepts for any joint, rad (or m): angles beyond a few
/// turns are typing errors, and at 1e300 the trigonometry returns noise.
pub const MAX_START_POSITION: f64 = 100.0;

/// The physics step of `--ideal`, s.
const IDEAL_STEP_S: f64 = 1e-4;

fn input(message: impl Into<String>) -> CliError {
    CliError::Input(message.into())
}

/// The start pose: `--q0` (checked against the joints' limits and [`MAX_START_POSITION`]),
/// else the shipped robot's home pose, else zeros.
fn start_pose(args: &PlantArgs, robot: &str, model: &TreeModel) -> Result<Vec<f64>, CliError> {
    let dof = model.dof();
    let Some(text) = &args.q0 else {
        return Ok(hya_robots::find(robot).map_or_else(|| vec![0.0; dof], |r| r.home.to_vec()));
    };
    // One row of the table format: blank- or comma-separated numbers.
    let mut row = Table::any(text.as_bytes(), None);
    let values = match row.next_line() {
        Some(line) => line.map(|_| row.values().to_vec()).map_err(|e| input(format!("--q0: {e}")))?,
        None if text.trim().is_empty() => Vec::new(),
        None => return Err(input(format!("--q0 {}: not a list of numbers", table::echo(text)))),
    };
    if row.next_line().is_some() {
        return Err(input(format!("--q0 {}: one line of angles, not several", table::echo(text))));
    }
    if values.len() != dof {
        return Err(input(format!("--q0: expected {dof} angles, got {}", values.len())));
    }
    for (body, &q) in model.bodies().iter().zip(&values) {
        let (lower, upper) =
            (body.limits.lower.unwrap_or(-MAX_START_POSITION), body.limits.upper.unwrap_or(MAX_START_POSITION));
        let (lower, upper) = (lower.max(-MAX_START_POSITION), upper.min(MAX_START_POSITION));
        if !(lower..=upper).contains(&q) {
            return Err(input(format!(
                "--q0: joint {} at {}: outside its range, {} to {}",
                table::echo(&body.joint),
                Short(q),
                Short(lower),
                Short(upper)
            )));
        }
    }
    Ok(values)
}

/// The torque rows `t τ1 … τn` of an arm with `joints`: times from 0, strictly increasing.
fn commands<const N: usize>(
    stdin: impl BufRead,
    args: &PlantArgs,
    joints: &Joints,
) -> Result<Vec<TorqueCommand<N>>, CliError> {
    let wanted = [vec![names::time()], joints.columns("tau", Unit::Effort)].concat();
    let mut table = Table::new(stdin, args.columns.spec()?, wanted, "t, then one torque per joint".into())?;
    let mut commands: Vec<TorqueCommand<N>> = Vec::new();
    while let Some(line) = table.next_line() {
        let line = line?;
        if commands.len() == MAX_TORQUE_ROWS {
            return Err(input(format!("line {line}: more than {MAX_TORQUE_ROWS} torque rows")));
        }
        let row = table.values();
        let time = row[0];
        match commands.last() {
            None if time != 0.0 => {
                return Err(input(format!("line {line}: the first row must be at t = 0, not {}", Short(time))))
            }
            Some(last) if time <= last.time => {
                return Err(input(format!("line {line}: t = {} does not come after {}", Short(time), Short(last.time))))
            }
            _ => {}
        }
        commands.push(TorqueCommand { time, torque: JointVector::from_column_slice(&row[1..]) });
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
    let dt = table::check_dt("--dt", args.dt)?;
    if let Some(until) = args.until {
        check_until("--until", until)?;
    }
    let q0 = JointVector::<N>::from_column_slice(&start_pose(args, robot, model)?);
    let scenario =
        if args.ideal { None } else { Some(crate::common::scenario(args.scenario.as_deref(), robot, " or --ideal")?) };
    let joints = Joints::of(model);
    let commands = commands::<N>(stdin, args, &joints)?;
    let Some(last) = commands.last() else { return Err(input("no torque rows on stdin")) };
    let until = match args.until {
        Some(until) => until,
        None => check_until("the last torque row's time", last.time)?,
    };
    let (mut plant, max_step) = match &scenario {
        None => (ideal_plant(model, q0)?, IDEAL_STEP_S),
        Some(scenario) => {
            let setup = PlantSetup::of(&scenario.plant, &scenario.loads)?;
            let spread_seed = (scenario.plant.parameter_spread, scenario.seed);
            (seeded_plant(model, &setup, spread_seed, (q0, commands[0].torque))?, Timing::of(scenario).physics_step_s())
        }
    };
    // Each interval between events (output rows, torque rows) takes ⌈span / max_step⌉ steps.
    let steps = until / max_step + until / dt + commands.len() as f64 + 1.0;
    if steps > MAX_STEPS {
        return Err(input(format!(
            "--until {} s at --dt {} s takes about {} integration steps (physics step {} s): more than {}",
            Short(until),
            Short(dt),
            Short(steps.round()),
            Short(max_step),
            Short(MAX_STEPS)
        )));
    }
    let columns =
        [vec![names::time()], joints.columns("q", Unit::Position), joints.columns("qd", Unit::Velocity)].concat();
    let mut writer = RowWriter::new(output, columns, args.header.header());
    open_loop(&mut plant, &commands, max_step, dt, until, |t, state| {
        writer
            .write(std::iter::once(t).chain(state.q.iter().copied()).chain(state.qd.iter().copied()))
            .map_err(|e| table::at(format_args!("t = {} s", Short(t)), e))
    })
}

/// Checks an end time: finite, from 0 to [`MAX_UNTIL_S`].
fn check_until(what: &str, until: f64) -> Result<f64, CliError> {
    if until.is_finite() && (0.0..=MAX_UNTIL_S).contains(&until) {
        Ok(until)
    } else {
        Err(input(format!("{what} {}: must be between 0 and {} s", Short(until), Short(MAX_UNTIL_S))))
    }
}

/// `hya plant`.
pub fn run(args: &PlantArgs, stdin: impl BufRead, output: &mut impl Write) -> Result<(), CliError> {
    let model = crate::common::model(&args.robot)?;
    let robot = args.robot.as_str();
    macro_rules! by_dof {
        ($($n:literal)*) => {
            match model.dof() {
                $($n => rollout::<$n>(args, robot, &model, stdin, output),)*
                n => Err(input(format!("hya plant runs arms of 1 to 12 joints; {} has {n}", table::echo(robot)))),
            }
        };
    }
    by_dof!(1 2 3 4 5 6 7 8 9 10 11 12)
}
