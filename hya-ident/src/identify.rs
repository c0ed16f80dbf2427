//! A log's identification, whole: its samples ([`crate::log`]) split into a fitted part and a
//! held-out part at the log's end, the fit ([`crate::fit()`]), full body parameters consistent
//! with it ([`crate::physical`]), and the held-out torque the identified and the nominal model
//! predict. `hya identify` writes this into its files and report; Python's `hya.identify`
//! returns it, so both compute the same numbers from the same rows.

use hya_core::model::TreeModel;
use hya_core::Short;

use nalgebra::DVector;

use crate::conditioning::Conditioning;
use crate::fit::{fit_reduced, fitted_rows, joint_weights, residual_rms, stacked, Fit, FitError, Law, Sample};
use crate::log::Filtered;
use crate::physical::{consistent_parameters, is_consistent, Consistent};
use crate::prior::{self, Problem, Validation};
use crate::regressor::{nominal_parameters, Regressor, PARAMETERS_PER_BODY};
use crate::BaseParameters;

/// What the fit is asked.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Options {
    /// The fraction of the samples, at the log's end, held out from the fit.
    pub held_out: f64,
    /// The friction model's smoothing velocity `s` in `c tanh(q̇/s)`, rad/s.
    pub smoothing_rad_s: f64,
    /// How much the nominal model is trusted ([`crate::prior`]).
    pub prior_weight: PriorWeight,
    /// Whether each joint has an armature `I_a q̈` to identify.
    pub armature: bool,
    /// Whether a joint's rows near its reversals are fitted too ([`Law::keep_reversals`]).
    pub keep_reversals: bool,
}

/// The weight `λ` of the prior (the nominal model) against the log.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PriorWeight {
    /// This `λ ≥ 0`; 0 is the fit without prior.
    Fixed(f64),
    /// Chosen on held-out blocks of the fitted part ([`prior::choose`]).
    Auto,
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
        if let PriorWeight::Fixed(lambda) = self.prior_weight {
            if !(lambda.is_finite() && lambda >= 0.0) {
                return Err(IdentifyError::Option(
                    "prior_weight",
                    format!("{}: must be finite and ≥ 0", Short(lambda)),
                ));
            }
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
    /// Per joint, the fitted samples whose row of that joint entered the fit: the others are
    /// near a reversal of the joint ([`Sample::fitted`]).
    pub fitted_rows: Vec<usize>,
    /// The held-out samples' times, s.
    pub held_out_time_s: Vec<f64>,
    /// The held-out samples' filtered torques, `[sample][joint]`, N·m.
    pub measured: Vec<Vec<f64>>,
    /// The nominal model's prediction of them (rigid body alone).
    pub nominal: Vec<Vec<f64>>,
    /// The nominal rigid bodies with the joint law (friction, and the armature if asked) fitted
    /// alone on the same samples: the baseline that identifying the bodies must beat.
    pub nominal_with_friction: Vec<Vec<f64>>,
    /// The identified model's: the bodies of `identified.urdf` (their base parameters, which
    /// miss the fitted ones by `full.base_mismatch`) and the fitted joint law.
    pub identified: Vec<Vec<f64>>,
    /// The prior weight `λ` the fit used.
    pub prior_weight: f64,
    /// How `λ` was chosen, if on the data.
    pub validation: Option<Validation>,
    /// The nominal model's base parameters `K π⁰`, the prior the fit is pulled toward.
    pub prior_base: DVector<f64>,
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
    let law = Law {
        smoothing_rad_s: options.smoothing_rad_s,
        armature: options.armature,
        keep_reversals: options.keep_reversals,
    };
    let unknowns = base.rank() + law.terms() * n;
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
            law.terms() * n
        )));
    }
    let split = ((1.0 - options.held_out) * log.samples.len() as f64) as usize;
    let (fitted_part, held_out) = log.samples.split_at(split);
    let nominal = nominal_parameters(model);
    let problem = Problem::new(base, &nominal, law, fitted_part);
    // The fitted part's rows reduced once (in blocks to choose λ on), and its joint weights.
    let rows = fitted_rows(fitted_part, law);
    // Each joint's own share of the equations, twice over, from the rows its reversals leave.
    let share = 2 * unknowns.div_ceil(n);
    if let Some(i) = (0..n).find(|&i| rows[i] < share) {
        return Err(IdentifyError::TooFew(format!(
            "joint `{}` keeps {} of the {} fitted samples: its rows where its filtered velocity turns or falls below \
             {} rad/s (3 times the smoothing velocity) within 10/ω are left out, and its share of the unknowns \
             needs at least {share}; fit those rows too (--keep-reversals, keep_reversals=True) or lower the \
             smoothing velocity",
            model.bodies()[i].joint,
            rows[i],
            fitted_part.len(),
            Short(law.least_speed_rad_s()),
        )));
    }
    // In blocks to choose λ on and in the parts that the standard deviations are estimated over.
    let blocks = prior::blocks(regressor, base, fitted_part, law)?;
    let (triangles, parts) = (prior::whole(&blocks), prior::parts(&blocks));
    let weights = joint_weights(&triangles, &rows);
    let (lambda, validation) = match options.prior_weight {
        PriorWeight::Fixed(lambda) => (lambda, None),
        PriorWeight::Auto => {
            let validation = prior::choose(&problem, &blocks, &weights);
            (validation.chosen, Some(validation))
        }
    };
    let (fitted, full) = if lambda > 0.0 {
        regularised(&problem, base, (&triangles, &parts), &weights, &rows, lambda, &nominal)?
    } else {
        let fitted = fit_reduced(&triangles, &parts, base, law, &rows)?;
        let full = consistent_parameters(base, &nominal, &fitted.base);
        (fitted, full)
    };
    // What the files predict: the bodies of `identified.urdf` (whose base parameters miss the
    // fitted ones where no physical bodies give those) and `friction.toml`.
    let as_written = Fit { base: base.of_parameters(&full.parameters), ..fitted.clone() };
    let identified = held_out
        .iter()
        .map(|s| Ok(as_written.predict(regressor, base, s)?.as_slice().to_vec()))
        .collect::<Result<_, IdentifyError>>()?;
    // The baseline, where the log determines the joint law alone; NaN where it does not.
    let nominal_with_friction = match friction_on_nominal(&problem, base, &triangles, &rows, &nominal) {
        Ok(alone) => held_out
            .iter()
            .map(|s| Ok(alone.predict(regressor, base, s)?.as_slice().to_vec()))
            .collect::<Result<_, IdentifyError>>()?,
        Err(_) => held_out.iter().map(|s| vec![f64::NAN; s.tau.len()]).collect(),
    };
    Ok(Identification {
        nominal_with_friction,
        prior_weight: lambda,
        validation,
        prior_base: problem.prior_base(),
        full,
        fitted_samples: split,
        fitted_rows: rows,
        held_out_time_s: log.time_s[split..].to_vec(),
        measured: held_out.iter().map(|s| s.tau.clone()).collect(),
        nominal: rigid_predictions(model, held_out)?,
        identified,
        fitted,
    })
}

/// The fit at prior weight `lambda > 0` to the joint triangles of `rows[i]` rows each (which join
/// `parts`, for the standard deviations), and its bodies (physical by construction).
fn regularised(
    problem: &Problem,
    base: &BaseParameters,
    (triangles, parts): (&[nalgebra::DMatrix<f64>], &[&[nalgebra::DMatrix<f64>]]),
    weights: &[f64],
    rows: &[usize],
    lambda: f64,
    nominal: &DVector<f64>,
) -> Result<(Fit, Consistent), IdentifyError> {
    let law = problem.law();
    let normal = problem.normal(triangles, weights, rows.iter().sum());
    let found = problem.spread_over(&normal, problem.solve(&normal, lambda)?, parts, weights)?;
    let theta = prior::base_coordinates(problem, &found);
    let r = base.rank();
    let fitted = Fit {
        base: theta.rows(0, r).into_owned(),
        base_std: found.base_std.clone(),
        friction: law.friction(found.friction.as_slice()),
        friction_std: found.friction_std.as_slice().chunks(law.terms()).map(<[f64]>::to_vec).collect(),
        residual_rms_nm: residual_rms(triangles, rows, &theta),
        conditioning: Conditioning::of(&stacked(triangles, weights).0),
    };
    let bodies = nominal.len() / PARAMETERS_PER_BODY;
    let body = |b: usize| &nominal.as_slice()[b * PARAMETERS_PER_BODY..][..PARAMETERS_PER_BODY];
    let full = Consistent {
        base_mismatch: base.of_parameters(&found.parameters) - &fitted.base,
        parameters: found.parameters,
        iterations: found.iterations,
        inconsistent_nominal_bodies: (0..bodies).filter(|&b| !is_consistent(body(b))).collect(),
    };
    Ok((fitted, full))
}

/// The joint law fitted alone to `rows[i]` rows each with the bodies held at the nominal ones (`nominal`,
/// as the URDF gives them): per joint, least squares of `τ_i − (Y_b K π⁰)_i` on its friction
/// terms (the joints do not share them).
fn friction_on_nominal(
    problem: &Problem,
    base: &BaseParameters,
    triangles: &[nalgebra::DMatrix<f64>],
    rows: &[usize],
    nominal: &DVector<f64>,
) -> Result<Fit, IdentifyError> {
    let law = problem.law();
    let (r, t) = (base.rank(), law.terms());
    let prior_base = base.of_parameters(nominal);
    let mut terms = vec![0.0; t * triangles.len()];
    let mut terms_std = Vec::with_capacity(triangles.len());
    for (i, triangle) in triangles.iter().enumerate() {
        let last = triangle.ncols() - 1;
        let a = triangle.columns(r + t * i, t).into_owned();
        let b = triangle.column(last) - triangle.columns(0, r) * &prior_base;
        let rank = || FitError::RankDeficient { rank: Conditioning::of(&a).rank, unknowns: t };
        let (solution, _) = crate::fit::solve(&a, &b).ok_or_else(rank)?;
        terms[t * i..t * (i + 1)].copy_from_slice(solution.as_slice());
        terms_std.push(vec![f64::NAN; t]);
    }
    let theta = DVector::from_iterator(r + terms.len(), prior_base.iter().chain(&terms).copied());
    Ok(Fit {
        base: prior_base.clone(),
        base_std: DVector::from_element(r, f64::NAN),
        friction: law.friction(&terms),
        friction_std: terms_std,
        residual_rms_nm: residual_rms(triangles, rows, &theta),
        conditioning: Conditioning { rank: r, condition_number: f64::NAN },
    })
}
