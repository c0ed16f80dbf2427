//! Full, physically consistent parameters from identified base parameters.
//!
//! Base parameters do not determine the bodies' parameters: every `π` with `K π = π_b` predicts
//! the same torques. This module picks one whose bodies are physical, starting from the nominal
//! model `π₀`. A body's parameters belong to some real mass distribution iff its pseudo-inertia
//!
//! ```text
//! J = [ ½ tr(I) 1 − I   h ]
//!     [ hᵀ              m ]      (I about the body frame's origin, h = m c)
//! ```
//!
//! is positive definite (Wensing, Kim & Slotine, RA-L 2018), which also gives a positive mass
//! and inertias obeying the triangle inequality. `J` is linear in `π`, so in the coordinates
//! of the bodies' `J` (Frobenius norm) the parameters matching `π_b` form an affine set and the
//! consistent ones a convex set (`J ⪰ ε 1` per body, `ε` a millionth of the nominal `J`'s
//! trace). Alternating projections between the two in that one norm (onto the affine set by
//! the pseudo-inverse, onto each body's set by raising the eigenvalues of its `J` to `ε`)
//! converge to a point of both when they meet (von Neumann; Bregman), and the last step is
//! always the consistency projection. So the result is always consistent; where the identified
//! `π_b` admit no consistent bodies (noise can put them there), it matches them only
//! approximately, and [`Consistent::base_mismatch`] says by how much. It is the point of the
//! intersection the projections reach from `π₀`, not the nearest one to `π₀` (that would need
//! a semidefinite program).

use nalgebra::{DMatrix, DVector, Matrix4};

use crate::base::BaseParameters;
use crate::regressor::PARAMETERS_PER_BODY;

/// Body parameters `(m, h, I)` as a pseudo-inertia `J`.
pub fn pseudo_inertia(p: &[f64]) -> Matrix4<f64> {
    let (m, h) = (p[0], [p[1], p[2], p[3]]);
    let i = [[p[4], p[5], p[7]], [p[5], p[6], p[8]], [p[7], p[8], p[9]]];
    let half_trace = (i[0][0] + i[1][1] + i[2][2]) / 2.0;
    Matrix4::from_fn(|r, c| match (r, c) {
        (3, 3) => m,
        (3, k) | (k, 3) => h[k],
        (r, c) => f64::from(u8::from(r == c)) * half_trace - i[r][c],
    })
}

/// Whether the body parameters `p` are those of a real mass distribution (`J ≻ 0`).
pub fn is_consistent(p: &[f64]) -> bool {
    pseudo_inertia(p).cholesky().is_some()
}

/// What [`consistent_parameters`] found.
#[derive(Debug, Clone, PartialEq)]
pub struct Consistent {
    /// `π`, ten per body, every body consistent.
    pub parameters: DVector<f64>,
    /// `K π − π_b`: how far `π` is from the identified base parameters.
    pub base_mismatch: DVector<f64>,
    /// Alternating projections made.
    pub iterations: usize,
    /// Bodies whose nominal parameters are not consistent themselves (the URDF's).
    pub inconsistent_nominal_bodies: Vec<usize>,
}

/// Body parameters from a pseudo-inertia: `m = J₃₃`, `h = J₀..₃,₃`, `I = tr(Σ) 1 − Σ`.
pub(crate) fn from_pseudo_inertia(j: &Matrix4<f64>) -> [f64; PARAMETERS_PER_BODY] {
    let trace = j[(0, 0)] + j[(1, 1)] + j[(2, 2)];
    let i = |r: usize, c: usize| f64::from(u8::from(r == c)) * trace - j[(r, c)];
    [j[(3, 3)], j[(0, 3)], j[(1, 3)], j[(2, 3)], i(0, 0), i(0, 1), i(1, 1), i(0, 2), i(1, 2), i(2, 2)]
}

/// The entries of `J` above and on the diagonal, off-diagonal ones times `√2`, so that the
/// Euclidean norm of the ten is the Frobenius norm of `J`.
const ENTRIES: [(usize, usize); PARAMETERS_PER_BODY] =
    [(0, 0), (1, 1), (2, 2), (3, 3), (0, 1), (0, 2), (1, 2), (0, 3), (1, 3), (2, 3)];

fn weight(r: usize, c: usize) -> f64 {
    if r == c {
        1.0
    } else {
        core::f64::consts::SQRT_2
    }
}

fn to_coordinates(j: &Matrix4<f64>) -> [f64; PARAMETERS_PER_BODY] {
    ENTRIES.map(|(r, c)| weight(r, c) * j[(r, c)])
}

fn from_coordinates(x: &[f64]) -> Matrix4<f64> {
    let mut j = Matrix4::zeros();
    for (&(r, c), v) in ENTRIES.iter().zip(x) {
        j[(r, c)] = v / weight(r, c);
        j[(c, r)] = j[(r, c)];
    }
    j
}

/// `x` projected onto `{J ⪰ floor 1}`: the eigenvalues of `J` raised to `floor`.
fn project_body(x: &[f64], floor: f64) -> [f64; PARAMETERS_PER_BODY] {
    let eigen = from_coordinates(x).symmetric_eigen();
    let clipped = eigen.eigenvalues.map(|e| e.max(floor));
    to_coordinates(&(eigen.eigenvectors * Matrix4::from_diagonal(&clipped) * eigen.eigenvectors.transpose()))
}

/// Alternating projections made at most.
const MAX_ITERATIONS: usize = 5000;

/// Full, consistent parameters matching `base_values` (see the module's notes).
pub fn consistent_parameters(base: &BaseParameters, nominal: &DVector<f64>, base_values: &DVector<f64>) -> Consistent {
    let bodies = nominal.len() / PARAMETERS_PER_BODY;
    let body = |p: &DVector<f64>, b: usize| p.as_slice()[b * PARAMETERS_PER_BODY..][..PARAMETERS_PER_BODY].to_vec();
    // π = M x, block diagonal, column k of a block the parameters of coordinate vector e_k.
    let block = DMatrix::from_fn(PARAMETERS_PER_BODY, PARAMETERS_PER_BODY, |row, k| {
        let mut e = [0.0; PARAMETERS_PER_BODY];
        e[k] = 1.0;
        from_pseudo_inertia(&from_coordinates(&e))[row]
    });
    let mut m = DMatrix::zeros(nominal.len(), nominal.len());
    for b in 0..bodies {
        let at = b * PARAMETERS_PER_BODY;
        m.view_mut((at, at), (PARAMETERS_PER_BODY, PARAMETERS_PER_BODY)).copy_from(&block);
    }
    let to_x = |p: &DVector<f64>| {
        DVector::from_iterator(p.len(), (0..bodies).flat_map(|b| to_coordinates(&pseudo_inertia(&body(p, b)))))
    };
    let a = &base.to_base * &m;
    let (rows, columns) = a.shape();
    let a_plus = a.clone().pseudo_inverse(1e-12).unwrap_or_else(|_| DMatrix::zeros(columns, rows));
    let floors: Vec<f64> =
        (0..bodies).map(|b| 1e-6 * pseudo_inertia(&body(nominal, b)).trace().abs().max(1e-9)).collect();
    let onto_affine = |x: &DVector<f64>| x + &a_plus * (base_values - &a * x);
    let onto_bodies = |x: &DVector<f64>| {
        DVector::from_iterator(
            x.len(),
            (0..bodies)
                .flat_map(|b| project_body(&x.as_slice()[b * PARAMETERS_PER_BODY..][..PARAMETERS_PER_BODY], floors[b])),
        )
    };
    let tolerance = 1e-10 * base_values.norm().max(1.0);
    let mut x = onto_bodies(&onto_affine(&to_x(nominal)));
    let mut iterations = 1;
    while iterations < MAX_ITERATIONS && (&a * &x - base_values).norm() > tolerance {
        x = onto_bodies(&onto_affine(&x));
        iterations += 1;
    }
    let parameters = &m * x;
    let base_mismatch = base.of_parameters(&parameters) - base_values;
    let inconsistent_nominal_bodies = (0..bodies).filter(|&b| !is_consistent(&body(nominal, b))).collect();
    Consistent { parameters, base_mismatch, iterations, inconsistent_nominal_bodies }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_real_body_is_consistent_and_a_violation_of_the_triangle_inequality_is_not() {
        // A 2 kg box-like body centred at (0.1, 0, 0): I_c = diag(0.02, 0.03, 0.04), shifted.
        let (m, c) = (2.0, [0.1, 0.0, 0.0]);
        let shift = |a: usize, b: usize| {
            let d2: f64 = c.iter().map(|x| x * x).sum();
            m * (if a == b { d2 } else { 0.0 } - c[a] * c[b])
        };
        let ic = [0.02, 0.03, 0.04];
        let i = |a: usize, b: usize| if a == b { ic[a] } else { 0.0 } + shift(a, b);
        let body = [m, m * c[0], m * c[1], m * c[2], i(0, 0), i(0, 1), i(1, 1), i(0, 2), i(1, 2), i(2, 2)];
        assert!(is_consistent(&body));
        // I_zz > I_xx + I_yy about the centre of mass: no mass distribution has that.
        let mut bad = body;
        bad[9] += 0.05;
        assert!(!is_consistent(&bad));
        let mut negative = body;
        negative[0] = -1.0;
        assert!(!is_consistent(&negative));
    }
}
