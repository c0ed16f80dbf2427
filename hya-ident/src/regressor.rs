//! The joint-torque regressor `Y(q, q̇, q̈)`, `n × 10 B`, with `τ = Y π`.
//!
//! Body `b`'s parameters, in Pinocchio's order (`Inertia::toDynamicParameters`):
//!
//! ```text
//! π_b = (m, h_x, h_y, h_z, I_xx, I_xy, I_yy, I_xz, I_yz, I_zz)
//! ```
//!
//! with `h = m c` the first moment of mass and `I` the rotational inertia **about the body
//! frame's origin** (not the centre of mass), all in the body frame. A body is what the
//! run-time model calls one: links joined by fixed joints are merged into the body of the joint
//! that moves them, and identified as one.
//!
//! RNEA is linear in the bodies' spatial inertias (gravity enters as the base's acceleration,
//! so the gravity torque is linear in them too). Column `(b, k)` of `Y` is therefore exactly
//! the inverse dynamics of the model with every inertia zero but parameter `k` of body `b`,
//! which is one: `Y e_{bk} = ID_{π = e_{bk}}(q, q̇, q̈)`. The columns are computed so, with the
//! run-time model's RNEA and an inertia source that hands out those unit inertias; exact to
//! rounding, for any URDF the loader accepts ([`Regressor::new`]). Its cost is `10 B` RNEAs
//! per state: this is for identification, not for the control loop.
//!
//! A shipped arm's generated code has a parameter-holding twin built from body inertias (the
//! folded kinematics unrolled, the inertias read as data): [`Regressor::generated`] builds one
//! twin per unit parameter once and computes each column with its generated inverse dynamics,
//! the same linearity on generated code.

use hya_core::model::algorithms::{self, Inertias};
use hya_core::model::{BodyState, ModelError, TreeModel};
use hya_core::spatial::RigidBodyInertia;
use hya_core::{Dynamics, JointVector};
use nalgebra::{DMatrix, DVector, Matrix3, Vector3};

/// Inertial parameters per body.
pub const PARAMETERS_PER_BODY: usize = 10;

/// The regressor of one model: the run-time model's RNEA, or generated twins.
pub struct Regressor<'a> {
    dof: usize,
    source: Source<'a>,
}

/// Where the columns come from.
enum Source<'a> {
    /// The run-time model, with unit inertias handed to its RNEA.
    Tree(&'a TreeModel),
    /// One generated twin per column, column order.
    Twins(Vec<Box<dyn UnitColumn + Send + Sync + 'a>>),
}

impl std::fmt::Debug for Regressor<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let source = match self.source {
            Source::Tree(model) => format!("run-time model `{}`", model.name()),
            Source::Twins(_) => "generated twins".to_owned(),
        };
        f.debug_struct("Regressor").field("dof", &self.dof).field("source", &source).finish()
    }
}

/// The inverse dynamics of a model whose only inertial parameter is one unit: one column of `Y`.
trait UnitColumn {
    /// `ID(q, q̇, q̈)` of that model into `tau`.
    fn torque(&self, state: (&[f64], &[f64], &[f64]), tau: &mut [f64]);
}

/// A generated twin of `N` joints with one unit parameter.
struct Twin<const N: usize>(Box<dyn Dynamics<N> + Send + Sync>);

impl<const N: usize> UnitColumn for Twin<N> {
    fn torque(&self, (q, qd, qdd): (&[f64], &[f64], &[f64]), tau: &mut [f64]) {
        let vector = JointVector::<N>::from_column_slice;
        tau.copy_from_slice(self.0.inverse_dynamics(&vector(q), &vector(qd), &vector(qdd)).as_slice());
    }
}

/// The inertia with parameter `k` (in the order of the module's notes) one and the rest zero.
fn unit_inertia(k: usize) -> RigidBodyInertia {
    let mut inertia = RigidBodyInertia::zero();
    let symmetric = |i: &mut RigidBodyInertia, r: usize, c: usize| {
        i.rotational[(r, c)] = 1.0;
        i.rotational[(c, r)] = 1.0;
    };
    match k {
        0 => inertia.mass = 1.0,
        1..=3 => inertia.first_moment[k - 1] = 1.0,
        4 => symmetric(&mut inertia, 0, 0),
        5 => symmetric(&mut inertia, 0, 1),
        6 => symmetric(&mut inertia, 1, 1),
        7 => symmetric(&mut inertia, 0, 2),
        8 => symmetric(&mut inertia, 1, 2),
        _ => symmetric(&mut inertia, 2, 2),
    }
    inertia
}

/// Body `body`'s parameters `π_b` from its spatial inertia.
pub fn body_parameters(inertia: &RigidBodyInertia) -> [f64; PARAMETERS_PER_BODY] {
    let (h, i) = (inertia.first_moment, inertia.rotational);
    [inertia.mass, h.x, h.y, h.z, i[(0, 0)], i[(0, 1)], i[(1, 1)], i[(0, 2)], i[(1, 2)], i[(2, 2)]]
}

/// The spatial inertia of parameters `π_b` (the inverse of [`body_parameters`]).
pub fn body_inertia(p: &[f64]) -> RigidBodyInertia {
    RigidBodyInertia {
        mass: p[0],
        first_moment: Vector3::new(p[1], p[2], p[3]),
        rotational: Matrix3::new(p[4], p[5], p[7], p[5], p[6], p[8], p[7], p[8], p[9]),
    }
}

/// `π` of the model's own inertias, body after body.
pub fn nominal_parameters(model: &TreeModel) -> DVector<f64> {
    DVector::from_iterator(
        PARAMETERS_PER_BODY * model.dof(),
        model.bodies().iter().flat_map(|body| body_parameters(&body.inertia)),
    )
}

/// Every inertia zero but one parameter of one body.
struct UnitParameter {
    body: usize,
    inertia: RigidBodyInertia,
}

impl Inertias<f64> for UnitParameter {
    fn inertia(&self, body: usize) -> RigidBodyInertia {
        if body == self.body {
            self.inertia
        } else {
            RigidBodyInertia::zero()
        }
    }
}

impl<'a> Regressor<'a> {
    /// The regressor of `model` (one body per joint) by its run-time RNEA.
    pub fn new(model: &'a TreeModel) -> Self {
        Self { dof: model.dof(), source: Source::Tree(model) }
    }

    /// The regressor of a shipped arm of `N` bodies by its generated code: `twin` builds its
    /// parameter-holding twin from body inertias in joint order (`hya_robots::Arm::parametric`),
    /// called once per column here.
    pub fn generated<const N: usize>(
        twin: impl Fn(&[RigidBodyInertia; N]) -> Box<dyn Dynamics<N> + Send + Sync>,
    ) -> Regressor<'static> {
        let mut columns: Vec<Box<dyn UnitColumn + Send + Sync>> = Vec::with_capacity(PARAMETERS_PER_BODY * N);
        for body in 0..N {
            for k in 0..PARAMETERS_PER_BODY {
                let inertias =
                    core::array::from_fn(|b| if b == body { unit_inertia(k) } else { RigidBodyInertia::zero() });
                columns.push(Box::new(Twin::<N>(twin(&inertias))));
            }
        }
        Regressor { dof: N, source: Source::Twins(columns) }
    }

    /// The regressor of the robot `robot` names (a shipped arm's name, or a URDF's path) with
    /// the model `model`: a shipped arm's generated code (about three times faster, the same
    /// columns to rounding), else the run-time model's. Every front end picks it so, and so
    /// gets the same numbers.
    pub fn of_robot(robot: &str, model: &'a TreeModel) -> Self {
        struct Generated;
        impl hya_robots::ForArm for Generated {
            type Output = Regressor<'static>;
            fn call<const N: usize>(self, arm: hya_robots::Arm<N>) -> Self::Output {
                Regressor::generated::<N>(arm.parametric)
            }
        }
        hya_robots::find(robot)
            .and_then(|_| hya_robots::with_arm(robot, Generated))
            .unwrap_or_else(|| Regressor::new(model))
    }

    /// Its columns: `10 B`.
    pub fn columns(&self) -> usize {
        PARAMETERS_PER_BODY * self.dof
    }

    /// `Y(q, q̇, q̈)` into the `n` rows of `y` starting at `row` (`y` has [`Self::columns`]
    /// columns), for stacking the samples of a log.
    pub fn rows_into(
        &self,
        (q, qd, qdd): (&[f64], &[f64], &[f64]),
        y: &mut DMatrix<f64>,
        row: usize,
    ) -> Result<(), ModelError> {
        let n = self.dof;
        if y.ncols() != self.columns() || y.nrows() < row + n {
            return Err(ModelError::Dimension { what: "regressor rows", expected: self.columns(), got: y.ncols() });
        }
        for (what, v) in [("q", q), ("q̇", qd), ("q̈", qdd)] {
            if v.len() != n {
                return Err(ModelError::Dimension { what, expected: n, got: v.len() });
            }
        }
        let mut tau = vec![0.0; n];
        let mut put = |column: usize, tau: &[f64]| {
            for (i, t) in tau.iter().enumerate() {
                y[(row + i, column)] = *t;
            }
        };
        match &self.source {
            Source::Tree(model) => {
                let mut states = vec![BodyState::new(); n];
                for body in 0..n {
                    for k in 0..PARAMETERS_PER_BODY {
                        let unit = UnitParameter { body, inertia: unit_inertia(k) };
                        algorithms::inverse_dynamics(model, &unit, (q, qd, qdd), &mut states, &mut tau)?;
                        put(PARAMETERS_PER_BODY * body + k, &tau);
                    }
                }
            }
            Source::Twins(columns) => {
                for (column, twin) in columns.iter().enumerate() {
                    twin.torque((q, qd, qdd), &mut tau);
                    put(column, &tau);
                }
            }
        }
        Ok(())
    }

    /// `Y(q, q̇, q̈)`, `n × 10 B`.
    pub fn rows(&self, state: (&[f64], &[f64], &[f64])) -> Result<DMatrix<f64>, ModelError> {
        let mut y = DMatrix::zeros(self.dof, self.columns());
        self.rows_into(state, &mut y, 0)?;
        Ok(y)
    }
}
