//! The loader on real-world messiness (accepted) and on a folder of malformed descriptions, each
//! refused with its own error that names the file and the joint or link at fault.
#![allow(clippy::unwrap_used)] // test helpers: a failed unwrap is a failed test

use std::path::PathBuf;

use hya_urdf::{load_file, Problem};

fn urdf(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/urdf").join(name)
}

#[test]
fn messy_description_loads_with_fixed_links_merged() {
    let loaded = load_file(urdf("messy_tree.urdf")).unwrap();
    let model = &loaded.model;
    assert_eq!(
        model.joint_names().collect::<Vec<_>>(),
        ["base_yaw", "lift", "left_shoulder", "left_elbow", "right_shoulder", "right_wrist"]
    );
    // Every link stays a named frame, merged or not.
    for frame in ["world", "base_link", "head_mount", "left_tool_frame", "right_dummy", "right_hand"] {
        assert!(model.frames().iter().any(|f| f.name == frame), "frame {frame} missing");
    }
    // The head mount (1.5 kg on a fixed joint) is part of the torso body moved by `lift`.
    let torso = &model.bodies()[1];
    assert!((torso.inertia.mass - 9.5).abs() < 1e-12, "torso body mass {}", torso.inertia.mass);
    // Axes are normalised: `0 0 2` becomes z, `1 1 0` becomes (1, 1, 0)/√2.
    assert!((model.bodies()[1].axis - nalgebra::Vector3::z()).norm() < 1e-15);
    assert!((model.bodies()[5].axis.norm() - 1.0).abs() < 1e-15);
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
}

/// `(file, check of the problem, words the message must contain)`.
type Case = (&'static str, fn(&Problem) -> bool, &'static [&'static str]);

#[test]
fn every_malformed_description_gets_its_own_error() {
    let cases: &[Case] = &[
        (
            "floating_joint",
            |p| matches!(p, Problem::UnsupportedJoint { kind, .. } if kind.starts_with("floating")),
            &["float"],
        ),
        (
            "planar_joint",
            |p| matches!(p, Problem::UnsupportedJoint { kind, .. } if kind.starts_with("planar")),
            &["slide"],
        ),
        ("mimic_joint", |p| matches!(p, Problem::UnsupportedJoint { kind: "mimic", .. }), &["j2", "mimic"]),
        ("several_roots", |p| matches!(p, Problem::SeveralRoots { .. }), &["base", "other_root"]),
        ("cycle", |p| matches!(p, Problem::Cycle { .. }), &["`b`", "cycle"]),
        ("missing_parent", |p| matches!(p, Problem::UnknownLink { role: "parent", .. }), &["j1", "nowhere"]),
        ("missing_child", |p| matches!(p, Problem::UnknownLink { role: "child", .. }), &["j2", "ghost"]),
        ("duplicate_link", |p| matches!(p, Problem::DuplicateLink { .. }), &["`a`"]),
        ("duplicate_joint", |p| matches!(p, Problem::DuplicateJoint { .. }), &["`j1`"]),
        ("two_parents", |p| matches!(p, Problem::SeveralParents { .. }), &["`b`", "j2", "j3"]),
        ("zero_axis", |p| matches!(p, Problem::ZeroAxis { .. }), &["j1", "axis"]),
        ("non_finite_origin", |p| matches!(p, Problem::NonFinite { field: "xyz", .. }), &["j1", "NaN"]),
        ("negative_mass", |p| matches!(p, Problem::NegativeMass { .. }), &["`a`", "-2"]),
        ("negative_principal_moment", |p| matches!(p, Problem::NegativePrincipalMoment { .. }), &["`a`", "principal"]),
        ("massless_joint", |p| matches!(p, Problem::MasslessJoint { .. }), &["j2", "no mass"]),
        ("no_moving_joint", |p| matches!(p, Problem::NoMovingJoint), &["no moving joint"]),
        ("not_xml", |p| matches!(p, Problem::Parse { .. }), &["not a valid URDF"]),
        ("absurd_mass", |p| matches!(p, Problem::Absurd { field: "mass", .. }), &["`a`", "mass", "1e308"]),
        ("absurd_com", |p| matches!(p, Problem::Absurd { field: "xyz", .. }), &["`a`", "xyz"]),
        ("absurd_inertia", |p| matches!(p, Problem::Absurd { field: "ixx", .. }), &["`a`", "ixx"]),
        ("tiny_mass", |p| matches!(p, Problem::TinyMass { .. }), &["`a`", "massless"]),
        ("point_mass_on_axis", |p| matches!(p, Problem::SingularJoint { .. }), &["j1", "singular"]),
    ];
    let folder = urdf("malformed");
    let files = std::fs::read_dir(&folder).unwrap().count();
    assert_eq!(files, cases.len(), "every file in {} has a case, and every case a file", folder.display());
    for (file, expected, words) in cases {
        let path = folder.join(format!("{file}.urdf"));
        let error = load_file(&path).expect_err(file);
        assert!(expected(&error.problem), "{file}: unexpected problem {:?}", error.problem);
        let message = error.to_string();
        assert!(message.starts_with(&path.display().to_string()), "{file}: message does not name the file: {message}");
        for word in *words {
            assert!(message.contains(word), "{file}: message lacks {word:?}: {message}");
        }
    }
}

#[test]
fn a_missing_file_is_an_error_naming_it() {
    let error = load_file("/no/such/robot.urdf").unwrap_err();
    assert!(matches!(error.problem, Problem::Read { .. }));
    assert!(error.to_string().contains("/no/such/robot.urdf"));
}
