//! The paper's third-order filter, channel by channel.

use hya_core::{FilterParams, JointVector, ThirdOrderFilter as CoreFilter};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::value_error;

/// The paper's third-order filter, one channel per entry of x0, discretised exactly at the
/// period dt for an input linear between samples (first-order hold):
///
///     H(s) = ω1 ω2² / ((s + ω1)(s² + 2 ζ ω2 s + ω2²))
///
/// Each step returns the filtered signal, its first and its second derivative.
#[pyclass(module = "hya")]
pub struct ThirdOrderFilter {
    channels: Vec<CoreFilter<1>>,
}

#[pymethods]
impl ThirdOrderFilter {
    #[new]
    #[pyo3(signature = (x0, zeta=0.8, omega1=50.0, omega2=50.0, dt=0.001))]
    fn new(x0: Vec<f64>, zeta: f64, omega1: f64, omega2: f64, dt: f64) -> PyResult<Self> {
        let params = FilterParams::new(zeta, omega1, omega2, dt).map_err(value_error)?;
        let channels = x0
            .iter()
            .map(|&x| CoreFilter::new(params, JointVector::<1>::new(x)).map_err(value_error))
            .collect::<PyResult<Vec<_>>>()?;
        Ok(Self { channels })
    }

    /// One step with input u (one value per channel): returns (x, ẋ, ẍ), each (channels,).
    fn step(&mut self, u: Vec<f64>) -> PyResult<(Vec<f64>, Vec<f64>, Vec<f64>)> {
        if u.len() != self.channels.len() {
            return Err(PyValueError::new_err(format!("u: {} values, expected {}", u.len(), self.channels.len())));
        }
        // Peek every channel first, so a bad input changes no channel.
        let next = self
            .channels
            .iter()
            .zip(&u)
            .map(|(f, &x)| f.peek("u", &JointVector::<1>::new(x)).map_err(value_error))
            .collect::<PyResult<Vec<_>>>()?;
        let mut out = (Vec::new(), Vec::new(), Vec::new());
        for ((filter, state), &x) in self.channels.iter_mut().zip(next).zip(&u) {
            out.0.push(state.x1[0]);
            out.1.push(state.x2[0]);
            out.2.push(state.x3[0]);
            filter.commit(state, JointVector::<1>::new(x));
        }
        Ok(out)
    }
}
