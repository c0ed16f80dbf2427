//! 3-vector and 3x3-matrix arithmetic written out by component, on any [`Real`].
//!
//! Sums of products are taken left to right (`(a₀b₀ + a₁b₁) + a₂b₂`), the order a tracing
//! number type folds best.

use nalgebra::{Matrix3, Vector3};

use crate::rigid_body::scalar::Real;

/// `a + b`.
pub fn add3<S: Real>(a: &Vector3<S>, b: &Vector3<S>) -> Vector3<S> {
    Vector3::new(a[0] + b[0], a[1] + b[1], a[2] + b[2])
}

/// `a − b`.
pub fn sub3<S: Real>(a: &Vector3<S>, b: &Vector3<S>) -> Vector3<S> {
    Vector3::new(a[0] - b[0], a[1] - b[1], a[2] - b[2])
}

/// `a s`.
pub fn scale3<S: Real>(a: &Vector3<S>, s: S) -> Vector3<S> {
    Vector3::new(a[0] * s, a[1] * s, a[2] * s)
}

/// `a · b`.
pub fn dot<S: Real>(a: &Vector3<S>, b: &Vector3<S>) -> S {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// `a × b`: component `i` is `a_j b_k − a_k b_j` with `(i, j, k)` cyclic.
pub fn cross<S: Real>(a: &Vector3<S>, b: &Vector3<S>) -> Vector3<S> {
    Vector3::from_fn(|i, _| {
        let (j, k) = ((i + 1) % 3, (i + 2) % 3);
        a[j] * b[k] - a[k] * b[j]
    })
}

/// Row `r` of `m`.
fn row<S: Real>(m: &Matrix3<S>, r: usize) -> Vector3<S> {
    Vector3::new(m[(r, 0)], m[(r, 1)], m[(r, 2)])
}

/// Column `c` of `m`.
fn column<S: Real>(m: &Matrix3<S>, c: usize) -> Vector3<S> {
    Vector3::new(m[(0, c)], m[(1, c)], m[(2, c)])
}

/// `M v`.
pub fn mat_vec<S: Real>(m: &Matrix3<S>, v: &Vector3<S>) -> Vector3<S> {
    Vector3::from_fn(|r, _| dot(&row(m, r), v))
}

/// `Mᵀ v`.
pub fn mat_tr_vec<S: Real>(m: &Matrix3<S>, v: &Vector3<S>) -> Vector3<S> {
    Vector3::from_fn(|c, _| dot(&column(m, c), v))
}

/// `A B`.
pub fn mat_mat<S: Real>(a: &Matrix3<S>, b: &Matrix3<S>) -> Matrix3<S> {
    Matrix3::from_fn(|r, c| dot(&row(a, r), &column(b, c)))
}

/// `Mᵀ`.
pub fn transpose<S: Real>(m: &Matrix3<S>) -> Matrix3<S> {
    Matrix3::from_fn(|r, c| m[(c, r)])
}

/// `u vᵀ`.
pub fn outer<S: Real>(u: &Vector3<S>, v: &Vector3<S>) -> Matrix3<S> {
    Matrix3::from_fn(|r, c| u[r] * v[c])
}

/// `A + B`.
pub fn add_mat<S: Real>(a: &Matrix3<S>, b: &Matrix3<S>) -> Matrix3<S> {
    Matrix3::from_fn(|r, c| a[(r, c)] + b[(r, c)])
}

/// `A − B`.
pub fn sub_mat<S: Real>(a: &Matrix3<S>, b: &Matrix3<S>) -> Matrix3<S> {
    Matrix3::from_fn(|r, c| a[(r, c)] - b[(r, c)])
}

/// `[v]×`, the matrix with `[v]× u = v × u`.
pub fn cross_matrix<S: Real>(v: &Vector3<S>) -> Matrix3<S> {
    let z = S::zero();
    Matrix3::new(z, -v[2], v[1], v[2], z, -v[0], -v[1], v[0], z)
}

/// The symmetric matrix whose upper triangle is `m`'s: the lower entries are copies, so a
/// tracing number type drops the operations that computed them.
pub fn symmetric_from_upper<S: Real>(m: &Matrix3<S>) -> Matrix3<S> {
    Matrix3::from_fn(|r, c| if r <= c { m[(r, c)] } else { m[(c, r)] })
}
