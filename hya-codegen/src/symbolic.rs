//! Spatial algebra on traced [`Value`]s: the operations of [`hya_core::spatial`], written so that
//! constant structure (axis-aligned joints, zero offsets, sparse inertias) folds away as the
//! algorithms run. Conventions are those of `hya_core::spatial`.

use hya_core::model::{Body, JointKind};
use hya_core::spatial::{RigidBodyInertia, Transform};
use nalgebra::{Matrix3, Vector3};

use crate::expr::{Emitter, Value, ZERO};

/// A 3-vector of traced values.
pub type Vec3 = [Value; 3];
/// A 3x3 matrix of traced values, row-major.
pub type Mat3 = [[Value; 3]; 3];

/// The zero 3-vector.
pub const ZERO3: Vec3 = [ZERO; 3];

/// A constant vector.
pub fn constant_vector(v: &Vector3<f64>) -> Vec3 {
    [Value::Const(v[0]), Value::Const(v[1]), Value::Const(v[2])]
}

/// A constant matrix; entries within 1e-14 of 0 or ±1 are snapped, so that rotations by
/// multiples of π/2 (whose cosines are 6e-17, not 0) fold like the exact rotations they mean.
pub fn constant_rotation(m: &Matrix3<f64>) -> Mat3 {
    let snap = |x: f64| [0.0, 1.0, -1.0].into_iter().find(|target| (x - target).abs() < 1e-14).unwrap_or(x);
    core::array::from_fn(|r| core::array::from_fn(|c| Value::Const(snap(m[(r, c)]))))
}

/// A spatial vector: `(ω, v)` for motion, `(n, f)` for force.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spatial {
    /// Angular part.
    pub angular: Vec3,
    /// Linear part.
    pub linear: Vec3,
}

/// The zero spatial vector.
pub const ZERO6: Spatial = Spatial { angular: ZERO3, linear: ZERO3 };

/// A spatial inertia `(m, h, I)` about a frame's origin, traced.
#[derive(Debug, Clone, Copy)]
pub struct Inertia {
    mass: Value,
    first_moment: Vec3,
    rotational: Mat3,
}

/// A Plücker transform `(E, r)`, traced.
#[derive(Debug, Clone, Copy)]
pub struct Xform {
    rotation: Mat3,
    translation: Vec3,
}

/// Vector and matrix arithmetic recorded on an [`Emitter`].
impl Emitter {
    /// `a + b`.
    pub fn add3(&mut self, a: &Vec3, b: &Vec3) -> Vec3 {
        core::array::from_fn(|i| self.add(a[i], b[i]))
    }

    /// `a − b`.
    pub fn sub3(&mut self, a: &Vec3, b: &Vec3) -> Vec3 {
        core::array::from_fn(|i| self.sub(a[i], b[i]))
    }

    /// `s a`.
    pub fn scale3(&mut self, a: &Vec3, s: Value) -> Vec3 {
        core::array::from_fn(|i| self.mul(a[i], s))
    }

    /// `a × b`.
    pub fn cross(&mut self, a: &Vec3, b: &Vec3) -> Vec3 {
        core::array::from_fn(|i| {
            let (j, k) = ((i + 1) % 3, (i + 2) % 3);
            let plus = self.mul(a[j], b[k]);
            let minus = self.mul(a[k], b[j]);
            self.sub(plus, minus)
        })
    }

    /// `M v`.
    pub fn mat_vec(&mut self, m: &Mat3, v: &Vec3) -> Vec3 {
        core::array::from_fn(|r| self.dot(&m[r], v))
    }

    /// `Mᵀ v`.
    pub fn mat_tr_vec(&mut self, m: &Mat3, v: &Vec3) -> Vec3 {
        core::array::from_fn(|c| self.dot(&[m[0][c], m[1][c], m[2][c]], v))
    }

    /// `A B`.
    fn mat_mat(&mut self, a: &Mat3, b: &Mat3) -> Mat3 {
        core::array::from_fn(|r| core::array::from_fn(|c| self.dot(&a[r], &[b[0][c], b[1][c], b[2][c]])))
    }

    /// `u vᵀ`.
    fn outer(&mut self, u: &Vec3, v: &Vec3) -> Mat3 {
        core::array::from_fn(|r| core::array::from_fn(|c| self.mul(u[r], v[c])))
    }

    fn add_mat(&mut self, a: &Mat3, b: &Mat3) -> Mat3 {
        core::array::from_fn(|r| core::array::from_fn(|c| self.add(a[r][c], b[r][c])))
    }

    fn sub_mat(&mut self, a: &Mat3, b: &Mat3) -> Mat3 {
        core::array::from_fn(|r| core::array::from_fn(|c| self.sub(a[r][c], b[r][c])))
    }

    /// `a + b` of spatial vectors.
    pub fn add6(&mut self, a: &Spatial, b: &Spatial) -> Spatial {
        Spatial { angular: self.add3(&a.angular, &b.angular), linear: self.add3(&a.linear, &b.linear) }
    }

    /// `s a` of a spatial vector.
    pub fn scale6(&mut self, a: &Spatial, s: Value) -> Spatial {
        Spatial { angular: self.scale3(&a.angular, s), linear: self.scale3(&a.linear, s) }
    }

    /// Power pairing `m · f`.
    pub fn dot6(&mut self, m: &Spatial, f: &Spatial) -> Value {
        let angular = self.dot(&m.angular, &f.angular);
        let linear = self.dot(&m.linear, &f.linear);
        self.add(angular, linear)
    }

    /// `m1 ×ₘ m2 = (ω1 × ω2, ω1 × v2 + v1 × ω2)`.
    pub fn cross_motion(&mut self, m1: &Spatial, m2: &Spatial) -> Spatial {
        let angular = self.cross(&m1.angular, &m2.angular);
        let a = self.cross(&m1.angular, &m2.linear);
        let b = self.cross(&m1.linear, &m2.angular);
        Spatial { angular, linear: self.add3(&a, &b) }
    }

    /// `m ×* f = (ω × n + v × f, ω × f)`.
    pub fn cross_force(&mut self, m: &Spatial, f: &Spatial) -> Spatial {
        let a = self.cross(&m.angular, &f.angular);
        let b = self.cross(&m.linear, &f.linear);
        Spatial { angular: self.add3(&a, &b), linear: self.cross(&m.angular, &f.linear) }
    }

    /// `X m = (E ω, E (v − r × ω))`.
    pub fn apply_motion(&mut self, x: &Xform, m: &Spatial) -> Spatial {
        let r_cross_w = self.cross(&x.translation, &m.angular);
        let shifted = self.sub3(&m.linear, &r_cross_w);
        Spatial { angular: self.mat_vec(&x.rotation, &m.angular), linear: self.mat_vec(&x.rotation, &shifted) }
    }

    /// `Xᵀ f = (Eᵀ n + r × Eᵀ f, Eᵀ f)`.
    pub fn apply_transpose_force(&mut self, x: &Xform, f: &Spatial) -> Spatial {
        let linear = self.mat_tr_vec(&x.rotation, &f.linear);
        let rotated = self.mat_tr_vec(&x.rotation, &f.angular);
        let moment = self.cross(&x.translation, &linear);
        Spatial { angular: self.add3(&rotated, &moment), linear }
    }

    /// `I m = (I ω + h × v, m v − h × ω)`.
    pub fn apply_inertia(&mut self, inertia: &Inertia, m: &Spatial) -> Spatial {
        let iw = self.mat_vec(&inertia.rotational, &m.angular);
        let hv = self.cross(&inertia.first_moment, &m.linear);
        let mv = self.scale3(&m.linear, inertia.mass);
        let hw = self.cross(&inertia.first_moment, &m.angular);
        Spatial { angular: self.add3(&iw, &hv), linear: self.sub3(&mv, &hw) }
    }

    /// `Xᵀ I X`: an inertia given in B expressed in A, where `x` maps A to B; with `R = Eᵀ`,
    /// `g = R h`: `h_A = g + m r`, `I_A = R I Rᵀ + (2 r·g + m |r|²) 1 − g rᵀ − r gᵀ − m r rᵀ`.
    pub fn inertia_in_parent(&mut self, x: &Xform, inertia: &Inertia) -> Inertia {
        let r = x.translation;
        let g = self.mat_tr_vec(&x.rotation, &inertia.first_moment);
        let rotation_t: Mat3 = core::array::from_fn(|i| core::array::from_fn(|j| x.rotation[j][i]));
        let ie = self.mat_mat(&inertia.rotational, &x.rotation);
        let rotated = self.mat_mat(&rotation_t, &ie);
        let rg = self.dot(&r, &g);
        let rr = self.dot(&r, &r);
        let two_rg = self.add(rg, rg);
        let m_rr = self.mul(inertia.mass, rr);
        let diagonal = self.add(two_rg, m_rr);
        let gr = self.outer(&g, &r);
        let rg_outer = self.outer(&r, &g);
        let mr = self.scale3(&r, inertia.mass);
        let mrr = self.outer(&r, &mr);
        let mut rotational = rotated;
        for (i, row) in rotational.iter_mut().enumerate() {
            row[i] = self.add(row[i], diagonal);
        }
        rotational = self.sub_mat(&rotational, &gr);
        rotational = self.sub_mat(&rotational, &rg_outer);
        rotational = self.sub_mat(&rotational, &mrr);
        Inertia { mass: inertia.mass, first_moment: self.add3(&g, &mr), rotational }
    }

    /// `first` maps A to B and `second` B to C; the result maps A to C:
    /// `E = E₂ E₁`, `r = r₁ + E₁ᵀ r₂`.
    pub fn compose(&mut self, first: &Xform, second: &Xform) -> Xform {
        let moved = self.mat_tr_vec(&first.rotation, &second.translation);
        Xform {
            rotation: self.mat_mat(&second.rotation, &first.rotation),
            translation: self.add3(&first.translation, &moved),
        }
    }

    /// `a + b` of inertias.
    pub fn add_inertia(&mut self, a: &Inertia, b: &Inertia) -> Inertia {
        Inertia {
            mass: self.add(a.mass, b.mass),
            first_moment: self.add3(&a.first_moment, &b.first_moment),
            rotational: self.add_mat(&a.rotational, &b.rotational),
        }
    }
}

impl Inertia {
    /// An inertia whose ten parameters `(m, h, I_xx, I_yy, I_zz, I_xy, I_xz, I_yz)` are traced
    /// values (see `RigidBodyInertia::parameters`).
    pub fn from_parameters(p: [Value; 10]) -> Self {
        Inertia {
            mass: p[0],
            first_moment: [p[1], p[2], p[3]],
            rotational: [[p[4], p[7], p[8]], [p[7], p[5], p[9]], [p[8], p[9], p[6]]],
        }
    }

    /// A body's constant inertia.
    pub fn constant(inertia: &RigidBodyInertia) -> Self {
        Inertia {
            mass: Value::Const(inertia.mass),
            first_moment: constant_vector(&inertia.first_moment),
            rotational: core::array::from_fn(|r| core::array::from_fn(|c| Value::Const(inertia.rotational[(r, c)]))),
        }
    }
}

impl Xform {
    /// Frames A and B coincide.
    pub fn identity() -> Self {
        Xform::constant(&Transform::identity())
    }

    /// `E` (rows) and `r`, for emitting.
    pub fn parts(&self) -> (&Mat3, &Vec3) {
        (&self.rotation, &self.translation)
    }

    /// A constant transform.
    pub fn constant(x: &Transform) -> Self {
        Xform { rotation: constant_rotation(&x.rotation), translation: constant_vector(&x.translation) }
    }
}

/// A body's transform from its parent, split as the constant tree part and the joint part
/// `X = X_J(q) X_tree`, so each is applied with its own sparsity.
#[derive(Debug, Clone, Copy)]
pub struct JointXform {
    tree: Xform,
    joint: Xform,
}

impl JointXform {
    /// The transform of `body` for a joint position whose sine and cosine (revolute) or value
    /// (prismatic) are traced. `E_J = R(a, q)ᵀ = a aᵀ + c (1 − a aᵀ) − s [a]×`.
    pub fn new(e: &mut Emitter, body: &Body, q: Value, sin_cos: Option<(Value, Value)>) -> Self {
        let axis = constant_vector(&body.axis);
        let joint = match (body.kind, sin_cos) {
            (JointKind::Revolute, Some((s, c))) => {
                let a = body.axis;
                let k = a.cross_matrix();
                let rotation = core::array::from_fn(|r| {
                    core::array::from_fn(|col| {
                        let projection = a[r] * a[col];
                        let identity = if r == col { 1.0 } else { 0.0 };
                        let cosine = e.mul(c, Value::Const(identity - projection));
                        let sine = e.mul(s, Value::Const(-k[(r, col)]));
                        let partial = e.add(Value::Const(projection), cosine);
                        e.add(partial, sine)
                    })
                });
                Xform { rotation, translation: ZERO3 }
            }
            _ => Xform { rotation: constant_rotation(&Matrix3::identity()), translation: e.scale3(&axis, q) },
        };
        JointXform { tree: Xform::constant(&body.tree_transform), joint }
    }

    /// The whole transform `X_J(q) X_tree` as one, for kinematics.
    pub fn combined(&self, e: &mut Emitter) -> Xform {
        e.compose(&self.tree, &self.joint)
    }

    /// `X m`.
    pub fn apply_motion(&self, e: &mut Emitter, m: &Spatial) -> Spatial {
        let in_joint_frame = e.apply_motion(&self.tree, m);
        e.apply_motion(&self.joint, &in_joint_frame)
    }

    /// `Xᵀ f`.
    pub fn apply_transpose_force(&self, e: &mut Emitter, f: &Spatial) -> Spatial {
        let in_joint_frame = e.apply_transpose_force(&self.joint, f);
        e.apply_transpose_force(&self.tree, &in_joint_frame)
    }

    /// `Xᵀ I X`.
    pub fn inertia_in_parent(&self, e: &mut Emitter, inertia: &Inertia) -> Inertia {
        let in_joint_frame = e.inertia_in_parent(&self.joint, inertia);
        e.inertia_in_parent(&self.tree, &in_joint_frame)
    }
}

/// The motion subspace `S` of a body, constant.
pub fn subspace(body: &Body) -> Spatial {
    let axis = constant_vector(&body.axis);
    match body.kind {
        JointKind::Revolute => Spatial { angular: axis, linear: ZERO3 },
        JointKind::Prismatic => Spatial { angular: ZERO3, linear: axis },
    }
}
