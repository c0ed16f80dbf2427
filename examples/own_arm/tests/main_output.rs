//! Runs the example's `main` and checks what it prints: the loop with the estimate `d̂` in the
//! command tracks better than without it, on every joint, and `d̂` follows the simulated arm's
//! disturbance. The thresholds are on the machinery (a smaller error than the same loop without
//! compensation, an estimate closer to `d` than zero is), not on figures from the paper. And the
//! README's section "On your robot" shows this crate's loop and output as they are.

use std::path::Path;
use std::process::Command;

/// The example's standard output; fails the test if it does not exit successfully.
fn run_main() -> String {
    let run = Command::new(env!("CARGO_BIN_EXE_own_arm")).output().expect("the example runs");
    let output = String::from_utf8(run.stdout).expect("UTF-8 output");
    assert!(run.status.success(), "exit {:?}\n{output}\n{}", run.status, String::from_utf8_lossy(&run.stderr));
    output
}

/// The README's section "On your robot", up to the next section.
fn readme_section() -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../README.md");
    let readme = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let start = readme.find("\n## On your robot\n").expect("README has a section \"On your robot\"") + 1;
    let end = readme[start + 1..].find("\n## ").map_or(readme.len(), |i| start + 1 + i);
    readme[start..end].to_string()
}

/// The contents of the section's code block opened by `fence` (e.g. "```text").
fn code_block<'a>(section: &'a str, fence: &str) -> &'a str {
    let open = section.find(&format!("{fence}\n")).unwrap_or_else(|| panic!("no {fence} block in:\n{section}"));
    let body = &section[open + fence.len() + 1..];
    &body[..body.find("```").expect("the block is closed")]
}

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
    let output = run_main();
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

#[test]
fn the_readme_shows_the_loop_of_main_rs() {
    let main = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("src/main.rs")).expect("main.rs");
    let section = readme_section();
    let shown = code_block(&section, "```rust,ignore");
    assert!(shown.lines().count() > 10, "{shown}");
    assert!(main.contains(shown), "the README's loop differs from src/main.rs:\n{shown}");
}

#[test]
fn the_readme_shows_what_main_prints() {
    let section = readme_section();
    let shown = code_block(&section, "```text");
    let printed = run_main();
    assert_eq!(shown.lines().count(), printed.lines().count(), "README:\n{shown}\nprinted:\n{printed}");
    for (readme, line) in shown.lines().zip(printed.lines()) {
        let words = |text: &str| text.split_whitespace().map(str::to_string).collect::<Vec<_>>();
        for (a, b) in words(readme).iter().zip(words(line).iter()) {
            // Figures agree to their printed precision (the last digit may differ where another
            // CPU rounds differently), words exactly.
            match (a.parse::<f64>(), b.parse::<f64>()) {
                (Ok(x), Ok(y)) => {
                    assert!((x - y).abs() <= 2e-4 * x.abs().max(1.0), "README {readme:?}, printed {line:?}")
                }
                _ => assert_eq!(a, b, "README {readme:?}, printed {line:?}"),
            }
        }
        assert_eq!(words(readme).len(), words(line).len(), "README {readme:?}, printed {line:?}");
    }
}
