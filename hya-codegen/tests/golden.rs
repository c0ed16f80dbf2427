//! The generated source of `planar2` and of HyA (both the constant-folded and the
//! parameter-holding type) is pinned by golden files, so any change to the generator's output
//! shows up in review. After a deliberate change: `UPDATE_GOLDEN=1 cargo test -p hya-codegen
//! --test golden`, then read the diff. The golden files are also compiled here and checked
//! against the run-time model (itself checked against Pinocchio by the workspace tests).
#![allow(clippy::unwrap_used)]
// test helpers: a failed unwrap is a failed test
// Generated code must compile in a crate that forbids `unsafe` (the golden files are included
// below): the one `unsafe` call of the fused variant lives in `hya_core::with_fma`.
#![forbid(unsafe_code)]

use std::path::PathBuf;

use hya_core::{Dynamics, JointVector};

mod compiled {
    include!("golden/hya.rs");
    include!("golden/hya_parametric.rs");
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn load(robot: &str) -> hya_urdf::LoadedModel {
    hya_urdf::load_file(root().join(format!("../robots/urdf/{robot}.urdf"))).unwrap()
}

/// Compares `source` with the golden file `name`, rewriting it first under `UPDATE_GOLDEN`.
fn check_golden(name: &str, source: &str) {
    let golden = root().join("tests/golden").join(name);
    if std::env::var_os("UPDATE_GOLDEN").is_some() {
        std::fs::write(&golden, source).unwrap();
    }
    let expected = std::fs::read_to_string(&golden).unwrap();
    assert!(source == expected, "generated code differs from {}; see the module docs", golden.display());
}

#[test]
fn generated_sources_match_the_golden_files() {
    check_golden("planar2.rs", &hya_codegen::generate(&load("planar2"), "Planar2").unwrap().source);
    let hya = load("hya");
    check_golden("hya.rs", &hya_codegen::generate(&hya, "Hya").unwrap().source);
    check_golden("hya_parametric.rs", &hya_codegen::generate_parametric(&hya, "HyaParametric").unwrap().source);
}

#[test]
fn generation_is_deterministic() {
    let planar2 = load("planar2");
    assert_eq!(
        hya_codegen::generate(&planar2, "Planar2").unwrap().source,
        hya_codegen::generate(&planar2, "Planar2").unwrap().source
    );
}

#[test]
fn the_golden_hya_code_computes_what_the_run_time_model_does() {
    let model = load("hya").model;
    let parametric = compiled::HyaParametric::new(&core::array::from_fn(|i| model.bodies()[i].inertia));
    let q = JointVector::<6>::from([0.1, -0.2, -0.5, 1.0, 0.3, 0.4]);
    let qd = JointVector::<6>::from([0.5, -0.4, 0.3, -0.2, 0.1, 0.6]);
    let qdd = JointVector::<6>::from([1.0, -1.0, 0.5, 0.8, -0.3, 0.2]);
    let tau = model.inverse_dynamics(q.as_slice(), qd.as_slice(), qdd.as_slice()).unwrap();
    let mass = model.mass_matrix(q.as_slice()).unwrap();
    let fd = model.forward_dynamics(q.as_slice(), qd.as_slice(), &tau).unwrap();
    let generated: [&dyn Dynamics<6>; 2] = [&compiled::Hya, &parametric];
    for d in generated {
        let close = |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(x, y)| (x - y).abs() <= 1e-12 * y.abs().max(1.0));
        assert!(close(d.inverse_dynamics(&q, &qd, &qdd).as_slice(), &tau));
        assert!(close(d.mass_matrix(&q).as_slice(), mass.as_slice()));
        let tau = JointVector::from_column_slice(&tau);
        assert!(close(d.forward_dynamics(&q, &qd, &tau).unwrap().as_slice(), &fd));
        assert!(close(fd.as_slice(), qdd.as_slice()), "FD(ID(q̈)) = q̈");
    }
    assert_eq!(compiled::Hya::DOF, model.dof());
    assert!(compiled::Hya::JOINT_NAMES.iter().copied().eq(model.joint_names()));
    assert!(compiled::Hya::EFFORT_LIMITS.iter().zip(model.bodies()).all(|(e, b)| *e == b.limits.effort));
    for (name, pose) in compiled::Hya::FRAME_NAMES.iter().zip(compiled::Hya.frame_poses(&q)) {
        let expected = model.frame_pose(name, q.as_slice()).unwrap();
        assert!((pose.rotation - expected.rotation).norm() < 1e-12, "{name}");
        assert!((pose.translation - expected.translation).norm() < 1e-12, "{name}");
    }
}
