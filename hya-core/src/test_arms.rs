//! Closed-form test arms: small arms whose dynamics are written out by hand, so that estimators,
//! observers and controllers can be tested against exact models before generated code exists.
//!
//! Both swing in a vertical plane: joint angles are measured from the horizontal, gravity `g`
//! acts along −y.

use libm::{cos, sin};

use crate::rigid_body::dynamics::{Dynamics, JointMatrix, JointVector};

/// A rotor of constant inertia `I` on a vertical axis: `I q̈ = τ`. The linear plant on which
/// observers show their design transfer functions exactly.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rotor {
    /// Rotational inertia about the axis, kg·m².
    pub inertia_kg_m2: f64,
}

impl Dynamics<1> for Rotor {
    fn inverse_dynamics(&self, _q: &JointVector<1>, _qd: &JointVector<1>, qdd: &JointVector<1>) -> JointVector<1> {
        qdd * self.inertia_kg_m2
    }
    fn coriolis_transpose_times_velocity(&self, _q: &JointVector<1>, _qd: &JointVector<1>) -> JointVector<1> {
        JointVector::zeros()
    }
}

/// A single link on a revolute joint: mass `m` with its centre at distance `l` from the axis and
/// rotational inertia `I` about its centre.
///
/// ```text
/// (m l² + I) q̈ + m g l cos q = τ
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pendulum {
    /// Mass, kg.
    pub mass_kg: f64,
    /// Distance from the axis to the centre of mass, m.
    pub length_m: f64,
    /// Rotational inertia about the centre of mass, kg·m².
    pub inertia_kg_m2: f64,
    /// Gravitational acceleration, m/s².
    pub gravity_m_s2: f64,
}

impl Default for Pendulum {
    fn default() -> Self {
        Self { mass_kg: 2.0, length_m: 0.5, inertia_kg_m2: 0.02, gravity_m_s2: crate::STANDARD_GRAVITY }
    }
}

impl Dynamics<1> for Pendulum {
    fn inverse_dynamics(&self, q: &JointVector<1>, _qd: &JointVector<1>, qdd: &JointVector<1>) -> JointVector<1> {
        self.mass_matrix(q) * qdd + self.gravity(q)
    }
    fn coriolis_transpose_times_velocity(&self, _q: &JointVector<1>, _qd: &JointVector<1>) -> JointVector<1> {
        JointVector::zeros()
    }
    fn gravity(&self, q: &JointVector<1>) -> JointVector<1> {
        JointVector::from([self.mass_kg * self.gravity_m_s2 * self.length_m * cos(q[0])])
    }
    fn mass_matrix(&self, _q: &JointVector<1>) -> JointMatrix<1> {
        JointMatrix::from([[self.mass_kg * self.length_m * self.length_m + self.inertia_kg_m2]])
    }
}

/// The textbook planar two-link arm (e.g. Spong, Hutchinson & Vidyasagar, ch. 7).
///
/// With `h = m2 l1 lc2 sin q2`:
///
/// ```text
/// M11 = m1 lc1² + I1 + m2 (l1² + lc2² + 2 l1 lc2 cos q2) + I2
/// M12 = m2 (lc2² + l1 lc2 cos q2) + I2,   M22 = m2 lc2² + I2
/// C   = (−h (2 q̇1 q̇2 + q̇2²),  h q̇1²)
/// C_mat = [[−h q̇2, −h (q̇1 + q̇2)], [h q̇1, 0]]   (Ṁ = C_mat + C_matᵀ)
/// G   = ((m1 lc1 + m2 l1) g cos q1 + m2 lc2 g cos(q1 + q2),  m2 lc2 g cos(q1 + q2))
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlanarTwoLink {
    /// Link masses, kg.
    pub mass_kg: [f64; 2],
    /// Length of the first link (axis to axis), m.
    pub length1_m: f64,
    /// Distance from each joint axis to its link's centre of mass, m.
    pub com_m: [f64; 2],
    /// Rotational inertia of each link about its centre of mass, kg·m².
    pub inertia_kg_m2: [f64; 2],
    /// Gravitational acceleration, m/s².
    pub gravity_m_s2: f64,
}

impl Default for PlanarTwoLink {
    fn default() -> Self {
        Self {
            mass_kg: [3.0, 2.0],
            length1_m: 0.5,
            com_m: [0.25, 0.2],
            inertia_kg_m2: [0.06, 0.03],
            gravity_m_s2: crate::STANDARD_GRAVITY,
        }
    }
}

impl PlanarTwoLink {
    /// `h = m2 l1 lc2 sin q2`, the factor common to every velocity term.
    fn coupling(&self, q: &JointVector<2>) -> f64 {
        self.mass_kg[1] * self.length1_m * self.com_m[1] * sin(q[1])
    }
}

impl Dynamics<2> for PlanarTwoLink {
    fn inverse_dynamics(&self, q: &JointVector<2>, qd: &JointVector<2>, qdd: &JointVector<2>) -> JointVector<2> {
        self.mass_matrix(q) * qdd + self.velocity_terms(q, qd) + self.gravity(q)
    }
    fn coriolis_transpose_times_velocity(&self, q: &JointVector<2>, qd: &JointVector<2>) -> JointVector<2> {
        let h = self.coupling(q);
        JointVector::from([0.0, -h * qd[0] * (qd[0] + qd[1])])
    }
    fn velocity_terms(&self, q: &JointVector<2>, qd: &JointVector<2>) -> JointVector<2> {
        let h = self.coupling(q);
        JointVector::from([-h * (2.0 * qd[0] * qd[1] + qd[1] * qd[1]), h * qd[0] * qd[0]])
    }
    fn gravity(&self, q: &JointVector<2>) -> JointVector<2> {
        let [m1, m2] = self.mass_kg;
        let [lc1, lc2] = self.com_m;
        let g = self.gravity_m_s2;
        let distal = m2 * lc2 * g * cos(q[0] + q[1]);
        JointVector::from([(m1 * lc1 + m2 * self.length1_m) * g * cos(q[0]) + distal, distal])
    }
    fn mass_matrix(&self, q: &JointVector<2>) -> JointMatrix<2> {
        let [m1, m2] = self.mass_kg;
        let [lc1, lc2] = self.com_m;
        let [i1, i2] = self.inertia_kg_m2;
        let l1 = self.length1_m;
        let c2 = cos(q[1]);
        let m22 = m2 * lc2 * lc2 + i2;
        let m12 = m2 * (lc2 * lc2 + l1 * lc2 * c2) + i2;
        let m11 = m1 * lc1 * lc1 + i1 + m2 * (l1 * l1 + lc2 * lc2 + 2.0 * l1 * lc2 * c2) + i2;
        nalgebra::Matrix2::new(m11, m12, m12, m22)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `Ṁ q̇` by central differences of `M` along `q̇`.
    fn mass_matrix_rate(arm: &PlanarTwoLink, q: &JointVector<2>, qd: &JointVector<2>) -> JointMatrix<2> {
        let h = 1e-6;
        (arm.mass_matrix(&(q + qd * h)) - arm.mass_matrix(&(q - qd * h))) / (2.0 * h)
    }

    #[test]
    fn two_link_coriolis_transpose_satisfies_mass_matrix_rate_identity() {
        let arm = PlanarTwoLink::default();
        let q = JointVector::from([0.3, -1.1]);
        let qd = JointVector::from([0.7, 1.9]);
        let lhs = mass_matrix_rate(&arm, &q, &qd) * qd;
        let rhs = arm.velocity_terms(&q, &qd) + arm.coriolis_transpose_times_velocity(&q, &qd);
        assert!((lhs - rhs).norm() < 1e-8, "{lhs} vs {rhs}");
    }

    #[test]
    fn default_trait_methods_agree_with_closed_forms() {
        /// Exposes only the two required methods, so every other method is the trait default.
        struct OnlyInverseDynamics(PlanarTwoLink);
        impl Dynamics<2> for OnlyInverseDynamics {
            fn inverse_dynamics(
                &self,
                q: &JointVector<2>,
                qd: &JointVector<2>,
                qdd: &JointVector<2>,
            ) -> JointVector<2> {
                self.0.inverse_dynamics(q, qd, qdd)
            }
            fn coriolis_transpose_times_velocity(&self, q: &JointVector<2>, qd: &JointVector<2>) -> JointVector<2> {
                self.0.coriolis_transpose_times_velocity(q, qd)
            }
        }
        let arm = PlanarTwoLink::default();
        let generic = OnlyInverseDynamics(arm);
        let q = JointVector::from([0.4, 0.9]);
        let qd = JointVector::from([-1.2, 0.5]);
        assert!((generic.mass_matrix(&q) - arm.mass_matrix(&q)).norm() < 1e-12);
        assert!((generic.gravity(&q) - arm.gravity(&q)).norm() < 1e-12);
        assert!((generic.velocity_terms(&q, &qd) - arm.velocity_terms(&q, &qd)).norm() < 1e-12);
        let tau = JointVector::from([3.0, -1.0]);
        let qdd = generic.forward_dynamics(&q, &qd, &tau).unwrap();
        assert!((arm.inverse_dynamics(&q, &qd, &qdd) - tau).norm() < 1e-10);
    }
}
