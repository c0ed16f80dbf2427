//! The rigid-body dynamics interface every estimator, observer and controller is generic over.
//!
//! Model: `M(q) q̈ + C(q, q̇) + G(q) = τ`, with `C` the vector of Coriolis and centripetal torques
//! and `G` the gravity torques. Where a Coriolis *matrix* is meant (`C = C_mat q̇`), it is the one
//! with `Ṁ = C_mat + C_matᵀ`, so `C_matᵀ q̇ = Ṁ q̇ − C`.

use nalgebra::{SMatrix, SVector};

use crate::rigid_body::through_inverse::{through_inverse, through_inverse_batch};
use crate::Error;

/// Standard gravity along the base's −z, m/s² (the paper's and Pinocchio's value).
pub const STANDARD_GRAVITY: f64 = 9.81;

/// A vector with one entry per joint.
pub type JointVector<const N: usize> = SVector<f64, N>;
/// An `N x N` matrix over the joints.
pub type JointMatrix<const N: usize> = SMatrix<f64, N, N>;

/// Rigid-body dynamics of a fixed-base arm with `N` joints.
///
/// Implemented by generated code (one type per robot), the runtime kinematic-tree model and the
/// closed-form robots of [`crate::test_arms`]. Only [`inverse_dynamics`](Self::inverse_dynamics) and
/// [`coriolis_transpose_times_velocity`](Self::coriolis_transpose_times_velocity) are required;
/// the defaults derive the rest from them and are correct but slower than specialised code.
pub trait Dynamics<const N: usize> {
    /// Inverse dynamics `ID(q, q̇, q̈) = M(q) q̈ + C(q, q̇) + G(q)`, N·m.
    fn inverse_dynamics(&self, q: &JointVector<N>, qd: &JointVector<N>, qdd: &JointVector<N>) -> JointVector<N>;

    /// `C_mat(q, q̇)ᵀ q̇ = Ṁ q̇ − C(q, q̇)`, as the generalized-momentum observer needs it.
    fn coriolis_transpose_times_velocity(&self, q: &JointVector<N>, qd: &JointVector<N>) -> JointVector<N>;

    /// Gravity torques `G(q) = ID(q, 0, 0)`.
    fn gravity(&self, q: &JointVector<N>) -> JointVector<N> {
        self.inverse_dynamics(q, &JointVector::zeros(), &JointVector::zeros())
    }

    /// Coriolis and centripetal torques `C(q, q̇) = ID(q, q̇, 0) − G(q)`.
    fn velocity_terms(&self, q: &JointVector<N>, qd: &JointVector<N>) -> JointVector<N> {
        self.inverse_dynamics(q, qd, &JointVector::zeros()) - self.gravity(q)
    }

    /// Joint-space mass matrix `M(q)`, symmetric positive definite; column `i` is
    /// `ID(q, 0, eᵢ) − G(q)` by default.
    fn mass_matrix(&self, q: &JointVector<N>) -> JointMatrix<N> {
        let zero = JointVector::zeros();
        let gravity = self.gravity(q);
        JointMatrix::from_fn(|row, col| {
            let unit = JointVector::from_fn(|i, _| if i == col { 1.0 } else { 0.0 });
            self.inverse_dynamics(q, &zero, &unit)[row] - gravity[row]
        })
    }

    /// `(∂τ/∂q, ∂τ/∂q̇)` of inverse dynamics at `(q, q̇, q̈)`; row `i` of each is `∂τ_i`.
    ///
    /// The default takes central differences with step `10⁻⁶` (an error near `10⁻¹⁰` relative,
    /// from rounding and curvature): generated dynamics and the run-time model override it with
    /// the exact analytic pass ([`crate::model::derivatives`]).
    fn inverse_dynamics_derivatives(
        &self,
        q: &JointVector<N>,
        qd: &JointVector<N>,
        qdd: &JointVector<N>,
    ) -> (JointMatrix<N>, JointMatrix<N>) {
        const STEP: f64 = 1e-6;
        let mut d_dq = JointMatrix::<N>::zeros();
        let mut d_dqd = JointMatrix::<N>::zeros();
        for j in 0..N {
            let unit = JointVector::from_fn(|i, _| if i == j { STEP } else { 0.0 });
            let by_q = self.inverse_dynamics(&(q + unit), qd, qdd) - self.inverse_dynamics(&(q - unit), qd, qdd);
            let by_qd = self.inverse_dynamics(q, &(qd + unit), qdd) - self.inverse_dynamics(q, &(qd - unit), qdd);
            d_dq.set_column(j, &(by_q / (2.0 * STEP)));
            d_dqd.set_column(j, &(by_qd / (2.0 * STEP)));
        }
        (d_dq, d_dqd)
    }

    /// Forward dynamics `q̈ = M(q)⁻¹ (τ − C(q, q̇) − G(q))`, by Cholesky factorisation of `M`.
    fn forward_dynamics(
        &self,
        q: &JointVector<N>,
        qd: &JointVector<N>,
        tau: &JointVector<N>,
    ) -> Result<JointVector<N>, Error> {
        let bias = self.inverse_dynamics(q, qd, &JointVector::zeros());
        let cholesky = self.mass_matrix(q).cholesky().ok_or(Error::SingularMassMatrix)?;
        Ok(cholesky.solve(&(tau - bias)))
    }

    /// `(∂q̈/∂q, ∂q̈/∂q̇, M⁻¹)` of forward dynamics at `(q, q̇, τ)` (`M⁻¹ = ∂q̈/∂τ`); row `i` of
    /// each is `∂q̈_i`. Differentiating `ID(q, q̇, q̈) = τ` at `q̈ = FD(q, q̇, τ)` (Carpentier and
    /// Mansard, RSS 2018):
    ///
    /// ```text
    /// ∂q̈/∂q = −M⁻¹ ∂ID/∂q,   ∂q̈/∂q̇ = −M⁻¹ ∂ID/∂q̇   (both at q̈ = FD(q, q̇, τ))
    /// ```
    ///
    /// so the cost is one forward dynamics, one [`inverse_dynamics_derivatives`](Self::inverse_dynamics_derivatives),
    /// one [`mass_matrix`](Self::mass_matrix) and its inverse by `L D Lᵀ` factors (no square
    /// roots) with the two products, on fused multiply-adds where the CPU has them (one state per
    /// vector lane in [`forward_dynamics_derivatives_batch`](Self::forward_dynamics_derivatives_batch)).
    /// [`Error::SingularMassMatrix`] where `M` is not positive
    /// definite.
    fn forward_dynamics_derivatives(
        &self,
        q: &JointVector<N>,
        qd: &JointVector<N>,
        tau: &JointVector<N>,
    ) -> Result<(JointMatrix<N>, JointMatrix<N>, JointMatrix<N>), Error> {
        let qdd = self.forward_dynamics(q, qd, tau)?;
        let (by_q, by_qd) = self.inverse_dynamics_derivatives(q, qd, &qdd);
        through_inverse(&self.mass_matrix(q), &by_q, &by_qd)
    }

    /// [`inverse_dynamics`](Self::inverse_dynamics) of many states: `tau[k] = ID(q[k], q̇[k], q̈[k])`.
    ///
    /// Batches take one slice of joint vectors per argument (an array of structures: state `k`
    /// is `q[k]`, `qd[k]`, …) and write one output per state; every slice must be as long as the
    /// output ([`Error::BatchLength`] otherwise, nothing written). Generated dynamics run
    /// [`BATCH_LANES`](crate::rigid_body::lanes::BATCH_LANES) states per step in vector registers
    /// ([`crate::rigid_body::lanes::batch`]); the defaults loop over the single call.
    fn inverse_dynamics_batch(
        &self,
        q: &[JointVector<N>],
        qd: &[JointVector<N>],
        qdd: &[JointVector<N>],
        tau: &mut [JointVector<N>],
    ) -> Result<(), Error> {
        check_batch(&[q.len(), qd.len(), qdd.len()], tau.len())?;
        for (k, tau) in tau.iter_mut().enumerate() {
            *tau = self.inverse_dynamics(&q[k], &qd[k], &qdd[k]);
        }
        Ok(())
    }

    /// [`gravity`](Self::gravity) of many states (see [`inverse_dynamics_batch`](Self::inverse_dynamics_batch)).
    fn gravity_batch(&self, q: &[JointVector<N>], g: &mut [JointVector<N>]) -> Result<(), Error> {
        check_batch(&[q.len()], g.len())?;
        for (k, g) in g.iter_mut().enumerate() {
            *g = self.gravity(&q[k]);
        }
        Ok(())
    }

    /// [`mass_matrix`](Self::mass_matrix) of many states (see [`inverse_dynamics_batch`](Self::inverse_dynamics_batch)).
    fn mass_matrix_batch(&self, q: &[JointVector<N>], m: &mut [JointMatrix<N>]) -> Result<(), Error> {
        check_batch(&[q.len()], m.len())?;
        for (k, m) in m.iter_mut().enumerate() {
            *m = self.mass_matrix(&q[k]);
        }
        Ok(())
    }

    /// [`forward_dynamics`](Self::forward_dynamics) of many states (see
    /// [`inverse_dynamics_batch`](Self::inverse_dynamics_batch)); stops at the first state whose
    /// mass matrix is singular, with the states before it written.
    fn forward_dynamics_batch(
        &self,
        q: &[JointVector<N>],
        qd: &[JointVector<N>],
        tau: &[JointVector<N>],
        qdd: &mut [JointVector<N>],
    ) -> Result<(), Error> {
        check_batch(&[q.len(), qd.len(), tau.len()], qdd.len())?;
        for (k, qdd) in qdd.iter_mut().enumerate() {
            *qdd = self.forward_dynamics(&q[k], &qd[k], &tau[k])?;
        }
        Ok(())
    }

    /// [`inverse_dynamics_derivatives`](Self::inverse_dynamics_derivatives) of many states (see
    /// [`inverse_dynamics_batch`](Self::inverse_dynamics_batch)); `d_dqd` as long as `d_dq`.
    fn inverse_dynamics_derivatives_batch(
        &self,
        q: &[JointVector<N>],
        qd: &[JointVector<N>],
        qdd: &[JointVector<N>],
        d_dq: &mut [JointMatrix<N>],
        d_dqd: &mut [JointMatrix<N>],
    ) -> Result<(), Error> {
        check_batch(&[q.len(), qd.len(), qdd.len(), d_dqd.len()], d_dq.len())?;
        for (k, (d_dq, d_dqd)) in d_dq.iter_mut().zip(d_dqd.iter_mut()).enumerate() {
            (*d_dq, *d_dqd) = self.inverse_dynamics_derivatives(&q[k], &qd[k], &qdd[k]);
        }
        Ok(())
    }

    /// [`forward_dynamics_derivatives`](Self::forward_dynamics_derivatives) of many states (see
    /// [`inverse_dynamics_batch`](Self::inverse_dynamics_batch)): `(d_dq[k], d_dqd[k],
    /// inverse[k])` for state `k`, the three outputs as long. The same computation as the single
    /// call, its three dynamics passes as batches ([`forward_dynamics_batch`](Self::forward_dynamics_batch),
    /// [`inverse_dynamics_derivatives_batch`](Self::inverse_dynamics_derivatives_batch),
    /// [`mass_matrix_batch`](Self::mass_matrix_batch)) over [`DERIVATIVE_CHUNK`] states at a time
    /// (their accelerations on the stack: no allocation), so each state's result is the single
    /// call's. Stops at the first state whose mass matrix is not positive definite
    /// ([`Error::SingularMassMatrix`]; the chunks before it are stored).
    fn forward_dynamics_derivatives_batch(
        &self,
        q: &[JointVector<N>],
        qd: &[JointVector<N>],
        tau: &[JointVector<N>],
        (d_dq, d_dqd, inverse): (&mut [JointMatrix<N>], &mut [JointMatrix<N>], &mut [JointMatrix<N>]),
    ) -> Result<(), Error> {
        check_batch(&[q.len(), qd.len(), tau.len(), d_dqd.len(), inverse.len()], d_dq.len())?;
        let mut qdd = [JointVector::<N>::zeros(); DERIVATIVE_CHUNK];
        for start in (0..q.len()).step_by(DERIVATIVE_CHUNK) {
            let range = start..(start + DERIVATIVE_CHUNK).min(q.len());
            let (q, qd, tau, qdd) =
                (&q[range.clone()], &qd[range.clone()], &tau[range.clone()], &mut qdd[..range.len()]);
            let (d_dq, d_dqd, inverse) = (&mut d_dq[range.clone()], &mut d_dqd[range.clone()], &mut inverse[range]);
            self.forward_dynamics_batch(q, qd, tau, qdd)?;
            self.inverse_dynamics_derivatives_batch(q, qd, qdd, d_dq, d_dqd)?;
            self.mass_matrix_batch(q, inverse)?;
            through_inverse_batch(inverse, d_dq, d_dqd)?;
        }
        Ok(())
    }
}

/// States per step of [`Dynamics::forward_dynamics_derivatives_batch`]: two steps of eight lanes.
pub const DERIVATIVE_CHUNK: usize = 16;

/// Each of `matrices` into its slice of `outputs`, row-major (the transpose's column-major
/// storage): how slices carry `N × N` results.
pub(crate) fn write_row_major<const N: usize, const K: usize>(
    outputs: [&mut [f64]; K],
    matrices: [&JointMatrix<N>; K],
) {
    for (out, matrix) in outputs.into_iter().zip(matrices) {
        out.copy_from_slice(matrix.transpose().as_slice());
    }
}

/// `Err(BatchLength)` for the first argument whose length is not the output's.
pub fn check_batch(arguments: &[usize], expected: usize) -> Result<(), Error> {
    match arguments.iter().position(|&got| got != expected) {
        Some(argument) => Err(Error::BatchLength { argument, expected, got: arguments[argument] }),
        None => Ok(()),
    }
}

/// Implements [`Dynamics`] for a pointer type by forwarding every method to its target.
macro_rules! delegate_dynamics {
    ($($pointer:ty),*) => {$(
impl<const N: usize, D: Dynamics<N> + ?Sized> Dynamics<N> for $pointer {
    fn inverse_dynamics(&self, q: &JointVector<N>, qd: &JointVector<N>, qdd: &JointVector<N>) -> JointVector<N> {
        (**self).inverse_dynamics(q, qd, qdd)
    }
    fn coriolis_transpose_times_velocity(&self, q: &JointVector<N>, qd: &JointVector<N>) -> JointVector<N> {
        (**self).coriolis_transpose_times_velocity(q, qd)
    }
    fn gravity(&self, q: &JointVector<N>) -> JointVector<N> {
        (**self).gravity(q)
    }
    fn velocity_terms(&self, q: &JointVector<N>, qd: &JointVector<N>) -> JointVector<N> {
        (**self).velocity_terms(q, qd)
    }
    fn mass_matrix(&self, q: &JointVector<N>) -> JointMatrix<N> {
        (**self).mass_matrix(q)
    }
    fn inverse_dynamics_derivatives(
        &self,
        q: &JointVector<N>,
        qd: &JointVector<N>,
        qdd: &JointVector<N>,
    ) -> (JointMatrix<N>, JointMatrix<N>) {
        (**self).inverse_dynamics_derivatives(q, qd, qdd)
    }
    fn forward_dynamics(
        &self,
        q: &JointVector<N>,
        qd: &JointVector<N>,
        tau: &JointVector<N>,
    ) -> Result<JointVector<N>, Error> {
        (**self).forward_dynamics(q, qd, tau)
    }
    fn forward_dynamics_derivatives(
        &self,
        q: &JointVector<N>,
        qd: &JointVector<N>,
        tau: &JointVector<N>,
    ) -> Result<(JointMatrix<N>, JointMatrix<N>, JointMatrix<N>), Error> {
        (**self).forward_dynamics_derivatives(q, qd, tau)
    }
    fn inverse_dynamics_batch(
        &self,
        q: &[JointVector<N>],
        qd: &[JointVector<N>],
        qdd: &[JointVector<N>],
        tau: &mut [JointVector<N>],
    ) -> Result<(), Error> {
        (**self).inverse_dynamics_batch(q, qd, qdd, tau)
    }
    fn gravity_batch(&self, q: &[JointVector<N>], g: &mut [JointVector<N>]) -> Result<(), Error> {
        (**self).gravity_batch(q, g)
    }
    fn mass_matrix_batch(&self, q: &[JointVector<N>], m: &mut [JointMatrix<N>]) -> Result<(), Error> {
        (**self).mass_matrix_batch(q, m)
    }
    fn forward_dynamics_batch(
        &self,
        q: &[JointVector<N>],
        qd: &[JointVector<N>],
        tau: &[JointVector<N>],
        qdd: &mut [JointVector<N>],
    ) -> Result<(), Error> {
        (**self).forward_dynamics_batch(q, qd, tau, qdd)
    }
    fn inverse_dynamics_derivatives_batch(
        &self,
        q: &[JointVector<N>],
        qd: &[JointVector<N>],
        qdd: &[JointVector<N>],
        d_dq: &mut [JointMatrix<N>],
        d_dqd: &mut [JointMatrix<N>],
    ) -> Result<(), Error> {
        (**self).inverse_dynamics_derivatives_batch(q, qd, qdd, d_dq, d_dqd)
    }
    fn forward_dynamics_derivatives_batch(
        &self,
        q: &[JointVector<N>],
        qd: &[JointVector<N>],
        tau: &[JointVector<N>],
        outputs: (&mut [JointMatrix<N>], &mut [JointMatrix<N>], &mut [JointMatrix<N>]),
    ) -> Result<(), Error> {
        (**self).forward_dynamics_derivatives_batch(q, qd, tau, outputs)
    }
}
    )*};
}

delegate_dynamics!(&D);
#[cfg(feature = "alloc")]
delegate_dynamics!(alloc::boxed::Box<D>, alloc::sync::Arc<D>);

/// Dynamics whose number of joints is known only at run time, on slices: the view a command
/// line or a loaded URDF needs. Every slice must have [`dof`](Self::dof) entries (`dof²` for
/// the row-major mass matrix); implementations may panic otherwise, so check lengths first.
pub trait SliceDynamics {
    /// Degrees of freedom.
    fn dof(&self) -> usize;
    /// `τ = ID(q, q̇, q̈)`.
    fn inverse_dynamics_into(&self, q: &[f64], qd: &[f64], qdd: &[f64], tau: &mut [f64]);
    /// `τ = G(q)`.
    fn gravity_into(&self, q: &[f64], tau: &mut [f64]);
    /// `M(q)`, row-major.
    fn mass_matrix_into(&self, q: &[f64], mass: &mut [f64]);
    /// `q̈ = FD(q, q̇, τ)`; an error where the mass matrix is singular.
    fn forward_dynamics_into(&self, q: &[f64], qd: &[f64], tau: &[f64], qdd: &mut [f64]) -> Result<(), Error>;
    /// `∂τ/∂q` and `∂τ/∂q̇` at `(q, q̇, q̈)`, each `dof²`, row-major (row `i` is `∂τ_i`).
    fn inverse_dynamics_derivatives_into(
        &self,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        d_dq: &mut [f64],
        d_dqd: &mut [f64],
    );

    /// `∂q̈/∂q`, `∂q̈/∂q̇` and `M⁻¹` at `(q, q̇, τ)`, each `dof²`, row-major (row `i` is `∂q̈_i`;
    /// see [`Dynamics::forward_dynamics_derivatives`]); an error where the mass matrix is singular.
    fn forward_dynamics_derivatives_into(
        &self,
        q: &[f64],
        qd: &[f64],
        tau: &[f64],
        outputs: [&mut [f64]; 3],
    ) -> Result<(), Error>;

    /// [`inverse_dynamics_into`](Self::inverse_dynamics_into) of many states, rows of
    /// [`dof`](Self::dof) values one after another (row-major `count × dof`); `tau` sets the
    /// count, and every argument must hold as many rows ([`Error::BatchLength`] otherwise) and end
    /// at a row's end ([`Error::PartialRow`] otherwise).
    /// Generated dynamics run them in batches ([`Dynamics::inverse_dynamics_batch`]).
    fn inverse_dynamics_rows(&self, q: &[f64], qd: &[f64], qdd: &[f64], tau: &mut [f64]) -> Result<(), Error> {
        let n = self.dof();
        check_batch(&[q.len(), qd.len(), qdd.len()], tau.len())?;
        whole_input_rows(&[q, qd, qdd], n)?;
        for (k, tau) in tau.chunks_mut(n.max(1)).enumerate() {
            let row = k * n..(k + 1) * n;
            self.inverse_dynamics_into(&q[row.clone()], &qd[row.clone()], &qdd[row], tau);
        }
        Ok(())
    }

    /// [`gravity_into`](Self::gravity_into) of many states (see
    /// [`inverse_dynamics_rows`](Self::inverse_dynamics_rows)).
    fn gravity_rows(&self, q: &[f64], g: &mut [f64]) -> Result<(), Error> {
        let n = self.dof();
        check_batch(&[q.len()], g.len())?;
        whole_input_rows(&[q], n)?;
        for (k, g) in g.chunks_mut(n.max(1)).enumerate() {
            self.gravity_into(&q[k * n..(k + 1) * n], g);
        }
        Ok(())
    }

    /// [`mass_matrix_into`](Self::mass_matrix_into) of many states, `dof²` outputs per row (see
    /// [`inverse_dynamics_rows`](Self::inverse_dynamics_rows)).
    fn mass_matrix_rows(&self, q: &[f64], mass: &mut [f64]) -> Result<(), Error> {
        let n = self.dof();
        check_batch(&[q.len() * n], mass.len())?;
        whole_input_rows(&[q], n)?;
        for (k, m) in mass.chunks_mut((n * n).max(1)).enumerate() {
            self.mass_matrix_into(&q[k * n..(k + 1) * n], m);
        }
        Ok(())
    }

    /// [`forward_dynamics_into`](Self::forward_dynamics_into) of many states (see
    /// [`inverse_dynamics_rows`](Self::inverse_dynamics_rows)); stops at the first singular one.
    fn forward_dynamics_rows(&self, q: &[f64], qd: &[f64], tau: &[f64], qdd: &mut [f64]) -> Result<(), Error> {
        let n = self.dof();
        check_batch(&[q.len(), qd.len(), tau.len()], qdd.len())?;
        whole_input_rows(&[q, qd, tau], n)?;
        for (k, qdd) in qdd.chunks_mut(n.max(1)).enumerate() {
            let row = k * n..(k + 1) * n;
            self.forward_dynamics_into(&q[row.clone()], &qd[row.clone()], &tau[row], qdd)?;
        }
        Ok(())
    }

    /// [`forward_dynamics_derivatives_into`](Self::forward_dynamics_derivatives_into) of many
    /// states: per row of `q`, `q̇`, `τ`, `3·dof²` numbers of `out`, `∂q̈/∂q`, `∂q̈/∂q̇` and `M⁻¹`
    /// one after another, each row-major (see [`inverse_dynamics_rows`](Self::inverse_dynamics_rows)).
    /// Stops at the first singular state, with an error (rows before it may be written).
    /// Generated dynamics run them in batches ([`Dynamics::forward_dynamics_derivatives_batch`]).
    fn forward_dynamics_derivatives_rows(
        &self,
        q: &[f64],
        qd: &[f64],
        tau: &[f64],
        out: &mut [f64],
    ) -> Result<(), Error> {
        let n = self.dof();
        check_batch(&[q.len() * 3 * n, qd.len() * 3 * n, tau.len() * 3 * n], out.len())?;
        whole_input_rows(&[q, qd, tau], n)?;
        for (k, row) in out.chunks_mut((3 * n * n).max(1)).enumerate() {
            let state = k * n..(k + 1) * n;
            let (by_q, rest) = row.split_at_mut(n * n);
            let (by_qd, inverse) = rest.split_at_mut(n * n);
            let outputs = [by_q, by_qd, inverse];
            self.forward_dynamics_derivatives_into(&q[state.clone()], &qd[state.clone()], &tau[state], outputs)?;
        }
        Ok(())
    }
}

/// Any [`Dynamics<N>`] seen as [`SliceDynamics`].
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct OnSlicesN<const N: usize, D>(pub D);

impl<const N: usize, D: Dynamics<N>> SliceDynamics for OnSlicesN<N, D> {
    fn dof(&self) -> usize {
        N
    }
    fn inverse_dynamics_into(&self, q: &[f64], qd: &[f64], qdd: &[f64], tau: &mut [f64]) {
        let [q, qd, qdd] = [q, qd, qdd].map(JointVector::<N>::from_column_slice);
        tau.copy_from_slice(self.0.inverse_dynamics(&q, &qd, &qdd).as_slice());
    }
    fn gravity_into(&self, q: &[f64], tau: &mut [f64]) {
        tau.copy_from_slice(self.0.gravity(&JointVector::from_column_slice(q)).as_slice());
    }
    fn mass_matrix_into(&self, q: &[f64], mass: &mut [f64]) {
        // M is symmetric, so its column-major storage is also its row-major layout.
        mass.copy_from_slice(self.0.mass_matrix(&JointVector::from_column_slice(q)).as_slice());
    }
    fn forward_dynamics_into(&self, q: &[f64], qd: &[f64], tau: &[f64], qdd: &mut [f64]) -> Result<(), Error> {
        let [q, qd, tau] = [q, qd, tau].map(JointVector::<N>::from_column_slice);
        qdd.copy_from_slice(self.0.forward_dynamics(&q, &qd, &tau)?.as_slice());
        Ok(())
    }
    fn inverse_dynamics_derivatives_into(
        &self,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        d_dq: &mut [f64],
        d_dqd: &mut [f64],
    ) {
        let [q, qd, qdd] = [q, qd, qdd].map(JointVector::<N>::from_column_slice);
        let (by_q, by_qd) = self.0.inverse_dynamics_derivatives(&q, &qd, &qdd);
        // Row-major: the transposes' column-major storage.
        d_dq.copy_from_slice(by_q.transpose().as_slice());
        d_dqd.copy_from_slice(by_qd.transpose().as_slice());
    }
    fn forward_dynamics_derivatives_into(
        &self,
        q: &[f64],
        qd: &[f64],
        tau: &[f64],
        outputs: [&mut [f64]; 3],
    ) -> Result<(), Error> {
        let [q, qd, tau] = [q, qd, tau].map(JointVector::<N>::from_column_slice);
        let (by_q, by_qd, inverse) = self.0.forward_dynamics_derivatives(&q, &qd, &tau)?;
        write_row_major(outputs, [&by_q, &by_qd, &inverse]);
        Ok(())
    }
    fn inverse_dynamics_rows(&self, q: &[f64], qd: &[f64], qdd: &[f64], tau: &mut [f64]) -> Result<(), Error> {
        check_batch(&[q.len(), qd.len(), qdd.len()], tau.len())?;
        in_place([q, qd, qdd], tau, |[q, qd, qdd], out| self.0.inverse_dynamics_batch(q, qd, qdd, out))
    }
    fn gravity_rows(&self, q: &[f64], g: &mut [f64]) -> Result<(), Error> {
        check_batch(&[q.len()], g.len())?;
        in_place([q], g, |[q], out| self.0.gravity_batch(q, out))
    }
    fn mass_matrix_rows(&self, q: &[f64], mass: &mut [f64]) -> Result<(), Error> {
        check_batch(&[q.len() * N], mass.len())?;
        // M is symmetric, so its column-major storage is also its row-major layout.
        in_place([q], mass, |[q], out| self.0.mass_matrix_batch(q, out))
    }
    fn forward_dynamics_rows(&self, q: &[f64], qd: &[f64], tau: &[f64], qdd: &mut [f64]) -> Result<(), Error> {
        check_batch(&[q.len(), qd.len(), tau.len()], qdd.len())?;
        in_place([q, qd, tau], qdd, |[q, qd, tau], out| self.0.forward_dynamics_batch(q, qd, tau, out))
    }
    /// [`Dynamics::forward_dynamics_derivatives_batch`] over [`DERIVATIVE_CHUNK`] states at a
    /// time, each chunk's matrices on the stack and then written row-major to its rows.
    fn forward_dynamics_derivatives_rows(
        &self,
        q: &[f64],
        qd: &[f64],
        tau: &[f64],
        out: &mut [f64],
    ) -> Result<(), Error> {
        let width = 3 * N * N;
        check_batch(&[q.len() * 3 * N, qd.len() * 3 * N, tau.len() * 3 * N], out.len())?;
        let [q, qd, tau] = whole_rows::<N, 3>([q, qd, tau])?;
        let [mut by_q, mut by_qd, mut inverse] = [[JointMatrix::<N>::zeros(); DERIVATIVE_CHUNK]; 3];
        for (start, rows) in (0..).step_by(DERIVATIVE_CHUNK).zip(out.chunks_mut(DERIVATIVE_CHUNK * width.max(1))) {
            let states = start..start + rows.len() / width.max(1);
            let used = states.len();
            let outputs = (&mut by_q[..used], &mut by_qd[..used], &mut inverse[..used]);
            self.0.forward_dynamics_derivatives_batch(
                &q[states.clone()],
                &qd[states.clone()],
                &tau[states],
                outputs,
            )?;
            for (k, row) in rows.chunks_mut(width.max(1)).enumerate() {
                let (by_q_row, rest) = row.split_at_mut(N * N);
                let (by_qd_row, inverse_row) = rest.split_at_mut(N * N);
                write_row_major([by_q_row, by_qd_row, inverse_row], [&by_q[k], &by_qd[k], &inverse[k]]);
            }
        }
        Ok(())
    }
}

/// Runs `batch` on the rows of `inputs` seen in place as joint vectors, writing each result's
/// `R·C` numbers (column-major storage) to its row of `out`: no copy, as a row of `N` numbers
/// has the layout of a `JointVector<N>`. [`Error::PartialRow`] if a slice ends inside a row.
fn in_place<const N: usize, const IN: usize, const R: usize, const C: usize>(
    inputs: [&[f64]; IN],
    out: &mut [f64],
    batch: impl FnOnce([&[JointVector<N>]; IN], &mut [SMatrix<f64, R, C>]) -> Result<(), Error>,
) -> Result<(), Error> {
    let arguments = whole_rows::<N, IN>(inputs)?;
    whole_row(IN, out.len(), R * C)?;
    batch(arguments, bytemuck::cast_slice_mut::<f64, SMatrix<f64, R, C>>(out))
}

/// The rows of `inputs` seen in place as joint vectors; [`Error::PartialRow`] if a slice ends
/// inside a row.
fn whole_rows<const N: usize, const IN: usize>(inputs: [&[f64]; IN]) -> Result<[&[JointVector<N>]; IN], Error> {
    whole_input_rows(&inputs, N)?;
    Ok(inputs.map(bytemuck::cast_slice::<f64, JointVector<N>>))
}

/// [`Error::PartialRow`] for the first of `inputs` that ends inside a row of `n` numbers.
fn whole_input_rows(inputs: &[&[f64]], n: usize) -> Result<(), Error> {
    inputs.iter().enumerate().try_for_each(|(argument, input)| whole_row(argument, input.len(), n))
}

/// [`Error::PartialRow`] unless `values` numbers of `argument` are whole rows of `width`.
fn whole_row(argument: usize, values: usize, width: usize) -> Result<(), Error> {
    match values % width.max(1) {
        0 => Ok(()),
        _ => Err(Error::PartialRow { argument, values, width }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_arms::PlanarTwoLink;

    /// Rows of three states, seen in place, give the single calls' results row by row; a slice
    /// that is not a whole number of rows is refused.
    #[test]
    fn rows_equal_single_calls_and_partial_rows_are_refused() {
        let arm = OnSlicesN::<2, _>(PlanarTwoLink::default());
        let q = [0.1, -0.4, 0.7, 0.2, -1.1, 0.9];
        let qd = [0.5, 0.3, -0.2, 1.0, 0.0, -0.6];
        let qdd = [1.5, -2.0, 0.4, 0.1, -0.3, 2.2];
        let (mut tau, mut g, mut m, mut fd) = ([0.0; 6], [0.0; 6], [0.0; 12], [0.0; 6]);
        arm.inverse_dynamics_rows(&q, &qd, &qdd, &mut tau).unwrap();
        arm.gravity_rows(&q, &mut g).unwrap();
        arm.mass_matrix_rows(&q, &mut m).unwrap();
        arm.forward_dynamics_rows(&q, &qd, &tau, &mut fd).unwrap();
        for k in 0..3 {
            let (row, (mut one, mut mass)) = (2 * k..2 * k + 2, ([0.0; 2], [0.0; 4]));
            arm.inverse_dynamics_into(&q[row.clone()], &qd[row.clone()], &qdd[row.clone()], &mut one);
            assert_eq!(one, tau[row.clone()], "ID, row {k}");
            arm.gravity_into(&q[row.clone()], &mut one);
            assert_eq!(one, g[row.clone()], "G, row {k}");
            arm.mass_matrix_into(&q[row.clone()], &mut mass);
            assert_eq!(mass, m[4 * k..4 * k + 4], "M, row {k}");
            arm.forward_dynamics_into(&q[row.clone()], &qd[row.clone()], &tau[row.clone()], &mut one).unwrap();
            assert_eq!(one, fd[row], "FD, row {k}");
        }
        let refused = arm.inverse_dynamics_rows(&q[..5], &qd[..5], &qdd[..5], &mut tau[..5]);
        assert_eq!(refused, Err(Error::PartialRow { argument: 0, values: 5, width: 2 }));
        assert!(arm.mass_matrix_rows(&q, &mut m[..11]).is_err());
    }

    /// The default row methods, on a type with the single calls only.
    struct SingleCalls(OnSlicesN<2, PlanarTwoLink>);

    impl SliceDynamics for SingleCalls {
        fn dof(&self) -> usize {
            2
        }
        fn inverse_dynamics_into(&self, q: &[f64], qd: &[f64], qdd: &[f64], tau: &mut [f64]) {
            self.0.inverse_dynamics_into(q, qd, qdd, tau);
        }
        fn gravity_into(&self, q: &[f64], tau: &mut [f64]) {
            self.0.gravity_into(q, tau);
        }
        fn mass_matrix_into(&self, q: &[f64], mass: &mut [f64]) {
            self.0.mass_matrix_into(q, mass);
        }
        fn forward_dynamics_into(&self, q: &[f64], qd: &[f64], tau: &[f64], qdd: &mut [f64]) -> Result<(), Error> {
            self.0.forward_dynamics_into(q, qd, tau, qdd)
        }
        fn inverse_dynamics_derivatives_into(
            &self,
            q: &[f64],
            qd: &[f64],
            qdd: &[f64],
            by_q: &mut [f64],
            by_qd: &mut [f64],
        ) {
            self.0.inverse_dynamics_derivatives_into(q, qd, qdd, by_q, by_qd);
        }
        fn forward_dynamics_derivatives_into(
            &self,
            q: &[f64],
            qd: &[f64],
            tau: &[f64],
            outputs: [&mut [f64]; 3],
        ) -> Result<(), Error> {
            self.0.forward_dynamics_derivatives_into(q, qd, tau, outputs)
        }
    }

    /// Forward-dynamics derivatives by rows, batched and by the default, are the single call's
    /// row by row; every default refuses a slice that ends inside a row, with an error, not a
    /// panic.
    #[test]
    fn derivative_rows_equal_single_calls_and_defaults_refuse_partial_rows() {
        let batched = OnSlicesN::<2, _>(PlanarTwoLink::default());
        let by_default = SingleCalls(batched);
        // Twenty states: a whole chunk of the batch and a part of the next.
        let q: [f64; 40] = core::array::from_fn(|i| (i as f64 * 0.37).sin());
        let qd: [f64; 40] = core::array::from_fn(|i| (i as f64 * 0.71).cos());
        let tau: [f64; 40] = core::array::from_fn(|i| 3.0 * (i as f64 * 0.13).sin());
        let (mut rows, mut default_rows) = ([0.0; 240], [0.0; 240]);
        batched.forward_dynamics_derivatives_rows(&q, &qd, &tau, &mut rows).unwrap();
        by_default.forward_dynamics_derivatives_rows(&q, &qd, &tau, &mut default_rows).unwrap();
        for k in 0..20 {
            let state = 2 * k..2 * k + 2;
            let mut one = [[0.0; 4]; 3];
            let [a, b, c] = &mut one;
            batched
                .forward_dynamics_derivatives_into(&q[state.clone()], &qd[state.clone()], &tau[state], [a, b, c])
                .unwrap();
            assert_eq!(one.concat(), rows[12 * k..12 * k + 12], "row {k}");
            assert_eq!(one.concat(), default_rows[12 * k..12 * k + 12], "row {k}, by default");
        }
        let partial = Err(Error::PartialRow { argument: 0, values: 5, width: 2 });
        let (mut five, mut ten) = ([0.0; 5], [0.0; 10]);
        assert_eq!(by_default.inverse_dynamics_rows(&q[..5], &qd[..5], &tau[..5], &mut five), partial);
        assert_eq!(by_default.gravity_rows(&q[..5], &mut five), partial);
        assert_eq!(by_default.mass_matrix_rows(&q[..5], &mut ten), partial);
        assert_eq!(by_default.forward_dynamics_rows(&q[..5], &qd[..5], &tau[..5], &mut five), partial);
        let mut thirty = [0.0; 30];
        assert_eq!(by_default.forward_dynamics_derivatives_rows(&q[..5], &qd[..5], &tau[..5], &mut thirty), partial);
        assert_eq!(batched.forward_dynamics_derivatives_rows(&q[..5], &qd[..5], &tau[..5], &mut thirty), partial);
    }
}
