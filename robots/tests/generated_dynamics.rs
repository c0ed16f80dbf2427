//! Generated dynamics of every shipped robot against the generic tree model loaded from the same
//! URDF at run time, and the laws every rigid-body model obeys.
#![allow(clippy::unwrap_used)] // test helpers: a failed unwrap is a failed test

use hya_core::model::{TreeDynamics, TreeModel};
use hya_core::spatial::RigidBodyInertia;
use hya_core::{Dynamics, JointMatrix, JointVector};
use proptest::prelude::*;

/// `|a − b| ≤ tol · max(|b|, floor)` entrywise.
fn close<const R: usize, const C: usize>(
    a: &nalgebra::SMatrix<f64, R, C>,
    b: &nalgebra::SMatrix<f64, R, C>,
    tol: f64,
    floor: f64,
) -> bool {
    a.iter().zip(b.iter()).all(|(x, y)| (x - y).abs() <= tol * y.abs().max(floor))
}

fn generic<const N: usize>(urdf: &str) -> TreeDynamics<N> {
    hya_urdf::load_str(urdf, "test").unwrap().model.into_dynamics().unwrap()
}

/// `(q, q̇, q̈ or τ)`.
type State<const N: usize> = (JointVector<N>, JointVector<N>, JointVector<N>);

fn state<const N: usize>() -> impl Strategy<Value = State<N>> {
    let vector = |bound: f64| proptest::array::uniform::<_, N>(-bound..bound).prop_map(JointVector::from);
    (vector(std::f64::consts::PI), vector(2.0), vector(5.0))
}

/// `Ṁ` along `q̇` by central differences.
fn mass_matrix_rate<const N: usize>(d: &impl Dynamics<N>, q: &JointVector<N>, qd: &JointVector<N>) -> JointMatrix<N> {
    let h = 1e-6;
    (d.mass_matrix(&(q + qd * h)) - d.mass_matrix(&(q - qd * h))) / (2.0 * h)
}

fn check_against_generic<const N: usize>(
    generated: &impl Dynamics<N>,
    generic: &TreeDynamics<N>,
    (q, qd, qdd): (JointVector<N>, JointVector<N>, JointVector<N>),
) -> Result<(), TestCaseError> {
    let (tol, floor) = (1e-12, 1.0);
    prop_assert!(close(
        &generated.inverse_dynamics(&q, &qd, &qdd),
        &generic.inverse_dynamics(&q, &qd, &qdd),
        tol,
        floor
    ));
    prop_assert!(close(&generated.gravity(&q), &generic.gravity(&q), tol, floor));
    prop_assert!(close(&generated.velocity_terms(&q, &qd), &generic.velocity_terms(&q, &qd), tol, floor));
    prop_assert!(close(&generated.mass_matrix(&q), &generic.mass_matrix(&q), tol, floor));
    prop_assert!(close(
        &generated.coriolis_transpose_times_velocity(&q, &qd),
        &generic.coriolis_transpose_times_velocity(&q, &qd),
        tol,
        floor
    ));
    let tau = generic.inverse_dynamics(&q, &qd, &qdd);
    prop_assert!(close(
        &generated.forward_dynamics(&q, &qd, &tau).unwrap(),
        &generic.forward_dynamics(&q, &qd, &tau).unwrap(),
        1e-9,
        floor
    ));
    let (by_q, by_qd) = generated.inverse_dynamics_derivatives(&q, &qd, &qdd);
    let (generic_by_q, generic_by_qd) = generic.inverse_dynamics_derivatives(&q, &qd, &qdd);
    prop_assert!(close(&by_q, &generic_by_q, tol, floor) && close(&by_qd, &generic_by_qd, tol, floor));
    Ok(())
}

fn check_laws<const N: usize>(
    d: &impl Dynamics<N>,
    (q, qd, qdd): (JointVector<N>, JointVector<N>, JointVector<N>),
) -> Result<(), TestCaseError> {
    let zero = JointVector::zeros();
    let m = d.mass_matrix(&q);
    prop_assert!(close(&m, &m.transpose(), 1e-14, 1.0), "M not symmetric");
    prop_assert!(m.cholesky().is_some(), "M not positive definite");
    let g = d.gravity(&q);
    prop_assert!(close(&d.inverse_dynamics(&q, &zero, &zero), &g, 1e-12, 1.0));
    prop_assert!(close(&(d.inverse_dynamics(&q, &zero, &qdd) - g), &(m * qdd), 1e-10, 1.0));
    let tau = d.inverse_dynamics(&q, &qd, &qdd);
    let qdd_back = d.forward_dynamics(&q, &qd, &tau).unwrap();
    prop_assert!(close(&d.inverse_dynamics(&q, &qd, &qdd_back), &tau, 1e-9, 1.0), "ID(FD(τ)) ≠ τ");
    let c = d.velocity_terms(&q, &qd);
    let m_dot = mass_matrix_rate(d, &q, &qd);
    let ct = d.coriolis_transpose_times_velocity(&q, &qd);
    prop_assert!(close(&(m_dot * qd), &(c + ct), 1e-6, 1.0), "Ṁq̇ ≠ C + Cᵀq̇");
    prop_assert!((qd.dot(&(m_dot * qd)) - 2.0 * qd.dot(&c)).abs() <= 1e-6 * c.norm().max(1.0), "q̇ᵀṀq̇ ≠ 2q̇ᵀC");
    Ok(())
}

/// Every batch entry point against the single call on each state, bit for bit: the batch runs
/// on lanes of the vector unit where the CPU has it and FMA, each lane with the single call's
/// fused arithmetic (the same operations, `sin` and `cos` included), and on the single call
/// itself elsewhere. The states' count is not a multiple of the lanes, so a short last step is
/// exercised.
fn check_batches<const N: usize>(
    d: &impl Dynamics<N>,
    states: &[(JointVector<N>, JointVector<N>, JointVector<N>)],
) -> Result<(), TestCaseError> {
    let n = states.len();
    let q: Vec<_> = states.iter().map(|s| s.0).collect();
    let qd: Vec<_> = states.iter().map(|s| s.1).collect();
    let qdd: Vec<_> = states.iter().map(|s| s.2).collect();
    let (mut tau, mut g, mut fd) =
        (vec![JointVector::zeros(); n], vec![JointVector::zeros(); n], vec![JointVector::zeros(); n]);
    let (mut m, mut by_q, mut by_qd) =
        (vec![JointMatrix::zeros(); n], vec![JointMatrix::zeros(); n], vec![JointMatrix::zeros(); n]);
    d.inverse_dynamics_batch(&q, &qd, &qdd, &mut tau).unwrap();
    d.gravity_batch(&q, &mut g).unwrap();
    d.mass_matrix_batch(&q, &mut m).unwrap();
    d.forward_dynamics_batch(&q, &qd, &tau, &mut fd).unwrap();
    d.inverse_dynamics_derivatives_batch(&q, &qd, &qdd, &mut by_q, &mut by_qd).unwrap();
    for k in 0..n {
        prop_assert_eq!(tau[k], d.inverse_dynamics(&q[k], &qd[k], &qdd[k]), "ID, state {}", k);
        prop_assert_eq!(g[k], d.gravity(&q[k]), "G, state {}", k);
        prop_assert_eq!(m[k], d.mass_matrix(&q[k]), "M, state {}", k);
        prop_assert_eq!(fd[k], d.forward_dynamics(&q[k], &qd[k], &tau[k]).unwrap(), "FD, state {}", k);
        prop_assert_eq!(
            (by_q[k], by_qd[k]),
            d.inverse_dynamics_derivatives(&q[k], &qd[k], &qdd[k]),
            "∂ID, state {}",
            k
        );
    }
    let mut short = vec![JointVector::zeros(); n + 1];
    prop_assert!(d.inverse_dynamics_batch(&q, &qd, &qdd, &mut short).is_err(), "lengths that differ are refused");
    // The forward-dynamics derivatives over more states than one chunk, the states cycled.
    let many = 2 * hya_core::dynamics::DERIVATIVE_CHUNK + 3;
    let cycled = |v: &[JointVector<N>]| (0..many).map(|k| v[k % n]).collect::<Vec<_>>();
    let (q, qd, tau) = (cycled(&q), cycled(&qd), cycled(&tau));
    let mut outputs =
        [vec![JointMatrix::zeros(); many], vec![JointMatrix::zeros(); many], vec![JointMatrix::zeros(); many]];
    let [by_q, by_qd, inverse] = &mut outputs;
    d.forward_dynamics_derivatives_batch(&q, &qd, &tau, (by_q, by_qd, inverse)).unwrap();
    for k in 0..many {
        let single = d.forward_dynamics_derivatives(&q[k], &qd[k], &tau[k]).unwrap();
        prop_assert_eq!((by_q[k], by_qd[k], inverse[k]), single, "∂FD, state {}", k);
    }
    Ok(())
}

/// The model with every body's mass, centre of mass and rotational inertia scaled by `factors`
/// (cycled), physically consistent.
fn perturbed(model: &TreeModel, factors: &[f64]) -> TreeModel {
    let mut k = 0;
    let mut next = || {
        k += 1;
        factors[k % factors.len()]
    };
    model.map_inertias(|_, inertia| {
        let (mass, com, about_com) = inertia.centre_of_mass_form().expect("shipped bodies have mass");
        RigidBodyInertia::from_centre_of_mass(mass * next(), com.map(|c| c * next()), about_com * next())
    })
}

/// `BodiesBatch` against the parametric twin of each state's own bodies, bit for bit (as
/// [`check_batches`]); a singular state's error is the batch's too.
fn check_bodies_batch<const N: usize, P: Dynamics<N>>(
    batch: &impl hya_core::BodiesBatch<N>,
    twin: impl Fn(&[RigidBodyInertia; N]) -> P,
    states: &[(State<N>, [RigidBodyInertia; N])],
) -> Result<(), TestCaseError> {
    let n = states.len();
    let q: Vec<_> = states.iter().map(|s| s.0 .0).collect();
    let qd: Vec<_> = states.iter().map(|s| s.0 .1).collect();
    let tau: Vec<_> = states.iter().map(|s| s.0 .2).collect();
    let columns: Vec<_> =
        states.iter().map(|s| hya_core::bodies_batch::body_columns(&s.1.map(|b| b.parameters()))).collect();
    let by_parameter: [Vec<JointVector<N>>; 10] = core::array::from_fn(|p| columns.iter().map(|c| c[p]).collect());
    let bodies: hya_core::BodyColumns<N> = core::array::from_fn(|p| by_parameter[p].as_slice());
    let mut qdd = vec![JointVector::zeros(); n];
    batch.forward_dynamics_of_bodies_batch(bodies, &q, &qd, &tau, &mut qdd).unwrap();
    for (k, state) in states.iter().enumerate() {
        let single = twin(&state.1).forward_dynamics(&q[k], &qd[k], &tau[k]).unwrap();
        prop_assert_eq!(qdd[k], single, "state {}", k);
    }
    let mut short = vec![JointVector::zeros(); n + 1];
    prop_assert!(batch.forward_dynamics_of_bodies_batch(bodies, &q, &qd, &tau, &mut short).is_err(), "lengths differ");
    // A massless, inertia-free arm has no articulated inertia: refused, not divided by.
    let empty = [JointVector::zeros(); 10];
    let singular: hya_core::BodyColumns<N> = core::array::from_fn(|p| core::slice::from_ref(&empty[p]));
    let refused = batch.forward_dynamics_of_bodies_batch(singular, &q[..1], &qd[..1], &tau[..1], &mut qdd[..1]);
    prop_assert_eq!(refused, Err(hya_core::Error::SingularMassMatrix));
    Ok(())
}

macro_rules! robot_tests {
    ($($module:ident $type:ident $parametric:ident $dof:literal [$($home:expr),*] $doc:literal;)*) => {$(
        mod $module {
            use super::*;
            use hya_robots::$module::{$parametric, $type, URDF};

            proptest! {
                #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

                #[test]
                fn generated_equals_generic(s in state::<$dof>()) {
                    check_against_generic(&$type, &generic::<$dof>(URDF), s)?;
                }

                #[test]
                fn batches_equal_single_calls(states in proptest::collection::vec(state::<$dof>(), 1..11)) {
                    check_batches(&$type, &states)?;
                    let model = hya_urdf::load_str(URDF, "test").unwrap().model;
                    let inertias: [RigidBodyInertia; $dof] = core::array::from_fn(|i| model.bodies()[i].inertia);
                    check_batches(&$parametric::new(&inertias), &states)?;
                }

                #[test]
                fn bodies_batch_equals_each_states_own_twin(
                    states in proptest::collection::vec((state::<$dof>(), proptest::collection::vec(0.8..1.2f64, 7)), 1..11),
                ) {
                    let model = hya_urdf::load_str(URDF, "test").unwrap().model;
                    let states: Vec<_> = states
                        .into_iter()
                        .map(|(s, factors)| {
                            let bodies = perturbed(&model, &factors);
                            (s, core::array::from_fn(|i| bodies.bodies()[i].inertia))
                        })
                        .collect();
                    check_bodies_batch(&$parametric([[0.0; 10]; $dof]), |b| $parametric::new(b), &states)?;
                }

                #[test]
                fn generated_obeys_the_laws(s in state::<$dof>()) {
                    check_laws(&$type, s)?;
                }

                #[test]
                fn generic_obeys_the_laws(s in state::<$dof>()) {
                    check_laws(&generic::<$dof>(URDF), s)?;
                }

                #[test]
                fn generated_frame_poses_equal_the_generic_model(s in state::<$dof>()) {
                    let model = hya_urdf::load_str(URDF, "test").unwrap().model;
                    let poses = $type.frame_poses(&s.0);
                    prop_assert_eq!($type::FRAME_NAMES.len(), model.frames().len());
                    for (name, pose) in $type::FRAME_NAMES.iter().zip(&poses) {
                        let expected = model.frame_pose(name, s.0.as_slice()).unwrap();
                        prop_assert!(close(&pose.rotation, &expected.rotation, 1e-12, 1.0), "{} rotation", name);
                        prop_assert!(close(&pose.translation, &expected.translation, 1e-12, 1.0), "{} origin", name);
                    }
                }

                #[test]
                fn parametric_equals_generic_for_perturbed_inertias(
                    s in state::<$dof>(),
                    factors in proptest::collection::vec(0.8..1.2f64, 7),
                ) {
                    let model = perturbed(&hya_urdf::load_str(URDF, "test").unwrap().model, &factors);
                    let inertias: [RigidBodyInertia; $dof] = core::array::from_fn(|i| model.bodies()[i].inertia);
                    let parametric = $parametric::new(&inertias);
                    check_against_generic(&parametric, &model.into_dynamics().unwrap(), s)?;
                }
            }
        }
    )*};
}

hya_robots::for_each_robot!(robot_tests);

#[test]
fn a_shipped_arms_dynamics_is_found_by_name_at_its_own_joint_count_only() {
    let q = JointVector::<6>::from([0.1, -0.4, 0.7, 0.2, -0.3, 0.5]);
    let found = hya_robots::nominal::<6>("ur5").unwrap_or_else(|| panic!("ur5 has 6 joints"));
    assert_eq!(found.gravity(&q), hya_robots::ur5::Ur5.gravity(&q));
    assert!(hya_robots::nominal::<7>("ur5").is_none(), "ur5 as 7 joints");
    assert!(hya_robots::nominal::<6>("ur6").is_none(), "no arm called ur6");
}
