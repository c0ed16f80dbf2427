//! Generated and generic dynamics against reference vectors from Pinocchio, an independent
//! implementation (`tools/pinocchio_reference.sh` wrote `tests/reference/*.csv`), to 1e-9.
#![allow(clippy::unwrap_used)] // test helpers: a failed unwrap is a failed test

use hya_core::SliceDynamics;

/// `|a − b| ≤ 1e-9 · max(|b|, 1)`.
const TOLERANCE: f64 = 1e-9;

/// Checks every row of a reference file; returns how many values were compared.
fn check(name: &str, dynamics: &dyn SliceDynamics, csv: &str) -> usize {
    let n = dynamics.dof();
    let mut compared = 0;
    for (line, text) in csv.lines().enumerate().filter(|(_, t)| !t.starts_with('#') && !t.starts_with("\"#")) {
        let fields: Vec<&str> = text.split(',').collect();
        let numbers: Vec<f64> = fields[1..].iter().map(|f| f.parse().unwrap()).collect();
        let (q, rest) = numbers.split_at(n);
        let (qd, rest) = rest.split_at(n);
        let (qdd, expected) = rest.split_at(n);
        let mut got = vec![0.0; expected.len()];
        match fields[0] {
            "id" => dynamics.inverse_dynamics_into(q, qd, qdd, &mut got),
            "mass" => dynamics.mass_matrix_into(q, &mut got),
            "gravity" => dynamics.gravity_into(q, &mut got),
            other => panic!("{name}: unknown kind {other}"),
        }
        for (i, (g, e)) in got.iter().zip(expected).enumerate() {
            assert!(
                (g - e).abs() <= TOLERANCE * e.abs().max(1.0),
                "{name} line {}: {} [{i}]: {g} vs pinocchio {e}",
                line + 1,
                fields[0]
            );
        }
        compared += expected.len();
    }
    compared
}

#[test]
fn shipped_robots_match_pinocchio_through_both_paths() {
    for robot in hya_robots::ROBOTS {
        let csv =
            std::fs::read_to_string(format!("{}/reference/{}.csv", env!("CARGO_MANIFEST_DIR"), robot.name)).unwrap();
        let generic = hya_codegen::load_str(robot.urdf, robot.name).unwrap().model;
        let generated_count = check(&format!("{} (generated)", robot.name), robot.generated, &csv);
        let generic_count = check(&format!("{} (generic)", robot.name), &generic, &csv);
        assert!(generated_count >= 64 && generic_count == generated_count, "{}: {generated_count} values", robot.name);
    }
}

#[test]
fn a_messy_branched_tree_matches_pinocchio() {
    let root = env!("CARGO_MANIFEST_DIR");
    let model = hya_codegen::load_file(format!("{root}/../hya-codegen/tests/urdf/messy_tree.urdf")).unwrap().model;
    let csv = std::fs::read_to_string(format!("{root}/reference/messy_tree.csv")).unwrap();
    assert!(check("messy_tree (generic)", &model, &csv) > 100);
}
