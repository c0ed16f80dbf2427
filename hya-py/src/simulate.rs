//! `hya.simulate`: one method of a scenario on the simulated arm, as NumPy time series;
//! `hya.rollouts`: many seeds (and scenarios) of one method at once, stacked.

use std::collections::BTreeMap;

use hya_core::JointVector;
use hya_sim::analysis::simulate::run_setup;
use hya_sim::run::trace::Recording;
use hya_sim::{ForRobot, Method, Robot, Scenario, SimError};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyString};

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
        outcome(&run.trace, &run.metrics)
    }
}

/// A run's trace and metrics as an [`Outcome`].
fn outcome<const N: usize>(trace: &hya_sim::Trace<N>, metrics: &hya_sim::Metrics) -> Result<Outcome, SimError> {
    let flat = |rows: &[JointVector<N>]| rows.iter().flat_map(|r| r.iter().copied()).collect::<Vec<f64>>();
    let series = BTreeMap::from([
        ("q", flat(&trace.q)),
        ("q_des", flat(&trace.q_des)),
        ("d_true", flat(&trace.d_true)),
        ("d_hat", flat(&trace.d_hat)),
        ("tau_cmd", flat(&trace.tau_cmd)),
    ]);
    Ok(Outcome { dof: N, time: trace.time.clone(), series, metrics: serde_json::to_string(metrics)? })
}

/// Seeds of one scenario under one method, run together ([`RunSetup::run_together`]: each what
/// `hya.simulate` gives it), each with its own outcome.
struct Seeds<'a> {
    scenario: &'a Scenario,
    method: Method,
    seeds: &'a [u64],
}

impl ForRobot for Seeds<'_> {
    type Output = Vec<Result<Outcome, String>>;
    fn call<const N: usize>(self, robot: Robot<N>) -> Result<Self::Output, SimError> {
        let setup = run_setup(self.scenario, self.method, &robot)?;
        let seeds: Vec<(u64, Recording)> = self.seeds.iter().map(|&seed| (seed, Recording::Bounded)).collect();
        let runs = setup.run_together(&seeds);
        Ok(runs
            .into_iter()
            .map(|run| run.and_then(|r| outcome(&r.trace, &r.metrics)).map_err(|e| e.to_string()))
            .collect())
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

/// The method a Python string names.
fn method_of(method: &str) -> PyResult<Method> {
    serde_json::from_value(serde_json::Value::String(method.to_owned()))
        .map_err(|_| PyValueError::new_err(format!("method `{method}`: expected none, pid, lu, chen, momentum or eso")))
}

/// One run, with the same refusals as `hya run`: every per-joint list that does not fit the
/// arm, at once.
fn run_one(scenario: &Scenario, method: Method) -> Result<Outcome, SimError> {
    scenario.check_for_robot()?;
    hya_sim::with_robot(&scenario.robot, Run { scenario, method })
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
    let method = method_of(method)?;
    let outcome = py.allow_threads(|| run_one(&scenario, method)).map_err(|e| PyValueError::new_err(e.to_string()))?;
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

/// Runs `method` on every scenario of `scenarios` (one, or a list: dicts of settings, TOML
/// paths or built-in names) with every seed of `seeds` (default: each scenario's own), all in
/// Rust, on every core, without the GIL and without a Python call per step.
///
/// Returns a dict: "time" (T,) in s; "q", "q_des", "d_true", "d_hat", "tau_cmd" stacked
/// (T, R, dof), R = len(scenarios) × len(seeds), scenario-major (run r is scenario
/// r // len(seeds) with seed seeds[r % len(seeds)]); "metrics", a list of R dicts; "runs", a list
/// of R (scenario name, seed) pairs; "method". Every run must share one time grid (the same arm,
/// duration and control period): otherwise a `ValueError` names the run that differs. The
/// whole batch is checked against the simulator's caps on integration steps and trace memory
/// before it starts.
#[pyfunction]
#[pyo3(signature = (scenarios, method="lu", seeds=None, quick=false))]
pub fn rollouts<'py>(
    py: Python<'py>,
    scenarios: &Bound<'py, PyAny>,
    method: &str,
    seeds: Option<Vec<u64>>,
    quick: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let listed: Vec<Bound<'py, PyAny>> = match scenarios.downcast::<PyList>() {
        Ok(list) => list.iter().collect(),
        Err(_) => vec![scenarios.clone()],
    };
    let mut bases = Vec::with_capacity(listed.len());
    for value in &listed {
        let scenario = scenario_of(value)?;
        bases.push(if quick { scenario.quick() } else { scenario });
    }
    if bases.is_empty() || seeds.as_ref().is_some_and(Vec::is_empty) {
        return Err(PyValueError::new_err("rollouts: no scenario or no seed to run"));
    }
    let method = method_of(method)?;
    // One time grid, checked before anything runs: the same arm, duration and control period.
    let grid = |s: &Scenario| (s.robot.clone(), s.duration_s.to_bits(), s.controller.dt_s.to_bits());
    if let Some((k, other)) = bases.iter().enumerate().find(|(_, s)| grid(s) != grid(&bases[0])) {
        return Err(PyValueError::new_err(format!(
            "scenario {k} ({}): its time grid or arm differs from scenario 0's ({}); rollouts stack runs of one \
             arm, duration and control period",
            other.name, bases[0].name
        )));
    }
    let per_scenario = seeds.as_ref().map_or(1, Vec::len);
    let cost = hya_sim::cost::Cost::of_rollouts(&bases, per_scenario);
    cost.check("run fewer seeds or shorter scenarios", None).map_err(|e| PyValueError::new_err(e.to_string()))?;
    // Every run, scenario-major: its scenario's index and its seed.
    let runs: Vec<(usize, u64)> = bases
        .iter()
        .enumerate()
        .flat_map(|(b, base)| seeds.clone().unwrap_or_else(|| vec![base.seed]).into_iter().map(move |seed| (b, seed)))
        .collect();
    let outcomes = py.allow_threads(|| in_parallel(&bases, &runs, method));
    let mut done = Vec::with_capacity(runs.len());
    for (r, outcome) in outcomes.into_iter().enumerate() {
        let outcome =
            outcome.map_err(|e| PyValueError::new_err(format!("run {r} ({}): {e}", bases[runs[r].0].name)))?;
        if let Some(first) = done.first() {
            let first: &Outcome = first;
            if outcome.dof != first.dof || outcome.time != first.time {
                return Err(PyValueError::new_err(format!(
                    "run {r} ({}, seed {}): its time grid differs from run 0's ({})",
                    bases[runs[r].0].name, runs[r].1, bases[runs[0].0].name
                )));
            }
        }
        done.push(outcome);
    }
    let (steps, count, dof) = (done[0].time.len(), done.len(), done[0].dof);
    let result = PyDict::new(py);
    result.set_item("time", output(py, done[0].time.clone(), steps, false, &[steps])?)?;
    let names: Vec<&'static str> = done[0].series.keys().copied().collect();
    for name in names {
        // Each run's series taken out as it is stacked: memory holds the traces and one stacked
        // series at a time, not two copies of everything.
        let parts: Vec<Vec<f64>> = done.iter_mut().map(|run| run.series.remove(name).unwrap_or_default()).collect();
        let mut stacked = Vec::with_capacity(steps * count * dof);
        for t in 0..steps {
            for part in &parts {
                stacked.extend_from_slice(&part[t * dof..(t + 1) * dof]);
            }
        }
        drop(parts);
        result.set_item(name, output(py, stacked, steps, true, &[count, dof])?)?;
    }
    let json = py.import("json")?;
    let metrics: Vec<Bound<'py, PyAny>> =
        done.iter().map(|run| json.call_method1("loads", (run.metrics.as_str(),))).collect::<PyResult<_>>()?;
    result.set_item("metrics", metrics)?;
    result.set_item("runs", runs.iter().map(|&(b, seed)| (bases[b].name.clone(), seed)).collect::<Vec<_>>())?;
    result.set_item("method", method.name())?;
    Ok(result)
}

/// Every run of `runs` (a scenario of `bases` by index, and a seed) on every core
/// ([`hya_sim::seeds::parallel_map`]), in order; a run's error as its message. A scenario's
/// seeds run together ([`hya_sim::seeds::lockstep_groups`]).
fn in_parallel(bases: &[Scenario], runs: &[(usize, u64)], method: Method) -> Vec<Result<Outcome, String>> {
    let groups = hya_sim::seeds::lockstep_groups(runs, |&(b, _)| b);
    let outcomes = hya_sim::seeds::parallel_map(&groups, |group| {
        let (scenario, seeds) = (&bases[group[0].0], group.iter().map(|&(_, seed)| seed).collect::<Vec<u64>>());
        let group = || {
            scenario.check_for_robot()?;
            hya_sim::with_robot(&scenario.robot, Seeds { scenario, method, seeds: &seeds })
        };
        // A panic (a bug) fails its own runs, not the others.
        let failed = match std::panic::catch_unwind(std::panic::AssertUnwindSafe(group)) {
            Ok(Ok(runs)) => return runs,
            Ok(Err(e)) => e.to_string(),
            Err(_) => "it panicked (a bug in hya, please report it)".to_owned(),
        };
        seeds.iter().map(|_| Err(failed.clone())).collect()
    });
    outcomes.into_iter().flatten().collect()
}
