//! Forward dynamics of many arms of one kinematic tree at once, each state with its own bodies:
//! the simulator's seeds in lockstep, each seed's plant a differently perturbed arm, stepped one
//! seed per vector lane.
//!
//! ```text
//! q̈_k = M_k(q_k)⁻¹ (τ_k − C_k(q_k, q̇_k) − G_k(q_k)),   M_k, C_k, G_k from state k's bodies
//! ```
//!
//! The bodies come as ten columns, one per inertial parameter in
//! [`RigidBodyInertia::parameters`](crate::spatial::RigidBodyInertia::parameters) order
//! `(m, h_x, h_y, h_z, I_xx, I_yy, I_zz, I_xy, I_xz, I_yz)`: entry `i` of `columns[p][k]` is
//! body `i`'s parameter `p` in state `k` (bodies in joint order, about their frames' origins).
//! Generated code implements [`BodiesBatch`] for each shipped arm's parametric twin, whose
//! kernel then reads the parameters as lane values where the twin's other functions read its
//! field.

use crate::{Error, JointVector};

/// How many inertial parameters a body has.
pub const BODY_PARAMETERS: usize = 10;

/// Each state's bodies, by parameter: see the module's notes.
pub type BodyColumns<'a, const N: usize> = [&'a [JointVector<N>]; BODY_PARAMETERS];

/// The columns of one set of bodies, `parameters[i]` body `i`'s ten parameters.
pub fn body_columns<const N: usize>(parameters: &[[f64; BODY_PARAMETERS]; N]) -> [JointVector<N>; BODY_PARAMETERS] {
    core::array::from_fn(|p| JointVector::from_fn(|i, _| parameters[i][p]))
}

/// Forward dynamics over states that each carry their own bodies (see the module's notes).
pub trait BodiesBatch<const N: usize> {
    /// `q̈_k` for every state `k` into `qdd[k]`, state `k`'s bodies from `bodies` (every slice
    /// as long as `qdd`); several states per vector register. An error if a length differs or a
    /// state's articulated inertia `D_i` is not positive (the states before it are stored).
    fn forward_dynamics_of_bodies_batch(
        &self,
        bodies: BodyColumns<'_, N>,
        q: &[JointVector<N>],
        qd: &[JointVector<N>],
        tau: &[JointVector<N>],
        qdd: &mut [JointVector<N>],
    ) -> Result<(), Error>;
}
