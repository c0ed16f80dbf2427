//! Small dense linear algebra that nalgebra does not offer without `std`.

use nalgebra::SMatrix;

/// Matrix exponential `e^A` by scaling and squaring with a Taylor series.
///
/// `A` is scaled by `2^-s` until its ∞-norm is at most 1/2, where 20 Taylor terms leave a
/// truncation error below `0.5^21 / 21!` (far under one ulp), then squared `s` times.
pub(crate) fn matrix_exponential<const D: usize>(a: &SMatrix<f64, D, D>) -> SMatrix<f64, D, D> {
    let norm = a.row_iter().map(|row| row.iter().map(|v| v.abs()).sum::<f64>()).fold(0.0, f64::max);
    // Callers bound `rate × dt` (`MAX_RATE_TIMES_DT`), which needs about twenty squarings; the
    // clamp keeps even a non-finite matrix from looping 2³¹ times.
    let squarings = if norm > 0.5 { libm::ceil(libm::log2(norm / 0.5)).min(64.0) as i32 } else { 0 };
    let scaled = a * libm::exp2(-f64::from(squarings));
    let mut term = SMatrix::<f64, D, D>::identity();
    let mut sum = term;
    for k in 1..=20 {
        term = term * scaled / f64::from(k);
        sum += term;
    }
    for _ in 0..squarings {
        sum = sum * sum;
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Matrix2;

    #[test]
    fn exponential_of_a_rotation_generator_is_a_rotation() {
        let angle = 7.3_f64;
        let generator = Matrix2::new(0.0, -angle, angle, 0.0);
        let expected = Matrix2::new(angle.cos(), -angle.sin(), angle.sin(), angle.cos());
        assert!((matrix_exponential(&generator) - expected).abs().max() < 1e-13);
    }

    #[test]
    fn exponential_of_a_nilpotent_matrix_is_its_finite_series() {
        let a = Matrix2::new(0.0, 3.0, 0.0, 0.0);
        assert_eq!(matrix_exponential(&a), Matrix2::new(1.0, 3.0, 0.0, 1.0));
    }
}

/// Eigenvalues of a symmetric matrix, ascending, by cyclic Jacobi rotations (for any const size,
/// which nalgebra's decompositions do not offer without type-level bounds).
///
/// Each sweep zeroes every off-diagonal entry once with a plane rotation; it stops when the
/// off-diagonal mass is below `1e-14` of the matrix's, or after 50 sweeps (Jacobi converges
/// quadratically, in well under 10 sweeps for the sizes here).
pub fn symmetric_eigenvalues<const D: usize>(m: &SMatrix<f64, D, D>) -> nalgebra::SVector<f64, D> {
    let mut a = (m + m.transpose()) * 0.5;
    let scale = a.iter().map(|x| x * x).sum::<f64>();
    for _ in 0..50 {
        let off: f64 = (0..D)
            .flat_map(|i| (0..D).filter(move |j| *j != i).map(move |j| (i, j)))
            .map(|(i, j)| a[(i, j)] * a[(i, j)])
            .sum();
        if off <= 1e-28 * scale {
            break;
        }
        for p in 0..D {
            for q in p + 1..D {
                if a[(p, q)] == 0.0 {
                    continue;
                }
                // The rotation angle that zeroes a_pq: t = tan θ, the smaller root.
                let theta = (a[(q, q)] - a[(p, p)]) / (2.0 * a[(p, q)]);
                let t = theta.signum() / (theta.abs() + libm::sqrt(theta * theta + 1.0));
                let t = if theta == 0.0 { 1.0 } else { t };
                let c = 1.0 / libm::sqrt(t * t + 1.0);
                let s = t * c;
                for k in 0..D {
                    let (akp, akq) = (a[(k, p)], a[(k, q)]);
                    a[(k, p)] = c * akp - s * akq;
                    a[(k, q)] = s * akp + c * akq;
                }
                for k in 0..D {
                    let (apk, aqk) = (a[(p, k)], a[(q, k)]);
                    a[(p, k)] = c * apk - s * aqk;
                    a[(q, k)] = s * apk + c * aqk;
                }
            }
        }
    }
    let mut values = a.diagonal();
    values.as_mut_slice().sort_unstable_by(f64::total_cmp);
    values
}

#[cfg(test)]
mod jacobi_tests {
    use super::*;
    use nalgebra::Matrix3;

    #[test]
    fn jacobi_finds_known_eigenvalues() {
        // Eigenvalues 2 − √2, 2, 2 + √2.
        let m = Matrix3::new(2.0, -1.0, 0.0, -1.0, 2.0, -1.0, 0.0, -1.0, 2.0);
        let values = symmetric_eigenvalues(&m);
        let expected = [2.0 - core::f64::consts::SQRT_2, 2.0, 2.0 + core::f64::consts::SQRT_2];
        for (v, e) in values.iter().zip(expected) {
            assert!((v - e).abs() < 1e-13, "{values:?}");
        }
        let diagonal = Matrix3::from_diagonal(&nalgebra::Vector3::new(3.0, 1.0, 2.0));
        assert_eq!(symmetric_eigenvalues(&diagonal).as_slice(), &[1.0, 2.0, 3.0]);
    }
}
