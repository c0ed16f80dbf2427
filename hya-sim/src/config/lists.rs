//! A per-joint list of the configuration checked for an arm of `N` joints (its length, every
//! entry finite, and where asked, in range), and one number checked likewise; the error names the
//! key, and the entry of a list.

use hya_core::JointVector;

use crate::error::{SettingError, SimError};

/// A per-joint list from the configuration, checked for length and finiteness.
pub fn per_joint<const N: usize>(name: &str, values: &[f64]) -> Result<JointVector<N>, SimError> {
    if values.len() != N {
        return Err(SimError::ListLength { key: name.to_owned(), expected: N, got: values.len() });
    }
    if let Some(i) = values.iter().position(|v| !v.is_finite()) {
        return Err(SettingError::new(format!("{name}[{i}]"), Some(values[i]), "must be a finite number").into());
    }
    Ok(JointVector::from_column_slice(values))
}

/// `values` with every entry checked by `ok`, which `requirement` describes.
pub fn each<const N: usize>(
    name: &str,
    values: JointVector<N>,
    ok: impl Fn(f64) -> bool,
    requirement: &str,
) -> Result<JointVector<N>, SimError> {
    match values.iter().position(|v| !ok(*v)) {
        Some(i) => Err(SettingError::new(format!("{name}[{i}]"), Some(values[i]), requirement).into()),
        None => Ok(values),
    }
}

/// [`per_joint`], every entry also checked by `ok`, which `requirement` describes.
pub fn per_joint_where<const N: usize>(
    name: &str,
    values: &[f64],
    ok: impl Fn(f64) -> bool,
    requirement: &str,
) -> Result<JointVector<N>, SimError> {
    each(name, per_joint(name, values)?, ok, requirement)
}

/// `v` if it is finite and `ok`, else the error naming `key` and `requirement`.
pub fn scalar(
    key: &str,
    v: f64,
    ok: impl Fn(f64) -> bool,
    requirement: impl Into<String>,
) -> Result<f64, SettingError> {
    if v.is_finite() && ok(v) {
        Ok(v)
    } else {
        Err(SettingError::new(key, Some(v), requirement))
    }
}
