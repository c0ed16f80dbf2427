//! `hya estimate`: the disturbance estimator of Lu, Sandy & Buchli over a recorded log, for
//! logs from any robot or simulator: rows `q τ` in, rows `d̂` out; with `--timestamps`, rows
//! `t q τ` in, each step filtered over its own length ([`hya_core::timed`]), rows `t d̂` out.

use std::io::{BufRead, Write};

use hya_core::dispatch::{with_joints, ForJoints, MAX_JOINTS};
use hya_core::filter::{PAPER_BANDWIDTH_RAD_S, PAPER_ZETA};
use hya_core::{BoxedObserver, ObserverDesign};
use hya_core::{DisturbanceEstimator, FilterParams, JointVector, Measurement, Short, TimedEstimator};
use hya_robots::ForArm;

use crate::table::names::{self, Joints, Unit};
use crate::table::{self, Column, ColumnSpec, ColumnsArg, HeaderArg, RowWriter, Table};
use crate::CliError;
use hya_ident::JointFriction;

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
    /// The log's sample time (one row per control tick), s [default: 0.001]. With
    /// `--timestamps`, the nominal one, at which the filters are designed and the gap limit's
    /// default is 2.5 times it [default: the median step of the log's first 1000 rows].
    #[arg(long)]
    dt: Option<f64>,
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
    /// (--columns) Read in the order t (with --timestamps), q, [q̇,] τ; other columns
    /// (currents, commands) are ignored.
    #[command(flatten)]
    columns: ColumnsArg,
    #[command(flatten)]
    header: HeaderArg,
    /// The estimator: `lu` (the paper's, with --zeta, --omega1, --omega2), or one of the
    /// observers it is compared with at --bandwidth, run at the fixed --dt: `chen` (Chen's
    /// nonlinear observer) and `momentum` (the generalized-momentum observer) read measured
    /// velocities, rows `q q̇ τ` (or t, q, q̇, τ from --columns), `eso` (the extended-state
    /// observer) angles and torques only. --timestamps runs `lu` only: the observers are
    /// discretised for one sample time.
    #[arg(long, value_enum, default_value_t = EstimateMethod::Lu)]
    method: EstimateMethod,
    /// The observers' design bandwidth, rad/s (chen, momentum, eso).
    #[arg(long, default_value_t = PAPER_BANDWIDTH_RAD_S)]
    bandwidth: f64,
    /// Joint friction the model knows (`friction.toml` from `hya identify`): the rows out are
    /// then what neither the rigid body nor that friction explains, `d̂ + τ_f(q̂̇)` (`+ I_a q̂̈`
    /// where the file has an armature), at the filtered velocity and acceleration. With
    /// `--method lu`.
    #[arg(long)]
    friction: Option<std::path::PathBuf>,
}

/// `--method`: the paper's estimator or an observer it is compared with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum EstimateMethod {
    /// The paper's estimator (Lu, Sandy & Buchli).
    Lu,
    /// Chen's nonlinear disturbance observer; reads q̇.
    Chen,
    /// The generalized-momentum observer; reads q̇.
    Momentum,
    /// The model-assisted extended-state observer.
    Eso,
}

impl EstimateMethod {
    /// Its name on the command line.
    fn name(self) -> &'static str {
        match self {
            Self::Lu => "lu",
            Self::Chen => "chen",
            Self::Momentum => "momentum",
            Self::Eso => "eso",
        }
    }

    /// Its design: the paper's estimator with `params`, an observer at pole magnitude
    /// `bandwidth_rad_s` and `params`' step.
    fn design(self, params: FilterParams, bandwidth_rad_s: f64) -> ObserverDesign {
        let dt_s = params.dt_s();
        match self {
            Self::Lu => ObserverDesign::Paper(params),
            Self::Chen => ObserverDesign::Nonlinear { bandwidth_rad_s, dt_s, gain: Default::default() },
            Self::Momentum => ObserverDesign::Momentum { bandwidth_rad_s, dt_s },
            Self::Eso => ObserverDesign::ExtendedState { bandwidth_rad_s, dt_s },
        }
    }

    /// Whether its rows hold measured velocities.
    fn reads_velocity(self) -> bool {
        matches!(self, Self::Chen | Self::Momentum)
    }
}

/// How `hya estimate` reads a row: its columns and whether it starts with a time.
#[derive(Clone)]
struct Layout {
    params: FilterParams,
    /// The nominal step is to be taken from the log (`--timestamps` without `--dt`), and the gap
    /// limit too unless `--max-step` gave it.
    step_from_log: Option<Option<f64>>,
    method: EstimateMethod,
    bandwidth_rad_s: f64,
    timestamps: bool,
    max_step_s: f64,
    columns: Option<ColumnSpec>,
    friction: Option<std::path::PathBuf>,
    /// The model's joints, for the columns' names and units.
    joints: Joints,
    header: bool,
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
    Paper(Box<DisturbanceEstimator<N, Nominal<'a, N>>>),
    Fixed(BoxedObserver<'a, N>),
    Timed(TimedEstimator<N, Nominal<'a, N>>),
}

/// The model every estimator runs on.
type Nominal<'a, const N: usize> = &'a (dyn hya_core::Dynamics<N> + Sync);

impl<'a, const N: usize> Running<'a, N> {
    /// The estimator of `layout` at rest on the first row.
    fn start(nominal: Nominal<'a, N>, layout: &Layout, t: f64, first: &Measurement<N>) -> Result<Self, CliError> {
        let setup = |e: hya_core::Error| CliError::Input(e.to_string());
        let (q, tau) = (first.position, first.torque);
        Ok(match layout.method {
            _ if layout.timestamps => {
                Self::Timed(TimedEstimator::new(nominal, layout.params, t, q, tau).map_err(setup)?)
            }
            EstimateMethod::Lu => {
                Self::Paper(Box::new(DisturbanceEstimator::new(nominal, layout.params, q, tau).map_err(setup)?))
            }
            other => {
                let design = other.design(layout.params, layout.bandwidth_rad_s);
                let (observer, _rates) = design
                    .build(nominal, first)
                    .map_err(|e| CliError::Input(format!("--method {}: {e}", other.name())))?;
                Self::Fixed(observer)
            }
        })
    }

    /// The latest `d̂`.
    fn disturbance(&self) -> JointVector<N> {
        match self {
            Self::Paper(e) => *e.disturbance(),
            Self::Fixed(e) => *e.disturbance(),
            Self::Timed(e) => *e.estimator().disturbance(),
        }
    }

    /// The filtered velocity and acceleration `(q̂̇, q̂̈)` of the paper's estimator (`None` for
    /// the observers).
    fn filtered(&self) -> Option<(JointVector<N>, JointVector<N>)> {
        let state = match self {
            Self::Paper(e) => e.joint_estimate(),
            Self::Fixed(_) => return None,
            Self::Timed(e) => e.estimator().joint_estimate(),
        };
        Some((state.x2, state.x3))
    }
}

/// Rows `[t] q τ` (`2N` or `2N + 1` numbers, or the columns `--columns` selects) in, rows
/// `[t] d̂` out; the first row starts the estimator at rest (`d̂ = G(q) − τ` there).
fn estimate<'a, const N: usize>(
    nominal: Nominal<'a, N>,
    layout: &Layout,
    input: impl BufRead,
    output: &mut impl Write,
) -> Result<(), CliError> {
    let offset = usize::from(layout.timestamps);
    let velocity = layout.method.reads_velocity();
    let what = format!(
        "{}the {N} joint angles q (rad), {}then the {N} joint torques τ (N·m)",
        if layout.timestamps { "the time t (s), then " } else { "" },
        if velocity { format!("then the {N} joint velocities q̇ (rad/s), ") } else { String::new() }
    );
    let joints = &layout.joints;
    let time = layout.timestamps.then(names::time);
    let wanted: Vec<Column> = time
        .iter()
        .cloned()
        .chain(joints.columns("q", Unit::Position))
        .chain(velocity.then(|| joints.columns("qd", Unit::Velocity)).into_iter().flatten())
        .chain(joints.columns("tau", Unit::Effort))
        .collect();
    let out_columns = time.into_iter().chain(joints.columns("d_hat", Unit::Effort)).collect();
    let friction = layout.friction.as_deref().map(|path| JointFriction::from_file(path, N)).transpose();
    let friction = friction.map_err(|e| CliError::Input(format!("--friction {e}")))?;
    let mut log = Table::new(input, layout.columns.clone(), wanted, what)?;
    let mut writer = RowWriter::new(output, out_columns, layout.header);
    let adopted;
    let layout = match layout.step_from_log {
        None => layout,
        Some(max_step) => {
            let (params, max_step_s) = log.adopt_nominal_step(&layout.params, max_step)?;
            adopted = Layout { params, max_step_s, ..layout.clone() };
            &adopted
        }
    };
    let mut running: Option<Running<'a, N>> = None;
    let mut gaps = Gaps::default();
    while let Some(line) = log.next_line() {
        let line = line?;
        let values = log.values();
        let t = values[0];
        let column = |k: usize| JointVector::<N>::from_column_slice(&values[offset + k * N..offset + (k + 1) * N]);
        let measurement = Measurement {
            position: column(0),
            velocity: velocity.then(|| column(1)),
            torque: column(1 + usize::from(velocity)),
        };
        let (q, tau) = (&measurement.position, &measurement.torque);
        let at_line = |e: hya_core::Error| CliError::Input(format!("line {}: {e}", line));
        let d_hat = match running.as_mut() {
            None => {
                let started = Running::start(nominal, layout, t, &measurement)
                    .map_err(|e| table::at(format_args!("line {}", line), e))?;
                let d_hat = started.disturbance();
                running = Some(started);
                d_hat
            }
            Some(Running::Paper(e)) => e.update(q, tau).map_err(at_line)?,
            Some(Running::Fixed(e)) => e.update(&measurement).map_err(at_line)?,
            Some(Running::Timed(e)) => timed_step(e, layout, line, t, q, tau, &mut gaps)?,
        };
        let d_hat = match (&friction, running.as_ref().and_then(Running::filtered)) {
            (Some(f), Some((v, a))) => JointVector::<N>::from_fn(|i, _| d_hat[i] + f.joint_torque(i, v[i], a[i])),
            _ => d_hat,
        };
        let time = layout.timestamps.then_some(t);
        writer
            .write(time.into_iter().chain(d_hat.iter().copied()))
            .map_err(|e| table::at(format_args!("line {}", line), e))?;
    }
    if gaps.all > REPORTED_GAPS {
        eprintln!(
            "hya: {} gaps in all, {} of them restarts of the estimator; the first {REPORTED_GAPS} reported",
            gaps.all, gaps.restarts
        );
    }
    Ok(())
}

/// How many gaps `hya estimate --timestamps` reports one by one, restarts or not; a count of all
/// follows (a log of 200,000 restarts once printed 33 MB of them).
const REPORTED_GAPS: usize = 20;

/// The gaps of a timestamped log so far.
#[derive(Debug, Default)]
struct Gaps {
    /// Steps longer than `--max-step`.
    all: usize,
    /// Those the filters could not bridge: the estimator restarted at rest.
    restarts: usize,
}

/// One timestamped row: refuses a time that does not increase, reports a gap or a restart on
/// stderr, and returns `d̂`.
fn timed_step<const N: usize>(
    estimator: &mut TimedEstimator<N, Nominal<'_, N>>,
    layout: &Layout,
    line: usize,
    t: f64,
    q: &JointVector<N>,
    tau: &JointVector<N>,
    gaps: &mut Gaps,
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
        gaps.all += 1;
        gaps.restarts += usize::from(step.restarted);
        if gaps.all > REPORTED_GAPS {
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

/// The sample time of a log without timestamps when `--dt` is not given, s.
const DEFAULT_DT_S: f64 = 0.001;

/// `hya estimate`.
pub fn run(args: &EstimateArgs, input: impl BufRead, output: &mut impl Write) -> Result<(), CliError> {
    let dt = args.dt.unwrap_or(DEFAULT_DT_S);
    let params = crate::filter::params(args.zeta, args.omega1, args.omega2, dt)?;
    let max_step_s = match args.max_step {
        None => 2.5 * dt,
        Some(s) if s.is_finite() && s > 0.0 => s,
        Some(s) => return Err(CliError::Input(format!("--max-step {}: must be finite and > 0 s", Short(s)))),
    };
    if !(args.bandwidth.is_finite() && args.bandwidth > 0.0) {
        return Err(CliError::Input(format!("--bandwidth {}: must be finite and > 0 rad/s", Short(args.bandwidth))));
    }
    let columns = args.columns.spec()?;
    if args.friction.is_some() && args.method != EstimateMethod::Lu {
        return Err(CliError::Input(format!(
            "--friction with --method {}: the friction is taken at the paper's filtered velocity; use --method lu",
            args.method.name()
        )));
    }
    if args.timestamps && args.method != EstimateMethod::Lu {
        return Err(CliError::Input(format!(
            "--method {} with --timestamps: only lu is discretised per step; the observers run at a fixed --dt",
            args.method.name()
        )));
    }
    let model = crate::common::model(&args.robot)?;
    let layout = Layout {
        params,
        step_from_log: (args.timestamps && args.dt.is_none()).then_some(args.max_step),
        method: args.method,
        bandwidth_rad_s: args.bandwidth,
        timestamps: args.timestamps,
        max_step_s,
        columns,
        friction: args.friction.clone(),
        joints: Joints::of(&model),
        header: args.header.header(),
    };
    let mut estimate = Estimate { model: None, layout, input, output };
    if hya_robots::find(&args.robot).is_some() {
        return hya_robots::with_arm(&args.robot, estimate)
            .unwrap_or_else(|| Err(CliError::Input(format!("robot `{}` has no dispatch", args.robot))));
    }
    let dof = model.dof();
    estimate.model = Some(model);
    with_joints(dof, estimate).unwrap_or_else(|| {
        Err(CliError::Input(format!(
            "{}: {dof} joints; the estimator runs arms of 1 to {MAX_JOINTS} joints",
            args.robot
        )))
    })
}
