//! The arm a command works on: a shipped robot by name or a URDF by path, its description's
//! text, and the scenario whose plant simulates it.

use hya_core::model::TreeModel;
use hya_core::spatial::RigidBodyInertia;
use hya_sim::Scenario;

use super::CliError;

/// A URDF file's model; the loader's warnings on stderr.
pub fn load(path: &str) -> Result<TreeModel, CliError> {
    let loaded = hya_urdf::load_file(path).map_err(|e| CliError::Input(e.to_string()))?;
    for warning in &loaded.warnings {
        eprintln!("hya: warning: {path}: {warning}");
    }
    Ok(loaded.model)
}

/// The run-time model of a shipped robot (by name) or of a URDF file (by path).
pub fn model(robot: &str) -> Result<TreeModel, CliError> {
    match hya_robots::find(robot) {
        Some(shipped) => hya_urdf::load_str(shipped.urdf, shipped.name)
            .map(|loaded| loaded.model)
            .map_err(|e| CliError::Input(e.to_string())),
        None if std::path::Path::new(robot).exists() => load(robot),
        None => Err(CliError::Input(hya_robots::unknown(robot))),
    }
}

/// The nominal description's text.
pub fn urdf_text(robot: &str) -> Result<String, CliError> {
    match hya_robots::find(robot) {
        Some(shipped) => Ok(shipped.urdf.to_owned()),
        None => hya_urdf::file::read_text(std::path::Path::new(robot), hya_urdf::MAX_FILE_BYTES as u64)
            .map_err(|e| CliError::Input(format!("{}: {e}", crate::table::echo(robot)))),
    }
}

/// The description of `robot` (whose model is `model`) with body `b`'s inertia `inertias[b]`
/// ([`hya_urdf::with_body_inertias`]), checked by loading it back as `file`.
pub fn with_body_inertias(
    robot: &str,
    model: &TreeModel,
    inertias: &[RigidBodyInertia],
    file: &str,
) -> Result<String, CliError> {
    hya_urdf::with_body_inertias(&urdf_text(robot)?, robot, model, inertias, file)
        .map_err(|e| CliError::Input(e.to_string()))
}

/// The scenario whose plant `hya plant` and `hya track` run: `path`, else the first built-in
/// scenario written for the shipped arm `robot`; the error for a URDF without one offers
/// `--scenario`, and `alternative` besides.
pub fn scenario(path: Option<&std::path::Path>, robot: &str, alternative: &str) -> Result<Scenario, CliError> {
    if let Some(path) = path {
        return Ok(Scenario::from_file(path)?);
    }
    if let Some(shipped) = hya_robots::find(robot) {
        for name in Scenario::builtin_names().chain(Scenario::arm_goto_names()) {
            let builtin = Scenario::builtin(name)?;
            if builtin.robot == shipped.name {
                return Ok(builtin);
            }
        }
    }
    Err(CliError::Input(format!(
        "{}: no built-in scenario describes this arm's plant; pass --scenario FILE (its friction, actuators and loads){alternative}",
        crate::table::echo(robot)
    )))
}
