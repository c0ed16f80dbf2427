//! `hya run` writes only inside `--out`: a scenario name cannot name a path, and a folder that
//! holds anything is refused (or, with `--force`, an earlier report in it replaced) before any
//! simulation starts.

use std::path::{Path, PathBuf};

use crate::common::{assert_rejected, hya};

fn scratch(tag: &str) -> PathBuf {
    crate::common::scratch(&format!("out-{tag}"))
}

/// A one-tick-long scenario named `name`, written into `dir`.
fn scenario(dir: &Path, name: &str) -> String {
    let path = dir.join("scenario.toml");
    let text = format!(
        "name = {name:?}\nduration_s = 0.6\nmethods = [\"none\"]\n[task]\nkind = \"hold\"\n[plant]\nactuator = \"ideal\"\nfriction = \"smooth\"\n"
    );
    std::fs::write(&path, text).unwrap();
    path.display().to_string()
}

#[test]
fn scenario_names_cannot_leave_the_report_folder() {
    let dir = scratch("names");
    for name in ["../escaped", "/tmp/hya-escaped", "a/b", "..", ".hidden", "", "x\ty", "C:\\x"] {
        let file = scenario(&dir, name);
        let out = dir.join("report");
        assert_rejected(&["run", &file, "--out", out.to_str().unwrap()], "", &["name"]);
        assert!(!out.exists(), "nothing is written for a refused scenario ({name:?})");
    }
    assert!(!dir.parent().unwrap().join("escaped_none.csv").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_non_empty_out_folder_is_refused_before_simulating() {
    let dir = scratch("nonempty");
    let file = scenario(&dir, "tiny");
    // `dir` holds the scenario file: not empty, and no earlier report.
    assert_rejected(&["run", &file, "--out", dir.to_str().unwrap()], "", &["not empty", "--force"]);
    assert_rejected(&["run", &file, "--out", dir.to_str().unwrap(), "--force"], "", &["no .hya-files"]);
    assert!(dir.join("scenario.toml").is_file(), "the refused folder keeps its files");
    // `--out` naming a file is refused too.
    assert_rejected(&["run", &file, "--out", &file], "", &["not a folder"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn force_replaces_an_earlier_report_and_keeps_other_files() {
    let dir = scratch("force");
    let file = scenario(&dir, "tiny");
    let out = dir.join("report");
    let first = hya(&["run", &file, "--out", out.to_str().unwrap(), "--seeds", "2"], "");
    assert_eq!(first.status.code(), Some(0), "{}", String::from_utf8_lossy(&first.stderr));
    assert!(out.join("summary.json").is_file() && out.join("tiny_none.csv").is_file());
    // The time series is in the row commands' format: `hya gravity` finds its angles by name.
    let series = std::fs::read_to_string(out.join("tiny_none.csv")).unwrap();
    assert!(series.starts_with("t [s],q_SAA [rad],q_SFE [rad]"), "{}", &series[..80]);
    let gravity = hya(&["gravity", "--robot", "hya"], &series);
    assert_eq!(gravity.status.code(), Some(0), "{}", String::from_utf8_lossy(&gravity.stderr));
    assert_eq!(crate::common::data_rows(&String::from_utf8(gravity.stdout).unwrap()).len(), series.lines().count() - 1);
    std::fs::write(out.join("notes.txt"), "mine").unwrap();
    std::fs::write(out.join("measurements.csv"), "mine").unwrap();
    // A second scenario over the first one's report: every file of the first goes.
    let other = scenario(&dir, "other");
    let again = hya(&["run", &other, "--out", out.to_str().unwrap(), "--force", "--seeds", "2"], "");
    assert_eq!(again.status.code(), Some(0), "{}", String::from_utf8_lossy(&again.stderr));
    assert!(!out.join("tiny_none.csv").exists(), "a stale report file stays mixed in");
    assert!(out.join("other_none.csv").is_file());
    assert!(
        out.join("notes.txt").is_file() && out.join("measurements.csv").is_file(),
        "a file hya did not write was removed"
    );
    assert!(String::from_utf8_lossy(&again.stderr).contains("notes.txt"), "the kept file is not named");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The reproduction of the hostile-input probe: a manifest that is a symbolic link to a file
/// elsewhere, and `report.md` a hard link to the user's own file. Neither file changes.
#[cfg(unix)]
#[test]
fn force_never_writes_through_links() {
    let dir = scratch("links");
    let file = scenario(&dir, "tiny");
    let out = dir.join("d");
    std::fs::create_dir_all(&out).unwrap();
    let victim = dir.join("victim.txt");
    std::fs::write(&victim, "victim\n").unwrap();
    std::os::unix::fs::symlink(&victim, out.join(".hya-files")).unwrap();
    let thesis = dir.join("thesis.md");
    std::fs::write(&thesis, "draft\n").unwrap();
    std::fs::hard_link(&thesis, out.join("report.md")).unwrap();
    assert_rejected(
        &["run", &file, "--seeds", "1", "--force", "--out", out.to_str().unwrap()],
        "",
        &["not a regular file"],
    );
    assert_eq!(std::fs::read_to_string(&victim).unwrap(), "victim\n");
    assert_eq!(std::fs::read_to_string(&thesis).unwrap(), "draft\n");
    // A planted manifest listing the user's data is not trusted either.
    std::fs::remove_file(out.join(".hya-files")).unwrap();
    std::fs::write(out.join(".hya-files"), "data.csv\nreport.md\n").unwrap();
    std::fs::write(out.join("data.csv"), "precious").unwrap();
    assert_rejected(
        &["run", &file, "--seeds", "1", "--force", "--out", out.to_str().unwrap()],
        "",
        &["nothing was removed"],
    );
    assert_eq!(std::fs::read_to_string(out.join("data.csv")).unwrap(), "precious");
    assert_eq!(std::fs::read_to_string(&thesis).unwrap(), "draft\n");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A second run into a folder another run holds is refused, naming the holder; so concurrent
/// shards into one `--out` cannot overwrite each other's `sweep.json`.
#[test]
fn a_folder_in_use_is_refused() {
    let dir = scratch("held");
    let file = scenario(&dir, "tiny");
    let out = dir.join("report");
    std::fs::create_dir_all(&out).unwrap();
    std::fs::write(out.join(".hya-lock"), "pid 1, hya sweep --shard 0/64\n").unwrap();
    let held = std::fs::File::open(&out).unwrap();
    held.try_lock().unwrap();
    assert_rejected(&["run", &file, "--seeds", "1", "--out", out.to_str().unwrap()], "", &["in use", "--shard 0/64"]);
    assert_rejected(&["sweep", "--quick", "--shard", "1/64", "--out", out.to_str().unwrap()], "", &["in use"]);
    drop(held);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn refused_runs_leave_no_folder_behind() {
    let dir = scratch("refused");
    let out = dir.join("report");
    // A scenario naming a URDF that does not exist is refused only when the robot loads.
    let path = dir.join("missing_robot.toml");
    std::fs::write(
        &path,
        "name = \"m\"\nrobot = \"no/such.urdf\"\nduration_s = 0.6\nmethods = [\"none\"]\n[task]\nkind = \"hold\"\n",
    )
    .unwrap();
    assert_rejected(
        &["run", path.to_str().unwrap(), "--seeds", "1", "--out", out.to_str().unwrap()],
        "",
        &["such.urdf"],
    );
    assert!(!out.exists(), "an empty --out is left behind");
    assert_rejected(
        &["sweep", "--quick", "--shard", "0/18446744073709551615", "--out", out.to_str().unwrap()],
        "",
        &["at most"],
    );
    assert!(!out.exists(), "an empty --out is left behind");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn one_seed_prints_no_interval_and_costs_are_capped() {
    let dir = scratch("seeds");
    let file = scenario(&dir, "tiny");
    let out = dir.join("report");
    let run = hya(&["run", &file, "--seeds", "1", "--out", out.to_str().unwrap()], "");
    assert_eq!(run.status.code(), Some(0), "{}", String::from_utf8_lossy(&run.stderr));
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(report.contains("± n/a") && !report.contains("inf"), "a single seed's interval");
    // An hour of simulated time at a thousand sub-steps over 20 seeds: refused with its figure.
    let long = dir.join("long.toml");
    std::fs::write(
        &long,
        "name = \"long\"\nduration_s = 3600\nmethods = [\"none\", \"lu\"]\n[task]\nkind = \"hold\"\n[plant]\nsubsteps = 1000\n",
    )
    .unwrap();
    let refused = dir.join("refused");
    assert_rejected(
        &["run", long.to_str().unwrap(), "--out", refused.to_str().unwrap()],
        "",
        &["integration steps", "--no-cost-limit"],
    );
    assert!(!refused.exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn unknown_scenarios_and_robots_are_named_with_the_nearest_one() {
    assert_rejected(
        &["run", "panda_gotoo"],
        "",
        &["neither a scenario file nor a built-in", "did you mean `panda_goto`"],
    );
    let dir = scratch("misspelt");
    let file = dir.join("scenario.toml");
    std::fs::write(
        &file,
        "name = \"x\"\nrobot = \"pnada\"\nduration_s = 1\nmethods = [\"none\"]\n[task]\nkind = \"hold\"\n",
    )
    .unwrap();
    let out = dir.join("out");
    assert_rejected(
        &["run", file.to_str().unwrap(), "--out", out.to_str().unwrap()],
        "",
        &["`pnada` is neither a shipped robot", "did you mean `panda`"],
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn scenarios_lists_every_built_in_scenario_once() {
    let output = hya(&["scenarios"], "");
    let text = String::from_utf8(output.stdout).unwrap();
    let names: Vec<&str> = text.lines().map(|l| l.split_whitespace().next().unwrap()).collect();
    let expected: Vec<&str> = hya_sim::Scenario::builtin_names()
        .chain(hya_sim::Scenario::arm_goto_names())
        .chain(hya_sim::Scenario::task_space_names())
        .collect();
    assert_eq!(names, expected);
    let json: serde_json::Value = serde_json::from_slice(&hya(&["scenarios", "--json"], "").stdout).unwrap();
    assert_eq!(json.as_array().unwrap().len(), expected.len());
    assert_eq!(json[0]["name"], "goto_internal");
}

/// A run killed (SIGKILL) at any moment leaves a folder that the next `--force` cleans
/// completely: every file in it afterwards is the new run's (listed in its manifest), and no
/// temporary file of the killed run stays.
#[cfg(unix)]
#[test]
fn a_run_killed_at_any_moment_leaves_a_folder_force_cleans() {
    let dir = scratch("killed");
    let file = scenario(&dir, "tiny");
    let out = dir.join("report");
    let out_arg = out.to_str().unwrap();
    for delay_ms in [0, 30, 80, 150, 300, 600, 1200] {
        let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_hya"))
            .args(["run", &file, "--out", out_arg, "--seeds", "2", "--force"])
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(std::time::Duration::from_millis(delay_ms));
        let _ = child.kill(); // SIGKILL; it may have finished already
        let _ = child.wait();
        let again = hya(&["run", &file, "--out", out_arg, "--seeds", "2", "--force"], "");
        assert_eq!(again.status.code(), Some(0), "after {delay_ms} ms: {}", String::from_utf8_lossy(&again.stderr));
        let manifest = std::fs::read_to_string(out.join(".hya-files")).unwrap();
        for entry in std::fs::read_dir(&out).unwrap() {
            let name = entry.unwrap().file_name().into_string().unwrap();
            assert!(
                name == ".hya-files" || manifest.lines().any(|l| l.ends_with(&format!("  {name}"))),
                "after {delay_ms} ms: {name} is left over"
            );
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn results_go_to_stdout_and_quiet_silences_the_rest() {
    let dir = scratch("quiet");
    let file = scenario(&dir, "tiny");
    let out = dir.join("report");
    let output = hya(&["run", &file, "--out", out.to_str().unwrap(), "--seeds", "2", "--quiet"], "");
    assert_eq!(output.status.code(), Some(0), "{}", String::from_utf8_lossy(&output.stderr));
    assert!(output.stderr.is_empty(), "quiet: {}", String::from_utf8_lossy(&output.stderr));
    let stdout = String::from_utf8(output.stdout).unwrap();
    assert!(stdout.lines().last().unwrap().starts_with("report: "), "{stdout}");
    let json = hya(&["run", &file, "--out", out.to_str().unwrap(), "--seeds", "2", "--force", "-q", "--json"], "");
    let value: serde_json::Value = serde_json::from_slice(&json.stdout).unwrap();
    assert!(value["claims"].is_array() && value["report"].as_str().unwrap().ends_with("report.md"), "{value}");
    let robots: serde_json::Value = serde_json::from_slice(&hya(&["robots", "--json"], "").stdout).unwrap();
    assert_eq!(robots[0]["name"], "planar2");
    assert_eq!(robots[0]["joints"][1], "elbow");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn every_per_joint_list_that_does_not_fit_is_named_at_once_before_the_cost() {
    let dir = scratch("lists");
    let file = dir.join("scenario.toml");
    std::fs::write(
        &file,
        "name = \"x\"\nrobot = \"planar2\"\nduration_s = 1\nmethods = [\"none\"]\n[task]\nkind = \"hold\"\n\
         [controller]\nnatural_frequency_rad_s = [12.0, 12.0]\ntorque_limit_nm = [150.0, 150.0]\n\
         [plant]\nactuator = \"ideal\"\nfriction = \"lugre\"\n",
    )
    .unwrap();
    let out = dir.join("out");
    let output = hya(&["run", file.to_str().unwrap(), "--out", out.to_str().unwrap()], "");
    let message = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{message}");
    for list in [
        "plant.static_nm",
        "plant.coulomb_nm",
        "plant.viscous_nm_s",
        "plant.bristle_stiffness_nm_rad",
        "plant.bristle_damping_nm_s_rad",
    ] {
        assert!(message.contains(&format!("`{list}` (6 values)")), "{list}: {message}");
    }
    assert!(message.contains("5 per-joint settings do not fit the arm's 2 joints"), "{message}");
    assert!(!message.contains("integration steps"), "refused after the cost line: {message}");
    std::fs::remove_dir_all(&dir).unwrap();
}
