//! The generated source of `planar2` is pinned by a golden file, so any change to the generator's
//! output shows up in review. After a deliberate change: `UPDATE_GOLDEN=1 cargo test -p
//! hya-codegen --test golden`, then read the diff. (The same source is compiled and checked
//! against Pinocchio by the `hya-robots` and workspace tests.)
#![allow(clippy::unwrap_used)] // test helpers: a failed unwrap is a failed test

use std::path::PathBuf;

fn generate_planar2() -> String {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let loaded = hya_codegen::load_file(root.join("../robots/urdf/planar2.urdf")).unwrap();
    hya_codegen::generate(&loaded.model, "Planar2").unwrap().source
}

#[test]
fn planar2_source_matches_the_golden_file() {
    let golden = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/golden/planar2.rs");
    let source = generate_planar2();
    if std::env::var_os("UPDATE_GOLDEN").is_some() {
        std::fs::write(&golden, &source).unwrap();
    }
    let expected = std::fs::read_to_string(&golden).unwrap();
    assert!(source == expected, "generated planar2 differs from {}; see the module docs", golden.display());
}

#[test]
fn generation_is_deterministic() {
    assert_eq!(generate_planar2(), generate_planar2());
}
