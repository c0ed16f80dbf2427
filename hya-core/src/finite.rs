//! Finiteness checks shared by the hot paths.

use crate::{Error, JointVector};

/// `Ok` if every entry of `values` is finite; otherwise names the first bad entry.
pub(crate) fn check<const N: usize>(signal: &'static str, values: &JointVector<N>) -> Result<(), Error> {
    match values.iter().position(|v| !v.is_finite()) {
        None => Ok(()),
        Some(index) => Err(Error::NonFinite { signal, index, value: values[index] }),
    }
}

/// `Ok` if `value` is finite and strictly positive; otherwise an [`Error::InvalidParameter`].
pub(crate) fn positive(name: &'static str, value: f64) -> Result<f64, Error> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(Error::InvalidParameter { name, value, requirement: "finite and > 0" })
    }
}
