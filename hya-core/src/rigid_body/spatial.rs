//! Spatial (6D) vector algebra in Featherstone's conventions, kept as rotation + translation
//! rather than dense 6x6 matrices, generic over the number type ([`Real`]): written once for the
//! run-time model, the code generator and derivatives.
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
//!
//! The arithmetic is written out component by component (no library matrix products), so that
//! a tracing number type sees exactly these operations and can fold the zeros and ones of a
//! constant axis or an axis-aligned frame.

use core::ops::{Add, AddAssign, Mul, Sub};

use nalgebra::{Matrix3, Vector3};

use crate::rigid_body::scalar::{Label, Quantity, Real};

mod articulated;
pub(crate) mod vector;

pub use articulated::ArticulatedInertia;
use vector::{add3, add_mat, cross, dot, mat_mat, mat_tr_vec, mat_vec, outer, scale3, sub3, sub_mat, transpose};

/// A spatial motion vector `(ω, v)`: rad/s and m/s (or their rates).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Motion<S = f64> {
    /// Angular part `ω`.
    pub angular: Vector3<S>,
    /// Linear part `v`, of the body point at the frame's origin.
    pub linear: Vector3<S>,
}

/// A spatial force vector `(n, f)`: N·m about the frame's origin, and N.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Force<S = f64> {
    /// Moment `n` about the frame's origin.
    pub angular: Vector3<S>,
    /// Force `f`.
    pub linear: Vector3<S>,
}

/// `(x, y, z)` of constants.
pub(crate) fn constant_vector<S: Real>(v: &Vector3<f64>) -> Vector3<S> {
    Vector3::new(S::constant(v[0]), S::constant(v[1]), S::constant(v[2]))
}

pub(crate) fn zero_vector<S: Real>() -> Vector3<S> {
    Vector3::new(S::zero(), S::zero(), S::zero())
}

fn label_vector<S: Real>(v: &Vector3<S>, body: usize, quantity: Quantity, first: u8) -> Vector3<S> {
    Vector3::from_fn(|i, _| v[i].labelled(Label { body, quantity, component: first + i as u8 }))
}

/// What motion and force vectors share: construction, zero, naming, and the linear operations
/// `a + b`, `a − b`, `a s`, `a += b`, part by part.
macro_rules! spatial_vector {
    ($type:ident) => {
        impl<S: Real> $type<S> {
            /// From its angular and linear parts.
            pub fn new(angular: Vector3<S>, linear: Vector3<S>) -> Self {
                Self { angular, linear }
            }

            /// The zero vector.
            pub fn zero() -> Self {
                Self { angular: zero_vector(), linear: zero_vector() }
            }

            /// The same vector with its components named `quantity` of `body` (see
            /// [`Real::labelled`]).
            pub fn labelled(&self, body: usize, quantity: Quantity) -> Self {
                Self {
                    angular: label_vector(&self.angular, body, quantity, 0),
                    linear: label_vector(&self.linear, body, quantity, 3),
                }
            }
        }

        impl Default for $type {
            fn default() -> Self {
                Self::zero()
            }
        }

        impl<S: Real> Add for $type<S> {
            type Output = Self;
            fn add(self, rhs: Self) -> Self {
                Self { angular: add3(&self.angular, &rhs.angular), linear: add3(&self.linear, &rhs.linear) }
            }
        }

        impl<S: Real> Sub for $type<S> {
            type Output = Self;
            fn sub(self, rhs: Self) -> Self {
                Self { angular: sub3(&self.angular, &rhs.angular), linear: sub3(&self.linear, &rhs.linear) }
            }
        }

        impl<S: Real> Mul<S> for $type<S> {
            type Output = Self;
            fn mul(self, rhs: S) -> Self {
                Self { angular: scale3(&self.angular, rhs), linear: scale3(&self.linear, rhs) }
            }
        }

        impl<S: Real> AddAssign for $type<S> {
            fn add_assign(&mut self, rhs: Self) {
                *self = *self + rhs;
            }
        }
    };
}

spatial_vector!(Motion);
spatial_vector!(Force);

impl<S: Real> Motion<S> {
    /// A constant motion vector.
    pub fn constant(m: &Motion<f64>) -> Self {
        Self { angular: constant_vector(&m.angular), linear: constant_vector(&m.linear) }
    }

    /// The motion cross product `m1 ×ₘ m2 = (ω1 × ω2, ω1 × v2 + v1 × ω2)`.
    pub fn cross_motion(&self, other: &Motion<S>) -> Motion<S> {
        Motion {
            angular: cross(&self.angular, &other.angular),
            linear: add3(&cross(&self.angular, &other.linear), &cross(&self.linear, &other.angular)),
        }
    }

    /// The force cross product `m ×* f = (ω × n + v × f, ω × f)`.
    pub fn cross_force(&self, force: &Force<S>) -> Force<S> {
        Force {
            angular: add3(&cross(&self.angular, &force.angular), &cross(&self.linear, &force.linear)),
            linear: cross(&self.angular, &force.linear),
        }
    }

    /// The power pairing `m · f = ω · n + v · f`.
    pub fn dot(&self, force: &Force<S>) -> S {
        dot(&self.angular, &force.angular) + dot(&self.linear, &force.linear)
    }
}

/// A Plücker coordinate transform `X = (E, r)` from frame A to frame B (see the module docs).
///
/// As a pose, it says where B is in A: B's axes are the rows of `E` in A coordinates, and its
/// origin is `r`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Transform<S = f64> {
    /// `E`: rotates A coordinates into B coordinates.
    pub rotation: Matrix3<S>,
    /// `r`: B's origin in A coordinates, m.
    pub translation: Vector3<S>,
}

impl Default for Transform {
    fn default() -> Self {
        Self::identity()
    }
}

impl Transform {
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
}

impl<S: Real> Transform<S> {
    /// Frames A and B coincide.
    pub fn identity() -> Self {
        Self::constant(&Transform { rotation: Matrix3::identity(), translation: Vector3::zeros() })
    }

    /// A constant transform. For a tracing number type, rotation entries within 1e-14 of 0 or
    /// ±1 are snapped, so that rotations by multiples of π/2 (whose cosines are 6e-17, not 0)
    /// are the exact rotations they mean and fold as such; numeric types take them as they are.
    pub fn constant(x: &Transform<f64>) -> Self {
        let snap = |v: f64| {
            let exact = [0.0, 1.0, -1.0].into_iter().find(|target| (v - target).abs() < 1e-14);
            exact.filter(|_| S::TRACES).unwrap_or(v)
        };
        Self {
            rotation: Matrix3::from_fn(|r, c| S::constant(snap(x.rotation[(r, c)]))),
            translation: constant_vector(&x.translation),
        }
    }

    /// B's orientation in A: its axes as columns, `Eᵀ`.
    pub fn orientation(&self) -> Matrix3<S> {
        transpose(&self.rotation)
    }

    /// Maps a motion vector from A to B coordinates.
    pub fn apply_motion(&self, m: &Motion<S>) -> Motion<S> {
        let shifted = sub3(&m.linear, &cross(&self.translation, &m.angular));
        Motion { angular: mat_vec(&self.rotation, &m.angular), linear: mat_vec(&self.rotation, &shifted) }
    }

    /// Maps a motion vector from B back to A coordinates (`X⁻¹ m`): `ω_A = Eᵀ ω`,
    /// `v_A = Eᵀ v + r × ω_A`.
    pub fn apply_inverse_motion(&self, m: &Motion<S>) -> Motion<S> {
        let angular = mat_tr_vec(&self.rotation, &m.angular);
        let linear = add3(&mat_tr_vec(&self.rotation, &m.linear), &cross(&self.translation, &angular));
        Motion { angular, linear }
    }

    /// Maps a force vector from B back to A coordinates (`Xᵀ f`).
    pub fn apply_transpose_force(&self, f: &Force<S>) -> Force<S> {
        let linear = mat_tr_vec(&self.rotation, &f.linear);
        let rotated = mat_tr_vec(&self.rotation, &f.angular);
        Force { angular: add3(&rotated, &cross(&self.translation, &linear)), linear }
    }

    /// `self` maps A to B and `next` maps B to C; the result maps A to C:
    /// `E = E₂ E₁`, `r = r₁ + E₁ᵀ r₂`.
    pub fn then(&self, next: &Transform<S>) -> Transform<S> {
        let moved = mat_tr_vec(&self.rotation, &next.translation);
        Transform { rotation: mat_mat(&next.rotation, &self.rotation), translation: add3(&self.translation, &moved) }
    }

    /// A point given in B coordinates, in A coordinates: `Eᵀ p + r`.
    pub fn point_to_parent(&self, p: &Vector3<S>) -> Vector3<S> {
        add3(&mat_tr_vec(&self.rotation, p), &self.translation)
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

/// The rotation part `E_J = R(a, q)ᵀ` of a revolute joint's transform from `sin q` and `cos q`,
/// entry by entry: `E_J = a aᵀ + c (1 − a aᵀ) − s [a]×`, so a constant axis folds.
pub fn revolute_rotation<S: Real>(axis: &Vector3<f64>, sin: S, cos: S) -> Matrix3<S> {
    let k = axis.cross_matrix();
    Matrix3::from_fn(|r, col| {
        let projection = axis[r] * axis[col];
        let identity = if r == col { 1.0 } else { 0.0 };
        let cosine = cos * S::constant(identity - projection);
        let sine = sin * S::constant(-k[(r, col)]);
        (S::constant(projection) + cosine) + sine
    })
}

/// Spatial inertia of a rigid body about a frame's origin: mass `m` (kg), first moment
/// `h = m c` (kg·m, `c` the centre of mass) and rotational inertia `I` about the origin (kg·m²).
///
/// ```text
/// I m = (I ω + h × v,  m v − h × ω)
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RigidBodyInertia<S = f64> {
    /// Mass `m`, kg.
    pub mass: S,
    /// First moment of mass `h = m c`, kg·m.
    pub first_moment: Vector3<S>,
    /// Rotational inertia about the frame's origin, kg·m².
    pub rotational: Matrix3<S>,
}

impl Default for RigidBodyInertia {
    fn default() -> Self {
        Self::zero()
    }
}

impl RigidBodyInertia {
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

    /// True when the body has neither mass nor rotational inertia.
    pub fn is_zero(&self) -> bool {
        self.mass == 0.0 && self.first_moment == Vector3::zeros() && self.rotational == Matrix3::zeros()
    }
}

impl<S: Real> RigidBodyInertia<S> {
    /// No mass at all.
    pub fn zero() -> Self {
        Self { mass: S::zero(), first_moment: zero_vector(), rotational: Matrix3::from_fn(|_, _| S::zero()) }
    }

    /// A constant inertia.
    pub fn constant(inertia: &RigidBodyInertia<f64>) -> Self {
        Self::from_parameters(&inertia.parameters().map(S::constant))
    }

    /// `I m`: the momentum of a body with this inertia moving with `m`.
    pub fn apply(&self, m: &Motion<S>) -> Force<S> {
        let iw = mat_vec(&self.rotational, &m.angular);
        let hv = cross(&self.first_moment, &m.linear);
        let mv = scale3(&m.linear, self.mass);
        let hw = cross(&self.first_moment, &m.angular);
        Force { angular: add3(&iw, &hv), linear: sub3(&mv, &hw) }
    }

    /// This inertia, given in frame B, expressed in frame A, where `x` maps A to B (`Xᵀ I X`).
    ///
    /// With `R = Eᵀ`, `g = R h`: `h_A = g + m r` and
    /// `I_A = R I Rᵀ + (2 r·g + m |r|²) 1 − g rᵀ − r gᵀ − m r rᵀ`.
    pub fn expressed_in_parent(&self, x: &Transform<S>) -> RigidBodyInertia<S> {
        let r = &x.translation;
        let g = mat_tr_vec(&x.rotation, &self.first_moment);
        let rotated = mat_mat(&transpose(&x.rotation), &mat_mat(&self.rotational, &x.rotation));
        let rg = dot(r, &g);
        let rr = dot(r, r);
        let diagonal = (rg + rg) + self.mass * rr;
        let mr = scale3(r, self.mass);
        let mut rotational = rotated;
        for i in 0..3 {
            rotational[(i, i)] = rotational[(i, i)] + diagonal;
        }
        let rotational = sub_mat(&sub_mat(&sub_mat(&rotational, &outer(&g, r)), &outer(r, &g)), &outer(r, &mr));
        RigidBodyInertia { mass: self.mass, first_moment: add3(&g, &mr), rotational }
    }

    /// `İ = v ×* I − I v×`: how this inertia, of a body moving with `v` and given in a fixed
    /// frame, changes. With `v = (ω, v_o)` and `I = (m, h, Ī)` it is again a rigid-body
    /// inertia, massless:
    ///
    /// ```text
    /// ṁ = 0,   ḣ = ω × h + m v_o,   dĪ/dt = [ω]× Ī − Ī [ω]× − h v_oᵀ − v_o hᵀ + 2 (v_o · h) 1
    /// ```
    pub fn rate(&self, v: &Motion<S>) -> RigidBodyInertia<S> {
        let (h, w, vo) = (&self.first_moment, &v.angular, &v.linear);
        // `[ω]× Ī − Ī [ω]× = A + Aᵀ` with `A = [ω]× Ī`, as `Ī` is symmetric.
        let a = mat_mat(&vector::cross_matrix(w), &self.rotational);
        let twice_power = dot(vo, h) + dot(vo, h);
        let upper = Matrix3::from_fn(|r, c| {
            let diagonal = if r == c { twice_power } else { S::zero() };
            ((a[(r, c)] + a[(c, r)]) - (h[r] * vo[c] + vo[r] * h[c])) + diagonal
        });
        RigidBodyInertia {
            mass: S::zero(),
            first_moment: add3(&cross(w, h), &scale3(vo, self.mass)),
            rotational: vector::symmetric_from_upper(&upper),
        }
    }

    /// The ten inertial parameters `(m, h_x, h_y, h_z, I_xx, I_yy, I_zz, I_xy, I_xz, I_yz)`,
    /// with `I` about the frame's origin: the order parametric generated dynamics read them in.
    pub fn parameters(&self) -> [S; 10] {
        let (h, r) = (&self.first_moment, &self.rotational);
        [self.mass, h.x, h.y, h.z, r[(0, 0)], r[(1, 1)], r[(2, 2)], r[(0, 1)], r[(0, 2)], r[(1, 2)]]
    }

    /// The inverse of [`parameters`](Self::parameters).
    pub fn from_parameters(p: &[S; 10]) -> Self {
        Self {
            mass: p[0],
            first_moment: Vector3::new(p[1], p[2], p[3]),
            rotational: Matrix3::new(p[4], p[7], p[8], p[7], p[5], p[9], p[8], p[9], p[6]),
        }
    }
}

impl<S: Real> Add for RigidBodyInertia<S> {
    type Output = RigidBodyInertia<S>;
    fn add(self, rhs: RigidBodyInertia<S>) -> RigidBodyInertia<S> {
        RigidBodyInertia {
            mass: self.mass + rhs.mass,
            first_moment: add3(&self.first_moment, &rhs.first_moment),
            rotational: add_mat(&self.rotational, &rhs.rotational),
        }
    }
}

impl<S: Real> AddAssign for RigidBodyInertia<S> {
    fn add_assign(&mut self, rhs: RigidBodyInertia<S>) {
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

    #[test]
    fn revolute_rotation_is_the_transposed_rodrigues_rotation() {
        let axis = Vector3::new(0.0, 0.6, 0.8);
        let (s, c) = crate::sin_cos(0.9);
        assert!((revolute_rotation(&axis, s, c) - axis_angle(&axis, 0.9).transpose()).norm() < 1e-15);
    }
}
