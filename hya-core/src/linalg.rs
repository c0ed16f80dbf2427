//! Small dense linear algebra that nalgebra does not offer without `std`.

use nalgebra::SMatrix;

/// Matrix exponential `e^A` by scaling and squaring with a Taylor series.
///
/// `A` is scaled by `2^-s` until its ∞-norm is at most 1/2, where 20 Taylor terms leave a
/// truncation error below `0.5^21 / 21!` (far under one ulp), then squared `s` times.
pub(crate) fn matrix_exponential<const D: usize>(a: &SMatrix<f64, D, D>) -> SMatrix<f64, D, D> {
    let norm = a.row_iter().map(|row| row.iter().map(|v| v.abs()).sum::<f64>()).fold(0.0, f64::max);
    let squarings = if norm > 0.5 { libm::ceil(libm::log2(norm / 0.5)) as i32 } else { 0 };
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
