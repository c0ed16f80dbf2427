//! `hya estimate`: the disturbance estimator of Lu, Sandy & Buchli over a recorded log, for
//! logs from any robot or simulator: rows `q τ` in, rows `d̂` out; with `--timestamps`, rows
//! `t q τ` in, each step filtered over its own length ([`hya_core::timed`]), rows `t d̂` out.

use std::io::{BufRead, Write};

use hya_core::dispatch::{with_joints, ForJoints, MAX_JOINTS};
use hya_core::filter::{PAPER_BANDWIDTH_RAD_S, PAPER_ZETA};
use hya_core::{DisturbanceEstimator, FilterParams, JointVector, Short, TimedEstimator};
use hya_robots::ForArm;

use crate::columns::{ColumnSpec, Selection};
use crate::{rows, CliError};

/// Parameters of `hya estimate`.
#[derive(Debug, clap::Args)]
pub struct EstimateArgs {
    /// A shipped robot's name (see `hya robots`) or the path of a URDF file: the estimator's
    /// model.
    #[arg(long)]
    robot: String,
    /// Damping ratio ζ of the filters' second-order factor.
    #[arg(long, default_value_t = PAPER_ZETA)]
    zeta: f64,
    /// Corner frequency ω1 of the first-order factor, rad/s.
    #[arg(long, default_value_t = PAPER_BANDWIDTH_RAD_S)]
    omega1: f64,
    /// Natural frequency ω2 of the second-order factor, rad/s.
    #[arg(long, default_value_t = PAPER_BANDWIDTH_RAD_S)]
    omega2: f64,
    /// The log's sample time (one row per control tick), s. With `--timestamps`, the nominal
    /// one: the gap limit's default is 2.5 times it.
    #[arg(long, default_value_t = 0.001)]
    dt: f64,
    /// Rows start with their time t (s, strictly increasing): `t q τ` in, `t d̂` out. Each step
    /// is filtered exactly over its own length (first-order hold between the rows). A step longer
    /// than --max-step is a gap, reported on stderr with its line and bridged the same exact way
    /// (the samples either side joined by a straight line); a step longer than 100 / max(ω1, ω2)
    /// (2 s at the paper's 50 rad/s), over which the filters forget everything anyway, restarts
    /// the estimator at rest on the row after it, also reported.
    #[arg(long)]
    timestamps: bool,
    /// With --timestamps: the longest step that is not reported as a gap, s [default: 2.5 × --dt].
    #[arg(long, requires = "timestamps")]
    max_step: Option<f64>,
    /// The columns to read, in the order t (with --timestamps), q, τ: header names, positions
    /// from 1, or ranges of either, comma-separated (`t,q1-q6,tau1-tau6`, `1,2-7,14-19`). Other
    /// columns (velocities, currents, commands) are ignored. A first line whose first field is
    /// not a number is the header, with or without --columns.
    #[arg(long)]
    columns: Option<String>,
}

/// How `hya estimate` reads a row: its columns and whether it starts with a time.
struct Layout {
    params: FilterParams,
    timestamps: bool,
    max_step_s: f64,
    columns: Option<ColumnSpec>,
}

/// The estimator over every row, for the arm's `N` joints: a shipped arm's generated dynamics
/// ([`ForArm`]), or a URDF's run-time model ([`ForJoints`], with the model in `model`).
struct Estimate<'a, R, W> {
    model: Option<hya_core::model::TreeModel>,
    layout: Layout,
    input: R,
    output: &'a mut W,
}

impl<R: BufRead, W: Write> ForArm for Estimate<'_, R, W> {
    type Output = Result<(), CliError>;
    fn call<const N: usize>(self, arm: hya_robots::Arm<N>) -> Self::Output {
        estimate::<N>(arm.nominal, &self.layout, self.input, self.output)
    }
}

impl<R: BufRead, W: Write> ForJoints for Estimate<'_, R, W> {
    type Output = Result<(), CliError>;
    fn call<const N: usize>(self) -> Self::Output {
        let model = self.model.ok_or_else(|| CliError::Input("no model to estimate with".into()))?;
        let nominal = model.into_dynamics::<N>().map_err(|e| CliError::Input(e.to_string()))?;
        estimate::<N>(&nominal, &self.layout, self.input, self.output)
    }
}

/// The estimator, fixed-step or timestamped, once the first row has started it.
#[allow(clippy::large_enum_variant)] // one per run, on the stack: the size costs nothing
enum Running<'a, const N: usize> {
    Fixed(DisturbanceEstimator<N, &'a dyn hya_core::Dynamics<N>>),
    Timed(TimedEstimator<N, &'a dyn hya_core::Dynamics<N>>),
}

/// Rows `[t] q τ` (`2N` or `2N + 1` numbers, or the columns `--columns` selects) in, rows
/// `[t] d̂` out; the first row starts the estimator at rest (`d̂ = G(q) − τ` there).
fn estimate<'a, const N: usize>(
    nominal: &'a dyn hya_core::Dynamics<N>,
    layout: &Layout,
    input: impl BufRead,
    output: &mut impl Write,
) -> Result<(), CliError> {
    let offset = usize::from(layout.timestamps);
    let what = if layout.timestamps {
        format!("the time t (s), then the {N} joint angles q (rad), then the {N} joint torques τ (N·m)")
    } else {
        format!("the {N} joint angles q (rad), then the {N} joint torques τ (N·m)")
    };
    let width = offset + 2 * N;
    if let Some(spec) = &layout.columns {
        if spec.len() != width {
            return Err(CliError::Input(format!("--columns selects {} columns; {width} are read: {what}", spec.len())));
        }
    }
    let mut reader = rows::Reader::with_header(input);
    let mut selection: Option<Selection> = None;
    let mut picked = Vec::with_capacity(width);
    let mut running: Option<Running<'a, N>> = None;
    let mut gaps = 0;
    while let Some(row) = reader.next() {
        let row = row?;
        let values = match &layout.columns {
            None => {
                rows::expect_width(&row, width, &what)?;
                &row.values
            }
            Some(spec) => {
                if selection.is_none() {
                    selection = Some(spec.resolve(reader.header())?);
                }
                selection.as_ref().map_or(Ok(()), |s| s.pick(&row, &mut picked))?;
                &picked
            }
        };
        let t = values[0];
        let q = JointVector::<N>::from_column_slice(&values[offset..offset + N]);
        let tau = JointVector::<N>::from_column_slice(&values[offset + N..]);
        let at_line = |e: hya_core::Error| CliError::Input(format!("line {}: {e}", row.line));
        let d_hat = match running.as_mut() {
            None => {
                let started = if layout.timestamps {
                    Running::Timed(TimedEstimator::new(nominal, layout.params, t, q, tau).map_err(at_line)?)
                } else {
                    Running::Fixed(DisturbanceEstimator::new(nominal, layout.params, q, tau).map_err(at_line)?)
                };
                let d_hat = match &started {
                    Running::Fixed(e) => *e.disturbance(),
                    Running::Timed(e) => *e.estimator().disturbance(),
                };
                running = Some(started);
                d_hat
            }
            Some(Running::Fixed(e)) => e.update(&q, &tau).map_err(at_line)?,
            Some(Running::Timed(e)) => timed_step(e, layout, row.line, t, &q, &tau, &mut gaps)?,
        };
        let time = layout.timestamps.then_some(t);
        rows::write(output, time.into_iter().chain(d_hat.iter().copied()))
            .map_err(|e| rows::at(format_args!("line {}", row.line), e))?;
    }
    if gaps > REPORTED_GAPS {
        eprintln!("hya: {gaps} gaps in all, the first {REPORTED_GAPS} reported");
    }
    Ok(())
}

/// How many gaps `hya estimate --timestamps` reports one by one (restarts are always reported);
/// a count of all follows.
const REPORTED_GAPS: usize = 20;

/// One timestamped row: refuses a time that does not increase, reports a gap or a restart on
/// stderr, and returns `d̂`.
fn timed_step<const N: usize>(
    estimator: &mut TimedEstimator<N, &dyn hya_core::Dynamics<N>>,
    layout: &Layout,
    line: usize,
    t: f64,
    q: &JointVector<N>,
    tau: &JointVector<N>,
    gaps: &mut usize,
) -> Result<JointVector<N>, CliError> {
    let previous = estimator.time_s();
    if t <= previous {
        return Err(CliError::Input(format!(
            "line {line}: t = {} s is not after the previous row's t = {} s: times must strictly increase",
            Short(t),
            Short(previous)
        )));
    }
    let step = estimator.update(t, q, tau).map_err(|e| CliError::Input(format!("line {line}: {e}")))?;
    if step.length_s > layout.max_step_s {
        *gaps += 1;
        if *gaps > REPORTED_GAPS && !step.restarted {
            return Ok(step.disturbance);
        }
        let what = if step.restarted {
            format!(
                "longer than {} s, the longest the filters bridge: the estimator restarted at rest here",
                Short(estimator.longest_bridge_s())
            )
        } else {
            "bridged exactly, the rows either side joined by a straight line".to_string()
        };
        eprintln!(
            "hya: line {line}: gap of {} s from t = {} s to {} s (--max-step {} s): {what}",
            Short(step.length_s),
            Short(previous),
            Short(t),
            Short(layout.max_step_s)
        );
    }
    Ok(step.disturbance)
}

/// `hya estimate`.
pub fn run(args: &EstimateArgs, input: impl BufRead, output: &mut impl Write) -> Result<(), CliError> {
    let params = crate::filter::params(args.zeta, args.omega1, args.omega2, args.dt)?;
    let max_step_s = match args.max_step {
        None => 2.5 * args.dt,
        Some(s) if s.is_finite() && s > 0.0 => s,
        Some(s) => return Err(CliError::Input(format!("--max-step {}: must be finite and > 0 s", Short(s)))),
    };
    let columns = args.columns.as_deref().map(ColumnSpec::parse).transpose()?;
    let layout = Layout { params, timestamps: args.timestamps, max_step_s, columns };
    let mut estimate = Estimate { model: None, layout, input, output };
    if hya_robots::find(&args.robot).is_some() {
        return hya_robots::with_arm(&args.robot, estimate)
            .unwrap_or_else(|| Err(CliError::Input(format!("robot `{}` has no dispatch", args.robot))));
    }
    let model = crate::dynamics::model(&args.robot)?;
    let dof = model.dof();
    estimate.model = Some(model);
    with_joints(dof, estimate).unwrap_or_else(|| {
        Err(CliError::Input(format!(
            "{}: {dof} joints; the estimator runs arms of 1 to {MAX_JOINTS} joints",
            args.robot
        )))
    })
}
