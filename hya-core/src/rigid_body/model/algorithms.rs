//! The dynamics algorithms on a [`TreeModel`], written once, generic over the number type
//! ([`Real`]): `f64` for the run-time model, dual numbers for derivatives, the code generator's
//! tracing type for unrolled code (Featherstone, *Rigid Body Dynamics Algorithms*, 2008).
//!
//! Every function takes the model's geometry, a source of body inertias (so that the generator
//! can read them as parameters), the joint inputs and a workspace of one [`BodyState`] per
//! body, and checks every length first.

use nalgebra::Vector3;

use super::workspace::{BodyState, JointTransform};
use super::{ModelError, TreeModel};
use crate::rigid_body::scalar::{Label, Pass, Quantity, Real};
use crate::rigid_body::spatial::{ArticulatedInertia, Motion, RigidBodyInertia, Transform};

/// Where body `i`'s spatial inertia (about its frame's origin) comes from.
pub trait Inertias<S> {
    /// Body `i`'s inertia.
    fn inertia(&self, body: usize) -> RigidBodyInertia<S>;
}

impl<S, F: Fn(usize) -> RigidBodyInertia<S>> Inertias<S> for F {
    fn inertia(&self, body: usize) -> RigidBodyInertia<S> {
        self(body)
    }
}

/// The model's own inertias, as constants of the number type.
#[derive(Debug, Clone, Copy)]
pub struct ModelInertias<'a>(pub &'a TreeModel);

impl<S: Real> Inertias<S> for ModelInertias<'_> {
    fn inertia(&self, body: usize) -> RigidBodyInertia<S> {
        RigidBodyInertia::constant(&self.0.bodies()[body].inertia)
    }
}

pub(super) fn check_len<T>(model: &TreeModel, what: &'static str, values: &[T]) -> Result<(), ModelError> {
    if values.len() == model.dof() {
        Ok(())
    } else {
        Err(ModelError::Dimension { what, expected: model.dof(), got: values.len() })
    }
}

pub(super) fn subspace<S: Real>(model: &TreeModel, i: usize) -> Motion<S> {
    Motion::constant(&model.bodies()[i].subspace())
}

fn joint_label(body: usize) -> Label {
    Label { body, quantity: Quantity::Joint, component: 0 }
}

/// The base's acceleration `a_0 = −g`: gravity enters as an upward acceleration of the base.
pub(super) fn base_acceleration<S: Real>(model: &TreeModel, with_gravity: bool) -> Motion<S> {
    let gravity = if with_gravity { -model.gravity_vector() } else { Vector3::zeros() };
    Motion::constant(&Motion::new(Vector3::zeros(), gravity))
}

/// `X_i(q_i)` for every body, into the workspace.
fn place_bodies<S: Real>(model: &TreeModel, q: &[S], states: &mut [BodyState<S>]) {
    for (i, body) in model.bodies().iter().enumerate() {
        states[i].transform = JointTransform::new(i, body, q[i]);
    }
}

/// Leaves first: `out_i = project(i, f_i)`, then `f_λ += X_iᵀ f_i`.
fn project_forces<S: Real>(
    model: &TreeModel,
    states: &mut [BodyState<S>],
    out: &mut [S],
    project: impl Fn(usize, &BodyState<S>) -> S,
) {
    for (i, body) in model.bodies().iter().enumerate().rev() {
        S::begin_pass(i, Pass::Backward);
        states[i].force = states[i].force.labelled(i, Quantity::Force);
        out[i] = project(i, &states[i]).labelled(joint_label(i));
        if let Some(p) = body.parent {
            let carried = states[i].transform.apply_transpose_force(&states[i].force);
            states[p].force += carried;
        }
    }
}

/// The recursive Newton-Euler algorithm; `None` rates are zero, and without gravity `a_0 = 0`.
///
/// ```text
/// v_i = X_i v_λ + S_i q̇_i,   a_i = X_i a_λ + S_i q̈_i + v_i ×ₘ S_i q̇_i
/// f_i = I_i a_i + v_i ×* I_i v_i,   τ_i = S_i · f_i,   f_λ += X_iᵀ f_i
/// ```
#[allow(clippy::too_many_arguments)]
fn rnea<S: Real>(
    model: &TreeModel,
    inertias: &impl Inertias<S>,
    q: &[S],
    qd: Option<&[S]>,
    qdd: Option<&[S]>,
    with_gravity: bool,
    states: &mut [BodyState<S>],
    tau: &mut [S],
) -> Result<(), ModelError> {
    check_len(model, "q", q)?;
    qd.map_or(Ok(()), |qd| check_len(model, "qd", qd))?;
    qdd.map_or(Ok(()), |qdd| check_len(model, "qdd", qdd))?;
    check_len(model, "workspace", states)?;
    check_len(model, "tau", tau)?;
    place_bodies(model, q, states);
    let base = base_acceleration(model, with_gravity);
    for (i, body) in model.bodies().iter().enumerate() {
        S::begin_pass(i, Pass::Forward);
        let s = subspace::<S>(model, i);
        let (parent_velocity, parent_acceleration) =
            body.parent.map_or((Motion::zero(), base), |p| (states[p].velocity, states[p].acceleration));
        let x = &states[i].transform;
        let joint_velocity = s * qd.map_or(S::zero(), |v| v[i]);
        let velocity = (x.apply_motion(&parent_velocity) + joint_velocity).labelled(i, Quantity::Velocity);
        let acceleration = (x.apply_motion(&parent_acceleration) + s * qdd.map_or(S::zero(), |a| a[i]))
            + velocity.cross_motion(&joint_velocity);
        let acceleration = acceleration.labelled(i, Quantity::Acceleration);
        let inertia = inertias.inertia(i);
        let force = inertia.apply(&acceleration) + velocity.cross_force(&inertia.apply(&velocity));
        let state = &mut states[i];
        (state.velocity, state.acceleration, state.force) = (velocity, acceleration, force);
    }
    project_forces(model, states, tau, |i, state| subspace::<S>(model, i).dot(&state.force));
    Ok(())
}

/// Inverse dynamics `τ = M(q) q̈ + C(q, q̇) + G(q)` by RNEA.
pub fn inverse_dynamics<S: Real>(
    model: &TreeModel,
    inertias: &impl Inertias<S>,
    (q, qd, qdd): (&[S], &[S], &[S]),
    states: &mut [BodyState<S>],
    tau: &mut [S],
) -> Result<(), ModelError> {
    rnea(model, inertias, q, Some(qd), Some(qdd), true, states, tau)
}

/// Gravity torques `G(q)`: RNEA at rest.
pub fn gravity<S: Real>(
    model: &TreeModel,
    inertias: &impl Inertias<S>,
    q: &[S],
    states: &mut [BodyState<S>],
    tau: &mut [S],
) -> Result<(), ModelError> {
    rnea(model, inertias, q, None, None, true, states, tau)
}

/// Coriolis and centripetal torques `C(q, q̇)`: RNEA without acceleration and gravity.
pub fn velocity_terms<S: Real>(
    model: &TreeModel,
    inertias: &impl Inertias<S>,
    (q, qd): (&[S], &[S]),
    states: &mut [BodyState<S>],
    tau: &mut [S],
) -> Result<(), ModelError> {
    rnea(model, inertias, q, Some(qd), None, false, states, tau)
}

/// `C_matᵀ q̇` (with `Ṁ = C_mat + C_matᵀ`), from the subtree momenta `h^C_i`:
///
/// ```text
/// h_i = I_i v_i,   h^C_λ += X_iᵀ h^C_i (leaves first),   (Cᵀq̇)_i = (v_i ×ₘ S_i) · h^C_i
/// ```
///
/// (From `ṗ = M q̈ + Ṁ q̇` for the generalized momentum `p_i = S_i · h^C_i`, whose rate is
/// `S_i · ḣ^C_i + (v_i ×ₘ S_i) · h^C_i` with `S_i · ḣ^C_i = (M q̈ + C)_i`.)
pub fn coriolis_transpose_times_velocity<S: Real>(
    model: &TreeModel,
    inertias: &impl Inertias<S>,
    (q, qd): (&[S], &[S]),
    states: &mut [BodyState<S>],
    out: &mut [S],
) -> Result<(), ModelError> {
    check_len(model, "q", q)?;
    check_len(model, "qd", qd)?;
    check_len(model, "workspace", states)?;
    check_len(model, "output", out)?;
    place_bodies(model, q, states);
    for (i, body) in model.bodies().iter().enumerate() {
        S::begin_pass(i, Pass::Forward);
        let parent_velocity = body.parent.map_or(Motion::zero(), |p| states[p].velocity);
        let velocity = states[i].transform.apply_motion(&parent_velocity) + subspace::<S>(model, i) * qd[i];
        let velocity = velocity.labelled(i, Quantity::Velocity);
        states[i].velocity = velocity;
        states[i].force = inertias.inertia(i).apply(&velocity);
    }
    project_forces(model, states, out, |i, state| state.velocity.cross_motion(&subspace(model, i)).dot(&state.force));
    Ok(())
}

/// The composite-rigid-body algorithm; `store(i, j, M_ij)` receives every entry of the lower
/// triangle of `M(q)` (`j ≤ i`) that is not structurally zero, once.
///
/// ```text
/// I^c_λ += X_iᵀ I^c_i X_i (leaves first);   F = I^c_i S_i,   M_ii = S_i · F
/// up the tree: F = X_jᵀ F, j = λ(j),   M_ij = S_j · F
/// ```
pub fn mass_matrix<S: Real>(
    model: &TreeModel,
    inertias: &impl Inertias<S>,
    q: &[S],
    states: &mut [BodyState<S>],
    mut store: impl FnMut(usize, usize, S),
) -> Result<(), ModelError> {
    check_len(model, "q", q)?;
    check_len(model, "workspace", states)?;
    place_bodies(model, q, states);
    for (i, state) in states.iter_mut().enumerate() {
        state.composite = inertias.inertia(i);
    }
    for (i, body) in model.bodies().iter().enumerate().rev() {
        S::begin_pass(i, Pass::Backward);
        if let Some(p) = body.parent {
            let carried = states[i].transform.inertia_in_parent(&states[i].composite);
            states[p].composite += carried;
        }
    }
    let bodies = model.bodies();
    for i in 0..bodies.len() {
        S::begin_pass(i, Pass::Final);
        let s = subspace::<S>(model, i);
        let mut force = states[i].composite.apply(&s);
        store(i, i, s.dot(&force));
        let mut j = i;
        while let Some(p) = bodies[j].parent {
            force = states[j].transform.apply_transpose_force(&force);
            j = p;
            store(i, j, subspace::<S>(model, j).dot(&force));
        }
    }
    Ok(())
}

/// Forward dynamics `q̈ = M(q)⁻¹ (τ − C(q, q̇) − G(q))` by the articulated-body algorithm, in
/// O(n) and without forming `M`. Afterwards each body's
/// [`joint_inertia`](BodyState::joint_inertia) `D_i` is in the workspace: all positive for a
/// physical model; a caller must check it before trusting `q̈`.
///
/// ```text
/// out:   v_i = X_i v_λ + S_i q̇_i,   c_i = v_i ×ₘ S_i q̇_i,   I^A_i = I_i,   p_i = v_i ×* I_i v_i
/// in:    U_i = I^A_i S_i,   D_i = S_i · U_i,   u_i = τ_i − S_i · p_i
///        I^A_λ += X_iᵀ (I^A_i − U_i U_iᵀ / D_i) X_i
///        p_λ   += X_iᵀ (p_i + (I^A_i − U_i U_iᵀ / D_i) c_i + U_i u_i / D_i)
/// out:   a'_i = X_i a_λ + c_i (a_0 = −g),   q̈_i = (u_i − U_i · a'_i) / D_i,   a_i = a'_i + S_i q̈_i
/// ```
pub fn forward_dynamics<S: Real>(
    model: &TreeModel,
    inertias: &impl Inertias<S>,
    (q, qd, tau): (&[S], &[S], &[S]),
    states: &mut [BodyState<S>],
    qdd: &mut [S],
) -> Result<(), ModelError> {
    check_len(model, "q", q)?;
    check_len(model, "qd", qd)?;
    check_len(model, "tau", tau)?;
    check_len(model, "workspace", states)?;
    check_len(model, "qdd", qdd)?;
    place_bodies(model, q, states);
    let bodies = model.bodies();
    for (i, body) in bodies.iter().enumerate() {
        S::begin_pass(i, Pass::Forward);
        let parent_velocity = body.parent.map_or(Motion::zero(), |p| states[p].velocity);
        let joint_velocity = subspace::<S>(model, i) * qd[i];
        let velocity =
            (states[i].transform.apply_motion(&parent_velocity) + joint_velocity).labelled(i, Quantity::Velocity);
        let inertia = inertias.inertia(i);
        let state = &mut states[i];
        state.velocity = velocity;
        // c_i waits in `acceleration` until the last pass adds X_i a_λ to it.
        state.acceleration = velocity.cross_motion(&joint_velocity);
        state.articulated = ArticulatedInertia::from(inertia);
        state.force = velocity.cross_force(&inertia.apply(&velocity));
    }
    let one = S::constant(1.0);
    for (i, body) in bodies.iter().enumerate().rev() {
        S::begin_pass(i, Pass::Backward);
        let s = subspace::<S>(model, i);
        let state = &mut states[i];
        let label = |quantity| Label { body: i, quantity, component: 0 };
        state.force = state.force.labelled(i, Quantity::Bias);
        let u = state.articulated.apply(&s).labelled(i, Quantity::InertiaTimesAxis);
        let d = s.dot(&u).labelled(label(Quantity::JointInertia));
        let joint_force = (tau[i] - s.dot(&state.force)).labelled(label(Quantity::JointForce));
        let inverse = one / d;
        (state.inertia_times_axis, state.joint_inertia, state.inverse_joint_inertia) = (u, d, inverse);
        // u_i waits in `qdd` until the last pass turns it into q̈_i.
        qdd[i] = joint_force;
        if let Some(p) = body.parent {
            let reduced = state.articulated.minus_projection(&u, inverse);
            let bias = state.force + reduced.apply(&state.acceleration) + u * (joint_force * inverse);
            let (carried_inertia, carried_bias) =
                (state.transform.articulated_in_parent(&reduced), state.transform.apply_transpose_force(&bias));
            states[p].articulated = states[p].articulated + carried_inertia;
            states[p].force += carried_bias;
        }
    }
    let base = base_acceleration(model, true);
    for (i, body) in bodies.iter().enumerate() {
        S::begin_pass(i, Pass::Final);
        let parent_acceleration = body.parent.map_or(base, |p| states[p].acceleration);
        let state = &mut states[i];
        let acceleration = state.transform.apply_motion(&parent_acceleration) + state.acceleration;
        qdd[i] = ((qdd[i] - acceleration.dot(&state.inertia_times_axis)) * state.inverse_joint_inertia)
            .labelled(joint_label(i));
        state.acceleration = (acceleration + subspace::<S>(model, i) * qdd[i]).labelled(i, Quantity::Acceleration);
    }
    Ok(())
}

/// Base frame to body `i`'s frame at `q`, for every body: `X_0i = X_0λ X_i`.
pub fn body_placements<S: Real>(
    model: &TreeModel,
    q: &[S],
    states: &mut [BodyState<S>],
    placements: &mut [Transform<S>],
) -> Result<(), ModelError> {
    check_len(model, "q", q)?;
    check_len(model, "workspace", states)?;
    check_len(model, "placements", placements)?;
    place_bodies(model, q, states);
    for (i, body) in model.bodies().iter().enumerate() {
        S::begin_pass(i, Pass::Forward);
        let step = states[i].transform.combined();
        placements[i] = body.parent.map_or(step, |p| placements[p].then(&step));
    }
    Ok(())
}
