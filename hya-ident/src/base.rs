//! Base parameters: the combinations of inertial parameters a log can identify.
//!
//! Stack the regressor at states that excite every direction (seeded random ones) into `W`,
//! and factor it by QR with column pivoting, `W P = Q R`. The first `r` pivoted columns (those
//! with `|R_kk| > RANK_TOLERANCE · |R_00|`) are independent, the rest depend on them:
//! with `P = [P₁ P₂]` and `R = [R₁₁ R₁₂; 0 0]`,
//!
//! ```text
//! W P₂ = W P₁ β,   β = R₁₁⁻¹ R₁₂
//! Y π  = Y P₁ (P₁ᵀ π + β P₂ᵀ π) = Y_b π_b,   π_b = K π,   K = P₁ᵀ + β P₂ᵀ
//! ```
//!
//! so the base regressor `Y_b` is `Y`'s independent columns, and each base parameter is one
//! independent parameter plus the dependent ones it absorbs (Gautier, IEEE TRA 1991; the
//! numerical counterpart of Khalil and Dombre's grouping rules). Going back, the full
//! parameters are not unique: any `π` with `K π = π_b` predicts the same torques.

use hya_core::model::TreeModel;
use nalgebra::{DMatrix, DVector};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::conditioning::RANK_TOLERANCE;
use crate::regressor::Regressor;

/// The identifiable combinations of one model's parameters.
#[derive(Debug, Clone, PartialEq)]
pub struct BaseParameters {
    /// The independent columns of `Y`, in pivot order: `Y_b = Y[:, independent]`.
    pub independent: Vec<usize>,
    /// `K`, `r × 10 B`: `π_b = K π`.
    pub to_base: DMatrix<f64>,
}

/// Random states stacked per parameter column (the stack has `STATES_PER_COLUMN · 10 B · n`
/// rows, many more than columns).
const STATES_PER_COLUMN: usize = 2;

impl BaseParameters {
    /// Of `model`, from its regressor at seeded random states (joint angles in `[−π, π]`,
    /// velocities in `[−3, 3]` rad/s, accelerations in `[−10, 10]` rad/s²).
    ///
    /// Refuses a model of more than [`crate::MAX_JOINTS`] joints before anything is allocated
    /// (the stack grows as the cube of the joint count: 400 joints would take 100 GB).
    pub fn of(model: &TreeModel, seed: u64) -> Result<Self, hya_core::model::ModelError> {
        crate::check_joint_count(model)?;
        let regressor = Regressor::new(model);
        let (n, columns) = (model.dof(), regressor.columns());
        let states = STATES_PER_COLUMN * columns;
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut w = DMatrix::zeros(states * n, columns);
        for k in 0..states {
            let mut draw = |scale: f64| -> Vec<f64> { (0..n).map(|_| scale * rng.gen_range(-1.0..1.0)).collect() };
            let (q, qd, qdd) = (draw(core::f64::consts::PI), draw(3.0), draw(10.0));
            regressor.rows_into((&q, &qd, &qdd), &mut w, k * n)?;
        }
        Ok(Self::of_stack(&w))
    }

    /// From a stacked regressor `w` that excites every identifiable direction.
    pub fn of_stack(w: &DMatrix<f64>) -> Self {
        let columns = w.ncols();
        let qr = w.clone().col_piv_qr();
        let r_full = qr.r();
        // The pivots as a list: the permutation applied to the row of column indices.
        let mut indices = DMatrix::from_fn(1, columns, |_, c| c as f64);
        qr.p().permute_columns(&mut indices);
        let order: Vec<usize> = indices.iter().map(|&c| c as usize).collect();
        let diagonal = r_full.diagonal();
        let largest = diagonal.iter().fold(0.0_f64, |m, d| m.max(d.abs()));
        let rank = diagonal.iter().take_while(|d| d.abs() > RANK_TOLERANCE * largest).count();
        let r11 = r_full.view((0, 0), (rank, rank)).into_owned();
        let r12 = r_full.view((0, rank), (rank, columns - rank)).into_owned();
        let beta = r11.solve_upper_triangular(&r12).unwrap_or_else(|| DMatrix::zeros(rank, columns - rank));
        let mut to_base = DMatrix::zeros(rank, columns);
        for (i, &c) in order[..rank].iter().enumerate() {
            to_base[(i, c)] = 1.0;
        }
        for (j, &c) in order[rank..].iter().enumerate() {
            for i in 0..rank {
                to_base[(i, c)] = beta[(i, j)];
            }
        }
        Self { independent: order[..rank].to_vec(), to_base }
    }

    /// `r`, the number of base parameters.
    pub fn rank(&self) -> usize {
        self.independent.len()
    }

    /// `π_b = K π`.
    pub fn of_parameters(&self, pi: &DVector<f64>) -> DVector<f64> {
        &self.to_base * pi
    }

    /// `Y_b`: the independent columns of `y`.
    pub fn base_regressor(&self, y: &DMatrix<f64>) -> DMatrix<f64> {
        y.select_columns(&self.independent)
    }
}
