//! `hya run` writes only inside `--out`: a scenario name cannot name a path, and a folder that
//! holds anything is refused (or, with `--force`, an earlier report in it replaced) before any
//! simulation starts.
#![allow(clippy::unwrap_used)] // test helpers: a failed unwrap is a failed test

mod common;

use std::path::{Path, PathBuf};

use common::{assert_rejected, hya};

fn scratch(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("hya-cli-out-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
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
