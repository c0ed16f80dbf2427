//! `hya track`: the simulated arm follows a reference read from stdin (rows `t q q̇ q̈`, as
//! `hya excite` prints them) under a scenario's controller, and prints the log a real arm would
//! record: rows `t q_m τ_m` of the measured joint angles and torques, one per control tick, with
//! the scenario's sensors (encoder quantisation, torque noise, delays). `--out DIR` also writes
//! `true.urdf`, the plant's rigid body (the nominal one perturbed by the scenario's seed), to
//! hold an identification against.

use std::io::{BufRead, Write};
use std::path::{Path, PathBuf};

use hya_core::spatial::RigidBodyInertia;
use hya_core::{JointVector, Reference, Short};
use hya_sim::io::output::OutputDir;
use hya_sim::run::trace::Recording;
use hya_sim::run::{closed_loop_on, true_model};
use hya_sim::scenario::Task;
use hya_sim::settings::Setup;
use hya_sim::task::{Samples, Trajectory};
use hya_sim::{ForRobot, Method, Robot, Scenario, SimError};

use crate::common::with_body_inertias;
use crate::table::names::{self, Joints, Unit};
use crate::table::{self, ColumnsArg, HeaderArg, RowWriter, Table};
use crate::CliError;

/// Parameters of `hya track`.
#[derive(Debug, clap::Args)]
pub struct TrackArgs {
    /// A shipped robot's name (see `hya robots`) or the path of a URDF file.
    #[arg(long)]
    robot: String,
    /// The scenario whose plant, sensors and controller run (its task and duration are replaced
    /// by the reference); without it, the shipped arm's built-in one (`goto_internal` for `hya`).
    #[arg(long)]
    scenario: Option<PathBuf>,
    /// The seed of the plant's perturbation, friction profiles and noise [default: the scenario's].
    #[arg(long)]
    seed: Option<u64>,
    /// The controller: none, pid, lu (the paper's), chen, momentum or eso.
    #[arg(long, default_value = "lu")]
    method: String,
    /// Where `true.urdf` goes, the plant's rigid body (created; held by this run alone).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Replace files hya wrote in `--out` before (see `hya run --help`).
    #[arg(long)]
    force: bool,
    /// (--columns) Read in the order t, q, q̇, q̈.
    #[command(flatten)]
    columns: ColumnsArg,
    #[command(flatten)]
    header: HeaderArg,
}

/// The most reference rows `hya track` reads (1e6: 10⁴ s at `hya excite`'s 100 rows a second);
/// they are held in memory.
pub const MAX_REFERENCE_ROWS: usize = 1_000_000;

/// The reference rows `t q q̇ q̈` of an `N`-joint arm with `joints`.
fn reference<const N: usize>(input: impl BufRead, args: &TrackArgs, joints: &Joints) -> Result<Samples<N>, CliError> {
    let what = format!("t, then the {N} joint angles q, velocities q̇ and accelerations q̈");
    let wanted = joints.reference();
    let mut log = Table::new(input, args.columns.spec()?, wanted, what)?;
    let (mut time, mut points) = (Vec::new(), Vec::new());
    while let Some(line) = log.next_line() {
        let line = line?;
        if time.len() == MAX_REFERENCE_ROWS {
            return Err(CliError::Input(format!("line {line}: more than {MAX_REFERENCE_ROWS} reference rows")));
        }
        let values = log.values();
        let column = |k: usize| JointVector::<N>::from_column_slice(&values[1 + k * N..1 + (k + 1) * N]);
        time.push(values[0]);
        points.push(Reference { position: column(0), velocity: column(1), acceleration: column(2) });
    }
    if time.is_empty() {
        return Err(CliError::Input("no reference rows on stdin (rows t q q̇ q̈, as `hya excite` prints)".into()));
    }
    Ok(Samples::new(time, points)?)
}

/// The run for an `N`-joint robot ([`ForRobot`]).
struct Track<'a, R, W> {
    args: &'a TrackArgs,
    scenario: Scenario,
    method: Method,
    input: R,
    output: &'a mut W,
}

impl<R: BufRead, W: Write> ForRobot for Track<'_, R, W> {
    type Output = Result<(), CliError>;
    fn call<const N: usize>(self, robot: Robot<N>) -> Result<Self::Output, SimError> {
        Ok(self.track(&robot))
    }
}

impl<R: BufRead, W: Write> Track<'_, R, W> {
    fn track<const N: usize>(mut self, robot: &Robot<N>) -> Result<(), CliError> {
        let joints = Joints::of(&robot.model);
        let samples = reference::<N>(self.input, self.args, &joints)?;
        samples.within_limits(&robot.model)?;
        let scenario = &mut self.scenario;
        scenario.initial_position_rad = Some(samples.start().as_slice().to_vec());
        scenario.duration_s = samples.duration_s();
        // The reference replaces the task, which is then only checked: holding checks nothing.
        scenario.task = Task::Hold {};
        scenario.methods = vec![self.method];
        if let Some(seed) = self.args.seed {
            scenario.seed = seed;
        }
        scenario.check()?;
        let cost = hya_sim::cost::Cost::of(std::slice::from_ref(scenario), 1);
        cost.check("track a shorter reference, or split it into parts", None)?;
        if let Some(dir) = &self.args.out {
            let robot_file = Path::new(&self.args.robot);
            let reads: Vec<&Path> = std::iter::once(robot_file)
                .chain(self.args.scenario.iter().map(PathBuf::as_path))
                .chain(scenario.files_read())
                .collect();
            let (out, _) = OutputDir::open(dir, self.args.force, "hya track", &reads)?;
            let (model, _) = true_model(&robot.model, scenario.plant.parameter_spread, scenario.seed);
            let inertias: Vec<RigidBodyInertia> = model.bodies().iter().map(|b| b.inertia).collect();
            out.save("true.urdf", &with_body_inertias(&self.args.robot, &robot.model, &inertias, "true.urdf")?)?;
        }
        let columns =
            [vec![names::time()], joints.columns("q", Unit::Position), joints.columns("tau", Unit::Effort)].concat();
        let mut writer = RowWriter::new(&mut *self.output, columns, self.args.header.header());
        let mut failed = None;
        let trajectory = Trajectory::sampled(samples);
        let settings = Setup::<N>::for_run(scenario, self.method, &robot.model)?;
        closed_loop_on(&settings, self.method, robot, (&trajectory, Recording::Off), |t, measurement| {
            if failed.is_none() {
                let values = std::iter::once(t).chain(measurement.position.iter().copied());
                if let Err(e) = writer.write(values.chain(measurement.torque.iter().copied())) {
                    failed = Some(e);
                }
            }
        })?;
        if let Some(e) = failed {
            return Err(e);
        }
        eprintln!(
            "hya track: {} s on {} with the plant and sensors of `{}`, under {} (seed {}), {} rows",
            Short(scenario.duration_s),
            robot.model.name(),
            scenario.name,
            self.method.name(),
            scenario.seed,
            (scenario.duration_s / scenario.controller.dt_s).round()
        );
        Ok(())
    }
}

/// `hya track`.
pub fn run(args: &TrackArgs, input: impl BufRead, output: &mut impl Write) -> Result<(), CliError> {
    let method = Method::from_name(&args.method).ok_or_else(|| {
        let names: Vec<&str> = Method::ALL.iter().map(|m| m.name()).collect();
        CliError::Input(format!("--method {}: one of {}", table::echo(&args.method), names.join(", ")))
    })?;
    let scenario = crate::common::scenario(args.scenario.as_deref(), &args.robot, "")?;
    hya_sim::with_robot(&args.robot, Track { args, scenario, method, input, output })?
}
