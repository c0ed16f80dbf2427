//! Identification regularised toward a prior model: the nominal bodies (Lee, Wensing & Park,
//! "Geometric robot dynamic identification: a convex programming approach", IEEE T-RO 36(2),
//! 2020). Over the full parameters `π` (ten per body) and the joints' friction terms `f`,
//!
//! ```text
//! minimise   (1/M) Σ_i w_i² ‖τ_i − W_i(K π, f)‖²  +  λ [ Σ_b D(J_b(π) ‖ J_b⁰)  +  Σ_k (s_k f_k)² ]
//! D(J ‖ J⁰) = tr(J⁰⁻¹ J) − log det(J⁰⁻¹ J) − 4
//! ```
//!
//! with `M` the rows fitted, `w_i` each joint's weight ([`crate::fit()`]'s `1/σ_i`), `J_b` a
//! body's pseudo-inertia ([`crate::physical`]) and `J_b⁰` the nominal one. `D` is the log-det
//! (Bregman) divergence of pseudo-inertias: zero at the prior, convex in `π`, and infinite where
//! a body stops being physical, so every minimiser has `J_b ≻ 0`: physical consistency is kept,
//! not projected afterwards. The friction terms are pulled toward zero, each scaled to the
//! torque it makes at the log's RMS velocity or acceleration over the joint's RMS torque (`s_k`),
//! so that `λ` weighs one dimensionless divergence against the whitened torque error. `λ = 0` is
//! the unregularised fit; at `λ > 0` the directions the log does not excite follow the prior
//! instead of the noise.
//!
//! The problem is smooth and strictly convex inside `J_b ≻ 0`; it is solved by Newton's method
//! from the prior (where it is feasible), each step halved until the bodies stay physical and
//! the objective falls enough (Armijo). The data term enters through each joint's reduced
//! triangle ([`crate::fit`](mod@crate::fit)), so the cost does not grow with the log.
//!
//! `λ` is chosen on the data ([`choose`]): the fitted samples are cut into contiguous blocks in
//! time; each block is held out in turn, the rest fitted, and the held-out block's whitened
//! error averaged; of the grid, the largest `λ` whose excess over the least error is within one
//! standard error of that excess over the blocks (Hastie, Tibshirani & Friedman's
//! one-standard-error rule, on paired differences) is taken: differences the blocks cannot
//! resolve go to the prior.

use nalgebra::{DMatrix, DVector, Matrix4};

use crate::base::BaseParameters;
use crate::fit::{fitted_rows, joined, reduced_parts, residual_squares, stacked, FitError, Law, Sample, SPREAD_PARTS};
use crate::physical::pseudo_inertia;
use crate::regressor::{Regressor, PARAMETERS_PER_BODY};

/// The weights `λ` tried when it is chosen on the data: 10⁻⁶ to 100 by decades. Not 0: the fit
/// without prior gives bodies that need not be physical, and the projection that makes them so
/// ([`crate::physical`]) moves them off the fit, so its held-out error would flatter the model
/// delivered; the smallest weight here keeps the bodies physical and still lets the log decide.
/// Not below 10⁻⁶: there the minimiser can lie so near a body's boundary that Newton's steps,
/// cut short by it, did not converge in [`MAX_NEWTON`] steps on a simulated HyA log.
pub const LAMBDA_GRID: [f64; 9] = [1e-6, 1e-5, 1e-4, 1e-3, 1e-2, 1e-1, 1.0, 10.0, 100.0];

/// The contiguous blocks the fitted samples are cut into to choose `λ`.
pub const FOLDS: usize = 4;

/// Newton steps made at most.
pub const MAX_NEWTON: usize = 500;

/// The parts of the problem that do not depend on `λ`.
pub struct Problem {
    /// `K`: full to base parameters.
    to_base: DMatrix<f64>,
    /// The prior's pseudo-inertias, one per body, and their inverses.
    prior: Vec<(Matrix4<f64>, Matrix4<f64>)>,
    /// The prior's parameters (each body's pseudo-inertia made positive definite if the
    /// nominal one is not).
    prior_parameters: DVector<f64>,
    /// `s_k`, per friction term.
    friction_scale: DVector<f64>,
    /// The joint law.
    law: Law,
    /// `E_k`: the pseudo-inertia of the body parameters' `k`-th unit vector.
    units: [Matrix4<f64>; PARAMETERS_PER_BODY],
}

/// A fit at one `λ`.
#[derive(Debug, Clone, PartialEq)]
pub struct PriorFit {
    /// `λ`.
    pub lambda: f64,
    /// `π`, ten per body, every body physical.
    pub parameters: DVector<f64>,
    /// The friction terms `f`, `law.terms()` per joint.
    pub friction: DVector<f64>,
    /// Standard deviations of `K π` (the base parameters) and of `f`: the spread of the estimate
    /// over the errors of the log, `H⁻¹ S H⁻¹` with `H = AᵀA + λ M/2 ∇²prior` of the whitened
    /// problem and `S` the spread of its data term's gradient: `σ̂² AᵀA` for white errors
    /// ([`Problem::solve`]), or estimated over contiguous parts of the log
    /// ([`Problem::spread_over`]). The prior is not counted as evidence: a direction only the
    /// prior fixes has a small spread, not a small error.
    pub base_std: DVector<f64>,
    /// Of `f`.
    pub friction_std: DVector<f64>,
    /// Newton steps taken.
    pub iterations: usize,
}

/// The data term of one set of samples: the whitened system `A x ≈ b` in the coordinates
/// `(π, f)` (its rows the joints' stacked triangles, a few hundred whatever the log's length),
/// `AᵀA`, and the samples' row count `M`. The objective and its gradient are evaluated from the
/// residual `A x − b` itself, not from the normal equations, which would lose the digits of the
/// torque's size over the noise's squared.
#[derive(Debug, Clone)]
pub struct Normal {
    a: DMatrix<f64>,
    b: DVector<f64>,
    ata: DMatrix<f64>,
    rows: usize,
}

/// One `λ` of the validation curve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ValidationPoint {
    /// `λ`.
    pub lambda: f64,
    /// The held-out blocks' whitened mean square error, mean over the blocks weighted by their
    /// fitted rows (1 is the noise level of the fit without prior); infinite where a fit failed.
    pub error: f64,
    /// The standard error, over the blocks, of its excess over the least error's (block by
    /// block: paired); 0 for the least itself.
    pub standard_error: f64,
}

/// What choosing `λ` measured.
#[derive(Debug, Clone, PartialEq)]
pub struct Validation {
    /// Per `λ` of [`LAMBDA_GRID`].
    pub curve: Vec<ValidationPoint>,
    /// The largest `λ` whose excess over the least error is within its standard error (the
    /// one-standard-error rule, on paired differences: where the blocks cannot tell weights
    /// apart, trust the prior more).
    pub chosen: f64,
}

impl Problem {
    /// The problem of `base`'s model with prior `nominal` (ten per body), friction law `law`
    /// and the fitted `samples` (for the friction terms' scales).
    pub fn new(base: &BaseParameters, nominal: &DVector<f64>, law: Law, samples: &[Sample]) -> Self {
        let units = core::array::from_fn(|k| {
            let mut e = [0.0; PARAMETERS_PER_BODY];
            e[k] = 1.0;
            pseudo_inertia(&e)
        });
        let bodies = nominal.len() / PARAMETERS_PER_BODY;
        let mut prior_parameters = nominal.clone();
        let prior = (0..bodies)
            .map(|b| {
                let body = &nominal.as_slice()[b * PARAMETERS_PER_BODY..][..PARAMETERS_PER_BODY];
                let j = positive_definite(&pseudo_inertia(body));
                let parameters = crate::physical::from_pseudo_inertia(&j);
                prior_parameters.rows_mut(b * PARAMETERS_PER_BODY, PARAMETERS_PER_BODY).copy_from_slice(&parameters);
                let inverse = j.try_inverse().unwrap_or_else(Matrix4::identity);
                (j, inverse)
            })
            .collect();
        let n = samples.first().map_or(0, |s| s.q.len());
        let rms = |f: &dyn Fn(&Sample) -> f64| {
            (samples.iter().map(|s| f(s).powi(2)).sum::<f64>() / samples.len().max(1) as f64).sqrt()
        };
        let friction_scale = DVector::from_iterator(
            law.terms() * n,
            (0..n).flat_map(|i| {
                let torque = rms(&|s| s.tau[i]).max(1e-9);
                // A joint that does not move still gets a (weak) prior on its terms.
                let (velocity, acceleration) = (rms(&|s| s.qd[i]).max(1e-6), rms(&|s| s.qdd[i]).max(1e-6));
                [1.0, velocity, 1.0, acceleration].into_iter().take(law.terms()).map(move |x| x / torque)
            }),
        );
        Self { to_base: base.to_base.clone(), prior, prior_parameters, friction_scale, law, units }
    }

    /// The unknowns: ten per body, then the friction terms.
    fn unknowns(&self) -> usize {
        self.prior_parameters.len() + self.friction_scale.len()
    }

    /// The whitened normal equations of joint triangles `triangles` (in base coordinates, as
    /// [`crate::fit`](mod@crate::fit) reduces them) with joint weights `weights`.
    pub fn normal(&self, triangles: &[DMatrix<f64>], weights: &[f64], rows: usize) -> Normal {
        let (r, p, f) = (self.to_base.nrows(), self.prior_parameters.len(), self.friction_scale.len());
        let (a, b) = stacked(triangles, weights);
        let mut full = DMatrix::zeros(a.nrows(), p + f);
        full.columns_mut(0, p).copy_from(&(a.columns(0, r) * &self.to_base));
        full.columns_mut(p, f).copy_from(&a.columns(r, f));
        Normal { ata: full.transpose() * &full, a: full, b, rows }
    }

    /// `Σ_b D(J_b ‖ J_b⁰) + Σ (s f)²`, its gradient and Hessian at `x`; `None` where a body is not
    /// physical (`J_b` not positive definite).
    fn prior_terms(&self, x: &DVector<f64>) -> Option<(f64, DVector<f64>, DMatrix<f64>)> {
        let (p, m) = (self.prior_parameters.len(), self.unknowns());
        let (mut value, mut gradient, mut hessian) = (0.0, DVector::zeros(m), DMatrix::zeros(m, m));
        for (b, (j0, j0_inverse)) in self.prior.iter().enumerate() {
            let at = b * PARAMETERS_PER_BODY;
            let j = pseudo_inertia(&x.as_slice()[at..][..PARAMETERS_PER_BODY]);
            let cholesky = j.cholesky()?;
            let j_inverse = cholesky.inverse();
            let log_det_ratio = 2.0 * cholesky.l().diagonal().map(f64::ln).sum() - j0.determinant().ln();
            value += (j0_inverse * j).trace() - log_det_ratio - 4.0;
            let products: Vec<Matrix4<f64>> = self.units.iter().map(|e| j_inverse * e).collect();
            for k in 0..PARAMETERS_PER_BODY {
                gradient[at + k] = (j0_inverse * self.units[k]).trace() - products[k].trace();
                for l in 0..PARAMETERS_PER_BODY {
                    hessian[(at + k, at + l)] = (products[k] * products[l]).trace();
                }
            }
        }
        for (k, s) in self.friction_scale.iter().enumerate() {
            let scaled = s * x[p + k];
            value += scaled * scaled;
            gradient[p + k] = 2.0 * s * scaled;
            hessian[(p + k, p + k)] = 2.0 * s * s;
        }
        Some((value, gradient, hessian))
    }

    /// The objective's data term `(1/M) ‖A x − b‖²` of `normal`.
    fn data(normal: &Normal, x: &DVector<f64>) -> f64 {
        (&normal.a * x - &normal.b).norm_squared() / normal.rows.max(1) as f64
    }

    /// The minimiser at `lambda > 0` of the data `normal` plus `λ` times the prior, followed
    /// down from the grid's largest weight: each minimiser starts Newton's method for the next
    /// smaller weight (a path, as interior-point methods follow theirs), so that a small weight,
    /// whose minimiser may lie near a body's boundary, is reached from nearby.
    pub fn solve(&self, normal: &Normal, lambda: f64) -> Result<PriorFit, FitError> {
        let mut weights: Vec<f64> = LAMBDA_GRID.iter().rev().copied().filter(|&l| l > lambda).collect();
        weights.push(lambda);
        let mut path = self.path(normal, &weights);
        path.pop().unwrap_or_else(|| Err(FitError::Samples("no prior weight".into())))
    }

    /// The minimisers at each of `weights` (decreasing), each started from the one before; once
    /// one fails, the rest start from the prior again.
    pub fn path(&self, normal: &Normal, weights: &[f64]) -> Vec<Result<PriorFit, FitError>> {
        let mut start: Option<DVector<f64>> = None;
        weights
            .iter()
            .map(|&lambda| {
                let found = self.newton(normal, lambda, start.take());
                if let Ok(fit) = &found {
                    let mut x = DVector::zeros(self.unknowns());
                    x.rows_mut(0, fit.parameters.len()).copy_from(&fit.parameters);
                    x.rows_mut(fit.parameters.len(), fit.friction.len()).copy_from(&fit.friction);
                    start = Some(x);
                }
                found
            })
            .collect()
    }

    /// Newton's method at `lambda` from `start` (the prior if none).
    fn newton(&self, normal: &Normal, lambda: f64, start: Option<DVector<f64>>) -> Result<PriorFit, FitError> {
        let m = self.unknowns();
        let scale = 1.0 / normal.rows.max(1) as f64;
        let mut x = start.unwrap_or_else(|| {
            let mut x = DVector::zeros(m);
            x.rows_mut(0, self.prior_parameters.len()).copy_from(&self.prior_parameters);
            x
        });
        let objective = |x: &DVector<f64>| self.prior_terms(x).map(|(v, ..)| Self::data(normal, x) + lambda * v);
        let stuck = || FitError::Samples(format!("the fit with prior weight {lambda} found no descent direction"));
        let mut iterations = 0;
        let mut value = objective(&x).ok_or_else(stuck)?;
        let mut converged = false;
        while iterations < MAX_NEWTON {
            let (_, prior_gradient, prior_hessian) = self.prior_terms(&x).ok_or_else(stuck)?;
            let gradient = normal.a.tr_mul(&(&normal.a * &x - &normal.b)) * (2.0 * scale) + prior_gradient * lambda;
            let hessian = &normal.ata * (2.0 * scale) + prior_hessian * lambda;
            let step = hessian.clone().cholesky().ok_or_else(stuck)?.solve(&-&gradient);
            let decrement = -gradient.dot(&step);
            iterations += 1;
            if decrement <= 1e-10 * value.abs().max(1e-12) {
                converged = true;
                break;
            }
            let mut t = 1.0;
            let accepted = loop {
                let trial = &x + &step * t;
                if let Some(v) = objective(&trial).filter(|v| *v <= value - 1e-4 * t * decrement) {
                    x = trial;
                    value = v;
                    break true;
                }
                t *= 0.5;
                if t < 1e-30 {
                    break false;
                }
            };
            if !accepted {
                // Rounding, not the problem, stops the descent once the decrement is this small
                // against the objective: the point is the minimiser to working precision.
                if decrement <= 1e-8 * value.abs().max(1e-12) {
                    converged = true;
                    break;
                }
                return Err(stuck());
            }
        }
        if !converged {
            return Err(FitError::Samples(format!(
                "the fit with prior weight {lambda} did not converge in {MAX_NEWTON} Newton steps"
            )));
        }
        let rows = normal.rows.max(1) as f64;
        let white = &normal.ata * ((&normal.a * &x - &normal.b).norm_squared() / rows);
        self.posterior(normal, lambda, x, iterations, &white)
    }

    /// `fit` (of `normal`, whose triangles join the contiguous `parts`, each part's joint
    /// triangles) with its standard deviations estimated over the parts, as [`crate::fit`](mod@crate::fit)'s
    /// are, instead of taking the errors as white: the parts' scores taken to `(π, f)` through
    /// `T: (π, f) ↦ (K π, f)`.
    pub fn spread_over(
        &self,
        normal: &Normal,
        fit: PriorFit,
        parts: &[&[DMatrix<f64>]],
        weights: &[f64],
    ) -> Result<PriorFit, FitError> {
        let (p, f) = (self.prior_parameters.len(), self.friction_scale.len());
        let r = self.to_base.nrows();
        let mut t = DMatrix::zeros(r + f, p + f);
        t.view_mut((0, 0), (r, p)).copy_from(&self.to_base);
        t.view_mut((r, p), (f, f)).fill_with_identity();
        let x = DVector::from_iterator(p + f, fit.parameters.iter().chain(fit.friction.iter()).copied());
        let spread = t.transpose() * crate::fit::score_spread(parts, weights, &(&t * &x)) * &t;
        self.posterior(normal, fit.lambda, x, fit.iterations, &spread)
    }

    /// The fit at `x` with its standard deviations, `H⁻¹ S H⁻¹` for the spread `S` of the data
    /// term's gradient.
    fn posterior(
        &self,
        normal: &Normal,
        lambda: f64,
        x: DVector<f64>,
        iterations: usize,
        spread: &DMatrix<f64>,
    ) -> Result<PriorFit, FitError> {
        let (p, f) = (self.prior_parameters.len(), self.friction_scale.len());
        let (_, _, prior_hessian) = self.prior_terms(&x).ok_or_else(|| FitError::Samples("a body left".into()))?;
        let rows = normal.rows.max(1) as f64;
        let information = &normal.ata + prior_hessian * (lambda * rows / 2.0);
        let covariance = information
            .try_inverse()
            .map(|inverse| &inverse * spread * &inverse)
            .unwrap_or_else(|| DMatrix::from_element(p + f, p + f, f64::NAN));
        let pi_covariance = covariance.view((0, 0), (p, p));
        let base_covariance = &self.to_base * pi_covariance * self.to_base.transpose();
        Ok(PriorFit {
            lambda,
            base_std: base_covariance.diagonal().map(|d| d.max(0.0).sqrt()),
            friction_std: DVector::from_fn(f, |k, _| covariance[(p + k, p + k)].max(0.0).sqrt()),
            parameters: x.rows(0, p).into_owned(),
            friction: x.rows(p, f).into_owned(),
            iterations,
        })
    }

    /// The prior's base parameters `K π⁰`.
    pub fn prior_base(&self) -> DVector<f64> {
        &self.to_base * &self.prior_parameters
    }

    /// The law of the friction terms.
    pub fn law(&self) -> Law {
        self.law
    }
}

/// `j` with its eigenvalues raised to a millionth of its trace: a nominal body that is not
/// physical made the nearest one that is, so that the prior is defined.
fn positive_definite(j: &Matrix4<f64>) -> Matrix4<f64> {
    let floor = 1e-6 * j.trace().abs().max(1e-9);
    let eigen = j.symmetric_eigen();
    eigen.eigenvectors
        * Matrix4::from_diagonal(&eigen.eigenvalues.map(|e| e.max(floor)))
        * eigen.eigenvectors.transpose()
}

/// One contiguous block of samples, reduced: its joint triangles and how many rows each holds.
#[derive(Debug, Clone)]
pub struct Block {
    /// Per joint, the triangle of its rows ([`crate::fit`](mod@crate::fit)).
    pub triangles: Vec<DMatrix<f64>>,
    /// Per joint, its rows that enter the fit ([`Sample::fitted`]).
    pub rows: Vec<usize>,
    /// Its contiguous parts' triangles, which it joins: every block's together are the
    /// [`SPREAD_PARTS`] parts the standard deviations are estimated over.
    pub parts: Vec<Vec<DMatrix<f64>>>,
}

/// The blocks of `samples`: [`FOLDS`] contiguous ones, each reduced in its share of
/// [`SPREAD_PARTS`] parts and joined.
pub fn blocks(
    regressor: &Regressor<'_>,
    base: &BaseParameters,
    samples: &[Sample],
    law: Law,
) -> Result<Vec<Block>, FitError> {
    let size = samples.len().div_ceil(FOLDS).max(1);
    samples
        .chunks(size)
        .map(|block| {
            let parts = reduced_parts(regressor, base, block, law, SPREAD_PARTS / FOLDS)?;
            let triangles = joined(&parts.iter().map(Vec::as_slice).collect::<Vec<_>>());
            Ok(Block { triangles, rows: fitted_rows(block, law), parts })
        })
        .collect()
}

/// Every part of every block, in order in time.
pub fn parts(blocks: &[Block]) -> Vec<&[DMatrix<f64>]> {
    blocks.iter().flat_map(|b| b.parts.iter().map(Vec::as_slice)).collect()
}

/// The whitened mean square error of `(π, f)` on the triangles `held_out` of `rows` rows.
fn held_out_error(held_out: &[DMatrix<f64>], weights: &[f64], theta: &DVector<f64>, rows: usize) -> f64 {
    let squares: f64 = held_out.iter().zip(weights).map(|(t, w)| w * w * residual_squares(t, theta)).sum();
    squares / rows.max(1) as f64
}

/// The base-coordinate unknowns `(K π, f)` of a prior fit.
pub fn base_coordinates(problem: &Problem, fit: &PriorFit) -> DVector<f64> {
    let base = &problem.to_base * &fit.parameters;
    DVector::from_iterator(base.len() + fit.friction.len(), base.iter().chain(fit.friction.iter()).copied())
}

/// Chooses `λ` from [`LAMBDA_GRID`] by holding out each block of `blocks` in turn (see the
/// module's notes), with the joint weights `weights` of the whole fitted part.
pub fn choose(problem: &Problem, blocks: &[Block], weights: &[f64]) -> Validation {
    // Per block held out, the path down the grid; then per weight, its errors block by block.
    let descending: Vec<f64> = LAMBDA_GRID.iter().rev().copied().collect();
    let by_block: Vec<Vec<f64>> = (0..blocks.len())
        .map(|k| {
            let rest: Vec<&[DMatrix<f64>]> =
                (0..blocks.len()).filter(|&j| j != k).map(|j| blocks[j].triangles.as_slice()).collect();
            let training = joined(&rest);
            let rows: usize = (0..blocks.len()).filter(|&j| j != k).map(|j| blocks[j].rows.iter().sum::<usize>()).sum();
            let normal = problem.normal(&training, weights, rows);
            let mut errors: Vec<f64> = problem
                .path(&normal, &descending)
                .into_iter()
                .map(|found| match found {
                    Ok(fit) => held_out_error(
                        &blocks[k].triangles,
                        weights,
                        &base_coordinates(problem, &fit),
                        blocks[k].rows.iter().sum(),
                    ),
                    Err(_) => f64::INFINITY,
                })
                .collect();
            errors.reverse();
            errors
        })
        .collect();
    let per_block: Vec<Vec<f64>> =
        (0..LAMBDA_GRID.len()).map(|g| by_block.iter().map(|errors| errors[g]).collect()).collect();
    let block_rows = |b: &Block| b.rows.iter().sum::<usize>() as f64;
    let total: f64 = blocks.iter().map(block_rows).sum::<f64>().max(1.0);
    let mean = |values: &[f64]| values.iter().zip(blocks).map(|(v, b)| v * block_rows(b)).sum::<f64>() / total;
    let errors: Vec<f64> = per_block.iter().map(|e| mean(e)).collect();
    let least = (0..errors.len()).filter(|&k| errors[k].is_finite()).min_by(|&a, &b| errors[a].total_cmp(&errors[b]));
    let curve: Vec<ValidationPoint> = (0..errors.len())
        .map(|k| {
            let standard_error = least.map_or(f64::NAN, |m| {
                let excess: Vec<f64> = per_block[k].iter().zip(&per_block[m]).map(|(a, b)| a - b).collect();
                let count = excess.len().max(1) as f64;
                let average = excess.iter().sum::<f64>() / count;
                let spread = excess.iter().map(|e| (e - average).powi(2)).sum::<f64>() / (count - 1.0).max(1.0);
                (spread / count).sqrt()
            });
            ValidationPoint { lambda: LAMBDA_GRID[k], error: errors[k], standard_error }
        })
        .collect();
    let chosen = least.map_or(LAMBDA_GRID[LAMBDA_GRID.len() - 1], |m| {
        curve
            .iter()
            .filter(|p| p.error - curve[m].error <= p.standard_error)
            .map(|p| p.lambda)
            .fold(curve[m].lambda, f64::max)
    });
    Validation { curve, chosen }
}

/// All blocks' triangles as one set, per joint.
pub fn whole(blocks: &[Block]) -> Vec<DMatrix<f64>> {
    joined(&blocks.iter().map(|b| b.triangles.as_slice()).collect::<Vec<_>>())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One 2 kg body (a box about its centre, shifted) and one joint's friction terms.
    fn problem() -> (Problem, DVector<f64>) {
        let body = [2.0, 0.2, -0.1, 0.05, 0.08, 0.01, 0.09, -0.02, 0.005, 0.07];
        let base = BaseParameters::of_stack(&DMatrix::identity(PARAMETERS_PER_BODY, PARAMETERS_PER_BODY));
        let sample = Sample::new(vec![0.1], vec![0.5], vec![2.0], vec![3.0]);
        let law = Law { smoothing_rad_s: 0.05, armature: true, keep_reversals: false };
        let problem = Problem::new(&base, &DVector::from_row_slice(&body), law, &[sample]);
        // A physical point off the prior: the body scaled and shifted, friction terms non-zero.
        let mut x = DVector::from_iterator(14, body.iter().map(|v| v * 1.1).chain([0.4, 0.3, -0.2, 0.05]));
        x[1] += 0.03;
        (problem, x)
    }

    #[test]
    fn the_prior_is_zero_at_the_nominal_bodies_and_its_derivatives_match_differences() {
        let (problem, x) = problem();
        let mut at_prior = DVector::zeros(14);
        at_prior.rows_mut(0, PARAMETERS_PER_BODY).copy_from(&problem.prior_parameters);
        let (zero, gradient_zero, _) = problem.prior_terms(&at_prior).unwrap();
        assert!(zero.abs() < 1e-12 && gradient_zero.amax() < 1e-9, "{zero} {gradient_zero}");
        let (value, gradient, hessian) = problem.prior_terms(&x).unwrap();
        assert!(value > 0.0);
        let h = 1e-6;
        for k in 0..14 {
            let step = |sign: f64| {
                let mut y = x.clone();
                y[k] += sign * h;
                problem.prior_terms(&y).unwrap()
            };
            let ((plus, g_plus, _), (minus, g_minus, _)) = (step(1.0), step(-1.0));
            let slope = (plus - minus) / (2.0 * h);
            assert!((slope - gradient[k]).abs() < 1e-6 * (1.0 + slope.abs()), "∂/∂x{k}: {slope} vs {}", gradient[k]);
            let column = (g_plus - g_minus) / (2.0 * h);
            for l in 0..14 {
                let (want, got) = (column[l], hessian[(l, k)]);
                assert!((want - got).abs() < 1e-5 * (1.0 + want.abs()), "∂²/∂x{l}∂x{k}: {want} vs {got}");
            }
        }
        // A body that is not physical has no divergence.
        let mut bad = x.clone();
        bad[0] = -1.0;
        assert!(problem.prior_terms(&bad).is_none());
    }
}
