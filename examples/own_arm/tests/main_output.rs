//! Runs the example's `main` and checks what it prints: the loop with the estimate `d̂` in the
//! command tracks better than without it, on every joint, and `d̂` follows the simulated arm's
//! disturbance. The thresholds are on the machinery (a smaller error than the same loop without
//! compensation, an estimate closer to `d` than zero is), not on figures from the paper.

use std::process::Command;

/// The numbers after `label` on the line that starts with it.
fn numbers(output: &str, label: &str) -> Vec<f64> {
    let line = output
        .lines()
        .find(|line| line.starts_with(label))
        .unwrap_or_else(|| panic!("no line {label:?} in:\n{output}"));
    line[label.len()..]
        .split_whitespace()
        .map(|word| word.parse().unwrap_or_else(|e| panic!("{word:?} in {line:?}: {e}")))
        .collect()
}

#[test]
fn compensation_tracks_better_and_the_estimate_follows_the_disturbance() {
    let run = Command::new(env!("CARGO_BIN_EXE_own_arm")).output().expect("the example runs");
    let output = String::from_utf8(run.stdout).expect("UTF-8 output");
    assert!(run.status.success(), "exit {:?}\n{output}\n{}", run.status, String::from_utf8_lossy(&run.stderr));
    let without = numbers(&output, "without compensation: tracking RMS (mrad)");
    let with = numbers(&output, "with compensation:    tracking RMS (mrad)");
    let d = numbers(&output, "disturbance d, with compensation: RMS (N·m)");
    let error = numbers(&output, "estimate error d̂ − d, with compensation: RMS (N·m)");
    for series in [&without, &with, &d, &error] {
        assert_eq!(series.len(), 3, "one figure per joint:\n{output}");
        assert!(series.iter().all(|x| x.is_finite() && *x >= 0.0), "{output}");
    }
    for joint in 0..3 {
        // The disturbance is there to be compensated (friction alone is ≥ 0.8 N·m when moving).
        assert!(d[joint] > 0.5, "joint {joint}: d is too small to test anything:\n{output}");
        // d̂ explains most of d: its error is well below d itself (as if d̂ were zero).
        assert!(error[joint] < 0.5 * d[joint], "joint {joint}: d̂ does not follow d:\n{output}");
        // Compensation at least halves the tracking error.
        assert!(with[joint] < 0.5 * without[joint], "joint {joint}: compensation does not help:\n{output}");
    }
}
