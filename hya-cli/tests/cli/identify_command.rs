//! `hya identify` on a log made here: the planar arm with a 20 % heavier forearm than its URDF
//! and joint friction, along a trajectory from `hya excite`'s design, torques exact (no noise).
//! The identified friction and forearm must come back and the held-out prediction beat the
//! nominal model.

use crate::common::{assert_rejected, hya};
use hya_ident::{ExcitationDesign, Limits};

const DT: f64 = 0.002;
const COULOMB: [f64; 2] = [1.5, 0.8];
const VISCOUS: [f64; 2] = [0.6, 0.3];

/// Rows `q τ` of two periods of a designed trajectory.
fn log() -> String {
    let urdf = include_str!("../../../robots/urdf/planar2.urdf");
    let nominal = hya_urdf::load_str(urdf, "planar2").unwrap().model;
    let truth =
        hya_urdf::load_str(&urdf.replace("<mass value=\"2.0\"/>", "<mass value=\"2.4\"/>"), "truth").unwrap().model;
    let limits = Limits::of(&nominal, 0.8, 0.5).unwrap();
    let (trajectory, _) =
        ExcitationDesign { candidates: 3, samples: 40, ..ExcitationDesign::default() }.run(&nominal, &limits).unwrap();
    let rows = (2.0 * trajectory.period_s() / DT) as usize;
    let mut text = String::new();
    for k in 0..rows {
        let (q, qd, qdd) = trajectory.at(k as f64 * DT);
        let rigid = truth.inverse_dynamics(&q, &qd, &qdd).unwrap();
        let tau: Vec<f64> =
            (0..2).map(|i| rigid[i] + COULOMB[i] * (qd[i] / 0.05).tanh() + VISCOUS[i] * qd[i]).collect();
        text += &format!("{} {} {} {}\n", q[0], q[1], tau[0], tau[1]);
    }
    text
}

/// The numbers of `key = [a, b]` in `toml`.
fn list(toml: &str, key: &str) -> Vec<f64> {
    let line = toml.lines().find(|l| l.starts_with(&format!("{key} = "))).unwrap();
    line[line.find('[').unwrap() + 1..line.find(']').unwrap()].split(", ").map(|v| v.parse().unwrap()).collect()
}

#[test]
fn identify_recovers_friction_and_beats_the_nominal_model_on_held_out_torques() {
    let out = std::env::temp_dir().join(format!("hya-identify-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let output = hya(&["identify", "--robot", "planar2", "--dt", "0.002", "--out", out.to_str().unwrap()], &log());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    let toml = std::fs::read_to_string(out.join("friction.toml")).unwrap();
    for (found, truth) in
        list(&toml, "coulomb_nm").iter().zip(COULOMB).chain(list(&toml, "viscous_nm_s").iter().zip(VISCOUS))
    {
        // The filters' lag and the model's nonlinearity leave a small bias; no noise otherwise.
        assert!((found - truth).abs() < 0.05 * truth + 0.02, "{found} vs {truth}\n{toml}");
    }
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    let rows: Vec<Vec<f64>> = report
        .lines()
        .filter(|l| l.starts_with("| shoulder |") || l.starts_with("| elbow |"))
        .take(2)
        .map(|l| l.split('|').filter_map(|c| c.trim().parse().ok()).collect())
        .collect();
    assert_eq!(rows.len(), 2, "{report}");
    // Columns: the measured torque's RMS, then the nominal and the identified model's errors.
    for row in rows {
        assert!(row[2] < 0.2 * row[1], "held-out RMS identified {} vs nominal {}\n{report}", row[2], row[1]);
    }
    // The forearm's first moment m·c_x is identifiable: 2.4 kg at 0.2 m in the log's arm, 2 kg
    // in the URDF's; identified.urdf carries it and loads.
    let identified = hya_urdf::load_file(out.join("identified.urdf").to_str().unwrap()).unwrap().model;
    let moment = identified.bodies()[1].inertia.first_moment.x;
    assert!((moment - 0.48).abs() < 0.01, "forearm m·c_x {moment}");
    assert!(report.contains("## Bodies (`identified.urdf`)"), "{report}");
    // Rows near each joint's reversals are left out, and with --keep-reversals fitted.
    let (samples, rows) = fitted(&report);
    assert!(rows.iter().all(|&r| r > samples / 2 && r < samples), "{samples} samples, rows {rows:?}");
    let kept = hya(
        &[
            "identify",
            "--robot",
            "planar2",
            "--dt",
            "0.002",
            "--keep-reversals",
            "--force",
            "--out",
            out.to_str().unwrap(),
        ],
        &log(),
    );
    assert!(kept.status.success(), "{}", String::from_utf8_lossy(&kept.stderr));
    let (samples, rows) = fitted(&std::fs::read_to_string(out.join("report.md")).unwrap());
    assert_eq!(rows, vec![samples; 2]);
    let _ = std::fs::remove_dir_all(&out);
}

/// The report's fitted samples and, per joint, the rows that entered the fit.
fn fitted(report: &str) -> (usize, Vec<usize>) {
    let number = |text: &str| text.trim().parse::<usize>().unwrap();
    let samples = report.split(" samples fitted").next().unwrap().rsplit(' ').next().unwrap();
    let rows = report.split("rows fitted per joint ").nth(1).unwrap().split(" (").next().unwrap();
    (number(samples), rows.split(", ").map(number).collect())
}

#[test]
fn identify_refuses_short_logs_and_bad_settings() {
    assert_rejected(
        &["identify", "--robot", "planar2", "--dt", "0.002", "--out", "/nonexistent/x"],
        "0.1 0.2 1 2\n",
        &["rows", "needs at least"],
    );
    assert_rejected(
        &["identify", "--robot", "planar2", "--dt", "0.002"],
        "0.1 0.2 1\n",
        &["line 1", "expected 4 values"],
    );
    assert_rejected(&["identify", "--robot", "planar2", "--dt", "0.002", "--held-out", "1"], "", &["--held-out"]);
    // A smoothing velocity beyond the log's speeds leaves a joint too few rows: said, with the way out.
    assert_rejected(
        &["identify", "--robot", "planar2", "--dt", "0.002", "--smoothing-rad-s", "5", "--out", "/nonexistent/x"],
        &log(),
        &["joint `", "keeps 0 of the", "15 rad/s", "--keep-reversals"],
    );
}

#[test]
fn force_never_removes_a_file_the_run_reads() {
    let dir = std::env::temp_dir().join(format!("hya-identify-inputs-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let out = dir.to_str().unwrap();
    let first = hya(&["identify", "--robot", "planar2", "--dt", "0.002", "--out", out], &log());
    assert!(first.status.success(), "{}", String::from_utf8_lossy(&first.stderr));
    let identified = dir.join("identified.urdf");
    let before = std::fs::read(&identified).unwrap();
    // The identification as its own --compare, replaced in place: the input would be deleted.
    let compare = identified.to_str().unwrap();
    let args = ["identify", "--robot", "planar2", "--dt", "0.002", "--compare", compare, "--out", out, "--force"];
    assert_rejected(&args, &log(), &["would remove identified.urdf, which this run reads"]);
    // A scenario whose controller runs on the identification, with its report into that folder.
    let scenario = std::env::temp_dir().join(format!("hya-identify-inputs-{}.toml", std::process::id()));
    // planar2's built-in scenario (its per-joint lists fit the arm), its controller on the file.
    let builtin = include_str!("../../../hya-sim/scenarios/planar2_goto.toml");
    let text = builtin.replacen("[controller]\n", &format!("[controller]\nmodel_urdf = {compare:?}\n"), 1);
    std::fs::write(&scenario, text).unwrap();
    let run = ["run", scenario.to_str().unwrap(), "--out", out, "--force"];
    assert_rejected(&run, "", &["would remove identified.urdf, which this run reads"]);
    assert_eq!(std::fs::read(&identified).unwrap(), before, "the identification is untouched");
    assert!(dir.join("report.md").is_file() && dir.join("friction.toml").is_file(), "nothing removed");
    std::fs::remove_dir_all(&dir).unwrap();
    std::fs::remove_file(&scenario).unwrap();
}

#[test]
fn joint_names_cannot_break_the_files_or_the_messages() {
    let dir = std::env::temp_dir().join(format!("hya-identify-names-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    // A line break and a TOML table header in a joint's name (legal XML).
    let urdf =
        include_str!("../../../robots/urdf/planar2.urdf").replace("name=\"shoulder\"", "name=\"shoulder&#10;[x]\"");
    let robot = dir.join("forged.urdf");
    std::fs::write(&robot, urdf).unwrap();
    let out = dir.join("out");
    let args = ["identify", "--robot", robot.to_str().unwrap(), "--dt", "0.002", "--out", out.to_str().unwrap()];
    let output = hya(&args, &log());
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let friction = out.join("friction.toml");
    let text = std::fs::read_to_string(&friction).unwrap();
    assert!(text.contains("# Joints: shoulder\\n[x], elbow"), "{text}");
    // The file reads back.
    let estimate = hya(
        &["estimate", "--robot", robot.to_str().unwrap(), "--friction", friction.to_str().unwrap()],
        "0.1 0.2 1 2\n",
    );
    assert!(estimate.status.success(), "{}", String::from_utf8_lossy(&estimate.stderr));
    // A --compare of a thousand long joint names: a short message, every name escaped.
    let mut many = String::from("<robot name=\"many\"><link name=\"l0\"/>");
    let long = "n".repeat(500);
    for k in 1..=1000 {
        many += &format!(
            "<link name=\"l{k}\"><inertial><mass value=\"1\"/><inertia ixx=\"0.01\" iyy=\"0.01\" izz=\"0.01\" \
             ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial></link><joint name=\"{long}{k}\" type=\"revolute\">\
             <parent link=\"l{}\"/><child link=\"l{k}\"/><axis xyz=\"0 0 1\"/></joint>",
            k - 1
        );
    }
    many += "</robot>";
    let compare = dir.join("many.urdf");
    std::fs::write(&compare, many).unwrap();
    let args = [
        "identify",
        "--robot",
        "planar2",
        "--dt",
        "0.002",
        "--compare",
        compare.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ];
    let output = hya(&args, &log());
    let message = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{message}");
    assert!(message.contains("(1000 in all)") && message.len() < 2000, "{} bytes: {message:.300}", message.len());
    std::fs::remove_dir_all(&dir).unwrap();
}
