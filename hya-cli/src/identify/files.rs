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
    fitted.friction.to_toml(joints, Some(&fitted.friction_std))
}

/// `identified.urdf`: each body's consistent inertia (see [`crate::common::with_body_inertias`]).
pub fn identified_urdf(robot: &str, model: &TreeModel, full: &Consistent) -> Result<String, CliError> {
    let inertias: Vec<RigidBodyInertia> = (0..model.bodies().len())
        .map(|b| body_inertia(&full.parameters.as_slice()[b * PARAMETERS_PER_BODY..][..PARAMETERS_PER_BODY]))
        .collect();
    crate::common::with_body_inertias(robot, model, &inertias, "identified.urdf")
}
