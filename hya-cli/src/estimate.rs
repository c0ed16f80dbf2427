//! `hya estimate`: the disturbance estimator of Lu, Sandy & Buchli over a recorded log, for
//! logs from any robot or simulator: rows `q τ` in, rows `d̂` out.

use std::io::{BufRead, Write};

use hya_core::dispatch::{with_joints, ForJoints, MAX_JOINTS};
use hya_core::filter::{PAPER_BANDWIDTH_RAD_S, PAPER_ZETA};
use hya_core::{DisturbanceEstimator, FilterParams, JointVector};
use hya_robots::ForArm;

use crate::{read_rows, rows, CliError};

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
    /// The log's sample time (one row per control tick), s.
    #[arg(long, default_value_t = 0.001)]
    dt: f64,
}

/// The estimator over every row, for the arm's `N` joints: a shipped arm's generated dynamics
/// ([`ForArm`]), or a URDF's run-time model ([`ForJoints`], with the model in `model`).
struct Estimate<'a, R, W> {
    model: Option<hya_core::model::TreeModel>,
    params: FilterParams,
    input: R,
    output: &'a mut W,
}

impl<R: BufRead, W: Write> ForArm for Estimate<'_, R, W> {
    type Output = Result<(), CliError>;
    fn call<const N: usize>(self, arm: hya_robots::Arm<N>) -> Self::Output {
        estimate::<N>(arm.nominal, self.params, self.input, self.output)
    }
}

impl<R: BufRead, W: Write> ForJoints for Estimate<'_, R, W> {
    type Output = Result<(), CliError>;
    fn call<const N: usize>(self) -> Self::Output {
        let model = self.model.ok_or_else(|| CliError::Input("no model to estimate with".into()))?;
        let nominal = model.into_dynamics::<N>().map_err(|e| CliError::Input(e.to_string()))?;
        estimate::<N>(&nominal, self.params, self.input, self.output)
    }
}

/// Rows `q τ` (`2N` numbers) in, rows `d̂` (`N`) out; the first row starts the estimator at rest
/// (`d̂ = G(q) − τ` there).
fn estimate<const N: usize>(
    nominal: &dyn hya_core::Dynamics<N>,
    params: FilterParams,
    input: impl BufRead,
    output: &mut impl Write,
) -> Result<(), CliError> {
    let mut estimator = None;
    for row in read_rows(input) {
        let row = row?;
        rows::expect_width(&row, 2 * N, "the joint angles q (rad), then the joint torques τ (N·m)")?;
        let q = JointVector::<N>::from_column_slice(&row.values[..N]);
        let tau = JointVector::<N>::from_column_slice(&row.values[N..]);
        let at_line = |e: hya_core::Error| CliError::Input(format!("line {}: {e}", row.line));
        let d_hat = match estimator.as_mut() {
            None => {
                let started = DisturbanceEstimator::new(nominal, params, q, tau).map_err(at_line)?;
                let d_hat = *started.disturbance();
                estimator = Some(started);
                d_hat
            }
            Some(e) => e.update(&q, &tau).map_err(at_line)?,
        };
        rows::write(output, d_hat.iter().copied()).map_err(|e| rows::at(format_args!("line {}", row.line), e))?;
    }
    Ok(())
}

/// `hya estimate`.
pub fn run(args: &EstimateArgs, input: impl BufRead, output: &mut impl Write) -> Result<(), CliError> {
    let params = crate::filter::params(args.zeta, args.omega1, args.omega2, args.dt)?;
    let mut estimate = Estimate { model: None, params, input, output };
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
