//! Python bindings of hya (the `hya` package's native module `hya._hya`): NumPy batch dynamics
//! for the shipped arms and any URDF, the disturbance estimator of Lu, Sandy & Buchli with the
//! observers it is compared with and the computed-torque controller, and the simulator.

mod arrays;
mod control;
mod estimation;
mod filter;
mod identification;
mod model;
mod simulate;

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

pyo3::create_exception!(
    hya,
    UrdfError,
    PyValueError,
    "A URDF that cannot be loaded; the message names the file and the link or joint at fault."
);

/// A `ValueError` with `e`'s message.
fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// The native module; `import hya` re-exports it.
#[pymodule]
fn _hya(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<model::Model>()?;
    m.add_class::<estimation::DisturbanceEstimator>()?;
    m.add_class::<estimation::MomentumObserver>()?;
    m.add_class::<estimation::NonlinearDisturbanceObserver>()?;
    m.add_class::<estimation::ExtendedStateObserver>()?;
    m.add_class::<filter::ThirdOrderFilter>()?;
    m.add_class::<control::ComputedTorque>()?;
    m.add_class::<control::CartesianImpedance>()?;
    m.add_function(wrap_pyfunction!(simulate::simulate, m)?)?;
    m.add_function(wrap_pyfunction!(simulate::rollouts, m)?)?;
    m.add_function(wrap_pyfunction!(identification::identify, m)?)?;
    m.add("UrdfError", m.py().get_type::<UrdfError>())?;
    Ok(())
}
