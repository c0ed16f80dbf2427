//! Articulated-body inertia: a symmetric 6x6 spatial inertia that is no longer one rigid body's
//! (Featherstone 2008, §7.2), in 3x3 blocks.

use nalgebra::Matrix3;

use super::vector::{
    add_mat, cross_matrix, mat_mat, mat_tr_vec, mat_vec, outer, scale3, sub_mat, symmetric_from_upper, transpose,
};
use super::{add3, Force, Motion, RigidBodyInertia, Transform};
use crate::rigid_body::scalar::Real;

/// `I^A = [[A, B], [Bᵀ, C]]` acting on motion `(ω, v)`: `I^A m = (A ω + B v, Bᵀ ω + C v)`,
/// with `A` and `C` symmetric.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ArticulatedInertia<S = f64> {
    /// `A`: moment per angular velocity.
    pub angular: Matrix3<S>,
    /// `B`: moment per linear velocity.
    pub coupling: Matrix3<S>,
    /// `C`: force per linear velocity.
    pub linear: Matrix3<S>,
}

impl<S: Real> From<RigidBodyInertia<S>> for ArticulatedInertia<S> {
    /// A rigid body's inertia: `A = I`, `B = [h]×`, `C = m 1`.
    fn from(inertia: RigidBodyInertia<S>) -> Self {
        let (m, z) = (inertia.mass, S::zero());
        Self {
            angular: inertia.rotational,
            coupling: cross_matrix(&inertia.first_moment),
            linear: Matrix3::new(m, z, z, z, m, z, z, z, m),
        }
    }
}

impl<S: Real> ArticulatedInertia<S> {
    /// `I^A m`.
    pub fn apply(&self, m: &Motion<S>) -> Force<S> {
        Force {
            angular: add3(&mat_vec(&self.angular, &m.angular), &mat_vec(&self.coupling, &m.linear)),
            linear: add3(&mat_tr_vec(&self.coupling, &m.angular), &mat_vec(&self.linear, &m.linear)),
        }
    }

    /// `I^A − U Uᵀ / D` for `U` a force and `inverse = 1 / D`: what a joint's free motion leaves
    /// of the inertia its subtree shows the parent.
    pub fn minus_projection(&self, u: &Force<S>, inverse: S) -> Self {
        let (ua, ul) = (&u.angular, &u.linear);
        let (wa, wl) = (scale3(ua, inverse), scale3(ul, inverse));
        Self {
            angular: symmetric_from_upper(&sub_mat(&self.angular, &outer(ua, &wa))),
            coupling: sub_mat(&self.coupling, &outer(ua, &wl)),
            linear: symmetric_from_upper(&sub_mat(&self.linear, &outer(ul, &wl))),
        }
    }

    /// This inertia, given in frame B, expressed in frame A, where `x` maps A to B (`Xᵀ I^A X`).
    /// With blocks rotated into A (`A' = Eᵀ A E`, likewise `B'`, `C'`) and `[r]×`:
    ///
    /// ```text
    /// A_A = A' − B'[r]× − (B'[r]×)ᵀ − [r]× C' [r]×,   B_A = B' + [r]× C',   C_A = C'
    /// ```
    pub fn expressed_in_parent(&self, x: &Transform<S>) -> Self {
        let e = &x.rotation;
        let et = transpose(e);
        let rotate = |m: &Matrix3<S>| mat_mat(&et, &mat_mat(m, e));
        let (a, b, c) = (rotate(&self.angular), rotate(&self.coupling), symmetric_from_upper(&rotate(&self.linear)));
        let rx = cross_matrix(&x.translation);
        let b_rx = mat_mat(&b, &rx);
        let rx_c = mat_mat(&rx, &c);
        let angular = sub_mat(&sub_mat(&sub_mat(&a, &b_rx), &transpose(&b_rx)), &mat_mat(&rx_c, &rx));
        Self { angular: symmetric_from_upper(&angular), coupling: add_mat(&b, &rx_c), linear: c }
    }
}

impl<S: Real> core::ops::Add for ArticulatedInertia<S> {
    type Output = Self;
    fn add(self, rhs: Self) -> Self {
        Self {
            angular: add_mat(&self.angular, &rhs.angular),
            coupling: add_mat(&self.coupling, &rhs.coupling),
            linear: add_mat(&self.linear, &rhs.linear),
        }
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::Vector3;

    use super::*;
    use crate::rigid_body::spatial::{roll_pitch_yaw, Transform};

    fn body() -> RigidBodyInertia {
        RigidBodyInertia::from_centre_of_mass(
            2.5,
            Vector3::new(0.1, 0.05, -0.2),
            Matrix3::new(0.03, 0.001, -0.002, 0.001, 0.02, 0.0005, -0.002, 0.0005, 0.04),
        )
    }

    #[test]
    fn a_rigid_body_acts_as_its_rigid_inertia_in_any_frame() {
        let x = Transform::from_pose(roll_pitch_yaw(&Vector3::new(0.3, -1.1, 2.0)), Vector3::new(0.2, -0.5, 0.9));
        let m = Motion::new(Vector3::new(0.4, -1.3, 0.7), Vector3::new(2.0, 0.1, -0.6));
        let rigid = body();
        let articulated = ArticulatedInertia::from(rigid).expressed_in_parent(&x);
        let expected = rigid.expressed_in_parent(&x).apply(&m);
        let got = articulated.apply(&m);
        assert!((got.angular - expected.angular).norm() < 1e-12 && (got.linear - expected.linear).norm() < 1e-12);
    }

    #[test]
    fn removing_the_joint_direction_leaves_no_response_along_it() {
        let s = Motion::new(Vector3::new(0.0, 0.6, 0.8), Vector3::zeros());
        let inertia = ArticulatedInertia::from(body());
        let u = inertia.apply(&s);
        let reduced = inertia.minus_projection(&u, 1.0 / s.dot(&u));
        let response = reduced.apply(&s);
        assert!(response.angular.norm() < 1e-15 && response.linear.norm() < 1e-15);
    }
}
