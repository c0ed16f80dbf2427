//! `hya track` (the simulated arm following a reference, logged as its sensors read it) and
//! `hya identify` on its logs: with timestamps, `--columns`, gaps and `--compare`.

use std::path::{Path, PathBuf};

use crate::common::{assert_rejected, hya};

/// A fresh folder name under the temporary directory.
fn scratch(name: &str) -> PathBuf {
    let path = std::env::temp_dir().join(format!("hya-track-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&path);
    path
}

fn stdout_of(args: &[&str], input: &str) -> String {
    let output = hya(args, input);
    assert!(output.status.success(), "hya {args:?}: {}", String::from_utf8_lossy(&output.stderr));
    String::from_utf8(output.stdout).unwrap()
}

/// `hya excite` for `robot`: `periods` of a trajectory at `base_hz`.
fn reference(robot: &str, periods: &str, base_hz: &str) -> String {
    stdout_of(&["excite", "--robot", robot, "--periods", periods, "--base-hz", base_hz, "--candidates", "5"], "")
}

/// The numbers of `key = [a, b]` in `toml`.
fn list(toml: &str, key: &str) -> Vec<f64> {
    let line = toml.lines().find(|l| l.starts_with(&format!("{key} = "))).unwrap();
    line[line.find('[').unwrap() + 1..line.find(']').unwrap()].split(", ").map(|v| v.parse().unwrap()).collect()
}

/// The held-out RMS table of a report: per joint, one value per model.
fn held_out_rms(report: &str, joints: &[&str]) -> Vec<Vec<f64>> {
    joints
        .iter()
        .map(|joint| {
            let line = report.lines().find(|l| l.starts_with(&format!("| {joint} |"))).unwrap();
            line.split('|').filter_map(|c| c.trim().parse().ok()).collect()
        })
        .collect()
}

#[test]
fn track_follows_the_reference_and_logs_the_sensors_and_the_true_body() {
    let out = scratch("planar");
    let reference = reference("planar2", "1", "0.5");
    let log = stdout_of(&["track", "--robot", "planar2", "--out", out.to_str().unwrap()], &reference);
    let header = "t [s],q_shoulder [rad],q_elbow [rad],tau_shoulder [N m],tau_elbow [N m]\n";
    assert!(log.starts_with(header), "{}", &log[..80]);
    let rows = crate::common::data_rows(&log);
    let wanted = crate::common::data_rows(&reference);
    // One row per control tick of the scenario (1 ms) over the reference's 2 s.
    let duration = wanted.last().unwrap()[0];
    assert_eq!(rows.len(), (duration / 0.001).round() as usize);
    // The logged angles follow the reference (at its own rows, 10 ms apart) to within a tenth
    // of its range: the scenario's controller is the paper's, not a tracking specialist.
    let worst = wanted
        .iter()
        .filter_map(|w| {
            rows.iter().find(|r| (r[0] - w[0]).abs() < 1e-9).map(|r| (r[1] - w[1]).abs().max((r[2] - w[2]).abs()))
        })
        .fold(0.0, f64::max);
    let range = |j: usize| {
        let values = wanted.iter().map(|w| w[j]);
        values.clone().fold(f64::NEG_INFINITY, f64::max) - values.fold(f64::INFINITY, f64::min)
    };
    let smallest_range = range(1).min(range(2));
    assert!(worst < 0.1 * smallest_range, "largest tracking error {worst} rad of a range of {smallest_range} rad");
    // true.urdf is the plant's body: the URDF's masses, each perturbed by at most the spread.
    let truth = hya_urdf::load_file(out.join("true.urdf").to_str().unwrap()).unwrap().model;
    let nominal = hya_urdf::load_str(include_str!("../../../robots/urdf/planar2.urdf"), "planar2").unwrap().model;
    let ratios: Vec<f64> =
        truth.bodies().iter().zip(nominal.bodies()).map(|(t, n)| t.inertia.mass / n.inertia.mass).collect();
    assert!(ratios.iter().all(|r| (r - 1.0).abs() <= 0.1 + 1e-12) && ratios.iter().any(|r| *r != 1.0), "{ratios:?}");
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn identify_reads_timestamps_and_columns_as_it_reads_fixed_steps() {
    let log = stdout_of(&["track", "--robot", "planar2", "--seed", "2"], &reference("planar2", "3", "0.5"));
    let untimed: String = log.lines().skip(1).map(|l| l.split_once(',').unwrap().1.to_owned() + "\n").collect();
    let (fixed, timed, picked) = (scratch("fixed"), scratch("timed"), scratch("picked"));
    let run = |out: &Path, extra: &[&str], input: &str| {
        let mut args = vec!["identify", "--robot", "planar2", "--dt", "0.001", "--out", out.to_str().unwrap()];
        args.extend_from_slice(extra);
        stdout_of(&args, input);
        std::fs::read_to_string(out.join("friction.toml")).unwrap()
    };
    let a = run(&fixed, &[], &untimed);
    let b = run(&timed, &["--timestamps"], &log);
    // Columns by name, in the order t, q, τ, from a log whose columns come in another order.
    let reordered: String = log
        .lines()
        .map(|l| {
            let v: Vec<&str> = l.split(',').collect();
            format!("{},{},{},{},{}\n", v[3], v[0], v[4], v[1], v[2])
        })
        .collect();
    let c = run(&picked, &["--timestamps", "--columns", "t,q_shoulder,q_elbow,tau_shoulder,tau_elbow"], &reordered);
    // Without --dt, the log's median step (1 ms here) is the nominal one: the same fit again.
    let median = scratch("median");
    let args = ["identify", "--robot", "planar2", "--timestamps", "--out", median.to_str().unwrap()];
    let output = hya(&args, &log);
    assert!(String::from_utf8_lossy(&output.stderr).contains("the log's median step, 0.001 s"));
    assert_eq!(std::fs::read_to_string(median.join("friction.toml")).unwrap(), b);
    let _ = std::fs::remove_dir_all(median);
    for key in ["coulomb_nm", "viscous_nm_s", "offset_nm"] {
        for ((x, y), z) in list(&a, key).iter().zip(list(&b, key)).zip(list(&c, key)) {
            // Timestamps printed in decimal make steps of 1 ms to within rounding: the same fit.
            assert!((x - y).abs() <= 1e-6 * (1.0 + x.abs()), "{key}: {x} vs {y}");
            assert_eq!(y, z, "{key}");
        }
    }
    assert!(std::fs::read_to_string(timed.join("held_out.svg")).unwrap().starts_with("<svg"));
    for dir in [fixed, timed, picked] {
        let _ = std::fs::remove_dir_all(dir);
    }
}

#[test]
fn identify_restarts_its_filters_after_a_gap() {
    let log = stdout_of(&["track", "--robot", "planar2", "--seed", "2"], &reference("planar2", "3", "0.5"));
    // Drop 50 ms in the middle of the log.
    let cut: String = log
        .lines()
        .filter(|l| l.split(',').next().and_then(|t| t.parse::<f64>().ok()).is_none_or(|t| !(3.0..3.05).contains(&t)))
        .map(|l| l.to_owned() + "\n")
        .collect();
    let out = scratch("gap");
    stdout_of(
        &["identify", "--robot", "planar2", "--dt", "0.001", "--timestamps", "--out", out.to_str().unwrap()],
        &cut,
    );
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(report.contains(", 1 gaps (longer than 0.0025 s)"), "{report}");
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn identify_on_a_tracked_hya_log_beats_the_nominal_model_and_holds_it_against_the_truth() {
    let (truth, id) = (scratch("hya-truth"), scratch("hya-id"));
    let log = stdout_of(
        &["track", "--robot", "hya", "--seed", "3", "--out", truth.to_str().unwrap()],
        &reference("hya", "2", "0.1"),
    );
    let true_urdf = truth.join("true.urdf");
    let args = [
        "identify",
        "--robot",
        "hya",
        "--dt",
        "0.001",
        "--timestamps",
        "--compare",
        true_urdf.to_str().unwrap(),
        "--out",
        id.to_str().unwrap(),
    ];
    stdout_of(&args, &log);
    let report = std::fs::read_to_string(id.join("report.md")).unwrap();
    let joints = ["SAA", "SFE", "HR", "EFE", "WR", "WFE"];
    for (joint, rms) in joints.iter().zip(held_out_rms(&report, &joints)) {
        // the measured torque, then the errors of the nominal model, the identified one, the
        // nominal bodies with the friction fitted alone, the true rigid body
        assert_eq!(rms.len(), 5, "{report}");
        assert!(rms[2] < rms[1], "{joint}: identified {} vs nominal {}\n{report}", rms[2], rms[1]);
    }
    assert!(report.contains("(identified − it)/σ"), "{report}");
    for dir in [truth, id] {
        let _ = std::fs::remove_dir_all(dir);
    }
}

#[test]
fn track_and_identify_refuse_bad_input_by_name() {
    assert_rejected(&["track", "--robot", "planar2", "--method", "magic"], "0 0 0 0 0 0 0\n", &["--method", "magic"]);
    assert_rejected(&["track", "--robot", "planar2"], "", &["no reference rows"]);
    assert_rejected(
        &["track", "--robot", "planar2"],
        "0 0 0 0 0 0 0\n0 0 0 0 0 0 0\n",
        &["reference sample 2", "increasing"],
    );
    assert_rejected(&["track", "--robot", "planar2"], "0.5 0 0 0 0 0 0\n", &["first sample's time must be 0"]);
    assert_rejected(&["track", "--robot", "planar2"], "0 0 0 0 0 0\n", &["line 1", "expected 7 values"]);
    assert_rejected(
        &["identify", "--robot", "planar2", "--dt", "0.001", "--timestamps"],
        "0 0 0 0 0\n0.001 0 0 0 0\n0.0005 0 0 0 0\n",
        &["line 3", "strictly increase"],
    );
    assert_rejected(
        &["identify", "--robot", "planar2", "--dt", "0.001", "--compare", "hya"],
        "0 0 0 0\n",
        &["--compare hya", "are not --robot's"],
    );
    assert_rejected(
        &["identify", "--robot", "planar2", "--dt", "0.001", "--columns", "q1-q3"],
        "0 0 0 0\n",
        &["--columns selects 3 columns; 4 are read"],
    );
}

#[test]
fn a_reference_beyond_the_joint_limits_is_refused_by_name() {
    let rows = "0 1e6 0 0 0 0 0  0 0 0 0 0 0  0 0 0 0 0 0\n1 1e6 0 0 0 0 0  0 0 0 0 0 0  0 0 0 0 0 0\n";
    assert_rejected(
        &["track", "--robot", "hya"],
        rows,
        &["reference sample 1 (t = 0 s), joint SAA", "= 1e6", "beyond the joint's limits"],
    );
}

#[test]
fn track_force_never_removes_the_urdf_it_tracks_on() {
    let dir = scratch("track-inputs");
    let out = dir.to_str().unwrap();
    let rows = reference("planar2", "1", "0.5");
    stdout_of(&["track", "--robot", "planar2", "--out", out], &rows);
    let truth = dir.join("true.urdf");
    let before = std::fs::read(&truth).unwrap();
    let scenario = format!("{}/../hya-sim/scenarios/planar2_goto.toml", env!("CARGO_MANIFEST_DIR"));
    let args = ["track", "--robot", truth.to_str().unwrap(), "--scenario", &scenario, "--out", out, "--force"];
    assert_rejected(&args, &rows, &["would remove true.urdf, which this run reads"]);
    assert_eq!(std::fs::read(&truth).unwrap(), before);
    let _ = std::fs::remove_dir_all(dir);
}
