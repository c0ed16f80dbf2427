//! Derivatives of inverse dynamics, `∂τ/∂q` and `∂τ/∂q̇`, by running RNEA on dual numbers
//! ([`Dual`]): one run per seeded direction, `2n` runs in all, each exact to rounding (no step
//! size). The same function traced by the code generator gives unrolled derivative code.

use super::algorithms::{self, Inertias};
use super::{BodyState, ModelError, TreeModel};
use crate::rigid_body::dual::Dual;
use crate::rigid_body::scalar::Real;
use crate::rigid_body::spatial::RigidBodyInertia;

/// Inertias of the number type `S` as fixed (tangent-free) dual numbers.
struct Fixed<'a, I>(&'a I);

impl<S: Real, I: Inertias<S>> Inertias<Dual<S>> for Fixed<'_, I> {
    fn inertia(&self, body: usize) -> RigidBodyInertia<Dual<S>> {
        RigidBodyInertia::from_parameters(&self.0.inertia(body).parameters().map(Dual::fixed))
    }
}

/// Which input a run differentiates along.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    /// `∂/∂q_j`.
    Position(usize),
    /// `∂/∂q̇_j`.
    Velocity(usize),
}

/// `τ = ID(q, q̇, q̈)` with the tangents of the outputs along `direction`: `tangent[i] = ∂τ_i/∂x`.
/// `scratch` holds `4n` dual numbers (the seeded inputs and the output).
#[allow(clippy::too_many_arguments)]
pub fn inverse_dynamics_directional<S: Real>(
    model: &TreeModel,
    inertias: &impl Inertias<S>,
    (q, qd, qdd): (&[S], &[S], &[S]),
    direction: Direction,
    states: &mut [BodyState<Dual<S>>],
    scratch: &mut [Dual<S>],
    tau: &mut [S],
    tangent: &mut [S],
) -> Result<(), ModelError> {
    let n = model.dof();
    if scratch.len() != 4 * n {
        return Err(ModelError::Dimension { what: "dual scratch (4 per joint)", expected: 4 * n, got: scratch.len() });
    }
    for (what, x) in [("q", q), ("qd", qd), ("qdd", qdd), ("tau", &*tau), ("tangent", &*tangent)] {
        if x.len() != n {
            return Err(ModelError::Dimension { what, expected: n, got: x.len() });
        }
    }
    let (inputs, out) = scratch.split_at_mut(3 * n);
    let (dual_q, rest) = inputs.split_at_mut(n);
    let (dual_qd, dual_qdd) = rest.split_at_mut(n);
    for (i, ((dq, dqd), dqdd)) in dual_q.iter_mut().zip(dual_qd.iter_mut()).zip(dual_qdd.iter_mut()).enumerate() {
        let seed = |x: &[S], seeded: bool| if seeded { Dual::variable(x[i]) } else { Dual::fixed(x[i]) };
        *dq = seed(q, direction == Direction::Position(i));
        *dqd = seed(qd, direction == Direction::Velocity(i));
        *dqdd = seed(qdd, false);
    }
    algorithms::inverse_dynamics(model, &Fixed(inertias), (dual_q, dual_qd, dual_qdd), states, out)?;
    for (i, d) in out.iter().enumerate() {
        (tau[i], tangent[i]) = (d.value, d.tangent);
    }
    Ok(())
}

/// `τ`, `∂τ/∂q` and `∂τ/∂q̇` (both `n x n`, row-major: row `i` is `∂τ_i`), by `2n` dual runs.
/// `scratch` holds `4n` dual numbers, `column` `n` numbers.
#[allow(clippy::too_many_arguments)]
pub fn inverse_dynamics_derivatives<S: Real>(
    model: &TreeModel,
    inertias: &impl Inertias<S>,
    inputs: (&[S], &[S], &[S]),
    states: &mut [BodyState<Dual<S>>],
    scratch: &mut [Dual<S>],
    tau: &mut [S],
    column: &mut [S],
    (d_dq, d_dqd): (&mut [S], &mut [S]),
) -> Result<(), ModelError> {
    let n = model.dof();
    for (what, m) in [("d_dq", &*d_dq), ("d_dqd", &*d_dqd)] {
        if m.len() != n * n {
            return Err(ModelError::Dimension { what, expected: n * n, got: m.len() });
        }
    }
    for j in 0..n {
        for (direction, matrix) in [(Direction::Position(j), &mut *d_dq), (Direction::Velocity(j), &mut *d_dqd)] {
            inverse_dynamics_directional(model, inertias, inputs, direction, states, scratch, tau, column)?;
            for (i, value) in column.iter().enumerate() {
                matrix[i * n + j] = *value;
            }
        }
    }
    Ok(())
}
