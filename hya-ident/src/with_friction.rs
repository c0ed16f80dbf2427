//! Rigid-body dynamics with the identified joint law added ([`JointFriction`]): the model the
//! controller and the estimator use once `hya identify` has found the friction (and armature):
//!
//! ```text
//! ID_f(q, q̇, q̈) = ID(q, q̇, q̈) + τ_f(q̇) + I_a q̈,   M_f(q) = M(q) + diag(I_a)
//! ```

use hya_core::{Dynamics, JointMatrix, JointVector};

use crate::JointFriction;

/// Rigid-body dynamics `D` with joint friction, and the armature `I_a q̈` where the friction file
/// has one, added to the torque it takes.
pub struct WithFriction<D> {
    dynamics: D,
    friction: JointFriction,
}

impl<D> WithFriction<D> {
    /// `dynamics` plus `friction` (checked for the arm's joints by its reader).
    pub fn new(dynamics: D, friction: JointFriction) -> Self {
        Self { dynamics, friction }
    }

    fn torque<const N: usize>(&self, qd: &JointVector<N>) -> JointVector<N> {
        JointVector::from_fn(|i, _| self.friction.torque(i, qd[i]))
    }
}

impl<const N: usize, D: Dynamics<N>> Dynamics<N> for WithFriction<D> {
    /// `ID(q, q̇, q̈) + τ_f(q̇) + I_a q̈`.
    fn inverse_dynamics(&self, q: &JointVector<N>, qd: &JointVector<N>, qdd: &JointVector<N>) -> JointVector<N> {
        let armature = JointVector::<N>::from_fn(|i, _| self.friction.armature(i) * qdd[i]);
        self.dynamics.inverse_dynamics(q, qd, qdd) + self.torque(qd) + armature
    }

    /// The rigid body's: friction stores no momentum.
    fn coriolis_transpose_times_velocity(&self, q: &JointVector<N>, qd: &JointVector<N>) -> JointVector<N> {
        self.dynamics.coriolis_transpose_times_velocity(q, qd)
    }

    /// The rigid body's plus the armature `diag(I_a)`: friction does not depend on `q̈`.
    fn mass_matrix(&self, q: &JointVector<N>) -> JointMatrix<N> {
        let mut mass = self.dynamics.mass_matrix(q);
        for i in 0..N {
            mass[(i, i)] += self.friction.armature(i);
        }
        mass
    }

    /// The rigid body's, with `∂τ_f,i/∂q̇_i = (c/s) sech²(q̇_i/s) + v` on the diagonal.
    fn inverse_dynamics_derivatives(
        &self,
        q: &JointVector<N>,
        qd: &JointVector<N>,
        qdd: &JointVector<N>,
    ) -> (JointMatrix<N>, JointMatrix<N>) {
        let (d_dq, mut d_dqd) = self.dynamics.inverse_dynamics_derivatives(q, qd, qdd);
        let f = &self.friction;
        for i in 0..N {
            let sech = 1.0 / (qd[i] / f.smoothing_rad_s).cosh();
            d_dqd[(i, i)] += f.coulomb_nm[i] / f.smoothing_rad_s * sech * sech + f.viscous_nm_s[i];
        }
        (d_dq, d_dqd)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use hya_core::model::TreeModel;

    fn planar() -> TreeModel {
        hya_urdf::load_str(include_str!("../../robots/urdf/planar2.urdf"), "planar2")
            .unwrap_or_else(|e| panic!("{e}"))
            .model
    }

    #[test]
    fn friction_adds_to_the_torque_and_its_derivative_matches_differences() {
        let rigid = planar().into_dynamics::<2>().unwrap_or_else(|e| panic!("{e}"));
        let friction = JointFriction::from_toml(
            "smoothing_rad_s = 0.1\ncoulomb_nm = [1.5, 0.8]\nviscous_nm_s = [0.6, 0.3]\noffset_nm = [0.1, -0.2]\n",
            2,
        )
        .unwrap_or_else(|e| panic!("{e}"));
        let model = WithFriction::new(&rigid, friction.clone());
        let (q, qd, qdd) =
            (JointVector::from([0.3, -0.4]), JointVector::from([0.05, -0.2]), JointVector::from([1.0, 2.0]));
        let added = model.inverse_dynamics(&q, &qd, &qdd) - rigid.inverse_dynamics(&q, &qd, &qdd);
        let want = JointVector::from([friction.torque(0, 0.05), friction.torque(1, -0.2)]);
        assert!((added - want).amax() < 1e-12, "{added} vs {want}");
        assert_eq!(model.mass_matrix(&q), rigid.mass_matrix(&q));
        let (_, exact) = model.inverse_dynamics_derivatives(&q, &qd, &qdd);
        let step = 1e-6;
        for j in 0..2 {
            let unit = JointVector::from_fn(|i, _| if i == j { step } else { 0.0 });
            let difference = (model.inverse_dynamics(&q, &(qd + unit), &qdd)
                - model.inverse_dynamics(&q, &(qd - unit), &qdd))
                / (2.0 * step);
            for i in 0..2 {
                assert!(
                    (exact[(i, j)] - difference[i]).abs() < 1e-7,
                    "∂τ{i}/∂q̇{j}: {} vs {}",
                    exact[(i, j)],
                    difference[i]
                );
            }
        }
    }
}
