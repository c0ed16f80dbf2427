//! Base parameters and joint friction from samples `(q, q̇, q̈, τ)` by weighted least squares
//! (Gautier and Khalil's inverse dynamic identification model):
//!
//! ```text
//! τ_i = (Y_b π_b)_i + c_i tanh(q̇_i / s) + v_i q̇_i + o_i  (+ I_a,i q̈_i)      joint i, every sample
//! ```
//!
//! stacked over the samples into `W θ = τ`, `θ = (π_b, c, v, o[, I_a])`, with `s` the friction's
//! smoothing velocity and `I_a` the optional armature (reflected motor inertia). A first ordinary least-squares solve gives each joint's residual
//! variance `σ_i²`; each joint's rows are then weighted by `1/σ_i` and solved again, so that a
//! noisy joint does not drown a quiet one.
//!
//! The parameters' standard deviations are the spread of the estimate over the log's errors,
//! estimated from the log itself in [`SPREAD_PARTS`] contiguous parts in time (a cluster-robust
//! sandwich, as in Liang and Zeger's and Newey and West's estimators):
//!
//! ```text
//! Cov θ̂ = (W_wᵀ W_w)⁻¹ [P/(P−1) Σ_p (g_p − ḡ)(g_p − ḡ)ᵀ] (W_wᵀ W_w)⁻¹,   g_p = W_w,pᵀ (W_w,p θ̂ − τ_w,p)
//! ```
//!
//! with `g_p` part `p`'s share of the weighted normal equations' residual. For errors white and
//! independent between samples this estimates `σ̂² (W_wᵀ W_w)⁻¹`; the samples of a log are
//! filtered (the torque and the accelerations through the same low-pass filters) and the model
//! misses what it misses along the trajectory, so its errors are correlated over tens of
//! samples, which shrinks the white formula's deviations several times over. Parts in time hold
//! that correlation inside a part; what stays correlated across parts (an error that repeats
//! with the trajectory) it does not see.
//!
//! No physical consistency is imposed here: base parameters are combinations of the bodies'
//! parameters and have no such constraint of their own.

use nalgebra::{DMatrix, DVector};

use crate::base::BaseParameters;
use crate::conditioning::Conditioning;
use crate::friction::JointFriction;
use crate::regressor::Regressor;

/// One sample of a log: the joint state and the torque measured in it.
#[derive(Debug, Clone, PartialEq)]
pub struct Sample {
    /// Positions, rad.
    pub q: Vec<f64>,
    /// Velocities, rad/s.
    pub qd: Vec<f64>,
    /// Accelerations, rad/s².
    pub qdd: Vec<f64>,
    /// Measured torques, N·m.
    pub tau: Vec<f64>,
    /// Per joint, its least speed over the filters' memory around the sample, rad/s, and 0
    /// where its velocity changed sign there ([`crate::log`]); infinite for a state known
    /// without filtering. The joint's row enters the fit only where this is at least
    /// [`Law::least_speed_rad_s`]: elsewhere the filtered friction torque is no function of the
    /// filtered velocity.
    pub speed_margin_rad_s: Vec<f64>,
}

impl Sample {
    /// A sample of a state known without filtering: every joint's row enters the fit.
    pub fn new(q: Vec<f64>, qd: Vec<f64>, qdd: Vec<f64>, tau: Vec<f64>) -> Self {
        let speed_margin_rad_s = vec![f64::INFINITY; tau.len()];
        Self { q, qd, qdd, tau, speed_margin_rad_s }
    }

    /// Whether joint `i`'s row enters a fit of `law` (see [`Sample::speed_margin_rad_s`]).
    pub fn fitted(&self, i: usize, law: Law) -> bool {
        self.speed_margin_rad_s.get(i).is_some_and(|m| law.keep_reversals || *m >= law.least_speed_rad_s())
    }
}

/// Per joint, the rows of `samples` that enter a fit of `law` ([`Sample::fitted`]).
pub(crate) fn fitted_rows(samples: &[Sample], law: Law) -> Vec<usize> {
    let n = samples.first().map_or(0, |s| s.tau.len());
    (0..n).map(|i| samples.iter().filter(|s| s.fitted(i, law)).count()).collect()
}

/// What the fit found.
#[derive(Debug, Clone, PartialEq)]
pub struct Fit {
    /// `π_b`.
    pub base: DVector<f64>,
    /// Their standard deviations.
    pub base_std: DVector<f64>,
    /// The friction.
    pub friction: JointFriction,
    /// Its parameters' standard deviations, in the order `c`, `v`, `o` (and `I_a` with an
    /// armature) of every joint.
    pub friction_std: Vec<Vec<f64>>,
    /// Each joint's residual RMS over its rows fitted, N·m.
    pub residual_rms_nm: Vec<f64>,
    /// The weighted system's conditioning.
    pub conditioning: Conditioning,
}

/// Why a fit failed.
#[derive(Debug, thiserror::Error)]
pub enum FitError {
    /// Fewer rows than unknowns, or a sample of the wrong size.
    #[error("{0}")]
    Samples(String),
    /// The regressor refused a sample.
    #[error(transparent)]
    Model(#[from] hya_core::model::ModelError),
    /// The system does not determine the unknowns (the motion did not excite them).
    #[error("the samples determine {rank} of the {unknowns} unknowns: the motion does not excite them all")]
    RankDeficient {
        /// The weighted system's rank.
        rank: usize,
        /// Base parameters and friction parameters.
        unknowns: usize,
    },
}

/// Samples whose rows are reduced together: a block of regressor rows per joint, then one QR.
const BLOCK_SAMPLES: usize = 512;

/// The contiguous parts in time the standard deviations are estimated over (see the module's
/// notes): enough that each standard deviation is known to about `1/√(2(P−1))` of itself
/// (13 %), few enough that a part is long against the filters' memory. With more unknowns than
/// parts (HyA's 54, the Panda's 64) the score spread has rank `P − 1` at most: it estimates each
/// parameter's deviation, not their joint covariance, and a sandwich over few parts reports a
/// little low (the test over repeated logs: 8 to 28 % on the planar arm).
pub const SPREAD_PARTS: usize = 32;

/// `samples` cut into `count` contiguous parts (fewer if there are fewer samples), each reduced
/// to its joint triangles ([`reduced`]).
pub(crate) fn reduced_parts(
    regressor: &Regressor<'_>,
    base: &BaseParameters,
    samples: &[Sample],
    law: Law,
    count: usize,
) -> Result<Vec<Vec<DMatrix<f64>>>, FitError> {
    let size = samples.len().div_ceil(count.max(1)).max(1);
    samples.chunks(size).map(|part| reduced(regressor, base, part, law)).collect()
}

/// One triangle per joint of all `parts` (each part's joint triangles) stacked: the triangles
/// of their samples together.
pub(crate) fn joined(parts: &[&[DMatrix<f64>]]) -> Vec<DMatrix<f64>> {
    let joints = parts.first().map_or(0, |p| p.len());
    (0..joints)
        .map(|i| {
            let columns = parts[0][i].ncols();
            let rows: usize = parts.iter().map(|p| p[i].nrows()).sum();
            let mut stack = DMatrix::zeros(rows, columns);
            let mut at = 0;
            for part in parts {
                stack.rows_mut(at, part[i].nrows()).copy_from(&part[i]);
                at += part[i].nrows();
            }
            stack.qr().r()
        })
        .collect()
}

/// `P/(P−1) Σ_p (g_p − ḡ)(g_p − ḡ)ᵀ` over `parts` (each part's joint triangles), with
/// `g_p = Σ_i w_i² W_p,iᵀ (W_p,i θ − τ_p,i)`, from the triangles alone (`[W τ]ᵀ[W τ] = RᵀR`).
pub(crate) fn score_spread(parts: &[&[DMatrix<f64>]], weights: &[f64], theta: &DVector<f64>) -> DMatrix<f64> {
    let unknowns = theta.len();
    let scores: Vec<DVector<f64>> = parts
        .iter()
        .map(|triangles| {
            triangles.iter().zip(weights).fold(DVector::zeros(unknowns), |g, (t, w)| {
                let w_part = t.columns(0, unknowns);
                g + w_part.tr_mul(&(w_part * theta - t.column(unknowns))) * (w * w)
            })
        })
        .collect();
    let count = scores.len() as f64;
    let mean = scores.iter().fold(DVector::zeros(unknowns), |m, g| m + g) / count.max(1.0);
    let spread = scores.iter().fold(DMatrix::zeros(unknowns, unknowns), |s, g| {
        let centred = g - &mean;
        s + &centred * centred.transpose()
    });
    spread * (count / (count - 1.0).max(1.0))
}

/// Each joint's rows of the stacked system `[W τ]`, reduced by orthogonal transformations to an
/// upper triangle `R_i` of at most `unknowns + 1` rows (a streamed, "tall and skinny" QR):
/// `Q_iᵀ [W_i τ_i] = [R_i; 0]`. For every `θ`,
///
/// ```text
/// ‖τ_i − W_i θ‖² = ‖R_i [θ; −1]‖²
/// ```
///
/// so the least-squares solution, each joint's residual and the singular values of `W` (and of
/// `W` weighted per joint) come from the `R_i` alone, exactly as from `W`: the fit's memory does
/// not grow with the log (an hour at 1 kHz once took 1.95 GB as the stacked `W` and its copies).
pub(crate) fn reduced(
    regressor: &Regressor<'_>,
    base: &BaseParameters,
    samples: &[Sample],
    law: Law,
) -> Result<Vec<DMatrix<f64>>, FitError> {
    let n = samples.first().map_or(0, |s| s.q.len());
    let terms = law.terms();
    let (r, unknowns) = (base.rank(), base.rank() + terms * n);
    let mut triangles = vec![DMatrix::zeros(0, unknowns + 1); n];
    let mut blocks = vec![DMatrix::zeros(BLOCK_SAMPLES, unknowns + 1); n];
    let mut y = DMatrix::zeros(n, regressor.columns());
    for (b, chunk) in samples.chunks(BLOCK_SAMPLES).enumerate() {
        for (k, s) in chunk.iter().enumerate() {
            if [&s.q, &s.qd, &s.qdd, &s.tau].iter().any(|v| v.len() != n) || s.speed_margin_rad_s.len() != n {
                let sample = b * BLOCK_SAMPLES + k;
                return Err(FitError::Samples(format!("sample {sample} has vectors of different lengths")));
            }
            regressor.rows_into((&s.q, &s.qd, &s.qdd), &mut y, 0)?;
            let yb = base.base_regressor(&y);
            for (i, block) in blocks.iter_mut().enumerate() {
                let mut row = block.row_mut(k);
                row.fill(0.0);
                row.columns_mut(0, r).copy_from(&yb.row(i));
                row[r + terms * i] = (s.qd[i] / law.smoothing_rad_s).tanh();
                row[r + terms * i + 1] = s.qd[i];
                row[r + terms * i + 2] = 1.0;
                if law.armature {
                    row[r + terms * i + 3] = s.qdd[i];
                }
                row[unknowns] = s.tau[i];
                if !s.fitted(i, law) {
                    // A row of zeros: left out of the triangle, and of the fit.
                    row.fill(0.0);
                }
            }
        }
        for (triangle, block) in triangles.iter_mut().zip(&blocks) {
            let mut stacked = DMatrix::zeros(triangle.nrows() + chunk.len(), unknowns + 1);
            stacked.rows_mut(0, triangle.nrows()).copy_from(triangle);
            stacked.rows_mut(triangle.nrows(), chunk.len()).copy_from(&block.rows(0, chunk.len()));
            *triangle = stacked.qr().r();
        }
    }
    Ok(triangles)
}

/// The joints' triangles stacked, joint `i`'s scaled by `weights[i]`: `(A, b)` with
/// `‖A θ − b‖² = Σ_i wᵢ² ‖τ_i − W_i θ‖²`, and the singular values of `A` those of the weighted `W`.
pub(crate) fn stacked(triangles: &[DMatrix<f64>], weights: &[f64]) -> (DMatrix<f64>, DVector<f64>) {
    let unknowns = triangles.first().map_or(0, |t| t.ncols() - 1);
    let rows: usize = triangles.iter().map(DMatrix::nrows).sum();
    let mut a = DMatrix::zeros(rows, unknowns);
    let mut b = DVector::zeros(rows);
    let mut at = 0;
    for (triangle, w) in triangles.iter().zip(weights) {
        let m = triangle.nrows();
        a.rows_mut(at, m).copy_from(&(triangle.columns(0, unknowns) * *w));
        b.rows_mut(at, m).copy_from(&(triangle.column(unknowns) * *w));
        at += m;
    }
    (a, b)
}

/// `‖τ_i − W_i θ‖²` of joint `i` from its triangle.
pub(crate) fn residual_squares(triangle: &DMatrix<f64>, theta: &DVector<f64>) -> f64 {
    let unknowns = triangle.ncols() - 1;
    (triangle.columns(0, unknowns) * theta - triangle.column(unknowns)).norm_squared()
}

/// Least squares `W θ ≈ b`, with `(WᵀW)⁻¹`; `None` if `W` is rank deficient.
pub(crate) fn solve(w: &DMatrix<f64>, b: &DVector<f64>) -> Option<(DVector<f64>, DMatrix<f64>)> {
    let svd = w.clone().svd(true, true);
    let largest = svd.singular_values.max();
    if svd.singular_values.iter().any(|s| *s <= crate::conditioning::RANK_TOLERANCE * largest) {
        return None;
    }
    let theta = svd.solve(b, 0.0).ok()?;
    let v_t = svd.v_t.as_ref()?;
    let inverse_squares = DMatrix::from_diagonal(&svd.singular_values.map(|s| 1.0 / (s * s)));
    Some((theta, v_t.transpose() * inverse_squares * v_t))
}

/// Fits base parameters and friction to `samples` of `regressor`'s model, in memory that does
/// not grow with the number of samples: each joint's rows of `[W τ]` are reduced block by block
/// to an upper triangle by QR, from which the solutions, residuals and singular values follow
/// exactly (`‖τ_i − W_i θ‖² = ‖R_i [θ; −1]‖²`).
pub fn fit(
    regressor: &Regressor<'_>,
    base: &BaseParameters,
    samples: &[Sample],
    smoothing_rad_s: f64,
) -> Result<Fit, FitError> {
    fit_with(regressor, base, samples, Law { smoothing_rad_s, armature: false, keep_reversals: false })
}

/// The joint law beside the rigid body: the friction's smoothing velocity, and whether each joint
/// has an armature `I_a q̈` to identify.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Law {
    /// `s` in `c tanh(q̇/s)`, rad/s.
    pub smoothing_rad_s: f64,
    /// Whether to identify an armature per joint.
    pub armature: bool,
    /// Whether to fit a joint's rows near its reversals too ([`Sample::speed_margin_rad_s`]):
    /// they fit the friction's switch as the filtered data smear it, which moves the
    /// parameters, and may predict a log like the fitted one better for it.
    pub keep_reversals: bool,
}

impl Law {
    /// The least speed, rad/s, a joint keeps over the filters' memory for its row to enter the
    /// fit (unless reversals are kept, [`Sample::fitted`]): `3 s`, beyond which `tanh(q̇/s)` is
    /// within 0.5 % of its limit `±1`, so that, where the true velocity stays as far from zero,
    /// the friction term is nearly the same function of the filtered velocity as of the true one.
    pub fn least_speed_rad_s(&self) -> f64 {
        3.0 * self.smoothing_rad_s
    }

    /// The unknowns per joint: `c`, `v`, `o` and, with an armature, `I_a`.
    pub fn terms(&self) -> usize {
        3 + usize::from(self.armature)
    }

    /// The friction whose per-joint terms are `values` (`terms()` per joint, in order).
    pub fn friction(&self, values: &[f64]) -> JointFriction {
        let t = self.terms();
        let part = |k: usize| values.chunks(t).map(|v| v[k]).collect();
        JointFriction {
            coulomb_nm: part(0),
            viscous_nm_s: part(1),
            offset_nm: part(2),
            armature_kg_m2: if self.armature { part(3) } else { Vec::new() },
            smoothing_rad_s: self.smoothing_rad_s,
        }
    }
}

/// [`fit()`] with the joint law `law`: an armature per joint if asked.
pub fn fit_with(
    regressor: &Regressor<'_>,
    base: &BaseParameters,
    samples: &[Sample],
    law: Law,
) -> Result<Fit, FitError> {
    let rows = fitted_rows(samples, law);
    enough_rows(&rows, base.rank() + law.terms() * rows.len())?;
    let parts = reduced_parts(regressor, base, samples, law, SPREAD_PARTS)?;
    let parts: Vec<&[DMatrix<f64>]> = parts.iter().map(Vec::as_slice).collect();
    fit_reduced(&joined(&parts), &parts, base, law, &rows)
}

/// At least twice as many rows (over the joints, `rows[i]` each) as unknowns.
fn enough_rows(rows: &[usize], unknowns: usize) -> Result<(), FitError> {
    let total: usize = rows.iter().sum();
    if rows.is_empty() || total < 2 * unknowns {
        return Err(FitError::Samples(format!(
            "{} joints' samples give {total} rows to fit (rows near a joint's reversals not counted unless \
             kept: --keep-reversals, keep_reversals=True); fitting {unknowns} unknowns needs at least {}",
            rows.len(),
            2 * unknowns
        )));
    }
    Ok(())
}

/// Each joint's weight `1/σ_i`, `σ_i²` its residual per degree of freedom in the unweighted
/// least-squares fit to `triangles` of `rows[i]` rows each. The residual is unique even where the
/// solution is not, so the minimum-norm solution serves a log that does not determine every
/// unknown (an armature that moves exactly as a link's inertia).
pub(crate) fn joint_weights(triangles: &[DMatrix<f64>], rows: &[usize]) -> Vec<f64> {
    let n = triangles.len();
    let unknowns = triangles.first().map_or(0, |t| t.ncols() - 1);
    let (a, b) = stacked(triangles, &vec![1.0; n]);
    let svd = a.svd(true, true);
    let tolerance = crate::conditioning::RANK_TOLERANCE * svd.singular_values.max();
    let theta = svd.solve(&b, tolerance).unwrap_or_else(|_| DVector::zeros(unknowns));
    let dof = |rows: usize| (rows as f64 - unknowns as f64 / n.max(1) as f64).max(1.0);
    triangles.iter().zip(rows).map(|(t, &m)| 1.0 / (residual_squares(t, &theta) / dof(m)).sqrt().max(1e-12)).collect()
}

/// [`fit_with`] on the joints' triangles of `rows[i]` rows each, already reduced ([`reduced`]),
/// and of the contiguous `parts` they join ([`joined`]), for the standard deviations.
pub(crate) fn fit_reduced(
    triangles: &[DMatrix<f64>],
    parts: &[&[DMatrix<f64>]],
    base: &BaseParameters,
    law: Law,
    rows: &[usize],
) -> Result<Fit, FitError> {
    let n = triangles.len();
    let terms = law.terms();
    let unknowns = base.rank() + terms * n;
    enough_rows(rows, unknowns)?;
    let weights = joint_weights(triangles, rows);
    let (aw, bw) = stacked(triangles, &weights);
    let rank_deficient = || FitError::RankDeficient { rank: Conditioning::of(&aw).rank, unknowns };
    let (theta, inverse) = solve(&aw, &bw).ok_or_else(rank_deficient)?;
    let covariance = &inverse * score_spread(parts, &weights, &theta) * &inverse;
    let std = covariance.diagonal().map(|d| d.max(0.0).sqrt());
    let r = base.rank();
    Ok(Fit {
        base: theta.rows(0, r).into_owned(),
        base_std: std.rows(0, r).into_owned(),
        friction: law.friction(&theta.as_slice()[r..]),
        friction_std: std.as_slice()[r..].chunks(terms).map(<[f64]>::to_vec).collect(),
        residual_rms_nm: residual_rms(triangles, rows, &theta),
        conditioning: Conditioning::of(&aw),
    })
}

/// Each joint's residual RMS at `theta` over its `rows[i]` rows (`triangles`), N·m.
pub(crate) fn residual_rms(triangles: &[DMatrix<f64>], rows: &[usize], theta: &DVector<f64>) -> Vec<f64> {
    triangles.iter().zip(rows).map(|(t, &m)| (residual_squares(t, theta) / m.max(1) as f64).sqrt()).collect()
}

impl Fit {
    /// The torque the fitted model predicts for `sample`'s state (its `tau` is ignored).
    pub fn predict(
        &self,
        regressor: &Regressor<'_>,
        base: &BaseParameters,
        sample: &Sample,
    ) -> Result<DVector<f64>, FitError> {
        let y = regressor.rows((&sample.q, &sample.qd, &sample.qdd))?;
        let rigid = base.base_regressor(&y) * &self.base;
        Ok(DVector::from_fn(rigid.len(), |i, _| rigid[i] + self.friction.joint_torque(i, sample.qd[i], sample.qdd[i])))
    }
}
