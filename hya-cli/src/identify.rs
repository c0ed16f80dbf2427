//! `hya identify`: base parameters and joint friction from a log of rows `q τ` (one per control
//! tick of `--dt`), written into `--out` as `identified.urdf`, `friction.toml` and `report.md`.
//!
//! `q̂, q̂̇, q̂̈` come from the paper's third-order filter on `q` (no numerical differentiation)
//! and `τ̂` from the same filter on `τ`, so that both carry the same lag, as in the estimator.
//! The first `10/ω` seconds (the filters' start) are left out; the rest is split into a part
//! fitted and a later part held out, on which the identified and the nominal model's torque
//! predictions are compared.

use std::fmt::Write as _;
use std::io::BufRead;
use std::path::PathBuf;

use hya_core::dispatch::{with_joints, ForJoints};
use hya_core::model::TreeModel;
use hya_core::spatial::RigidBodyInertia;
use hya_core::{FilterParams, JointVector, ThirdOrderFilter};
use hya_ident::{
    body_inertia, consistent_parameters, fit, nominal_parameters, BaseParameters, Consistent, Fit, Regressor, Sample,
    PARAMETERS_PER_BODY,
};
use hya_sim::io::output::OutputDir;

use crate::rows::{check_dt, expect_width};
use crate::{read_rows, CliError};

/// Parameters of `hya identify`.
#[derive(Debug, clap::Args)]
pub struct IdentifyArgs {
    /// A shipped robot's name (see `hya robots`) or the path of a URDF file: the nominal model.
    #[arg(long)]
    robot: String,
    /// The log's sample time, s (rows `q τ`, one per tick).
    #[arg(long)]
    dt: f64,
    /// Where `friction.toml` and `report.md` go (created; held by this run alone).
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
}

/// Filters the rows `q τ` into samples `(q̂, q̂̇, q̂̈, τ̂)`, leaving out the first `skip`.
struct Filtered<'a> {
    rows: &'a [Vec<f64>],
    params: FilterParams,
    skip: usize,
}

impl ForJoints for Filtered<'_> {
    type Output = Result<Vec<Sample>, CliError>;
    fn call<const N: usize>(self) -> Self::Output {
        let split = |row: &Vec<f64>| {
            (JointVector::<N>::from_column_slice(&row[..N]), JointVector::<N>::from_column_slice(&row[N..]))
        };
        let (q0, tau0) = split(&self.rows[0]);
        let filter = |x0| ThirdOrderFilter::<N>::new(self.params, x0).map_err(|e| CliError::Input(e.to_string()));
        let (mut angles, mut torques) = (filter(q0)?, filter(tau0)?);
        let mut samples = Vec::with_capacity(self.rows.len().saturating_sub(self.skip));
        for (k, row) in self.rows.iter().enumerate() {
            let (q, tau) = split(row);
            let state = *angles.step(&q).map_err(|e| CliError::Input(format!("row {}: {e}", k + 1)))?;
            let tau_hat = torques.step(&tau).map_err(|e| CliError::Input(format!("row {}: {e}", k + 1)))?.x1;
            if k >= self.skip {
                samples.push(Sample {
                    q: state.x1.as_slice().to_vec(),
                    qd: state.x2.as_slice().to_vec(),
                    qdd: state.x3.as_slice().to_vec(),
                    tau: tau_hat.as_slice().to_vec(),
                });
            }
        }
        Ok(samples)
    }
}

/// Per-joint RMS of `prediction(sample) − τ̂` over `samples`, N·m.
fn rms(
    samples: &[Sample],
    n: usize,
    mut prediction: impl FnMut(&Sample) -> Result<Vec<f64>, CliError>,
) -> Result<Vec<f64>, CliError> {
    let mut sums = vec![0.0; n];
    for sample in samples {
        for (i, p) in prediction(sample)?.iter().enumerate() {
            sums[i] += (p - sample.tau[i]).powi(2);
        }
    }
    Ok(sums.iter().map(|s| (s / samples.len() as f64).sqrt()).collect())
}

fn list(values: impl IntoIterator<Item = f64>) -> String {
    values.into_iter().map(|v| format!("{v:.6}")).collect::<Vec<_>>().join(", ")
}

/// `friction.toml`: the identified friction, with standard deviations as comments.
fn friction_toml(fitted: &Fit, joints: &[&str]) -> String {
    let f = &fitted.friction;
    let column = |k: usize| list(fitted.friction_std.iter().map(|s| s[k]));
    format!(
        "# Joint friction identified by hya identify: the torque each joint needs beyond the rigid\n\
         # body, tau_f = coulomb_nm * tanh(qd / smoothing_rad_s) + viscous_nm_s * qd + offset_nm.\n\
         # Joints: {}\n\
         smoothing_rad_s = {}\n\
         coulomb_nm = [{}]\n\
         # standard deviations: [{}]\n\
         viscous_nm_s = [{}]\n\
         # standard deviations: [{}]\n\
         offset_nm = [{}]\n\
         # standard deviations: [{}]\n",
        joints.join(", "),
        f.smoothing_rad_s,
        list(f.coulomb_nm.iter().copied()),
        column(0),
        list(f.viscous_nm_s.iter().copied()),
        column(1),
        list(f.offset_nm.iter().copied()),
        column(2),
    )
}

/// The name of parameter `column` of the regressor (`joint: m·c_x`, …).
fn parameter_name(joints: &[&str], column: usize) -> String {
    const NAMES: [&str; 10] = ["m", "m·c_x", "m·c_y", "m·c_z", "I_xx", "I_xy", "I_yy", "I_xz", "I_yz", "I_zz"];
    format!("{} {}", joints[column / NAMES.len()], NAMES[column % NAMES.len()])
}

/// The nominal description's text.
fn urdf_text(robot: &str) -> Result<String, CliError> {
    match hya_robots::find(robot) {
        Some(shipped) => Ok(shipped.urdf.to_owned()),
        None => std::fs::read_to_string(robot).map_err(|e| CliError::Input(format!("{robot}: {e}"))),
    }
}

/// `identified.urdf`: each body's consistent inertia on the link of its joint, the links merged
/// into it by fixed joints made massless (their mass is in the body's); checked by loading it
/// back.
fn identified_urdf(robot: &str, model: &TreeModel, full: &Consistent) -> Result<String, CliError> {
    let inertia =
        |b: usize| body_inertia(&full.parameters.as_slice()[b * PARAMETERS_PER_BODY..][..PARAMETERS_PER_BODY]);
    let mut inertias: Vec<(&str, RigidBodyInertia)> =
        model.bodies().iter().enumerate().map(|(b, body)| (body.link.as_str(), inertia(b))).collect();
    for frame in model.frames() {
        if frame.body.is_some_and(|b| model.bodies()[b].link != frame.name) {
            inertias.push((frame.name.as_str(), RigidBodyInertia::zero()));
        }
    }
    let text =
        hya_urdf::with_inertias(&urdf_text(robot)?, robot, &inertias).map_err(|e| CliError::Input(e.to_string()))?;
    let written = hya_urdf::load_str(&text, "identified.urdf").map_err(|e| CliError::Input(e.to_string()))?.model;
    for (b, body) in written.bodies().iter().enumerate() {
        let (got, want) = (&body.inertia, inertia(b));
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * (1.0 + b.abs());
        let same = close(got.mass, want.mass)
            && (0..3).all(|k| close(got.first_moment[k], want.first_moment[k]))
            && (0..9).all(|k| close(got.rotational[k], want.rotational[k]));
        if !same {
            return Err(CliError::Input(format!(
                "identified.urdf would not reproduce body `{}`'s identified inertia (a bug: please report it)",
                body.link
            )));
        }
    }
    Ok(text)
}

/// `hya identify`.
pub fn run(args: &IdentifyArgs, input: impl BufRead) -> Result<(), CliError> {
    let dt = check_dt("--dt", args.dt)?;
    if !(args.held_out > 0.0 && args.held_out < 0.9) {
        return Err(CliError::Input(format!("--held-out {}: must be in (0, 0.9)", args.held_out)));
    }
    if !(args.smoothing_rad_s > 0.0 && args.smoothing_rad_s.is_finite()) {
        return Err(CliError::Input(format!("--smoothing-rad-s {}: must be positive", args.smoothing_rad_s)));
    }
    let params = FilterParams::new(0.8, args.bandwidth_rad_s, args.bandwidth_rad_s, dt)
        .map_err(|e| CliError::Input(format!("--bandwidth-rad-s, --dt: {e}")))?;
    let model = crate::dynamics::model(&args.robot)?;
    let n = model.dof();
    let mut rows = Vec::new();
    for row in read_rows(input) {
        let row = row?;
        expect_width(&row, 2 * n, "q then τ, one per joint")?;
        rows.push(row.values);
    }
    let skip = (10.0 / args.bandwidth_rad_s / dt).ceil() as usize;
    let regressor = Regressor::new(&model);
    let base = BaseParameters::of(&model, 5).map_err(|e| CliError::Input(e.to_string()))?;
    let needed = skip + 4 * (base.rank() + 3 * n).div_ceil(n);
    if rows.len() < needed {
        return Err(CliError::Input(format!(
            "the log has {} rows; identifying {} base parameters and {} friction terms needs at least {needed} \
             (the first {skip} settle the filters)",
            rows.len(),
            base.rank(),
            3 * n
        )));
    }
    let filtered = with_joints(n, Filtered { rows: &rows, params, skip }).ok_or_else(|| {
        CliError::Input(format!("{} joints: hya handles 1 to {}", n, hya_core::dispatch::MAX_JOINTS))
    })??;
    // The filters make neighbouring samples' noise alike over about 1/ω: the fit takes one sample
    // per 1/ω so that its residuals are near independent, as its standard deviations assume.
    let stride = ((1.0 / (args.bandwidth_rad_s * dt)).round() as usize).max(1);
    let samples: Vec<Sample> = filtered.into_iter().step_by(stride).collect();
    let split = ((1.0 - args.held_out) * samples.len() as f64) as usize;
    let (fitted_part, held_out) = samples.split_at(split);
    let fitted =
        fit(&regressor, &base, fitted_part, args.smoothing_rad_s).map_err(|e| CliError::Input(e.to_string()))?;

    let model_error = |e: hya_core::model::ModelError| CliError::Input(e.to_string());
    let identified = rms(held_out, n, |s| {
        Ok(fitted.predict(&regressor, &base, s).map_err(|e| CliError::Input(e.to_string()))?.as_slice().to_vec())
    })?;
    let nominal = rms(held_out, n, |s| model.inverse_dynamics(&s.q, &s.qd, &s.qdd).map_err(model_error))?;
    let joints: Vec<&str> = model.joint_names().collect();
    let nominal_base = base.of_parameters(&nominal_parameters(&model));

    let (out, _) =
        OutputDir::open(&args.out, args.force, "hya identify").map_err(|e| CliError::Input(e.to_string()))?;
    let save = |name: &str, text: &str| out.save(name, text).map_err(|e| CliError::Input(e.to_string()));
    let full = consistent_parameters(&base, &nominal_parameters(&model), &fitted.base);
    save("identified.urdf", &identified_urdf(&args.robot, &model, &full)?)?;
    save("friction.toml", &friction_toml(&fitted, &joints))?;

    let mut report = String::new();
    let _ = writeln!(report, "# Identification of `{}`\n", model.name());
    let _ = writeln!(
        report,
        "{} rows at {dt} s; the first {skip} left out while the filters (ζ 0.8, ω {} rad/s) settle, then one \
         row in {stride} (one per 1/ω, over which the filters make the noise of neighbouring rows alike); \
         {} samples fitted, the last {} held out. {} base parameters of {} and {} friction terms, by weighted \
         least squares; condition number of the weighted system {:.3e}. Standard deviations assume the \
         remaining noise white; the filters' lag adds a bias they do not count. Torques are compared \
         after the same filter.\n",
        rows.len(),
        args.bandwidth_rad_s,
        fitted_part.len(),
        held_out.len(),
        base.rank(),
        regressor.columns(),
        3 * n,
        fitted.conditioning.condition_number
    );
    let _ = writeln!(report, "## Torque prediction on the held-out part, RMS (N·m)\n");
    let _ = writeln!(report, "| joint | nominal model | identified model |\n|---|---|---|");
    for ((joint, nominal), identified) in joints.iter().zip(&nominal).zip(&identified) {
        let _ = writeln!(report, "| {joint} | {nominal:.4} | {identified:.4} |");
    }
    let _ = writeln!(report, "\nThe nominal model has no friction; the identified one has `friction.toml`'s.\n");
    let _ = writeln!(report, "## Base parameters\n");
    let _ = writeln!(
        report,
        "Each is the named parameter plus the dependent ones it absorbs (`π_b = K π`, `hya_ident::base`).\n"
    );
    let _ = writeln!(report, "| # | named after | nominal | identified | standard deviation |\n|---|---|---|---|---|");
    for (j, &column) in base.independent.iter().enumerate() {
        let _ = writeln!(
            report,
            "| {j} | {} | {:.6} | {:.6} | {:.2e} |",
            parameter_name(&joints, column),
            nominal_base[j],
            fitted.base[j],
            fitted.base_std[j]
        );
    }
    let _ = writeln!(
        report,
        "\n## Friction\n\n| joint | coulomb (N·m) | viscous (N·m·s/rad) | offset (N·m) |\n|---|---|---|---|"
    );
    for (i, joint) in joints.iter().enumerate() {
        let (f, s) = (&fitted.friction, fitted.friction_std[i]);
        let _ = writeln!(
            report,
            "| {} | {:.4} ± {:.1e} | {:.4} ± {:.1e} | {:.4} ± {:.1e} |",
            joint, f.coulomb_nm[i], s[0], f.viscous_nm_s[i], s[1], f.offset_nm[i], s[2]
        );
    }
    let mismatch = (0..base.rank()).map(|j| full.base_mismatch[j].abs() / fitted.base_std[j]).fold(0.0, f64::max);
    let _ = writeln!(
        report,
        "\n## Bodies (`identified.urdf`)\n\nFull parameters of real bodies (every pseudo-inertia positive definite), \
         from the nominal ones by {} alternating projections (`hya_ident::physical`); they match the identified base \
         parameters to within {mismatch:.2} of their standard deviations.{}\n",
        full.iterations,
        if full.inconsistent_nominal_bodies.is_empty() {
            String::new()
        } else {
            let names: Vec<&str> =
                full.inconsistent_nominal_bodies.iter().map(|&b| model.bodies()[b].link.as_str()).collect();
            format!(" The nominal description's inertia of {} is not that of a real body.", names.join(", "))
        }
    );
    let _ = writeln!(
        report,
        "A body's own mass is identifiable only where a base parameter is that mass alone; elsewhere the \
         masses below are one consistent choice among many that predict the same torques.\n"
    );
    let _ = writeln!(report, "| link | nominal mass (kg) | identified mass (kg) |\n|---|---|---|");
    for (b, body) in model.bodies().iter().enumerate() {
        let _ = writeln!(
            report,
            "| {} | {:.4} | {:.4} |",
            body.link,
            body.inertia.mass,
            full.parameters[b * PARAMETERS_PER_BODY]
        );
    }
    save("report.md", &report)?;
    eprintln!(
        "hya identify: {} base parameters and {} friction terms from {} samples; held-out RMS (N·m) nominal [{}], \
         identified [{}]; {}",
        base.rank(),
        3 * n,
        fitted_part.len(),
        list(nominal.iter().copied()),
        list(identified.iter().copied()),
        out.path().join("report.md").display()
    );
    Ok(())
}
