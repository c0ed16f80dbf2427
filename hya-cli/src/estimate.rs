//! `hya estimate`: the disturbance estimator of Lu, Sandy & Buchli over a recorded log, for
//! logs from any robot or simulator: rows `q τ` in, rows `d̂` out.

use std::io::{BufRead, Write};

use hya_core::filter::{PAPER_BANDWIDTH_RAD_S, PAPER_ZETA};
use hya_core::{DisturbanceEstimator, FilterParams, JointVector};
use hya_sim::{ForJoints, SimError};

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

/// The estimator over every row, for `N` joints.
struct Estimate<'a, R, W> {
    robot: &'a str,
    params: FilterParams,
    input: R,
    output: &'a mut W,
}

impl<R: BufRead, W: Write> ForJoints for Estimate<'_, R, W> {
    type Output = Result<(), CliError>;
    fn call<const N: usize>(self) -> Result<Self::Output, SimError> {
        let nominal = hya_sim::nominal_dynamics::<N>(self.robot)?;
        Ok(estimate::<N>(nominal.as_ref(), self.params, self.input, self.output))
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
    let dof = crate::dynamics::model(&args.robot)?.bodies().len();
    hya_sim::with_joints(dof, Estimate { robot: &args.robot, params, input, output })
        .map_err(|e| CliError::Input(e.to_string()))?
}
