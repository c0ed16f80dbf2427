//! `friction.toml` and `identified.urdf`, the files a user loads back into hya.

use hya_core::model::TreeModel;
use hya_ident::{Consistent, Fit};

use crate::CliError;

/// `values` as `a, b, c` with six decimals.
pub fn list(values: impl IntoIterator<Item = f64>) -> String {
    values.into_iter().map(|v| format!("{v:.6}")).collect::<Vec<_>>().join(", ")
}

/// `friction.toml`: the identified friction, with standard deviations as comments.
pub fn friction_toml(fitted: &Fit, joints: &[&str]) -> String {
    fitted.friction.to_toml(joints, Some(&fitted.friction_std))
}

/// `identified.urdf` ([`hya_ident::identify::identified_urdf`]) of the robot `robot`.
pub fn identified_urdf(robot: &str, model: &TreeModel, full: &Consistent) -> Result<String, CliError> {
    hya_ident::identify::identified_urdf(&crate::common::urdf_text(robot)?, robot, model, full)
        .map_err(|e| CliError::Input(e.to_string()))
}
