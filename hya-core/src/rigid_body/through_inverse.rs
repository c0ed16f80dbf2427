//! The last step of the forward-dynamics derivatives (Carpentier and Mansard, RSS 2018): from
//! `M(q)` and the inverse-dynamics derivatives at `q̈ = FD(q, q̇, τ)`,
//!
//! ```text
//! ∂q̈/∂q = −M⁻¹ ∂ID/∂q,   ∂q̈/∂q̇ = −M⁻¹ ∂ID/∂q̇,   ∂q̈/∂τ = M⁻¹
//! ```
//!
//! `M⁻¹` by a square-root-free Cholesky factorisation `M = L D Lᵀ` (`L` unit lower triangular,
//! `D` the pivots, all positive exactly where `M` is positive definite), then
//! `M⁻¹ = L⁻ᵀ D⁻¹ L⁻¹`:
//!
//! ```text
//! l_ij d_j = m_ij − Σ_{k<j} l_ik (l_jk d_k)          (i > j)
//! d_j      = m_jj − Σ_{k<j} l_jk (l_jk d_k)
//! w_ij     = −(l_ij + Σ_{j<k<i} l_ik w_kj)            W = L⁻¹, unit lower triangular (i > j)
//! (M⁻¹)_ij = w_ij / d_i + Σ_{k>i} (w_ki / d_k) w_kj   (i ≥ j; w_ii = 1; symmetric)
//! ```
//!
//! about `N³/2` multiply-adds and `N` divisions, and `2N³` for the two products: written once on
//! any [`Arithmetic`], so a single call runs it with fused multiply-adds where the CPU has them
//! and a batch runs one state per vector lane, each lane's result the single call's bit for bit.

use crate::lanes::{with_vector_fma, Arithmetic, Fused, VectorLanes};
use nalgebra::{ArrayStorage, SMatrix};

use crate::Error;

/// `dynamics::JointMatrix` (spelled out: that module calls this one).
type JointMatrix<const N: usize> = SMatrix<f64, N, N>;

/// An `N × N` matrix as nalgebra stores it: `x[c][r]` is row `r` of column `c`.
type Columns<A, const N: usize> = [[A; N]; N];

/// The module's computation on `A`, in place: `m` becomes `M⁻¹`, `by_q` and `by_qd` their
/// products `−M⁻¹ ∂ID`; returns the pivots `D`. `M` and `M⁻¹` are symmetric (as
/// [`Dynamics::mass_matrix`](crate::Dynamics::mass_matrix) promises), so `m[i][j]` is `M_ij` in
/// either order; "below the diagonal" below means `i > j` in `m[i][j]`, which is nalgebra's
/// upper triangle. The products are read and written by columns.
///
/// The factors live in `m` as they are made: `l_ij` below the diagonal, `l_ij d_j` above it (at
/// `(j, i)`), then `W = L⁻¹` over `L` column by column (each `w_ij` needs `l_ik` of later columns
/// only), then `M⁻¹`'s lower triangle over `W` row by row (row `i` needs `w_ki` for `k ≥ i`
/// only), mirrored at the end. Loops only, no closures: this runs inside functions compiled for
/// FMA or a vector unit ([`with_fma`](crate::with_fma)), and a closure LLVM leaves out of line
/// would be compiled without them (each fused multiply-add a call to the C library's `fma`).
#[inline(always)]
#[allow(clippy::needless_range_loop)] // index loops, as the notes above say
fn solve<A: Arithmetic, const N: usize>(
    m: &mut Columns<A, N>,
    by_q: &mut Columns<A, N>,
    by_qd: &mut Columns<A, N>,
) -> [A; N] {
    let zero = A::from(0.0);
    let (mut pivots, mut pivot_inverses) = ([zero; N], [zero; N]);
    for j in 0..N {
        let mut pivot = m[j][j];
        for k in 0..j {
            pivot = A::mul_add(-m[j][k], m[k][j], pivot);
        }
        pivots[j] = pivot;
        pivot_inverses[j] = A::from(1.0) / pivot;
        for i in j + 1..N {
            let mut scaled = m[i][j];
            for k in 0..j {
                scaled = A::mul_add(-m[i][k], m[k][j], scaled);
            }
            m[j][i] = scaled;
            m[i][j] = scaled * pivot_inverses[j];
        }
    }
    for j in 0..N {
        for i in j + 1..N {
            let mut sum = m[i][j];
            for k in j + 1..i {
                sum = A::mul_add(m[i][k], m[k][j], sum);
            }
            m[i][j] = -sum;
        }
    }
    for i in 0..N {
        for j in 0..=i {
            let mut sum = if i == j { pivot_inverses[i] } else { m[i][j] * pivot_inverses[i] };
            for k in i + 1..N {
                sum = A::mul_add(m[k][i] * pivot_inverses[k], m[k][j], sum);
            }
            m[i][j] = sum;
        }
    }
    for i in 0..N {
        for j in i + 1..N {
            m[i][j] = m[j][i];
        }
    }
    for b in [by_q, by_qd] {
        for c in 0..N {
            let mut column = [zero; N];
            for i in 0..N {
                let mut sum = zero;
                for j in 0..N {
                    sum = A::mul_add(m[i][j], b[c][j], sum);
                }
                column[i] = sum;
            }
            for i in 0..N {
                // `0 − x`, not `−x`: an exact zero stays +0 (a negated one prints as `-0`).
                b[c][i] = zero - column[i];
            }
        }
    }
    pivots
}

/// Whether a pivot shows `M` positive definite, with a finite inverse (a subnormal pivot's is
/// not).
fn positive(pivot: f64) -> bool {
    pivot > 0.0 && pivot.is_finite() && (1.0 / pivot).is_finite()
}

/// `(−M⁻¹ by_q, −M⁻¹ by_qd, M⁻¹)`: with fused multiply-adds where the CPU has them
/// ([`with_fma`](crate::with_fma)). [`Error::SingularMassMatrix`] where `m` is not positive
/// definite.
pub(crate) fn through_inverse<const N: usize>(
    m: &JointMatrix<N>,
    by_q: &JointMatrix<N>,
    by_qd: &JointMatrix<N>,
) -> Result<(JointMatrix<N>, JointMatrix<N>, JointMatrix<N>), Error> {
    // Shared with the closure [`with_fma`](crate::with_fma) needs (an `Fn`), written in place.
    let matrices = core::cell::RefCell::new([m.data.0, by_q.data.0, by_qd.data.0]);
    let pivots = crate::with_fma(
        #[inline(always)]
        || on::<Fused, N>(&mut matrices.borrow_mut()),
    )
    .unwrap_or_else(
        #[inline(always)]
        || on::<f64, N>(&mut matrices.borrow_mut()),
    );
    if !pivots.iter().all(|&d| positive(d)) {
        return Err(Error::SingularMassMatrix);
    }
    let [inverse, by_q, by_qd] = matrices.into_inner().map(|x| JointMatrix::<N>::from_array_storage(ArrayStorage(x)));
    Ok((by_q, by_qd, inverse))
}

/// [`solve`] of `matrices` (`M`, `∂ID/∂q`, `∂ID/∂q̇`, replaced by the results) on `A`'s first
/// lane; returns the pivots.
#[inline(always)]
#[allow(clippy::needless_range_loop)] // index loops, as `solve`'s notes say
fn on<A: Arithmetic, const N: usize>(matrices: &mut [Columns<f64, N>; 3]) -> [f64; N] {
    let zero = A::from(0.0);
    let mut lanes = [[[zero; N]; N]; 3];
    for p in 0..3 {
        for c in 0..N {
            for r in 0..N {
                lanes[p][c][r] = A::from(matrices[p][c][r]);
            }
        }
    }
    let [m, by_q, by_qd] = &mut lanes;
    let pivots = solve::<A, N>(m, by_q, by_qd);
    for p in 0..3 {
        for c in 0..N {
            for r in 0..N {
                matrices[p][c][r] = lanes[p][c][r].lane(0);
            }
        }
    }
    let mut out = [0.0; N];
    for i in 0..N {
        out[i] = pivots[i].lane(0);
    }
    out
}

/// [`through_inverse`] of every state in place: `m[k]` becomes `M⁻¹`, `by_q[k]` and `by_qd[k]`
/// their products `−M⁻¹ ∂ID`; one state per vector lane where the CPU has a vector unit with
/// fused multiply-adds ([`with_vector_fma`]), each state's result [`through_inverse`]'s bit for
/// bit. Stops at the first state whose `M` is not positive definite
/// ([`Error::SingularMassMatrix`]), the states before it written. The three slices are as long.
pub(crate) fn through_inverse_batch<const N: usize>(
    m: &mut [JointMatrix<N>],
    by_q: &mut [JointMatrix<N>],
    by_qd: &mut [JointMatrix<N>],
) -> Result<(), Error> {
    let lanes = with_vector_fma(
        #[inline(always)]
        || in_lanes::<VectorLanes, N>([m, by_q, by_qd]),
    );
    lanes.unwrap_or_else(|| {
        for k in 0..m.len() {
            (by_q[k], by_qd[k], m[k]) = through_inverse(&m[k], &by_q[k], &by_qd[k])?;
        }
        Ok(())
    })
}

/// [`through_inverse_batch`] of `[M, ∂ID/∂q, ∂ID/∂q̇]` on the lanes of `A`; a short last step
/// repeats its states cyclically in the unused lanes, whose results are dropped.
#[inline(always)]
#[allow(clippy::needless_range_loop)] // index loops, as `solve`'s notes say
fn in_lanes<A: Arithmetic, const N: usize>(states: [&mut [JointMatrix<N>]; 3]) -> Result<(), Error> {
    let [m, by_q, by_qd] = states;
    let count = m.len();
    let zero = A::from(0.0);
    let mut lanes = [[[zero; N]; N]; 3];
    let mut start = 0;
    while start < count {
        let used = A::LANES.min(count - start);
        // (The division only in a short step.)
        let state = |l: usize| start + if used == A::LANES { l } else { l % used };
        let matrices = [&*m, &*by_q, &*by_qd];
        for p in 0..3 {
            for c in 0..N {
                for r in 0..N {
                    lanes[p][c][r] = A::from_lanes(
                        #[inline(always)]
                        |l| matrices[p][state(l)].data.0[c][r],
                    );
                }
            }
        }
        let [inverse, products_q, products_qd] = &mut lanes;
        let pivots = solve::<A, N>(inverse, products_q, products_qd);
        for l in 0..used {
            for pivot in &pivots {
                if !positive(pivot.lane(l)) {
                    return Err(Error::SingularMassMatrix);
                }
            }
            let k = start + l;
            for c in 0..N {
                for r in 0..N {
                    m[k].data.0[c][r] = inverse[c][r].lane(l);
                    by_q[k].data.0[c][r] = products_q[c][r].lane(l);
                    by_qd[k].data.0[c][r] = products_qd[c][r].lane(l);
                }
            }
        }
        start += A::LANES;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A symmetric positive definite matrix with entries of mixed size, and two others.
    fn inputs() -> (JointMatrix<6>, JointMatrix<6>, JointMatrix<6>) {
        let a = JointMatrix::<6>::from_fn(|i, j| ((i * 7 + j * 3) % 11) as f64 * 0.1 - 0.4);
        let m = a * a.transpose() + JointMatrix::<6>::identity() * 0.5;
        let b = JointMatrix::<6>::from_fn(|i, j| (i as f64 - 2.0 * j as f64).sin());
        (m, b, b.transpose() * 3.0)
    }

    #[test]
    fn inverse_and_products_match_a_cholesky_inverse() {
        let (m, by_q, by_qd) = inputs();
        let (dq, dqd, inverse) = through_inverse(&m, &by_q, &by_qd).unwrap_or_else(|e| panic!("{e}"));
        let expected = m.cholesky().unwrap_or_else(|| panic!("not positive definite")).inverse();
        let close = |x: &JointMatrix<6>, y: &JointMatrix<6>| (x - y).abs().max() <= 1e-12 * y.abs().max();
        assert!(close(&inverse, &expected), "{inverse} against {expected}");
        assert_eq!(inverse, inverse.transpose());
        assert!(close(&dq, &-(expected * by_q)));
        assert!(close(&dqd, &-(expected * by_qd)));
    }

    #[test]
    fn a_matrix_that_is_not_positive_definite_is_refused() {
        let (mut m, by_q, by_qd) = inputs();
        m[(3, 3)] = -1.0;
        assert_eq!(through_inverse(&m, &by_q, &by_qd).err(), Some(Error::SingularMassMatrix));
        m[(3, 3)] = f64::NAN;
        assert_eq!(through_inverse(&m, &by_q, &by_qd).err(), Some(Error::SingularMassMatrix));
    }

    #[test]
    fn the_batch_is_the_single_call_and_stops_at_a_singular_state() {
        let (m, by_q, by_qd) = inputs();
        // Seven states: a step of four lanes and a short one of three.
        let states: [_; 7] = core::array::from_fn(|k| {
            let s = (k + 1) as f64 * 0.37;
            (m * s, by_q * (1.0 - s), by_qd * s)
        });
        let single = |k: usize| through_inverse(&states[k].0, &states[k].1, &states[k].2);
        let (mut ms, mut qs, mut qds) = (states.map(|s| s.0), states.map(|s| s.1), states.map(|s| s.2));
        through_inverse_batch(&mut ms, &mut qs, &mut qds).unwrap_or_else(|e| panic!("{e}"));
        for k in 0..7 {
            assert_eq!(Ok((qs[k], qds[k], ms[k])), single(k), "state {k}");
        }
        let (mut ms, mut qs, mut qds) = (states.map(|s| s.0), states.map(|s| s.1), states.map(|s| s.2));
        ms[5] = -ms[5];
        let untouched = ms[6];
        assert_eq!(through_inverse_batch(&mut ms, &mut qs, &mut qds).err(), Some(Error::SingularMassMatrix));
        assert_eq!(Ok(ms[4]), single(4).map(|s| s.2));
        assert_eq!(ms[6], untouched);
    }
}
