//! A log's identification, whole: its samples ([`crate::log`]) split into a fitted part and a
//! held-out part at the log's end, the fit ([`crate::fit()`]), full body parameters consistent
//! with it ([`crate::physical`]), and the held-out torque the identified and the nominal model
//! predict. `hya identify` writes this into its files and report; Python's `hya.identify`
//! returns it, so both compute the same numbers from the same rows.

use hya_core::model::TreeModel;
use hya_core::Short;

use crate::fit::{fit, Fit, FitError, Sample};
use crate::log::Filtered;
use crate::physical::{consistent_parameters, Consistent};
use crate::regressor::{nominal_parameters, Regressor};
use crate::BaseParameters;

/// What the fit is asked.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Options {
    /// The fraction of the samples, at the log's end, held out from the fit.
    pub held_out: f64,
    /// The friction model's smoothing velocity `s` in `c tanh(q̇/s)`, rad/s.
    pub smoothing_rad_s: f64,
}

/// Why a log cannot be identified.
#[derive(Debug, thiserror::Error)]
pub enum IdentifyError {
    /// An option out of its range: the option's name and why.
    #[error("{0} {1}")]
    Option(&'static str, String),
    /// Too few samples for the unknowns.
    #[error("{0}")]
    TooFew(String),
    /// The fit failed.
    #[error(transparent)]
    Fit(#[from] FitError),
    /// A model refused a sample.
    #[error(transparent)]
    Model(#[from] hya_core::model::ModelError),
}

impl Options {
    /// Checks the held-out fraction (in `(0, 0.9)`) and the smoothing (within `friction.toml`'s
    /// range, so that the file written reads back).
    pub fn check(&self) -> Result<(), IdentifyError> {
        if !(self.held_out > 0.0 && self.held_out < 0.9) {
            return Err(IdentifyError::Option("held_out", format!("{}: must be in (0, 0.9)", Short(self.held_out))));
        }
        let (_, lo, hi, _) = crate::friction::PLAUSIBLE_FRICTION[0];
        if !(self.smoothing_rad_s.is_finite() && (lo..=hi).contains(&self.smoothing_rad_s)) {
            return Err(IdentifyError::Option(
                "smoothing_rad_s",
                format!(
                    "{}: must be between {} and {} rad/s (friction.toml's range)",
                    Short(self.smoothing_rad_s),
                    Short(lo),
                    Short(hi)
                ),
            ));
        }
        Ok(())
    }
}

/// What identification found, and the held-out part it is tested on.
#[derive(Debug, Clone)]
pub struct Identification {
    /// The fit on the first part.
    pub fitted: Fit,
    /// Full body parameters of real bodies, nearest the nominal ones, that give the fitted base
    /// parameters.
    pub full: Consistent,
    /// How many samples were fitted (the first ones).
    pub fitted_samples: usize,
    /// The held-out samples' times, s.
    pub held_out_time_s: Vec<f64>,
    /// The held-out samples' filtered torques, `[sample][joint]`, N·m.
    pub measured: Vec<Vec<f64>>,
    /// The nominal model's prediction of them (rigid body alone).
    pub nominal: Vec<Vec<f64>>,
    /// The identified model's (base parameters and friction).
    pub identified: Vec<Vec<f64>>,
}

/// `identified.urdf`: the description `urdf` (of `source`, whose model is `model`) with each
/// body's inertia from `full`, checked by loading it back (see [`hya_urdf::with_body_inertias`]).
pub fn identified_urdf(
    urdf: &str,
    source: &str,
    model: &TreeModel,
    full: &Consistent,
) -> Result<String, hya_urdf::LoadError> {
    let inertias: Vec<hya_core::spatial::RigidBodyInertia> = (0..model.bodies().len())
        .map(|b| {
            crate::regressor::body_inertia(
                &full.parameters.as_slice()[b * crate::PARAMETERS_PER_BODY..][..crate::PARAMETERS_PER_BODY],
            )
        })
        .collect();
    hya_urdf::with_body_inertias(urdf, source, model, &inertias, "identified.urdf")
}

/// Per joint, the RMS of `predicted − measured` over the samples (`[sample][joint]`), N·m.
pub fn rms_error(predicted: &[Vec<f64>], measured: &[Vec<f64>]) -> Vec<f64> {
    let n = measured.first().map_or(0, Vec::len);
    let mut sums = vec![0.0; n];
    for (predicted, measured) in predicted.iter().zip(measured) {
        for (i, (p, y)) in predicted.iter().zip(measured).enumerate() {
            sums[i] += (p - y).powi(2);
        }
    }
    sums.iter().map(|s| (s / measured.len().max(1) as f64).sqrt()).collect()
}

/// Each of `samples`' torques as `model` predicts it (rigid body alone).
pub fn rigid_predictions(model: &TreeModel, samples: &[Sample]) -> Result<Vec<Vec<f64>>, IdentifyError> {
    Ok(samples.iter().map(|s| model.inverse_dynamics(&s.q, &s.qd, &s.qdd)).collect::<Result<_, _>>()?)
}

/// Identifies `model`'s base parameters `base` (through `regressor`) and its joints' friction
/// from `log`, holding out its end.
pub fn identify(
    model: &TreeModel,
    regressor: &Regressor<'_>,
    base: &BaseParameters,
    log: &Filtered,
    options: Options,
) -> Result<Identification, IdentifyError> {
    options.check()?;
    let n = crate::check_joint_count(model)?;
    let unknowns = base.rank() + 3 * n;
    // At least twice as many equations as unknowns in the fitted part, and a held-out part.
    let needed = ((2 * unknowns).div_ceil(n) as f64 / (1.0 - options.held_out)).ceil() as usize + 1;
    if log.samples.len() < needed {
        return Err(IdentifyError::TooFew(format!(
            "the log has {} rows, giving {} samples (one per 1/ω = {} s after the filters' first {} s{}); \
             identifying {} base parameters and {} friction terms needs at least {needed}",
            log.rows,
            log.samples.len(),
            log.spacing_s,
            log.settling_s,
            if log.gaps > 0 { format!(", and again after each of {} gaps", log.gaps) } else { String::new() },
            base.rank(),
            3 * n
        )));
    }
    let split = ((1.0 - options.held_out) * log.samples.len() as f64) as usize;
    let (fitted_part, held_out) = log.samples.split_at(split);
    let fitted = fit(regressor, base, fitted_part, options.smoothing_rad_s)?;
    let identified = held_out
        .iter()
        .map(|s| Ok(fitted.predict(regressor, base, s)?.as_slice().to_vec()))
        .collect::<Result<_, IdentifyError>>()?;
    let full = consistent_parameters(base, &nominal_parameters(model), &fitted.base);
    Ok(Identification {
        full,
        fitted_samples: split,
        held_out_time_s: log.time_s[split..].to_vec(),
        measured: held_out.iter().map(|s| s.tau.clone()).collect(),
        nominal: rigid_predictions(model, held_out)?,
        identified,
        fitted,
    })
}
