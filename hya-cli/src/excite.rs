//! `hya excite`: an exciting trajectory for identification (hya_ident::excitation), printed as
//! rows `t q… q̇… q̈…` for a robot to follow while its log is recorded.

use std::io::Write;

use hya_core::Short;
use hya_ident::{ExcitationDesign, Limits};

use crate::table::names::Joints;
use crate::table::RowWriter;
use crate::CliError;

/// Parameters of `hya excite`.
#[derive(Debug, clap::Args)]
pub struct ExciteArgs {
    /// A shipped robot's name (see `hya robots`) or the path of a URDF file; every joint needs
    /// position and velocity limits in it.
    #[arg(long)]
    robot: String,
    /// Harmonics per joint of the Fourier series.
    #[arg(long, default_value_t = 5)]
    harmonics: usize,
    /// Base frequency, Hz: the trajectory repeats every 1/base seconds.
    #[arg(long, default_value_t = 0.1)]
    base_hz: f64,
    /// Periods printed (each starts and ends at rest).
    #[arg(long, default_value_t = 1)]
    periods: usize,
    /// Rows per second.
    #[arg(long, default_value_t = 100.0)]
    rate_hz: f64,
    /// Fraction of each joint's position range the trajectory may use (about its middle).
    #[arg(long, default_value_t = 0.8)]
    range_fraction: f64,
    /// Fraction of each joint's velocity limit the trajectory may reach.
    #[arg(long, default_value_t = 0.5)]
    velocity_fraction: f64,
    /// Candidates drawn; the best-conditioned one is printed.
    #[arg(long, default_value_t = 50)]
    candidates: usize,
    /// Seed of the candidates' draw.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    #[command(flatten)]
    header: crate::table::HeaderArg,
}

/// Longest output, rows: a day at 1 kHz is far beyond any identification log.
const MAX_ROWS: f64 = 1e8;

/// Design time past which `hya excite` says how long the design will take, s.
const ANNOUNCED_S: f64 = 2.0;

/// Times the first candidate and, if the `candidates` will take longer than [`ANNOUNCED_S`], says
/// how long on stderr before the rest run.
fn announce_cost(candidates: usize) -> impl FnMut(usize) {
    let start = std::time::Instant::now();
    move |done| {
        if done == 1 {
            let each = start.elapsed().as_secs_f64();
            let total = each * candidates as f64;
            if total > ANNOUNCED_S {
                eprintln!(
                    "hya excite: {candidates} candidates at {} ms each (the first, timed): about {} s",
                    Short(each * 1e3),
                    Short(total.round())
                );
            }
        }
    }
}

/// `hya excite`.
pub fn run(args: &ExciteArgs, output: &mut impl Write) -> Result<(), CliError> {
    let rows = args.periods as f64 / args.base_hz * args.rate_hz;
    if !(args.rate_hz > 0.0 && args.rate_hz <= 1e5) {
        return Err(CliError::Input(format!("--rate-hz {}: must be in (0, 100000]", Short(args.rate_hz))));
    }
    if args.periods == 0 || rows.is_nan() || rows > MAX_ROWS {
        return Err(CliError::Input(format!(
            "--periods {} at --base-hz {} and --rate-hz {} makes {} rows; give 1 to {MAX_ROWS:.0}",
            args.periods,
            Short(args.base_hz),
            Short(args.rate_hz),
            Short(rows.round())
        )));
    }
    let model = crate::common::model(&args.robot)?;
    let input = |e: hya_ident::ExcitationError| CliError::Input(format!("{}: {e}", crate::table::echo(&args.robot)));
    let limits = Limits::of(&model, args.range_fraction, args.velocity_fraction).map_err(input)?;
    let design = ExcitationDesign {
        harmonics: args.harmonics,
        base_hz: args.base_hz,
        candidates: args.candidates,
        seed: args.seed,
        ..ExcitationDesign::default()
    };
    let (trajectory, conditioning) =
        design.run_observed(&model, &limits, announce_cost(args.candidates)).map_err(input)?;
    eprintln!(
        "hya excite: {} ({} joints), {} harmonics at {} Hz, best of {} candidates: regressor over one period \
         of rank {} of {} parameters, condition number {:.3e} (σ1/σr)",
        model.name(),
        model.dof(),
        args.harmonics,
        Short(args.base_hz),
        args.candidates,
        conditioning.rank,
        hya_ident::PARAMETERS_PER_BODY * model.dof(),
        conditioning.condition_number
    );
    let joints = Joints::of(&model);
    let columns = joints.reference();
    let mut writer = RowWriter::new(output, columns, args.header.header());
    for k in 0..=rows.round() as usize {
        let t = k as f64 / args.rate_hz;
        let (q, qd, qdd) = trajectory.at(t);
        writer.write(std::iter::once(t).chain(q.iter().chain(&qd).chain(&qdd).copied()))?;
    }
    Ok(())
}
