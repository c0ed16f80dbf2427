//! `friction.toml` and `identified.urdf`, the files a user loads back into hya.

use hya_core::model::TreeModel;
use hya_core::spatial::RigidBodyInertia;
use hya_ident::{body_inertia, Consistent, Fit, PARAMETERS_PER_BODY};

use crate::CliError;

/// `values` as `a, b, c` with six decimals.
pub fn list(values: impl IntoIterator<Item = f64>) -> String {
    values.into_iter().map(|v| format!("{v:.6}")).collect::<Vec<_>>().join(", ")
}

/// `friction.toml`: the identified friction, with standard deviations as comments.
pub fn friction_toml(fitted: &Fit, joints: &[&str]) -> String {
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
        hya_urdf::name_list(joints.iter().copied()),
        f.smoothing_rad_s,
        list(f.coulomb_nm.iter().copied()),
        column(0),
        list(f.viscous_nm_s.iter().copied()),
        column(1),
        list(f.offset_nm.iter().copied()),
        column(2),
    )
}

/// The nominal description's text.
fn urdf_text(robot: &str) -> Result<String, CliError> {
    match hya_robots::find(robot) {
        Some(shipped) => Ok(shipped.urdf.to_owned()),
        None => hya_urdf::file::read_text(std::path::Path::new(robot), hya_urdf::MAX_FILE_BYTES as u64)
            .map_err(|e| CliError::Input(format!("{}: {e}", crate::table::echo(robot)))),
    }
}

/// `identified.urdf`: each body's consistent inertia (see [`with_body_inertias`]).
pub fn identified_urdf(robot: &str, model: &TreeModel, full: &Consistent) -> Result<String, CliError> {
    let inertias: Vec<RigidBodyInertia> = (0..model.bodies().len())
        .map(|b| body_inertia(&full.parameters.as_slice()[b * PARAMETERS_PER_BODY..][..PARAMETERS_PER_BODY]))
        .collect();
    with_body_inertias(robot, model, &inertias, "identified.urdf")
}

/// The description of `robot` (whose model is `model`) with body `b`'s inertia `inertias[b]` on
/// the link of its joint, and the links merged into a body by fixed joints made massless (their
/// mass is in the body's); checked by loading it back as `file`.
pub fn with_body_inertias(
    robot: &str,
    model: &TreeModel,
    inertias: &[RigidBodyInertia],
    file: &str,
) -> Result<String, CliError> {
    let mut links: Vec<(&str, RigidBodyInertia)> =
        model.bodies().iter().zip(inertias).map(|(body, inertia)| (body.link.as_str(), *inertia)).collect();
    for frame in model.frames() {
        if frame.body.is_some_and(|b| model.bodies()[b].link != frame.name) {
            links.push((frame.name.as_str(), RigidBodyInertia::zero()));
        }
    }
    let text =
        hya_urdf::with_inertias(&urdf_text(robot)?, robot, &links).map_err(|e| CliError::Input(e.to_string()))?;
    let written = hya_urdf::load_str(&text, file).map_err(|e| CliError::Input(e.to_string()))?.model;
    for (body, want) in written.bodies().iter().zip(inertias) {
        let got = &body.inertia;
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * (1.0 + b.abs());
        let same = close(got.mass, want.mass)
            && (0..3).all(|k| close(got.first_moment[k], want.first_moment[k]))
            && (0..9).all(|k| close(got.rotational[k], want.rotational[k]));
        if !same {
            return Err(CliError::Input(format!(
                "{file} would not reproduce body `{}`'s inertia (a bug: please report it)",
                body.link
            )));
        }
    }
    Ok(text)
}
