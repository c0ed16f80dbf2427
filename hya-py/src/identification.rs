//! `hya.identify`: a model's base parameters and joint friction from the arrays of a log, as
//! `hya identify` finds them from the same rows (the same library calls: the log filter, the
//! fit, the held-out test and the identified URDF are `hya_ident`'s).

use hya_core::dispatch::ForJoints;
use hya_core::FilterParams;
use hya_ident::identify::PriorWeight;
use hya_ident::log::{Filtered, LogFilter, Timing};
use hya_ident::{identify as identify_log, BaseParameters, Options, Regressor};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays::{checked, converted, row, same_count};
use crate::model::Model;
use crate::value_error;

/// The log's rows through [`LogFilter`] for `N` joints.
struct FilterRows<'a> {
    params: FilterParams,
    timing: Timing,
    t: Option<&'a [f64]>,
    q: &'a [f64],
    tau: &'a [f64],
}

impl ForJoints for FilterRows<'_> {
    type Output = Result<Filtered, String>;
    fn call<const N: usize>(self) -> Self::Output {
        let mut filter = LogFilter::<N>::new(self.params, self.timing).map_err(|e| format!("max_step: {e}"))?;
        for k in 0..self.q.len() / N.max(1) {
            let t = self.t.map_or(f64::NAN, |t| t[k]);
            filter.push(t, row(self.q, k, N), row(self.tau, k, N)).map_err(|e| format!("row {k}: {e}"))?;
        }
        Ok(filter.finish())
    }
}

/// Identifies `model` from a log: rows of joint angles `q` (rad) and torques `tau` (N·m), one
/// per `dt` seconds, or at the times `t` (s) with `dt` their nominal step; a step longer than
/// `max_step` (default 2.5 `dt`) is a gap. The same as `hya identify` with `--dt`,
/// `--timestamps`, `--max-step`, `--held-out`, `--smoothing-rad-s`, `--bandwidth-rad-s`,
/// `--prior-weight` (`"auto"` or a number), `--armature` and `--keep-reversals` on those rows; returns a dict of the fit, the held-out test and `identified_urdf`, the
/// text `hya identify` writes.
#[pyfunction]
#[pyo3(signature = (model, q, tau, dt, *, t=None, max_step=None, held_out=0.25, smoothing_rad_s=0.05, bandwidth_rad_s=50.0, prior_weight=None, armature=false, keep_reversals=false))]
#[allow(clippy::too_many_arguments)]
pub fn identify<'py>(
    py: Python<'py>,
    model: &Model,
    q: &Bound<'py, PyAny>,
    tau: &Bound<'py, PyAny>,
    dt: f64,
    t: Option<Vec<f64>>,
    max_step: Option<f64>,
    held_out: f64,
    smoothing_rad_s: f64,
    bandwidth_rad_s: f64,
    prior_weight: Option<&Bound<'py, PyAny>>,
    armature: bool,
    keep_reversals: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let prior_weight = match prior_weight {
        None => PriorWeight::Fixed(0.0),
        Some(w) if w.extract::<String>().is_ok_and(|s| s == "auto") => PriorWeight::Auto,
        Some(w) if w.is_instance_of::<pyo3::types::PyBool>() => {
            return Err(PyValueError::new_err("prior_weight: \"auto\" or a number ≥ 0, not a bool"))
        }
        Some(w) => PriorWeight::Fixed(
            w.extract::<f64>().map_err(|_| PyValueError::new_err("prior_weight: \"auto\" or a number ≥ 0"))?,
        ),
    };
    let n = model.dof_count();
    let (q, tau) = (converted("q", q, n)?, converted("tau", tau, n)?);
    checked([&q, &tau])?;
    same_count([&q, &tau])?;
    if let Some(t) = t.as_ref().filter(|t| t.len() != q.count) {
        return Err(PyValueError::new_err(format!("t: {} times, but q has {} rows", t.len(), q.count)));
    }
    let timing = match (&t, max_step) {
        (Some(_), max_step) => Timing::Stamped { max_step_s: max_step.unwrap_or(2.5 * dt) },
        (None, Some(_)) => return Err(PyValueError::new_err("max_step: only with t (gaps are between times)")),
        (None, None) => Timing::Fixed,
    };
    let options = Options { held_out, smoothing_rad_s, prior_weight, armature, keep_reversals };
    options.check().map_err(value_error)?;
    let params = FilterParams::new(0.8, bandwidth_rad_s, bandwidth_rad_s, dt).map_err(value_error)?;
    let tree = model.tree();
    hya_ident::check_joint_count(tree).map_err(value_error)?;
    let rows = FilterRows { params, timing, t: t.as_deref(), q: q.values()?, tau: tau.values()? };
    let log = hya_core::dispatch::with_joints(n, rows)
        .ok_or_else(|| {
            PyValueError::new_err(format!("{n} joints: hya handles 1 to {}", hya_core::dispatch::MAX_JOINTS))
        })?
        .map_err(PyValueError::new_err)?;
    // A shipped arm's generated twins only for a model built from it (a URDF file whose name is
    // a shipped arm's is another model).
    let regressor = match model.is_shipped() {
        true => Regressor::of_robot(model.source(), tree),
        false => Regressor::new(tree),
    };
    let base = BaseParameters::of(tree, 5).map_err(value_error)?;
    let found = identify_log(tree, &regressor, &base, &log, options).map_err(value_error)?;
    let urdf =
        hya_ident::identify::identified_urdf(model.urdf(), model.source(), tree, &found.full).map_err(value_error)?;
    let out = PyDict::new(py);
    let fitted = &found.fitted;
    out.set_item("base", fitted.base.as_slice().to_vec())?;
    out.set_item("base_std", fitted.base_std.as_slice().to_vec())?;
    let friction = PyDict::new(py);
    friction.set_item("smoothing_rad_s", fitted.friction.smoothing_rad_s)?;
    friction.set_item("coulomb_nm", fitted.friction.coulomb_nm.clone())?;
    friction.set_item("viscous_nm_s", fitted.friction.viscous_nm_s.clone())?;
    friction.set_item("offset_nm", fitted.friction.offset_nm.clone())?;
    if fitted.friction.has_armature() || armature {
        friction.set_item("armature_kg_m2", fitted.friction.armature_kg_m2.clone())?;
    }
    out.set_item("friction", friction)?;
    out.set_item("prior_weight", found.prior_weight)?;
    if let Some(validation) = &found.validation {
        let curve: Vec<(f64, f64, f64)> =
            validation.curve.iter().map(|p| (p.lambda, p.error, p.standard_error)).collect();
        out.set_item("validation", curve)?;
    }
    out.set_item("parameters", found.full.parameters.as_slice().to_vec())?;
    out.set_item("identified_urdf", urdf)?;
    out.set_item("condition_number", fitted.conditioning.condition_number)?;
    out.set_item("rows", log.rows)?;
    out.set_item("gaps", log.gaps)?;
    out.set_item("fitted_samples", found.fitted_samples)?;
    out.set_item("fitted_rows", found.fitted_rows.clone())?;
    out.set_item("held_out_samples", found.measured.len())?;
    let rms = PyDict::new(py);
    rms.set_item("nominal", hya_ident::identify::rms_error(&found.nominal, &found.measured))?;
    rms.set_item("identified", hya_ident::identify::rms_error(&found.identified, &found.measured))?;
    out.set_item("held_out_rms_nm", rms)?;
    Ok(out)
}
