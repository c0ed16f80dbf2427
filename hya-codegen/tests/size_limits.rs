//! Unrolled code is the right tool for arms, not for long chains: the generator warns past
//! `WARN_ABOVE_JOINTS` joints and refuses past `MAX_JOINTS`, naming the run-time model instead.
#![allow(clippy::unwrap_used)] // test helpers: a failed unwrap is a failed test

use hya_codegen::{generate, size_warning, GenerateError, MAX_JOINTS, WARN_ABOVE_JOINTS};
use hya_urdf::load_str;

/// A serial chain of `n` revolute joints, alternating axes.
fn chain(n: usize) -> String {
    let mut urdf = String::from("<robot name=\"chain\"><link name=\"l0\"/>");
    for i in 1..=n {
        let axis = if i % 2 == 0 { "0 1 0" } else { "0 0 1" };
        urdf += &format!(
            "<link name=\"l{i}\"><inertial><mass value=\"1\"/><origin xyz=\"0.05 0 0\"/><inertia ixx=\"0.01\" iyy=\"0.01\" izz=\"0.01\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial></link>\
             <joint name=\"j{i}\" type=\"revolute\"><parent link=\"l{}\"/><child link=\"l{i}\"/><origin xyz=\"0.1 0 0\"/><axis xyz=\"{axis}\"/></joint>",
            i - 1
        );
    }
    urdf + "</robot>"
}

#[test]
fn long_chains_are_warned_about_then_refused() {
    let small = load_str(&chain(WARN_ABOVE_JOINTS), "small.urdf").unwrap().model;
    assert!(size_warning(&small).is_none());
    let long = load_str(&chain(WARN_ABOVE_JOINTS + 1), "long.urdf").unwrap().model;
    let warning = size_warning(&long).unwrap();
    assert!(warning.contains("TreeModel") && warning.contains(&format!("{}", WARN_ABOVE_JOINTS + 1)), "{warning}");
    let huge_loaded = load_str(&chain(MAX_JOINTS + 1), "huge.urdf").unwrap();
    let huge = &huge_loaded.model;
    let refused = generate(&huge_loaded, "Huge").unwrap_err();
    assert_eq!(refused, GenerateError::TooLarge(MAX_JOINTS + 1));
    assert!(refused.to_string().contains("run-time model"));
    // The run-time model still serves it.
    assert_eq!(huge.gravity(&[0.0; MAX_JOINTS + 1]).unwrap().len(), MAX_JOINTS + 1);
}
