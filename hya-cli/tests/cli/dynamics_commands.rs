//! `hya robots`, `hya id [--derivatives]`, `hya fd [--derivatives]`, `hya jacobian`, `hya mass`, `hya gravity`, `hya generate` end to end: against Pinocchio's reference
//! rows through the generated code, the generic model and a URDF loaded at run time, and every
//! malformed URDF refused with exit code 2.

use crate::common::{assert_rejected, data_rows, hya};

fn workspace(path: &str) -> String {
    format!("{}/../{path}", env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn robots_lists_the_shipped_arms_with_their_joints() {
    let output = hya(&["robots"], "");
    let text = String::from_utf8(output.stdout).unwrap();
    let dof: Vec<(&str, usize)> = text
        .lines()
        .map(|line| {
            let mut fields = line.split_whitespace();
            let name = fields.next().unwrap();
            let n: usize = fields.next().unwrap().parse().unwrap();
            assert_eq!(fields.count(), n, "{line}");
            (name, n)
        })
        .collect();
    let registry: Vec<(&str, usize)> = hya_robots::ROBOTS.iter().map(|r| (r.name, r.dof)).collect();
    assert_eq!(dof, registry);
    assert!(dof.contains(&("hya", 6)) && dof.contains(&("panda", 7)), "{dof:?}");
    let text = String::from_utf8(hya(&["robots", "--urdf", &workspace("robots/urdf/hya.urdf")], "").stdout).unwrap();
    assert_eq!(text, "hya 6 SAA SFE HR EFE WR WFE\n");
}

/// Feeds a reference file's rows of one kind to `hya COMMAND ROBOT_ARGS` and compares to 1e-9.
fn check_against_pinocchio(reference: &str, dof: usize, robot_args: &[&str]) {
    let csv = std::fs::read_to_string(workspace(&format!("tests/reference/{reference}.csv"))).unwrap();
    let kinds = [("id", "id", 3 * dof), ("mass", "mass", dof), ("gravity", "gravity", dof), ("aba", "fd", 3 * dof)];
    for (kind, command, inputs) in kinds {
        let rows: Vec<Vec<f64>> = csv
            .lines()
            .filter(|l| l.starts_with(&format!("{kind},")))
            .map(|l| l.split(',').skip(1).map(|v| v.parse().unwrap()).collect())
            .collect();
        let input: String = rows
            .iter()
            .map(|r| r[..inputs].iter().map(|v| format!("{v:?}")).collect::<Vec<_>>().join(" ") + "\n")
            .collect();
        let args: Vec<&str> = [command].into_iter().chain(robot_args.iter().copied()).collect();
        let output = hya(&args, &input);
        assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
        let text = String::from_utf8(output.stdout).unwrap();
        let quantity = text.lines().next().unwrap().split('_').next().unwrap();
        assert_eq!(quantity, ["tau", "M", "g", "qdd"][kinds.iter().position(|k| k.0 == kind).unwrap()], "{text}");
        let got_rows = data_rows(&text);
        assert_eq!(got_rows.len(), rows.len());
        for (got, row) in got_rows.iter().zip(&rows) {
            let expected = &row[3 * dof..];
            assert_eq!(got.len(), expected.len());
            for (g, e) in got.iter().zip(expected) {
                assert!((g - e).abs() <= 1e-9 * e.abs().max(1.0), "{reference} {command} {robot_args:?}: {g} vs {e}");
            }
        }
    }
}

#[test]
fn id_mass_gravity_agree_with_pinocchio_through_every_path() {
    for robot in hya_robots::ROBOTS {
        let (name, dof) = (robot.name, robot.dof);
        check_against_pinocchio(name, dof, &["--robot", name]);
        check_against_pinocchio(name, dof, &["--robot", name, "--generic"]);
        check_against_pinocchio(name, dof, &["--robot", &workspace(&format!("robots/urdf/{name}.urdf"))]);
    }
    // A description the project never shipped: a branched tree with a prismatic joint.
    check_against_pinocchio("messy_tree", 6, &["--robot", &workspace("hya-urdf/tests/urdf/messy_tree.urdf")]);
}

#[test]
fn every_malformed_urdf_exits_with_2_naming_the_file() {
    let folder = workspace("hya-urdf/tests/urdf/malformed");
    for entry in std::fs::read_dir(&folder).unwrap() {
        let path = entry.unwrap().path().display().to_string();
        assert_rejected(&["gravity", "--robot", &path], "0\n", &[&path]);
    }
}

#[test]
fn bad_rows_and_unknown_robots_are_named() {
    assert_rejected(
        &["id", "--robot", "planar2"],
        "0 0 0 0 0 0\n1 2\n",
        &["line 2: 2 values, but the first row, line 1, has 6"],
    );
    assert_rejected(&["mass", "--robot", "hya"], "0 0 0 0 0 nan\n", &["line 1", "non-finite"]);
    assert_rejected(&["gravity", "--robot", "nope"], "0\n", &["nope", "hya", "panda"]);
}

#[test]
fn overflowing_results_and_non_utf8_input_are_refused_with_the_line() {
    // q̇ = 1e154 squares to infinity in the velocity terms.
    let row = "0 0 0 0 0 0  1e154 0 0 0 0 0  0 0 0 0 0 0\n";
    crate::common::assert_rejected(
        &["id", "--robot", "hya"],
        &format!("0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0\n{row}"),
        &["line 2", "overflows"],
    );
    let output = crate::common::hya_bytes(&["gravity", "--robot", "hya"], b"0 0 0 0 0 0\n\xff\xfe 0 0 0 0 0\n");
    assert_eq!(output.status.code(), Some(2));
    let message = String::from_utf8_lossy(&output.stderr);
    assert!(message.contains("line 2") && message.contains("UTF-8"), "{message}");
}

#[test]
fn id_with_derivatives_prints_tau_then_both_jacobians_as_pinocchio_does() {
    let csv = std::fs::read_to_string(workspace("tests/reference/ur5.csv")).unwrap();
    let row = |kind: &str| -> Vec<f64> {
        let line = csv.lines().find(|l| l.starts_with(&format!("{kind},"))).unwrap();
        line.split(',').skip(1).map(|v| v.parse().unwrap()).collect()
    };
    let (id, by_q, by_qd) = (row("id"), row("id_dq"), row("id_dqd"));
    assert_eq!(id[..18], by_q[..18], "the reference rows share their state");
    let input: String = id[..18].iter().map(|v| format!("{v:?} ")).collect();
    for generic in [false, true] {
        let mut args = vec!["id", "--robot", "ur5", "--derivatives"];
        args.extend(generic.then_some("--generic"));
        let output = hya(&args, &input);
        let got = data_rows(&String::from_utf8(output.stdout).unwrap()).concat();
        let expected: Vec<f64> = id[18..].iter().chain(&by_q[18..]).chain(&by_qd[18..]).copied().collect();
        assert_eq!(got.len(), 6 + 2 * 36);
        for (g, e) in got.iter().zip(&expected) {
            assert!((g - e).abs() <= 1e-9 * e.abs().max(1.0), "{g} vs pinocchio {e}");
        }
    }
}

#[test]
fn generate_prints_code_naming_its_urdf_and_refuses_a_bad_type_name() {
    let output = hya(&["generate", &workspace("robots/urdf/planar2.urdf"), "--name", "Planar2"], "");
    let source = String::from_utf8(output.stdout).unwrap();
    assert!(source.starts_with("// Generated by hya-codegen") && source.contains("from planar2.urdf, SHA-256 "));
    assert!(source.contains("let q_shoulder = q[0];"), "joint inputs are named by joint");
    let stats = String::from_utf8(
        hya(&["generate", &workspace("robots/urdf/planar2.urdf"), "--name", "P", "--stats"], "").stdout,
    )
    .unwrap();
    assert!(stats.lines().any(|l| l.starts_with("forward_dynamics")), "{stats}");
    assert_rejected(
        &["generate", &workspace("robots/urdf/planar2.urdf"), "--name", "not a type"],
        "",
        &["not a valid Rust type name"],
    );
}

/// `hya jacobian [--bias] --frame F` and `hya fd --derivatives` against Pinocchio's rows
/// (`tests/reference/kinematics/`, `tools/kinematics_reference.py`): every link's Jacobian and
/// `J̇ q̇` to 1e-12, `∂q̈/∂q`, `∂q̈/∂q̇` and `M⁻¹` to 1e-10.
fn check_kinematics_against_pinocchio(reference: &str, dof: usize, robot: &str) -> usize {
    let csv = std::fs::read_to_string(workspace(&format!("tests/reference/kinematics/{reference}.csv"))).unwrap();
    let mut compared = 0;
    for line in csv.lines().filter(|l| !l.starts_with('"')) {
        let fields: Vec<&str> = line.split(',').collect();
        let numbers: Vec<f64> = fields[2..].iter().map(|v| v.parse().unwrap()).collect();
        let (args, inputs, tolerance): (Vec<&str>, usize, f64) = match fields[0] {
            "jacobian" => (vec!["jacobian", "--robot", robot, "--frame", fields[1]], dof, 1e-12),
            "bias" => (vec!["jacobian", "--robot", robot, "--frame", fields[1], "--bias"], 2 * dof, 1e-12),
            "fd_derivatives" => (vec!["fd", "--robot", robot, "--derivatives"], 3 * dof, 1e-10),
            other => panic!("unknown kind {other}"),
        };
        let input = numbers[..inputs].iter().map(|v| format!("{v:?}")).collect::<Vec<_>>().join(" ") + "\n";
        let output = hya(&args, &input);
        assert!(output.status.success(), "{args:?}: {}", String::from_utf8_lossy(&output.stderr));
        let got = data_rows(&String::from_utf8(output.stdout).unwrap()).remove(0);
        let expected = &numbers[inputs..];
        assert_eq!(got.len(), expected.len(), "{args:?}");
        let scale = expected.iter().fold(1.0f64, |m, e| m.max(e.abs()));
        for (i, (g, e)) in got.iter().zip(expected).enumerate() {
            assert!((g - e).abs() <= tolerance * scale, "{reference} {args:?} [{i}]: {g} vs pinocchio {e}");
        }
        compared += expected.len();
    }
    compared
}

#[test]
fn jacobian_and_fd_derivatives_agree_with_pinocchio() {
    assert!(check_kinematics_against_pinocchio("panda", 7, "panda") > 500);
    assert!(
        check_kinematics_against_pinocchio("slider_arm", 4, &workspace("hya-urdf/tests/urdf/slider_arm.urdf")) > 200
    );
    assert_rejected(
        &["jacobian", "--robot", "planar2", "--frame", "nowhere"],
        "0 0\n",
        &["--frame nowhere", "base, upper_arm, forearm, tip"],
    );
    assert_rejected(&["jacobian", "--robot", "planar2", "--bias"], "0 0\n", &["line 1", "q, qd"]);
    // Without --frame, the last link: planar2's tip, 0.9 m out along x at rest.
    let text = String::from_utf8(hya(&["jacobian", "--robot", "planar2"], "0 0\n").stdout).unwrap();
    let row = data_rows(&text).remove(0);
    assert!((row[4] - -0.9).abs() < 1e-12, "∂z_tip/∂q_shoulder: {row:?}");
}
