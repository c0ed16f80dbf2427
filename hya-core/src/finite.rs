//! Finiteness checks shared by the hot paths.

use crate::Error;

/// `Ok` if every entry of `values` is finite; otherwise names the first bad entry.
///
/// Inlined, with no exit inside the loop, so the hot paths' vectors stay in registers; the
/// error is built out of line.
#[inline(always)]
/// Any fixed-size matrix, a [`JointVector`](crate::JointVector) among them: the index is the entry's column-major one.
pub(crate) fn check<const R: usize, const C: usize>(
    signal: &'static str,
    values: &nalgebra::SMatrix<f64, R, C>,
) -> Result<(), Error> {
    if values.iter().fold(true, |finite, v| finite & v.is_finite()) {
        Ok(())
    } else {
        Err(first_non_finite(signal, values))
    }
}

/// [`check`]'s error: the first entry of `values` that is not finite.
#[cold]
#[inline(never)]
fn first_non_finite<const R: usize, const C: usize>(
    signal: &'static str,
    values: &nalgebra::SMatrix<f64, R, C>,
) -> Error {
    let index = values.iter().position(|v| !v.is_finite()).unwrap_or(0);
    Error::NonFinite { signal, index, value: values[index] }
}

/// `Ok` if `value` is finite and strictly positive; otherwise an [`Error::InvalidParameter`].
pub(crate) fn positive(name: &'static str, value: f64) -> Result<f64, Error> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(Error::InvalidParameter { name, value, requirement: "finite and > 0" })
    }
}

/// `Ok` if every entry of the result `values` is finite; otherwise [`Error::NonFiniteResult`]
/// naming the first bad entry. Python and the C ABI check the results of a dynamics call with
/// this before handing them out; the command line refuses any non-finite value of an output row
/// as it writes it (`rows::write`), dynamics or not.
pub fn finite_result(quantity: &'static str, values: &[f64]) -> Result<(), Error> {
    if values.iter().fold(true, |finite, v| finite & v.is_finite()) {
        Ok(())
    } else {
        let index = values.iter().position(|v| !v.is_finite()).unwrap_or(0);
        Err(Error::NonFiniteResult { quantity, index, value: values[index] })
    }
}

/// The largest `rate × dt` a discretised filter or observer accepts: 100 is thirty times the
/// Nyquist limit `π`, far beyond any useful design, and keeps the matrix exponential's scaling
/// to about twenty squarings (an unbounded product would make it loop for minutes, then overflow).
pub const MAX_RATE_TIMES_DT: f64 = 100.0;

/// `Ok(rate)` if `rate` is finite, positive and `rate × dt ≤` [`MAX_RATE_TIMES_DT`].
pub(crate) fn discretisable(name: &'static str, rate: f64, dt: f64) -> Result<f64, Error> {
    let rate = positive(name, rate)?;
    if rate * dt <= MAX_RATE_TIMES_DT {
        Ok(rate)
    } else {
        Err(Error::InvalidParameter {
            name,
            value: rate,
            requirement: "such that it times dt_s is at most 100 (thirty times the Nyquist limit)",
        })
    }
}
