//! Spatial (6D) vector algebra in Featherstone's conventions, kept as rotation + translation
//! rather than dense 6x6 matrices.
//!
//! A motion vector is `(ω, v)`: angular velocity and the linear velocity of the body point at the
//! frame's origin. A force vector is `(n, f)`: moment about the origin and force. A
//! [`Transform`] `X = (E, r)` maps coordinates of frame A to frame B, where `E` rotates A
//! coordinates into B coordinates and `r` is B's origin in A coordinates:
//!
//! ```text
//! X m = (E ω, E (v − r × ω))          motion, A → B
//! Xᵀ f = (Eᵀ n + r × Eᵀ f, Eᵀ f)      force, B → A
//! ```

use core::ops::{Add, AddAssign, Mul, Sub};

use nalgebra::{Matrix3, Vector3};

/// A spatial motion vector `(ω, v)`: rad/s and m/s (or their rates).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Motion {
    /// Angular part `ω`.
    pub angular: Vector3<f64>,
    /// Linear part `v`, of the body point at the frame's origin.
    pub linear: Vector3<f64>,
}

/// A spatial force vector `(n, f)`: N·m about the frame's origin, and N.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Force {
    /// Moment `n` about the frame's origin.
    pub angular: Vector3<f64>,
    /// Force `f`.
    pub linear: Vector3<f64>,
}

impl Motion {
    /// `(ω, v)`.
    pub fn new(angular: Vector3<f64>, linear: Vector3<f64>) -> Self {
        Self { angular, linear }
    }

    /// The motion cross product `m1 ×ₘ m2 = (ω1 × ω2, ω1 × v2 + v1 × ω2)`.
    pub fn cross_motion(&self, other: &Motion) -> Motion {
        Motion {
            angular: self.angular.cross(&other.angular),
            linear: self.angular.cross(&other.linear) + self.linear.cross(&other.angular),
        }
    }

    /// The force cross product `m ×* f = (ω × n + v × f, ω × f)`.
    pub fn cross_force(&self, force: &Force) -> Force {
        Force {
            angular: self.angular.cross(&force.angular) + self.linear.cross(&force.linear),
            linear: self.angular.cross(&force.linear),
        }
    }

    /// The power pairing `m · f = ω · n + v · f`.
    pub fn dot(&self, force: &Force) -> f64 {
        self.angular.dot(&force.angular) + self.linear.dot(&force.linear)
    }
}

impl Add for Motion {
    type Output = Motion;
    fn add(self, rhs: Motion) -> Motion {
        Motion { angular: self.angular + rhs.angular, linear: self.linear + rhs.linear }
    }
}

impl Sub for Motion {
    type Output = Motion;
    fn sub(self, rhs: Motion) -> Motion {
        Motion { angular: self.angular - rhs.angular, linear: self.linear - rhs.linear }
    }
}

impl Mul<f64> for Motion {
    type Output = Motion;
    fn mul(self, rhs: f64) -> Motion {
        Motion { angular: self.angular * rhs, linear: self.linear * rhs }
    }
}

impl Add for Force {
    type Output = Force;
    fn add(self, rhs: Force) -> Force {
        Force { angular: self.angular + rhs.angular, linear: self.linear + rhs.linear }
    }
}

impl AddAssign for Force {
    fn add_assign(&mut self, rhs: Force) {
        self.angular += rhs.angular;
        self.linear += rhs.linear;
    }
}

/// A Plücker coordinate transform `X = (E, r)` from frame A to frame B (see the module docs).
///
/// As a pose, it says where B is in A: B's axes are the rows of `E` in A coordinates, and its
/// origin is `r`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Transform {
    /// `E`: rotates A coordinates into B coordinates.
    pub rotation: Matrix3<f64>,
    /// `r`: B's origin in A coordinates, m.
    pub translation: Vector3<f64>,
}

impl Default for Transform {
    fn default() -> Self {
        Self::identity()
    }
}

impl Transform {
    /// Frames A and B coincide.
    pub fn identity() -> Self {
        Self { rotation: Matrix3::identity(), translation: Vector3::zeros() }
    }

    /// The transform to a frame B placed in A at `origin` with orientation `orientation`
    /// (B's axes as the columns, in A coordinates, as URDF's `<origin>` gives them).
    pub fn from_pose(orientation: Matrix3<f64>, origin: Vector3<f64>) -> Self {
        Self { rotation: orientation.transpose(), translation: origin }
    }

    /// `E` from its rows and `r` from its components (the form generated code uses).
    pub fn from_arrays(rotation_rows: [[f64; 3]; 3], translation: [f64; 3]) -> Self {
        let [a, b, c] = rotation_rows;
        Self {
            rotation: Matrix3::new(a[0], a[1], a[2], b[0], b[1], b[2], c[0], c[1], c[2]),
            translation: Vector3::from(translation),
        }
    }

    /// B's orientation in A: its axes as columns, `Eᵀ`.
    pub fn orientation(&self) -> Matrix3<f64> {
        self.rotation.transpose()
    }

    /// Maps a motion vector from A to B coordinates.
    pub fn apply_motion(&self, m: &Motion) -> Motion {
        Motion {
            angular: self.rotation * m.angular,
            linear: self.rotation * (m.linear - self.translation.cross(&m.angular)),
        }
    }

    /// Maps a force vector from B back to A coordinates (`Xᵀ f`).
    pub fn apply_transpose_force(&self, f: &Force) -> Force {
        let linear = self.rotation.tr_mul(&f.linear);
        Force { angular: self.rotation.tr_mul(&f.angular) + self.translation.cross(&linear), linear }
    }

    /// `self` maps A to B and `next` maps B to C; the result maps A to C.
    pub fn then(&self, next: &Transform) -> Transform {
        Transform {
            rotation: next.rotation * self.rotation,
            translation: self.translation + self.rotation.tr_mul(&next.translation),
        }
    }

    /// A point given in B coordinates, in A coordinates: `Eᵀ p + r`.
    pub fn point_to_parent(&self, p: &Vector3<f64>) -> Vector3<f64> {
        self.rotation.tr_mul(p) + self.translation
    }
}

/// Rotation matrix `R(axis, angle)` of a unit axis by Rodrigues' formula; columns are the rotated
/// frame's axes.
pub fn axis_angle(axis: &Vector3<f64>, angle: f64) -> Matrix3<f64> {
    let (s, c) = (libm::sin(angle), libm::cos(angle));
    let k = axis.cross_matrix();
    Matrix3::identity() + k * s + k * k * (1.0 - c)
}

/// `R = Rz(yaw) Ry(pitch) Rx(roll)`: URDF's fixed-axis roll, pitch, yaw.
pub fn roll_pitch_yaw(rpy: &Vector3<f64>) -> Matrix3<f64> {
    axis_angle(&Vector3::z(), rpy[2]) * axis_angle(&Vector3::y(), rpy[1]) * axis_angle(&Vector3::x(), rpy[0])
}

/// Spatial inertia of a rigid body about a frame's origin: mass `m` (kg), first moment
/// `h = m c` (kg·m, `c` the centre of mass) and rotational inertia `I` about the origin (kg·m²).
///
/// ```text
/// I m = (I ω + h × v,  m v − h × ω)
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RigidBodyInertia {
    /// Mass `m`, kg.
    pub mass: f64,
    /// First moment of mass `h = m c`, kg·m.
    pub first_moment: Vector3<f64>,
    /// Rotational inertia about the frame's origin, kg·m².
    pub rotational: Matrix3<f64>,
}

impl Default for RigidBodyInertia {
    fn default() -> Self {
        Self::zero()
    }
}

impl RigidBodyInertia {
    /// No mass at all.
    pub fn zero() -> Self {
        Self { mass: 0.0, first_moment: Vector3::zeros(), rotational: Matrix3::zeros() }
    }

    /// From mass, centre of mass `c` and inertia about the centre of mass `Ī` (all in this frame):
    /// `I = Ī + m (|c|² 1 − c cᵀ)` (parallel-axis theorem).
    pub fn from_centre_of_mass(mass: f64, com: Vector3<f64>, inertia_about_com: Matrix3<f64>) -> Self {
        let parallel_axis = (Matrix3::identity() * com.norm_squared() - com * com.transpose()) * mass;
        Self { mass, first_moment: com * mass, rotational: inertia_about_com + parallel_axis }
    }

    /// The inverse of [`from_centre_of_mass`](Self::from_centre_of_mass):
    /// `(m, c = h/m, Ī = I − m (|c|² 1 − c cᵀ))`; `None` for a massless body.
    pub fn centre_of_mass_form(&self) -> Option<(f64, Vector3<f64>, Matrix3<f64>)> {
        if self.mass <= 0.0 {
            return None;
        }
        let com = self.first_moment / self.mass;
        let parallel_axis = (Matrix3::identity() * com.norm_squared() - com * com.transpose()) * self.mass;
        Some((self.mass, com, self.rotational - parallel_axis))
    }

    /// `I m`: the momentum of a body with this inertia moving with `m`.
    pub fn apply(&self, m: &Motion) -> Force {
        Force {
            angular: self.rotational * m.angular + self.first_moment.cross(&m.linear),
            linear: m.linear * self.mass - self.first_moment.cross(&m.angular),
        }
    }

    /// This inertia, given in frame B, expressed in frame A, where `x` maps A to B (`Xᵀ I X`).
    ///
    /// With `R = Eᵀ`, `g = R h`: `h_A = g + m r` and
    /// `I_A = R I Rᵀ + (2 r·g + m |r|²) 1 − g rᵀ − r gᵀ − m r rᵀ`.
    pub fn expressed_in_parent(&self, x: &Transform) -> RigidBodyInertia {
        let r = x.translation;
        let g = x.rotation.tr_mul(&self.first_moment);
        let rotated = x.rotation.tr_mul(&(self.rotational * x.rotation));
        let rotational = rotated + Matrix3::identity() * (2.0 * r.dot(&g) + self.mass * r.norm_squared())
            - g * r.transpose()
            - r * g.transpose()
            - r * r.transpose() * self.mass;
        RigidBodyInertia { mass: self.mass, first_moment: g + r * self.mass, rotational }
    }

    /// The ten inertial parameters `(m, h_x, h_y, h_z, I_xx, I_yy, I_zz, I_xy, I_xz, I_yz)`,
    /// with `I` about the frame's origin: the order parametric generated dynamics read them in.
    pub fn parameters(&self) -> [f64; 10] {
        let (h, r) = (&self.first_moment, &self.rotational);
        [self.mass, h.x, h.y, h.z, r[(0, 0)], r[(1, 1)], r[(2, 2)], r[(0, 1)], r[(0, 2)], r[(1, 2)]]
    }

    /// The inverse of [`parameters`](Self::parameters).
    pub fn from_parameters(p: &[f64; 10]) -> Self {
        Self {
            mass: p[0],
            first_moment: Vector3::new(p[1], p[2], p[3]),
            rotational: Matrix3::new(p[4], p[7], p[8], p[7], p[5], p[9], p[8], p[9], p[6]),
        }
    }

    /// True when the body has neither mass nor rotational inertia.
    pub fn is_zero(&self) -> bool {
        self.mass == 0.0 && self.first_moment == Vector3::zeros() && self.rotational == Matrix3::zeros()
    }
}

impl Add for RigidBodyInertia {
    type Output = RigidBodyInertia;
    fn add(self, rhs: RigidBodyInertia) -> RigidBodyInertia {
        RigidBodyInertia {
            mass: self.mass + rhs.mass,
            first_moment: self.first_moment + rhs.first_moment,
            rotational: self.rotational + rhs.rotational,
        }
    }
}

impl AddAssign for RigidBodyInertia {
    fn add_assign(&mut self, rhs: RigidBodyInertia) {
        *self = *self + rhs;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample_transform() -> Transform {
        Transform::from_pose(roll_pitch_yaw(&Vector3::new(0.3, -1.1, 2.0)), Vector3::new(0.2, -0.5, 0.9))
    }

    fn sample_motion() -> Motion {
        Motion::new(Vector3::new(0.4, -1.3, 0.7), Vector3::new(2.0, 0.1, -0.6))
    }

    #[test]
    fn power_is_invariant_under_change_of_frame() {
        let x = sample_transform();
        let m_a = sample_motion();
        let f_b = Force { angular: Vector3::new(1.0, 2.0, -3.0), linear: Vector3::new(-0.5, 0.25, 4.0) };
        let power_b = x.apply_motion(&m_a).dot(&f_b);
        let power_a = m_a.dot(&x.apply_transpose_force(&f_b));
        assert!((power_a - power_b).abs() < 1e-12);
    }

    #[test]
    fn inertia_in_parent_gives_the_same_momentum_and_energy() {
        let x = sample_transform();
        let inertia_b = RigidBodyInertia::from_centre_of_mass(
            2.5,
            Vector3::new(0.1, 0.05, -0.2),
            Matrix3::new(0.03, 0.001, -0.002, 0.001, 0.02, 0.0005, -0.002, 0.0005, 0.04),
        );
        let inertia_a = inertia_b.expressed_in_parent(&x);
        let m_a = sample_motion();
        let momentum_a = inertia_a.apply(&m_a);
        let momentum_via_b = x.apply_transpose_force(&inertia_b.apply(&x.apply_motion(&m_a)));
        assert!((momentum_a.angular - momentum_via_b.angular).norm() < 1e-12);
        assert!((momentum_a.linear - momentum_via_b.linear).norm() < 1e-12);
    }

    #[test]
    fn composed_transforms_act_in_sequence() {
        let ab = sample_transform();
        let bc = Transform::from_pose(axis_angle(&Vector3::new(0.0, 0.6, 0.8), 0.7), Vector3::new(1.0, 0.0, -0.3));
        let m = sample_motion();
        let direct = ab.then(&bc).apply_motion(&m);
        let stepwise = bc.apply_motion(&ab.apply_motion(&m));
        assert!((direct - stepwise).angular.norm() < 1e-12 && (direct - stepwise).linear.norm() < 1e-12);
    }

    #[test]
    fn roll_pitch_yaw_matches_urdf_convention() {
        // rpy = (π/2, 0, 0) turns y into z.
        let r = roll_pitch_yaw(&Vector3::new(core::f64::consts::FRAC_PI_2, 0.0, 0.0));
        assert!((r * Vector3::y() - Vector3::z()).norm() < 1e-15);
    }
}
