//! One command's output is the next one's input: `hya excite | hya track | hya estimate`
//! (and `identify`, `id`, `gravity`), in the one table format, with its header, quoting,
//! ragged rows and empty cells.

use crate::common::{assert_rejected, data_rows, hya};

/// `hya ARGS` on `input`, which must succeed: its stdout.
fn run(args: &[&str], input: &str) -> String {
    let output = hya(args, input);
    assert!(output.status.success(), "{args:?}: {}", String::from_utf8_lossy(&output.stderr));
    String::from_utf8(output.stdout).unwrap()
}

/// A 6 s reference for planar2 and the log `hya track` records on it.
fn reference_and_log() -> (String, String) {
    let reference =
        run(&["excite", "--robot", "planar2", "--periods", "3", "--base-hz", "0.5", "--candidates", "5"], "");
    let log = run(&["track", "--robot", "planar2", "--seed", "2"], &reference);
    (reference, log)
}

#[test]
fn excite_track_estimate_identify_id_and_gravity_read_each_others_rows() {
    let (reference, log) = reference_and_log();
    // estimate finds t, q and τ by name in the log track wrote.
    let estimate = run(&["estimate", "--robot", "planar2", "--timestamps"], &log);
    assert!(estimate.starts_with("t [s],d_hat_shoulder [N m],d_hat_elbow [N m]\n"), "{}", &estimate[..80]);
    assert_eq!(data_rows(&estimate).len(), data_rows(&log).len());
    // identify reads the same log.
    let out = std::env::temp_dir().join(format!("hya-pipes-identify-{}", std::process::id()));
    run(&["identify", "--robot", "planar2", "--timestamps", "--out", out.to_str().unwrap()], &log);
    assert!(std::fs::read_to_string(out.join("friction.toml")).unwrap().contains("coulomb_nm"));
    let _ = std::fs::remove_dir_all(&out);
    // id reads q, q̇, q̈ by name from the reference excite wrote (its t left out), as by position.
    let by_name = run(&["id", "--robot", "planar2"], &reference);
    assert!(by_name.starts_with("tau_shoulder [N m],tau_elbow [N m]\n"), "{by_name}");
    assert_eq!(by_name, run(&["id", "--robot", "planar2", "--columns", "2-7"], &reference));
    assert_eq!(data_rows(&by_name).len(), data_rows(&reference).len());
    // gravity reads q by name from track's log: the same through every way of naming them.
    let gravity = run(&["gravity", "--robot", "planar2"], &log);
    for columns in ["q_shoulder,q_elbow", "q_shoulder-q_elbow", "2,3", "2-3"] {
        assert_eq!(run(&["gravity", "--robot", "planar2", "--columns", columns], &log), gravity, "{columns}");
    }
    let rows = data_rows(&gravity);
    assert_eq!(rows.len(), data_rows(&log).len());
    assert!(rows.iter().all(|r| r.len() == 2 && r.iter().all(|g| g.is_finite())));
}

#[test]
fn quoted_headers_blank_separated_rows_and_raw_rows_read_the_same() {
    let (_, log) = reference_and_log();
    let estimate = run(&["estimate", "--robot", "planar2", "--timestamps"], &log);
    // The header's cells quoted, as spreadsheets and pandas may write them.
    let (header, rows) = log.split_once('\n').unwrap();
    let quoted: Vec<String> = header.split(',').map(|c| format!("\"{c}\"")).collect();
    assert_eq!(run(&["estimate", "--robot", "planar2", "--timestamps"], &(quoted.join(" , ") + "\n" + rows)), estimate);
    // Rows of numbers alone, separated by blanks, read by position.
    let raw = run(&["track", "--robot", "planar2", "--seed", "2", "--no-header"], &reference_and_log().0);
    assert!(raw.starts_with("0.0,"), "{}", &raw[..40]);
    let blank = raw.replace(',', "  \t");
    let raw_estimate = run(&["estimate", "--robot", "planar2", "--timestamps", "--no-header"], &blank);
    assert_eq!(raw_estimate, estimate.split_once('\n').unwrap().1);
}

#[test]
fn ragged_rows_empty_cells_and_other_units_are_refused_by_line_and_column() {
    let (_, log) = reference_and_log();
    let lines: Vec<&str> = log.lines().collect();
    let with_line = |k: usize, replacement: &str| -> String {
        let mut edited: Vec<&str> = lines.clone();
        edited[k] = replacement;
        edited.join("\n") + "\n"
    };
    let estimate = ["estimate", "--robot", "planar2", "--timestamps"];
    // A cell too few on line 11 (the tenth row).
    let short = lines[10].rsplit_once(',').unwrap().0.to_string();
    assert_rejected(&estimate, &with_line(10, &short), &["line 11: 4 values, but the header on line 1 names 5"]);
    // An empty cell: its line and column, whether or not the command reads that column.
    let cells: Vec<&str> = lines[20].split(',').collect();
    let empty = [cells[0], cells[1], "", cells[3], cells[4]].join(",");
    assert_rejected(&estimate, &with_line(20, &empty), &["line 21, column 3: an empty cell"]);
    // A log in degrees is not read as radians.
    let degrees = lines[0].replacen("q_shoulder [rad]", "q_shoulder [deg]", 1);
    assert_rejected(&estimate, &with_line(0, &degrees), &["line 1, column 2", "[deg]", "never converted"]);
    // Columns hya cannot find by name or by count are asked for.
    assert_rejected(&["gravity", "--robot", "hya"], &log, &["expected 6 values", "no column \"q_SAA\"", "--columns"]);
}
