//! `hya.simulate`: one method of a scenario on the simulated arm, as NumPy time series.

use std::collections::BTreeMap;

use hya_core::JointVector;
use hya_sim::{ForRobot, Method, Robot, Scenario, SimError};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};

use crate::arrays::output;

/// A finished run, without its joint count: series row-major, metrics as JSON.
struct Outcome {
    dof: usize,
    time: Vec<f64>,
    series: BTreeMap<&'static str, Vec<f64>>,
    metrics: String,
}

struct Run<'a> {
    scenario: &'a Scenario,
    method: Method,
}

impl ForRobot for Run<'_> {
    type Output = Outcome;
    fn call<const N: usize>(self, robot: Robot<N>) -> Result<Outcome, SimError> {
        let run = hya_sim::simulate(self.scenario, self.method, &robot)?;
        let flat = |rows: &[JointVector<N>]| rows.iter().flat_map(|r| r.iter().copied()).collect::<Vec<f64>>();
        let trace = &run.trace;
        let series = BTreeMap::from([
            ("q", flat(&trace.q)),
            ("q_des", flat(&trace.q_des)),
            ("d_true", flat(&trace.d_true)),
            ("d_hat", flat(&trace.d_hat)),
            ("tau_cmd", flat(&trace.tau_cmd)),
        ]);
        let metrics = serde_json::to_string(&run.metrics)?;
        Ok(Outcome { dof: N, time: trace.time.clone(), series, metrics })
    }
}

/// The scenario a Python value names: a dict of its settings (the TOML keys), the path of a
/// TOML file, or a built-in scenario's name.
fn scenario_of(value: &Bound<'_, PyAny>) -> PyResult<Scenario> {
    let py = value.py();
    let error = |e: SimError| PyValueError::new_err(e.to_string());
    if let Ok(dict) = value.downcast::<PyDict>() {
        let text: String = py.import("json")?.call_method1("dumps", (dict,))?.extract()?;
        let scenario: Scenario =
            serde_json::from_str(&text).map_err(|e| PyValueError::new_err(format!("scenario: {e}")))?;
        scenario.check().map_err(error)?;
        return Ok(scenario);
    }
    let Ok(text) = value.downcast::<PyString>() else {
        return Err(PyValueError::new_err("scenario: expected a dict, a TOML path or a built-in scenario's name"));
    };
    let name: String = text.extract()?;
    Scenario::file_or_builtin(&name).map_err(error)
}

/// Runs one method of a scenario (a dict of its settings, a TOML path, or a built-in name such
/// as "goto_internal") on the simulated arm.
///
/// Returns a dict: "time" (T,) in s; "q" and "q_des" (T, dof) in rad; "d_true" and "d_hat"
/// (T, dof) in N·m (true and estimated disturbance, d = M q̈ + C + G − τ_act − τ_o on the nominal
/// model, τ_o the torque sensors' constant offset); "tau_cmd" (T, dof) in N·m; "metrics", the run's metrics as in the report's
/// summary.json (from every control tick); and "scenario", "method", "seed". The series hold
/// every control tick up to 30 000 ticks (30 s at 1 kHz) and every k-th tick of a longer run,
/// so that memory does not grow with the duration: "time" says which.
#[pyfunction]
#[pyo3(signature = (scenario, method="lu", seed=None, quick=false))]
pub fn simulate<'py>(
    py: Python<'py>,
    scenario: &Bound<'py, PyAny>,
    method: &str,
    seed: Option<u64>,
    quick: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let mut scenario = scenario_of(scenario)?;
    if quick {
        scenario = scenario.quick();
    }
    if let Some(seed) = seed {
        scenario.seed = seed;
    }
    let method: Method = serde_json::from_value(serde_json::Value::String(method.to_owned())).map_err(|_| {
        PyValueError::new_err(format!("method `{method}`: expected none, pid, lu, chen, momentum or eso"))
    })?;
    // The same refusals as `hya run`: every per-joint list that does not fit the arm, at once.
    let outcome = py
        .allow_threads(|| {
            scenario.check_for_robot()?;
            hya_sim::with_robot(&scenario.robot, Run { scenario: &scenario, method })
        })
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    let result = PyDict::new(py);
    let steps = outcome.time.len();
    result.set_item("time", output(py, outcome.time, steps, false, &[steps])?)?;
    for (name, data) in outcome.series {
        result.set_item(name, output(py, data, steps, true, &[outcome.dof])?)?;
    }
    result.set_item("metrics", py.import("json")?.call_method1("loads", (outcome.metrics,))?)?;
    result.set_item("scenario", scenario.name.clone())?;
    result.set_item("method", method.name())?;
    result.set_item("seed", scenario.seed)?;
    Ok(result)
}
