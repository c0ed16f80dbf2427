//! The generator's output is pinned by small golden files, one per feature of the generator
//! (`tests/golden/<feature>.urdf`: a prismatic joint, off-axis joints, a fixed-joint merge, a
//! branched tree, a massless link; and `planar2`, the teaching example), so that a change to
//! the generator shows up in review as a diff a reviewer can read. HyA is pinned by its
//! operation counts and size (`hya.stats`, what `hya generate --stats` prints), not by its text.
//! After a deliberate change: `UPDATE_GOLDEN=1 cargo test -p hya-codegen --test golden`, then
//! read the diff.
//!
//! The golden files are also compiled here, in a crate that denies unused variables (every
//! statement generated is read) and `unsafe` (the one `unsafe` call lives in `hya_core`), and
//! checked against the run-time model (itself checked against Pinocchio by the workspace tests),
//! single calls and batches alike.
#![allow(clippy::unwrap_used)] // test helpers: a failed unwrap is a failed test
#![forbid(unsafe_code)]
#![deny(unused_variables, unused_assignments)]

use std::path::PathBuf;

use hya_core::model::TreeModel;
use hya_core::{Dynamics, FrameJacobian, FrameKinematics, FrameVector, JointMatrix, JointVector};

#[allow(dead_code)] // the constants each type carries, not all read here
mod compiled {
    include!("golden/planar2.rs");
    include!("golden/prismatic.rs");
    include!("golden/off_axis.rs");
    include!("golden/fixed_merge.rs");
    include!("golden/branched.rs");
    include!("golden/massless.rs");
}

/// `(file stem, type name)` of each feature's golden input.
const FEATURES: [(&str, &str); 5] = [
    ("prismatic", "Prismatic"),
    ("off_axis", "OffAxis"),
    ("fixed_merge", "FixedMerge"),
    ("branched", "Branched"),
    ("massless", "Massless"),
];

/// Source bytes HyA's generated dynamics may take (the budget; 1.5 MB before the
/// functions were written once over `hya_core::Arithmetic`).
const HYA_SOURCE_BUDGET: usize = 600_000;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn load(path: &str) -> hya_urdf::LoadedModel {
    hya_urdf::load_file(root().join(path)).unwrap()
}

/// Compares `text` with the golden file `name`, rewriting it first under `UPDATE_GOLDEN`.
fn check_golden(name: &str, text: &str) {
    let golden = root().join("tests/golden").join(name);
    if std::env::var_os("UPDATE_GOLDEN").is_some() {
        std::fs::write(&golden, text).unwrap();
    }
    let expected = std::fs::read_to_string(&golden).unwrap();
    assert!(text == expected, "generated code differs from {}; see the module docs", golden.display());
}

#[test]
fn generated_sources_match_the_golden_files() {
    check_golden("planar2.rs", &hya_codegen::generate(&load("../robots/urdf/planar2.urdf"), "Planar2").unwrap().source);
    for (feature, type_name) in FEATURES {
        let loaded = load(&format!("tests/golden/{feature}.urdf"));
        check_golden(&format!("{feature}.rs"), &hya_codegen::generate(&loaded, type_name).unwrap().source);
    }
}

#[test]
fn hya_is_pinned_by_its_operation_counts_and_size() {
    let hya = load("../robots/urdf/hya.urdf");
    let fixed = hya_codegen::generate(&hya, "Hya").unwrap();
    let parametric = hya_codegen::generate_parametric(&hya, "HyaParametric").unwrap();
    let stats = format!(
        "Hya: {} bytes\n{}\nHyaParametric: {} bytes\n{}",
        fixed.source.len(),
        fixed.stats_table(),
        parametric.source.len(),
        parametric.stats_table()
    );
    check_golden("hya.stats", &stats);
    assert!(fixed.source.len() <= HYA_SOURCE_BUDGET, "HyA's generated source is {} bytes", fixed.source.len());
}

#[test]
fn generation_is_deterministic() {
    let planar2 = load("../robots/urdf/planar2.urdf");
    assert_eq!(
        hya_codegen::generate(&planar2, "Planar2").unwrap().source,
        hya_codegen::generate(&planar2, "Planar2").unwrap().source
    );
}

/// `|a − b| ≤ 1e-12 · max(|b|, 1)` entrywise.
fn close(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| (x - y).abs() <= 1e-12 * y.abs().max(1.0))
}

/// A few states of `N` joints, varied in every joint.
fn states<const N: usize>() -> Vec<(JointVector<N>, JointVector<N>, JointVector<N>)> {
    (0..7)
        .map(|k| {
            let f = |scale: f64, phase: f64| {
                JointVector::<N>::from_fn(|i, _| scale * (1.3 * k as f64 + phase * i as f64 + 0.2).sin())
            };
            (f(1.2, 0.7), f(0.8, 1.9), f(2.0, 2.3))
        })
        .collect()
}

/// The generated `d` against the run-time `model` on single calls, and its batches against
/// its single calls.
fn check<const N: usize>(
    d: &(impl Dynamics<N> + FrameKinematics<N>),
    model: &TreeModel,
    frame_poses: impl Fn(&JointVector<N>) -> Vec<hya_core::spatial::Transform>,
) {
    let states = states::<N>();
    for (q, qd, qdd) in &states {
        let tau = model.inverse_dynamics(q.as_slice(), qd.as_slice(), qdd.as_slice()).unwrap();
        assert!(close(d.inverse_dynamics(q, qd, qdd).as_slice(), &tau), "{}: ID", model.name());
        let mass = model.mass_matrix(q.as_slice()).unwrap();
        assert!(close(d.mass_matrix(q).as_slice(), mass.as_slice()), "{}: M", model.name());
        let fd = d.forward_dynamics(q, qd, &JointVector::from_column_slice(&tau)).unwrap();
        assert!(close(fd.as_slice(), qdd.as_slice()), "{}: FD(ID(q̈)) = q̈", model.name());
        for (name, pose) in model.frames().iter().map(|f| &f.name).zip(frame_poses(q)) {
            let expected = model.frame_pose(name, q.as_slice()).unwrap();
            assert!((pose.rotation - expected.rotation).norm() < 1e-12, "{name}");
            assert!((pose.translation - expected.translation).norm() < 1e-12, "{name}");
        }
        // The tip's kinematics against the run-time model's, which Pinocchio holds.
        let tip = d.frame_name();
        assert_eq!(Some(tip), model.tip_frame().map(|f| f.name.as_str()));
        let jacobian = model.frame_jacobian(tip, q.as_slice()).unwrap();
        assert!(close(d.frame_jacobian(q).as_slice(), jacobian.as_slice()), "{}: J of {tip}", model.name());
        let bias = model.frame_acceleration_bias(tip, q.as_slice(), qd.as_slice()).unwrap();
        assert!(close(d.frame_acceleration_bias(q, qd).as_slice(), &bias), "{}: J̇ q̇ of {tip}", model.name());
        let (pose, expected) = (d.frame_pose(q), model.frame_pose(tip, q.as_slice()).unwrap());
        assert!(close(pose.rotation.as_slice(), expected.rotation.as_slice()), "{}: pose of {tip}", model.name());
        assert!(close(pose.translation.as_slice(), expected.translation.as_slice()), "{}: {tip}", model.name());
    }
    let (q, qd, qdd): (Vec<_>, Vec<_>, Vec<_>) = states.iter().cloned().fold((vec![], vec![], vec![]), |mut acc, s| {
        acc.0.push(s.0);
        acc.1.push(s.1);
        acc.2.push(s.2);
        acc
    });
    let n = q.len();
    let mut tau = vec![JointVector::<N>::zeros(); n];
    d.inverse_dynamics_batch(&q, &qd, &qdd, &mut tau).unwrap();
    let mut mass = vec![JointMatrix::<N>::zeros(); n];
    d.mass_matrix_batch(&q, &mut mass).unwrap();
    let mut fd = vec![JointVector::<N>::zeros(); n];
    d.forward_dynamics_batch(&q, &qd, &tau, &mut fd).unwrap();
    let mut jacobian = vec![FrameJacobian::<N>::zeros(); n];
    d.frame_jacobian_batch(&q, &mut jacobian).unwrap();
    let mut bias = vec![FrameVector::zeros(); n];
    d.frame_acceleration_bias_batch(&q, &qd, &mut bias).unwrap();
    // The same batches on four lanes (AVX2 where the CPU has AVX-512, which the default takes):
    // every lane computes its state alone, so the widths agree bit for bit.
    hya_core::lanes::limit_batch_lanes(4).unwrap();
    let (mut narrow_tau, mut narrow_mass) = (tau.clone(), mass.clone());
    d.inverse_dynamics_batch(&q, &qd, &qdd, &mut narrow_tau).unwrap();
    d.mass_matrix_batch(&q, &mut narrow_mass).unwrap();
    let (mut narrow_jacobian, mut narrow_bias) = (jacobian.clone(), bias.clone());
    d.frame_jacobian_batch(&q, &mut narrow_jacobian).unwrap();
    d.frame_acceleration_bias_batch(&q, &qd, &mut narrow_bias).unwrap();
    hya_core::lanes::limit_batch_lanes(8).unwrap();
    assert_eq!(
        (narrow_tau, narrow_mass, narrow_jacobian, narrow_bias),
        (tau.clone(), mass.clone(), jacobian.clone(), bias.clone()),
        "{}: batches on four and eight lanes",
        model.name()
    );
    for k in 0..n {
        assert!(close(tau[k].as_slice(), d.inverse_dynamics(&q[k], &qd[k], &qdd[k]).as_slice()), "batch ID {k}");
        assert!(close(mass[k].as_slice(), d.mass_matrix(&q[k]).as_slice()), "batch M {k}");
        assert!(close(fd[k].as_slice(), qdd[k].as_slice()), "batch FD {k}");
        assert_eq!(jacobian[k], d.frame_jacobian(&q[k]), "batch J {k}");
        assert_eq!(bias[k], d.frame_acceleration_bias(&q[k], &qd[k]), "batch J̇ q̇ {k}");
    }
}

#[test]
fn the_golden_code_computes_what_the_run_time_model_does() {
    check(&compiled::Planar2, &load("../robots/urdf/planar2.urdf").model, |q| {
        compiled::Planar2.frame_poses(q).to_vec()
    });
    let model = |feature: &str| load(&format!("tests/golden/{feature}.urdf")).model;
    check(&compiled::Prismatic, &model("prismatic"), |q| compiled::Prismatic.frame_poses(q).to_vec());
    check(&compiled::OffAxis, &model("off_axis"), |q| compiled::OffAxis.frame_poses(q).to_vec());
    check(&compiled::FixedMerge, &model("fixed_merge"), |q| compiled::FixedMerge.frame_poses(q).to_vec());
    check(&compiled::Branched, &model("branched"), |q| compiled::Branched.frame_poses(q).to_vec());
    check(&compiled::Massless, &model("massless"), |q| compiled::Massless.frame_poses(q).to_vec());
}

#[test]
fn each_golden_input_shows_its_feature() {
    let model = |feature: &str| load(&format!("tests/golden/{feature}.urdf")).model;
    assert_eq!(compiled::Prismatic::DOF, 2);
    assert_eq!(model("fixed_merge").dof(), 2, "the fixed joint adds no degree of freedom");
    assert!(model("fixed_merge").frames().iter().any(|f| f.name == "housing"), "the merged link stays a frame");
    assert_eq!(compiled::Branched::DOF, 3);
    let source = std::fs::read_to_string(root().join("tests/golden/massless.rs")).unwrap();
    assert!(source.contains("Massless"), "the massless link's arm generates");
}
