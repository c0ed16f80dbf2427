//! Derivatives of inverse dynamics, `∂τ/∂q` and `∂τ/∂q̇`, analytically: one pass over the
//! tree in base coordinates and a sweep over joint pairs (the route of Carpentier and Mansard,
//! RSS 2018, derived here for this crate's conventions). Written once over any [`Real`]: the
//! run-time model runs it on `f64` and the code generator traces it into unrolled code.
//!
//! In one fixed frame (the base's; but see the last paragraph), with `Ŝ_i` joint `i`'s axis, `λ` a body's
//! parent and `a_0 = −g`:
//!
//! ```text
//! v_i = v_λ + Ŝ_i q̇_i      a_i = a_λ + Ŝ_i q̈_i + v_i × Ŝ_i q̇_i
//! f_i = I_i a_i + v_i ×* I_i v_i      τ_i = Ŝ_i · F_i,   F_i = Σ_{k ⪰ i} f_k
//! ```
//!
//! Moving joint `j` turns its subtree: `∂Ŝ_k/∂q_j = Ŝ_j × Ŝ_k` and `∂I_k/∂q_j = Ŝ_j ×* I_k − I_k Ŝ_j×`
//! for every `k ⪰ j`, while what lies above `j` stays. Differentiating the sums, with
//! `δv_j = v_λ(j) × Ŝ_j`:
//!
//! ```text
//! ∂v_k/∂q_j = Ŝ_j × v_k + δv_j                       ∂v_k/∂q̇_j = Ŝ_j
//! ∂a_k/∂q_j = Ŝ_j × a_k + α_j − v_k × δv_j           ∂a_k/∂q̇_j = γ_j − v_k × Ŝ_j
//! α_j = a_λ(j) × Ŝ_j + v_λ(j) × δv_j                 γ_j = 2 δv_j
//! ```
//!
//! so that `∂f_k/∂q_j = Ŝ_j ×* f_k + I_k α_j + İ_k δv_j + δv_j ×* h_k` and
//! `∂f_k/∂q̇_j = I_k γ_j + İ_k Ŝ_j + Ŝ_j ×* h_k`, with `h_k = I_k v_k` the body's momentum and
//! `İ_k = v_k ×* I_k − I_k v_k×` its inertia's rate ([`RigidBodyInertia::rate`]). Summed over
//! subtrees (composites `I^C`, `İ^C`, `H`, `F`), and using `Ŝ_i · (m ×* f) = −(m × Ŝ_i) · f`:
//!
//! ```text
//! i ⪰ j:   ∂τ_i/∂q_j = α_j · P_i + δv_j · Q_i        ∂τ_i/∂q̇_j = γ_j · P_i + Ŝ_j · Q_i
//! i ≺ j:   ∂τ_i/∂q_j = Ŝ_i · (Ŝ_j ×* F_j + I^C_j α_j + İ^C_j δv_j + δv_j ×* H_j)
//!          ∂τ_i/∂q̇_j = Ŝ_i · (I^C_j γ_j + İ^C_j Ŝ_j + Ŝ_j ×* H_j)
//! P_i = I^C_i Ŝ_i,   Q_i = İ^C_i Ŝ_i − Ŝ_i ×* H_i
//! ```
//!
//! and zero where neither joint is above the other. The cost is one pass over the bodies and
//! six-vector products per pair of related joints, against `2n` runs of RNEA for forward-mode
//! dual numbers (the tests keep that route, [`Dual`](crate::rigid_body::dual::Dual), as the
//! independent check).
//!
//! Every term above is a product of vectors and inertias all in one frame, so the value is
//! the same in any frame, including one that moves with `q` at the `q` it is taken at. A tree
//! with one root is worked in that root body's frame: gravity enters as `a_0 = X_root(q_root) (−g)`,
//! and the root joint's rotation, which no torque depends on where it turns about gravity,
//! folds away in generated code instead of turning every vector (30 % fewer operations on HyA).

use super::algorithms::{base_acceleration, check_len, subspace, Inertias};
use super::workspace::JointTransform;
use super::{ModelError, TreeModel};
use crate::rigid_body::scalar::{Pass, Real};
use crate::rigid_body::spatial::{Force, Motion, RigidBodyInertia, Transform};

/// What the derivative pass keeps for one body, in the frame the pass works in.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DerivativeState<S = f64> {
    placement: Transform<S>,
    /// `Ŝ_i`.
    axis: Motion<S>,
    velocity: Motion<S>,
    acceleration: Motion<S>,
    /// `I_i`, then the composite `I^C_i`.
    inertia: RigidBodyInertia<S>,
    /// `İ_i`, then `İ^C_i`.
    inertia_rate: RigidBodyInertia<S>,
    /// `h_i`, then `H_i`.
    momentum: Force<S>,
    /// `f_i`, then `F_i`.
    force: Force<S>,
    /// `P_i = I^C_i Ŝ_i`.
    axis_inertia: Force<S>,
    /// `Q_i = İ^C_i Ŝ_i − Ŝ_i ×* H_i`.
    axis_rate: Force<S>,
}

impl<S: Real> DerivativeState<S> {
    /// Scratch space holding zeros.
    pub fn new() -> Self {
        Self {
            placement: Transform::identity(),
            axis: Motion::zero(),
            velocity: Motion::zero(),
            acceleration: Motion::zero(),
            inertia: RigidBodyInertia::zero(),
            inertia_rate: RigidBodyInertia::zero(),
            momentum: Force::zero(),
            force: Force::zero(),
            axis_inertia: Force::zero(),
            axis_rate: Force::zero(),
        }
    }
}

impl<S: Real> Default for DerivativeState<S> {
    fn default() -> Self {
        Self::new()
    }
}

/// Whether body `ancestor` is `body` or lies on its path to the base.
fn supports(model: &TreeModel, ancestor: usize, body: usize) -> bool {
    let mut next = Some(body);
    while let Some(k) = next {
        if k == ancestor {
            return true;
        }
        next = model.bodies()[k].parent;
    }
    false
}

/// `τ = ID(q, q̇, q̈)`, `∂τ/∂q` and `∂τ/∂q̇` (both `n x n`, row-major: row `i` is `∂τ_i`), by the
/// analytic pass of the module's notes. `states` holds one [`DerivativeState`] per body.
pub fn inverse_dynamics_derivatives<S: Real>(
    model: &TreeModel,
    inertias: &impl Inertias<S>,
    (q, qd, qdd): (&[S], &[S], &[S]),
    states: &mut [DerivativeState<S>],
    tau: &mut [S],
    (d_dq, d_dqd): (&mut [S], &mut [S]),
) -> Result<(), ModelError> {
    let n = model.dof();
    for (what, x) in [("q", q), ("qd", qd), ("qdd", qdd), ("tau", &*tau)] {
        check_len(model, what, x)?;
    }
    check_len(model, "workspace", states)?;
    for (what, m) in [("d_dq", &*d_dq), ("d_dqd", &*d_dqd)] {
        if m.len() != n * n {
            return Err(ModelError::Dimension { what, expected: n * n, got: m.len() });
        }
    }
    // The sums hold in any one frame. A tree with one root (body 0, parents coming first) is
    // worked in that body's frame rather than the base's: no torque depends on how the root
    // joint turns the whole tree about gravity, and in its own frame that rotation folds away.
    let root_frame = model.bodies().iter().filter(|b| b.parent.is_none()).count() == 1;
    let gravity = base_acceleration::<S>(model, true);
    let base = if root_frame {
        JointTransform::new(0, &model.bodies()[0], q[0]).combined().apply_motion(&gravity)
    } else {
        gravity
    };
    // The parent's velocity and acceleration, `(v_λ, a_λ)`.
    let above = |states: &[DerivativeState<S>], i: usize| {
        model.bodies()[i].parent.map_or((Motion::zero(), base), |p| (states[p].velocity, states[p].acceleration))
    };
    for (i, body) in model.bodies().iter().enumerate() {
        S::begin_pass(i, Pass::Forward);
        let placement = match body.parent {
            Some(p) => states[p].placement.then(&JointTransform::new(i, body, q[i]).combined()),
            None if root_frame => Transform::identity(),
            None => JointTransform::new(i, body, q[i]).combined(),
        };
        let axis = placement.apply_inverse_motion(&subspace(model, i));
        let (parent_velocity, parent_acceleration) = above(states, i);
        let joint_velocity = axis * qd[i];
        let velocity = parent_velocity + joint_velocity;
        let acceleration = parent_acceleration + axis * qdd[i] + velocity.cross_motion(&joint_velocity);
        let inertia = inertias.inertia(i).expressed_in_parent(&placement);
        let momentum = inertia.apply(&velocity);
        let force = inertia.apply(&acceleration) + velocity.cross_force(&momentum);
        let inertia_rate = inertia.rate(&velocity);
        let zero = Force::zero();
        states[i] = DerivativeState {
            placement,
            axis,
            velocity,
            acceleration,
            inertia,
            inertia_rate,
            momentum,
            force,
            axis_inertia: zero,
            axis_rate: zero,
        };
    }
    for (i, body) in model.bodies().iter().enumerate().rev() {
        S::begin_pass(i, Pass::Backward);
        let state = &mut states[i];
        tau[i] = state.axis.dot(&state.force);
        state.axis_inertia = state.inertia.apply(&state.axis);
        state.axis_rate = state.inertia_rate.apply(&state.axis) - state.axis.cross_force(&state.momentum);
        let state = *state;
        if let Some(p) = body.parent {
            let parent = &mut states[p];
            parent.inertia += state.inertia;
            parent.inertia_rate += state.inertia_rate;
            parent.momentum += state.momentum;
            parent.force += state.force;
        }
    }
    d_dq.fill(S::zero());
    d_dqd.fill(S::zero());
    for j in 0..n {
        S::begin_pass(j, Pass::Final);
        let (parent_velocity, parent_acceleration) = above(states, j);
        let sj = states[j];
        let dv = parent_velocity.cross_motion(&sj.axis);
        let alpha = parent_acceleration.cross_motion(&sj.axis) + parent_velocity.cross_motion(&dv);
        let gamma = dv + dv;
        // `∂F_j/∂q_j` and `∂F_j/∂q̇_j`: what joint `j`'s ancestors feel.
        let by_q = sj.axis.cross_force(&sj.force)
            + sj.inertia.apply(&alpha)
            + sj.inertia_rate.apply(&dv)
            + dv.cross_force(&sj.momentum);
        let by_qd = sj.inertia.apply(&gamma) + sj.inertia_rate.apply(&sj.axis) + sj.axis.cross_force(&sj.momentum);
        for i in 0..n {
            let si = &states[i];
            let (dq, dqd) = if supports(model, j, i) {
                let (p, q_i) = (&si.axis_inertia, &si.axis_rate);
                (alpha.dot(p) + dv.dot(q_i), gamma.dot(p) + sj.axis.dot(q_i))
            } else if supports(model, i, j) {
                (si.axis.dot(&by_q), si.axis.dot(&by_qd))
            } else {
                continue;
            };
            (d_dq[i * n + j], d_dqd[i * n + j]) = (dq, dqd);
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use alloc::vec;
    use alloc::vec::Vec;

    use nalgebra::{Matrix3, Vector3};

    use super::*;
    use crate::rigid_body::dual::Dual;
    use crate::rigid_body::model::algorithms::{self, ModelInertias};
    use crate::rigid_body::model::{Body, BodyState, Frame, JointKind, JointLimits};
    use crate::rigid_body::spatial::roll_pitch_yaw;

    /// A branching tree with both joint kinds, skewed axes, offset centres of mass and inertias
    /// that are not diagonal: body 0 carries two branches (1–2–3 and 4–5), 3 is prismatic; with
    /// `two_roots`, branch 4–5 hangs from the base instead.
    fn branching_tree(two_roots: bool) -> TreeModel {
        let body = |k: usize, parent: Option<usize>, kind: JointKind, axis: Vector3<f64>| {
            let f = k as f64;
            let rotation = roll_pitch_yaw(&Vector3::new(0.3 * f, -0.2 + 0.1 * f, 0.7 - 0.2 * f));
            let about_com = Matrix3::new(0.3, 0.01, -0.02, 0.01, 0.25, 0.03, -0.02, 0.03, 0.2) * (1.0 + 0.1 * f);
            Body {
                link: alloc::format!("link{k}"),
                joint: alloc::format!("joint{k}"),
                parent,
                kind,
                axis: axis.normalize(),
                tree_transform: Transform::from_pose(rotation, Vector3::new(0.1 + 0.05 * f, -0.2, 0.3 - 0.04 * f)),
                inertia: RigidBodyInertia::from_centre_of_mass(
                    2.0 + f,
                    Vector3::new(0.05 * f, 0.1 - 0.02 * f, 0.15),
                    about_com,
                ),
                limits: JointLimits::default(),
            }
        };
        let revolute = JointKind::Revolute;
        let bodies = vec![
            body(0, None, revolute, Vector3::z()),
            body(1, Some(0), revolute, Vector3::new(0.2, 1.0, -0.1)),
            body(2, Some(1), revolute, Vector3::new(1.0, 0.3, 0.2)),
            body(3, Some(2), JointKind::Prismatic, Vector3::new(0.1, -0.4, 1.0)),
            body(4, (!two_roots).then_some(0), revolute, Vector3::new(-0.5, 0.2, 1.0)),
            body(5, Some(4), revolute, Vector3::x()),
        ];
        let frame = Frame { name: "tip".into(), body: Some(5), placement: Transform::default() };
        TreeModel::new("branching", bodies, vec![frame]).unwrap()
    }

    /// `(τ, ∂τ/∂q, ∂τ/∂q̇)` by forward-mode dual numbers: RNEA once per seeded direction.
    fn by_dual_numbers(model: &TreeModel, (q, qd, qdd): (&[f64], &[f64], &[f64])) -> [Vec<f64>; 3] {
        let n = model.dof();
        let (mut tau, mut by_q, mut by_qd) = (vec![0.0; n], vec![0.0; n * n], vec![0.0; n * n]);
        let inertias = |b: usize| {
            let fixed: RigidBodyInertia<Dual<f64>> = RigidBodyInertia::constant(&model.bodies()[b].inertia);
            fixed
        };
        for j in 0..2 * n {
            let seed = |x: &[f64], k: usize, seeded: bool| {
                if seeded {
                    Dual::variable(x[k])
                } else {
                    Dual::fixed(x[k])
                }
            };
            let dq: Vec<_> = (0..n).map(|k| seed(q, k, j == k)).collect();
            let dqd: Vec<_> = (0..n).map(|k| seed(qd, k, j == n + k)).collect();
            let dqdd: Vec<_> = (0..n).map(|k| seed(qdd, k, false)).collect();
            let mut out = vec![Dual::fixed(0.0); n];
            algorithms::inverse_dynamics(
                model,
                &inertias,
                (&dq, &dqd, &dqdd),
                &mut vec![BodyState::new(); n],
                &mut out,
            )
            .unwrap();
            let matrix = if j < n { &mut by_q } else { &mut by_qd };
            for (i, d) in out.iter().enumerate() {
                tau[i] = d.value;
                matrix[i * n + j % n] = d.tangent;
            }
        }
        [tau, by_q, by_qd]
    }

    #[test]
    fn the_analytic_pass_equals_dual_numbers_on_branching_trees_with_one_root_and_two() {
        for (case, two_roots) in (0..6).map(|case| (case, case % 2 == 1)) {
            let model = branching_tree(two_roots).with_gravity(Vector3::new(0.3, -0.2, -9.81));
            let n = model.dof();
            let c = case as f64;
            let x = |k: usize, scale: f64| scale * ((1.7 * k as f64 + 0.9 * c).sin() + 0.3 * c);
            let q: Vec<f64> = (0..n).map(|k| x(k, 1.1)).collect();
            let qd: Vec<f64> = (0..n).map(|k| x(k + 3, 2.3)).collect();
            let qdd: Vec<f64> = (0..n).map(|k| x(k + 7, 4.1)).collect();
            let (mut tau, mut by_q, mut by_qd) = (vec![0.0; n], vec![0.0; n * n], vec![0.0; n * n]);
            inverse_dynamics_derivatives(
                &model,
                &ModelInertias(&model),
                (&q, &qd, &qdd),
                &mut vec![DerivativeState::new(); n],
                &mut tau,
                (&mut by_q, &mut by_qd),
            )
            .unwrap();
            let [tau_ref, by_q_ref, by_qd_ref] = by_dual_numbers(&model, (&q, &qd, &qdd));
            for (name, got, want) in
                [("tau", &tau, &tau_ref), ("d_dq", &by_q, &by_q_ref), ("d_dqd", &by_qd, &by_qd_ref)]
            {
                let scale = want.iter().fold(1.0f64, |m, x| m.max(x.abs()));
                for (k, (g, w)) in got.iter().zip(want.iter()).enumerate() {
                    assert!((g - w).abs() <= 1e-12 * scale, "case {case}, {name}[{k}]: {g} against dual {w}");
                }
            }
        }
    }

    #[test]
    fn an_unrelated_pair_of_joints_has_no_derivative_and_lengths_are_checked() {
        let model = branching_tree(false);
        let n = model.dof();
        let x = vec![0.4; n];
        let (mut tau, mut by_q, mut by_qd) = (vec![0.0; n], vec![1.0; n * n], vec![1.0; n * n]);
        let mut states = vec![DerivativeState::new(); n];
        let inertias = ModelInertias(&model);
        inverse_dynamics_derivatives(&model, &inertias, (&x, &x, &x), &mut states, &mut tau, (&mut by_q, &mut by_qd))
            .unwrap();
        // Joints 2 and 5 sit on different branches.
        assert_eq!((by_q[2 * n + 5], by_qd[5 * n + 2]), (0.0, 0.0));
        let short = vec![0.0; n - 1];
        let result = inverse_dynamics_derivatives(
            &model,
            &inertias,
            (&x, &short, &x),
            &mut states,
            &mut tau,
            (&mut by_q, &mut by_qd),
        );
        assert!(matches!(result, Err(ModelError::Dimension { what: "qd", .. })));
    }
}
