//! `hya plant`: open-loop rollouts from the shell. The ideal plant follows MuJoCo's rollout of
//! the same torque rows (an independent, accurate integration: RK4 at 0.1 ms, checked against
//! 0.01 ms) to 1e-4 rad over 1 s; bad rows are refused with their line number.

use std::path::PathBuf;

use crate::common::{assert_rejected, hya};

fn reference(file: &str) -> String {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../hya-sim/tests/data").join(file);
    std::fs::read_to_string(path).unwrap()
}

#[test]
fn the_ideal_rollout_follows_mujoco() {
    let torque = reference("mujoco_hya_torque.csv");
    // The torque file's last row acts from 0.99 s; run on to 1 s as the reference does.
    let output = hya(&["plant", "--robot", "hya", "--ideal", "--until", "1.0"], &torque);
    assert_eq!(output.status.code(), Some(0), "{}", String::from_utf8_lossy(&output.stderr));
    let ours = crate::common::data_rows(&String::from_utf8(output.stdout).unwrap());
    let theirs = crate::common::data_rows(&reference("mujoco_hya_rollout.csv"));
    assert_eq!(ours.len(), theirs.len(), "one row per millisecond from 0 to 1 s");
    let worst = ours
        .iter()
        .zip(&theirs)
        .flat_map(|(a, b)| a[1..=6].iter().zip(&b[1..=6]).map(|(x, y)| (x - y).abs()))
        .fold(0.0, f64::max);
    assert!(worst < 1e-4, "hya plant --ideal departs from MuJoCo by {worst} rad");
}

#[test]
fn the_default_plant_holds_the_arm_with_gravity_torques() {
    // The goto_internal plant at HyA's home pose, its actuators commanded the nominal gravity
    // torques: friction and the torque loops hold the arm within a few milliradians.
    let gravity = "0 0 40.2959021342 4.9492114049 4.5932244126 0.2688694044 -0.0555794064\n1 0 40.2959021342 4.9492114049 4.5932244126 0.2688694044 -0.0555794064\n";
    let output = hya(&["plant", "--robot", "hya", "--dt", "0.5"], gravity);
    assert_eq!(output.status.code(), Some(0), "{}", String::from_utf8_lossy(&output.stderr));
    let rows = crate::common::data_rows(&String::from_utf8(output.stdout).unwrap());
    assert_eq!(rows.len(), 3, "rows at 0, 0.5 and 1 s");
    let home = hya_robots::hya::HOME;
    for row in &rows {
        let drift = row[1..=6].iter().zip(home).map(|(q, h)| (q - h).abs()).fold(0.0, f64::max);
        assert!(drift < 5e-3, "the held arm moved {drift} rad by t = {}", row[0]);
    }
}

#[test]
fn bad_rows_are_refused_with_their_line() {
    let args = ["plant", "--robot", "hya", "--ideal"];
    assert_rejected(&args, "0 1 2 3\n", &["line 1", "expected 7 values"]);
    assert_rejected(&args, "0.1 0 0 0 0 0 0\n", &["line 1", "t = 0"]);
    assert_rejected(&args, "0 0 0 0 0 0 0\n# a comment\n0 0 0 0 0 0 0\n", &["line 3", "does not come after"]);
    assert_rejected(&args, "0 0 0 0 0 0 0\n0.5 0 x 0 0 0 0\n", &["line 2", "not a number"]);
    assert_rejected(&args, "", &["no torque rows"]);
    assert_rejected(&["plant", "--robot", "hya", "--ideal", "--q0", "0 0"], "0 0 0 0 0 0 0\n", &["--q0", "6 angles"]);
    let two_lines = "0 0 0 0 0 0\n0.1 0 0 0 0 0";
    assert_rejected(
        &["plant", "--robot", "hya", "--ideal", "--q0", two_lines],
        "0 0 0 0 0 0 0\n",
        &["--q0", "one line"],
    );
    // Without --scenario panda runs its own built-in scenario; its rows are still checked.
    assert_rejected(&["plant", "--robot", "panda"], "0 0 0 0 0 0 0\n", &["line 1", "expected 8 values"]);
}

#[test]
fn a_runaway_is_named_as_one_not_blamed_on_the_mass_matrix() {
    // 100 and 60 N·m on the planar arm's hydraulic plant: the state runs away within 0.2 s; the
    // mass matrix (positive definite everywhere) was once blamed.
    let output = hya(&["plant", "--robot", "planar2", "--until", "1"], "0 100 60\n");
    let message = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{message}");
    assert!(
        message.contains("the simulated arm diverged: joint 2 passed 100 rad/s, a speed no arm reaches, at t = 0.17"),
        "{message}"
    );
    assert!(!message.starts_with("hya: numerical failure"), "{message}");
}
