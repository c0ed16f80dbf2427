//! `hya identify`: base parameters and joint friction from a log of rows `[t] q τ`, written into
//! `--out` as `identified.urdf`, `friction.toml`, `report.md` and `held_out.svg`.
//!
//! The log is filtered into samples ([`log`]); the first part is fitted and a later part held
//! out, on which the identified and the nominal model's torque predictions are compared (and
//! those of `--compare`'s model, whose base parameters the report also holds against the
//! identified ones, in standard deviations).

pub mod files;
mod log;
mod report;

use std::io::BufRead;
use std::path::PathBuf;

use hya_core::dispatch::with_joints;
use hya_core::model::TreeModel;
use hya_core::{FilterParams, Short};
use hya_ident::identify::{rigid_predictions, PriorWeight};
use hya_ident::{identify, nominal_parameters, BaseParameters, IdentifyError, Law, Options, Regressor};
use hya_sim::io::output::OutputDir;

use crate::table::names::Joints;
use crate::table::{check_dt, ColumnsArg};
use crate::CliError;
use files::{friction_toml, identified_urdf, list};
use log::{Filter, Layout};
use report::{Compared, Findings, Predictions};

/// Parameters of `hya identify`.
#[derive(Debug, clap::Args)]
pub struct IdentifyArgs {
    /// A shipped robot's name (see `hya robots`) or the path of a URDF file: the nominal model.
    #[arg(long)]
    robot: String,
    /// The log's sample time, s (rows `q τ`, one per tick). With `--timestamps`, the nominal
    /// step: the filters are designed at it and each row is filtered over its own step
    /// [default with --timestamps: the median step of the log's first 1000 rows].
    #[arg(long, required_unless_present = "timestamps")]
    dt: Option<f64>,
    /// Rows start with their time t, s: `t q τ`, filtered over each step's own length.
    #[arg(long)]
    timestamps: bool,
    /// With --timestamps: the longest step that is not a gap, s [default: 2.5 × --dt]; the
    /// filters restart after a gap and settle again before samples are taken.
    #[arg(long, requires = "timestamps")]
    max_step: Option<f64>,
    /// (--columns) Read in the order t (with --timestamps), q, τ; other columns are ignored.
    #[command(flatten)]
    columns: ColumnsArg,
    /// A URDF (the same joints as --robot) to hold the identified model against: its base
    /// parameters in standard deviations of the identified ones, and its held-out prediction
    /// (a published identified model, or a simulation's true one).
    #[arg(long)]
    compare: Option<String>,
    /// Where the files go (created; held by this run alone).
    #[arg(long, default_value = "hya-identify")]
    out: PathBuf,
    /// Replace files hya wrote in `--out` before (see `hya run --help`).
    #[arg(long)]
    force: bool,
    /// The fraction of the log, at its end, held out from the fit to test the prediction.
    #[arg(long, default_value_t = 0.25)]
    held_out: f64,
    /// The friction model's smoothing velocity `s` in `c tanh(q̇/s)`, rad/s.
    #[arg(long, default_value_t = 0.05)]
    smoothing_rad_s: f64,
    /// The filters' bandwidth ω, rad/s (damping 0.8, as the paper's).
    #[arg(long, default_value_t = 50.0)]
    bandwidth_rad_s: f64,
    /// How far the fit trusts the nominal model (--robot) against the log: `auto` chooses the
    /// weight λ on held-out blocks in time of the fitted part (the report shows the curve); a
    /// number λ ≥ 0 fixes it; 0 fits the log alone (with the bodies made physical afterwards,
    /// which can move them off the fit). The prior pulls each body toward its nominal one by the
    /// log-det divergence of their pseudo-inertias, and keeps every body physical.
    #[arg(long, default_value = "0", value_parser = prior_weight)]
    prior_weight: PriorWeight,
    /// Identify each joint's armature, the motor inertia reflected through the gear (`I_a q̈`),
    /// which no URDF link carries; written to friction.toml as `armature_kg_m2`.
    #[arg(long)]
    armature: bool,
    /// Fit each joint's rows near its reversals too. By default they are left out: where the
    /// joint's filtered velocity turns, or falls below 3 times the smoothing velocity
    /// (--smoothing-rad-s), within 10/ω of a sample, the filtered torque holds friction's switch smeared by the filters and
    /// no parameter of the model explains it, so fitting those rows moves the parameters. With a
    /// smoothing velocity large against the log's speeds most rows are left out: the report
    /// gives the rows fitted per joint.
    #[arg(long)]
    keep_reversals: bool,
}

/// `--prior-weight`: `auto` or a number.
fn prior_weight(text: &str) -> Result<PriorWeight, String> {
    match text {
        "auto" => Ok(PriorWeight::Auto),
        number => number
            .parse::<f64>()
            .ok()
            .filter(|l| l.is_finite() && *l >= 0.0)
            .map(PriorWeight::Fixed)
            .ok_or_else(|| format!("`{}`: `auto` or a finite number ≥ 0", hya_core::Clipped(number, 40))),
    }
}

fn input(e: impl std::fmt::Display) -> CliError {
    CliError::Input(e.to_string())
}

/// The model of `--compare`: a URDF with the nominal model's joints, in its order.
fn compared_model(path: &str, nominal: &TreeModel) -> Result<TreeModel, CliError> {
    let model = crate::common::model(path)?;
    if let Some(why) = hya_urdf::joints_differ(&model, nominal, "--robot's") {
        return Err(CliError::Input(format!("--compare {}: {why}", hya_core::Clipped(path, 200))));
    }
    Ok(model)
}

/// An identification error as the command line says it: an option by its flag.
fn identify_error(e: IdentifyError) -> CliError {
    match e {
        IdentifyError::Option(name, why) => CliError::Input(format!("--{} {why}", name.replace('_', "-"))),
        other => input(other),
    }
}

/// The filters' step until a timestamped log without `--dt` gives its own, s.
const PROVISIONAL_DT_S: f64 = 0.001;

/// `hya identify`.
pub fn run(args: &IdentifyArgs, stdin: impl BufRead) -> Result<(), CliError> {
    // Without --dt, a timestamped log's own median step, taken while it is read (`log::filter`).
    let dt = check_dt("--dt", args.dt.unwrap_or(PROVISIONAL_DT_S))?;
    let options = Options {
        held_out: args.held_out,
        smoothing_rad_s: args.smoothing_rad_s,
        prior_weight: args.prior_weight,
        armature: args.armature,
        keep_reversals: args.keep_reversals,
    };
    options.check().map_err(identify_error)?;
    let model = crate::common::model(&args.robot)?;
    let max_step_s = match args.max_step {
        None => 2.5 * dt,
        Some(s) if s.is_finite() && s > 0.0 => s,
        Some(s) => {
            return Err(CliError::Input(format!("--max-step {}: must be a positive number of seconds", Short(s))))
        }
    };
    let layout = Layout {
        params: FilterParams::new(0.8, args.bandwidth_rad_s, args.bandwidth_rad_s, dt)
            .map_err(|e| CliError::Input(format!("--bandwidth-rad-s, --dt: {e}")))?,
        timestamps: args.timestamps,
        max_step_s,
        columns: args.columns.spec()?,
        step_from_log: (args.timestamps && args.dt.is_none()).then_some(args.max_step),
        joints: Joints::of(&model),
    };
    hya_ident::check_joint_count(&model).map_err(input)?;
    // `--compare`'s name in the report, and its model.
    let compared = match &args.compare {
        Some(path) => Some((hya_core::Clipped(path, 60).to_string(), compared_model(path, &model)?)),
        None => None,
    };
    let n = model.dof();
    let regressor = Regressor::of_robot(&args.robot, &model);
    let base = BaseParameters::of(&model, 5).map_err(input)?;
    let log = with_joints(n, Filter { input: stdin, layout: &layout }).ok_or_else(|| {
        CliError::Input(format!("{} joints: hya handles 1 to {}", n, hya_core::dispatch::MAX_JOINTS))
    })??;
    let found = identify(&model, &regressor, &base, &log.log, options).map_err(identify_error)?;
    let held_out = &log.log.samples[found.fitted_samples..];
    let mut models = vec![
        ("nominal model".to_owned(), found.nominal.clone()),
        ("identified model".to_owned(), found.identified.clone()),
        ("nominal model + friction fit".to_owned(), found.nominal_with_friction.clone()),
    ];
    if let Some((name, compared)) = &compared {
        models.push((name.clone(), rigid_predictions(compared, held_out).map_err(input)?));
    }
    let predictions = Predictions { time_s: found.held_out_time_s.clone(), measured: found.measured.clone(), models };
    let (fitted, full) = (&found.fitted, &found.full);
    let terms = fitted.friction_std.first().map_or(3, Vec::len);
    let joints: Vec<&str> = model.joint_names().collect();
    // The report shows each name escaped and cut, as messages do: no name can forge a line.
    let shown: Vec<String> = joints.iter().map(|name| hya_urdf::name_list([*name])).collect();
    let shown: Vec<&str> = shown.iter().map(String::as_str).collect();
    let findings = Findings {
        model: &model,
        joints: &shown,
        base: &base,
        fitted,
        full,
        nominal_base: base.of_parameters(&nominal_parameters(&model)).as_slice().to_vec(),
        compared: compared.as_ref().map(|(name, compared)| Compared {
            name: name.clone(),
            base: base.of_parameters(&nominal_parameters(compared)).as_slice().to_vec(),
        }),
        predictions: &predictions,
        prior_weight: found.prior_weight,
        validation: found.validation.as_ref(),
        setup: format!(
            "{} rows{} at {} s{}{}; filtered (ζ 0.8, ω {} rad/s), the first {} s after each start left out \
             while the filters settle, then one sample per 1/ω (over which the filters make neighbouring rows' \
             noise alike): {} samples fitted, the last {} held out. {}: rows fitted per joint {} (the held-out \
             RMS is over every held-out sample). {} base \
             parameters of {} and {} friction terms, by weighted least squares{}; condition number of the weighted \
             system {:.3e}. Standard \
             deviations are the spread of the residual's share over {} contiguous parts of the fitted samples \
             (a cluster-robust sandwich), so errors correlated within a part count; the filters' lag adds a \
             bias they do not count. Torques are compared after the same filter.",
            log.log.rows,
            if args.timestamps { " with timestamps" } else { "" },
            Short(log.dt_s),
            if args.dt.is_none() { " (the log's median step)" } else { "" },
            if log.log.gaps > 0 {
                format!(", {} gaps (longer than {} s)", log.log.gaps, Short(log.max_step_s))
            } else {
                String::new()
            },
            Short(args.bandwidth_rad_s),
            log.log.settling_s,
            found.fitted_samples,
            held_out.len(),
            if args.keep_reversals {
                "Every joint's rows fitted, those near its reversals too (--keep-reversals)".to_string()
            } else {
                format!(
                    "A joint's row of a sample is left out of the fit where its filtered velocity turns or falls below \
                     3 s = {} rad/s within 10/ω of the sample (there the filtered friction torque is no function of \
                     the filtered velocity)",
                    Short(Law { smoothing_rad_s: args.smoothing_rad_s, armature: false, keep_reversals: false }.least_speed_rad_s())
                )
            },
            found.fitted_rows.iter().map(usize::to_string).collect::<Vec<_>>().join(", "),
            base.rank(),
            regressor.columns(),
            terms * n,
            if found.prior_weight > 0.0 { " pulled toward the nominal model (see Prior)" } else { "" },
            fitted.conditioning.condition_number,
            hya_ident::fit::SPREAD_PARTS
        ),
    };

    let reads = [Some(&args.robot), args.compare.as_ref()].into_iter().flatten().map(std::path::Path::new);
    let (out, _) = OutputDir::open(&args.out, args.force, "hya identify", &reads.collect::<Vec<_>>()).map_err(input)?;
    let save = |name: &str, text: &str| out.save(name, text).map_err(input);
    save("identified.urdf", &identified_urdf(&args.robot, &model, full)?)?;
    let friction = friction_toml(fitted, &joints);
    // The reader's own checks: a fitted term beyond its plausible range is said now, not when
    // `estimate --friction` or `controller.friction_toml` refuses the file.
    if let Err(why) = hya_ident::JointFriction::from_toml(&friction, n) {
        eprintln!("hya identify: warning: friction.toml is written, but hya will refuse to read it back: {why}");
    }
    save("friction.toml", &friction)?;
    save("report.md", &findings.markdown())?;
    save("held_out.svg", &findings.figure())?;
    let rms = |m: usize| list(predictions.rms(m));
    eprintln!(
        "hya identify: {} base parameters and {} friction terms from {} samples (prior weight {}); held-out RMS \
         (N·m) nominal [{}], identified [{}], nominal + friction fit [{}]; relative to the torque's RMS, mean over \
         joints: nominal {:.4}, identified {:.4}, nominal + friction fit {:.4}{}; {}",
        base.rank(),
        terms * n,
        found.fitted_samples,
        found.prior_weight,
        rms(0),
        rms(1),
        rms(2),
        predictions.relative(0),
        predictions.relative(1),
        predictions.relative(2),
        findings.largest_deviation().map_or(String::new(), |d| format!(
            ", compared [{}], identified base parameters within {d:.2} σ of the compared model's",
            rms(3)
        )),
        out.path().join("report.md").display()
    );
    Ok(())
}
