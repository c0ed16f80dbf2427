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
//! rounding, for any URDF the loader accepts. Its cost is `10 B` RNEAs per state: this is for
//! identification, not for the control loop.

use hya_core::model::algorithms::{self, Inertias};
use hya_core::model::{BodyState, ModelError, TreeModel};
use hya_core::spatial::RigidBodyInertia;
use nalgebra::{DMatrix, DVector, Matrix3, Vector3};

/// Inertial parameters per body.
pub const PARAMETERS_PER_BODY: usize = 10;

/// The regressor of one model.
#[derive(Debug, Clone)]
pub struct Regressor<'a> {
    model: &'a TreeModel,
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
    /// The regressor of `model` (one body per joint).
    pub fn new(model: &'a TreeModel) -> Self {
        Self { model }
    }

    /// Its columns: `10 B`.
    pub fn columns(&self) -> usize {
        PARAMETERS_PER_BODY * self.model.dof()
    }

    /// `Y(q, q̇, q̈)` into the `n` rows of `y` starting at `row` (`y` has [`Self::columns`]
    /// columns), for stacking the samples of a log.
    pub fn rows_into(
        &self,
        (q, qd, qdd): (&[f64], &[f64], &[f64]),
        y: &mut DMatrix<f64>,
        row: usize,
    ) -> Result<(), ModelError> {
        let n = self.model.dof();
        if y.ncols() != self.columns() || y.nrows() < row + n {
            return Err(ModelError::Dimension { what: "regressor rows", expected: self.columns(), got: y.ncols() });
        }
        let mut states = vec![BodyState::new(); n];
        let mut tau = vec![0.0; n];
        for body in 0..n {
            for k in 0..PARAMETERS_PER_BODY {
                let unit = UnitParameter { body, inertia: unit_inertia(k) };
                algorithms::inverse_dynamics(self.model, &unit, (q, qd, qdd), &mut states, &mut tau)?;
                let column = PARAMETERS_PER_BODY * body + k;
                for (i, t) in tau.iter().enumerate() {
                    y[(row + i, column)] = *t;
                }
            }
        }
        Ok(())
    }

    /// `Y(q, q̇, q̈)`, `n × 10 B`.
    pub fn rows(&self, state: (&[f64], &[f64], &[f64])) -> Result<DMatrix<f64>, ModelError> {
        let mut y = DMatrix::zeros(self.model.dof(), self.columns());
        self.rows_into(state, &mut y, 0)?;
        Ok(y)
    }
}
