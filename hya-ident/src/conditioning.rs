//! How well a stack of regressor rows identifies the parameters.
//!
//! Some combinations of inertial parameters never act on the joints (a body's mass along a
//! joint axis through it, the base's inertia, …), so the stacked regressor `W` of any log is
//! rank deficient: only its `r` = rank directions, the base parameters, are identifiable. Its
//! conditioning on them is `κ = σ_1 / σ_r`, the largest singular value over the smallest one
//! that counts. A singular value counts if it is above `RANK_TOLERANCE · σ_1`. `κ` depends on
//! the parameters' units (kg, kg·m, kg·m²), as every figure of this kind does.

use nalgebra::DMatrix;

/// Singular values below this fraction of the largest count as zero.
pub const RANK_TOLERANCE: f64 = 1e-9;

/// The rank and conditioning of a stacked regressor.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Conditioning {
    /// Numerical rank `r`: the number of identifiable parameter combinations.
    pub rank: usize,
    /// `σ_1 / σ_r`.
    pub condition_number: f64,
}

impl Conditioning {
    /// Of the stacked regressor `w`.
    pub fn of(w: &DMatrix<f64>) -> Self {
        let singular = w.singular_values();
        let largest = singular.max();
        let counted: Vec<f64> = singular.iter().copied().filter(|s| *s > RANK_TOLERANCE * largest).collect();
        let smallest = counted.iter().copied().fold(f64::INFINITY, f64::min);
        Self {
            rank: counted.len(),
            condition_number: if counted.is_empty() { f64::INFINITY } else { largest / smallest },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_diagonal_matrix_has_the_ratio_of_its_extreme_entries() {
        let w = DMatrix::from_diagonal(&nalgebra::DVector::from_vec(vec![4.0, 0.5, 2.0, 0.0]));
        let c = Conditioning::of(&w);
        assert_eq!(c.rank, 3);
        assert!((c.condition_number - 8.0).abs() < 1e-12, "{}", c.condition_number);
    }
}
