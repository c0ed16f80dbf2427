//! Hostile input to the row commands (issue 18): lines without end, rows without end, absurd
//! intervals, step counts and start poses, and results that overflow. Each is refused with exit
//! code 2 and a short message naming the line, option or value; no command prints NaN or inf.

use crate::common::{assert_rejected, hya, hya_bytes};

/// Every command that reads rows, with arguments that make it run.
const ROW_COMMANDS: [&[&str]; 8] = [
    &["filter"],
    &["estimate", "--robot", "hya"],
    &["id", "--robot", "hya"],
    &["fd", "--robot", "hya"],
    &["mass", "--robot", "hya"],
    &["gravity", "--robot", "hya"],
    &["plant", "--robot", "hya", "--ideal"],
    &["plant", "--robot", "hya"],
];

fn stderr(output: &std::process::Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

/// A command's output must hold no NaN or infinity.
fn assert_all_finite(stdout: &[u8]) {
    let text = String::from_utf8_lossy(stdout);
    // The header is the first line, if its first cell is not a number ("inf" and "NaN" are).
    let header = text.lines().next().is_some_and(|l| l.split(',').next().unwrap().parse::<f64>().is_err());
    for value in text.lines().skip(usize::from(header)).flat_map(|l| l.split(',')) {
        let v: f64 = value.parse().unwrap();
        assert!(v.is_finite(), "{value} written");
    }
}

#[test]
fn a_line_longer_than_the_limit_is_refused_by_every_row_command() {
    // 2 MiB of digits and spaces on one line: once took gigabytes in `hya filter`.
    let line: Vec<u8> = b"1 ".iter().copied().cycle().take(2 << 20).collect();
    for args in ROW_COMMANDS {
        let mut input = b"# a comment, then the long line\n".to_vec();
        input.extend_from_slice(&line);
        let output = hya_bytes(args, &input);
        assert_eq!(output.status.code(), Some(2), "{args:?}: {}", stderr(&output));
        let message = stderr(&output);
        assert!(message.contains("line 2") && message.contains("1048576 bytes"), "{args:?}: {message}");
        assert!(message.len() < 200, "{message}");
    }
}

#[test]
fn a_row_of_too_many_values_is_refused_before_any_state_is_made() {
    // 100 000 one-digit values fit in 1 MiB; `hya filter` would have made a filter for each.
    let row = "1 ".repeat(100_000) + "\n";
    assert_rejected(&["filter"], &row, &["line 1", "more than 4096 values"]);
    // The cap itself is accepted.
    let output = hya(&["filter"], &("0.5 ".repeat(4096) + "\n"));
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    assert_eq!(crate::common::data_rows(&String::from_utf8(output.stdout).unwrap()).concat().len(), 3 * 4096);
}

#[cfg(unix)]
#[test]
fn dev_zero_on_stdin_is_refused_at_once() {
    use std::process::{Command, Stdio};
    use std::time::{Duration, Instant};
    for args in [&["filter"][..], &["estimate", "--robot", "hya"], &["plant", "--robot", "hya", "--ideal"]] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_hya"))
            .args(args)
            .stdin(std::fs::File::open("/dev/zero").unwrap())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let start = Instant::now();
        let status = loop {
            if let Some(status) = child.try_wait().unwrap() {
                break status;
            }
            if start.elapsed() > Duration::from_secs(20) {
                child.kill().unwrap();
                child.wait().unwrap();
                panic!("{args:?} still reading /dev/zero after 20 s");
            }
            std::thread::sleep(Duration::from_millis(10));
        };
        let output = child.wait_with_output().unwrap();
        assert_eq!(status.code(), Some(2), "{args:?}");
        let message = stderr(&output);
        assert!(message.contains("line 1") && message.contains("1048576 bytes"), "{args:?}: {message}");
    }
}

#[test]
fn absurd_sample_times_are_refused_with_the_value_in_short() {
    let q_tau = "0 0 -0.78 0.78 0.78 0 0 0 0 0 0 0\n0 0 -0.78 0.78 0.78 0 0 0 0 0 0 0\n";
    // Once accepted, every output row equal to the first.
    assert_rejected(&["estimate", "--robot", "hya", "--dt", "1e-300"], q_tau, &["--dt 1e-300", "1e-6"]);
    assert_rejected(&["estimate", "--robot", "hya", "--dt", "4.9e-324"], q_tau, &["--dt 4.941e-324"]);
    assert_rejected(&["estimate", "--robot", "hya", "--dt", "2"], q_tau, &["--dt 2", "between 1e-6 and 1 s"]);
    assert_rejected(&["filter", "--dt", "1e-300"], "0\n1\n", &["--dt 1e-300"]);
    assert_rejected(&["plant", "--robot", "hya", "--ideal", "--dt", "1e-300"], "0 0 0 0 0 0 0\n", &["--dt 1e-300"]);
    // Parameters that leave the filter still between samples, or never damped.
    assert_rejected(&["filter", "--omega1", "1e-300"], "0\n", &["--omega1 1e-300", "--dt 0.001"]);
    assert_rejected(&["filter", "--zeta", "1e-300"], "0\n", &["--zeta 1e-300", "at least"]);
    // hya-core's own refusals, value in short.
    assert_rejected(&["filter", "--omega2", "1e300"], "0\n", &["--omega2 1e300", "times --dt", "100"]);
    for args in [&["estimate", "--robot", "hya", "--dt", "1e-300"][..], &["filter", "--omega1", "1e300"]] {
        let message = stderr(&hya(args, q_tau));
        assert!(message.len() < 200, "{message}");
    }
}

#[test]
fn plant_steps_are_capped() {
    // 1e6 s under the 0.1 ms ideal physics step: 1e10 steps, once accepted as 1e6 rows.
    let output = hya(&["plant", "--robot", "hya", "--ideal", "--until", "1e6", "--dt", "1"], "0 0 0 0 0 0 0\n");
    assert_eq!(output.status.code(), Some(2));
    let message = stderr(&output);
    assert!(message.contains("1e10 integration steps") && message.contains("more than 1e7"), "{message}");
    assert!(output.stdout.is_empty(), "refused before running");
    assert_rejected(&["plant", "--robot", "hya", "--ideal", "--until", "1e300"], "0 0 0 0 0 0 0\n", &["--until 1e300"]);
    assert_rejected(&["plant", "--robot", "hya", "--ideal"], "0 0 0 0 0 0 0\n1e300 0 0 0 0 0 0\n", &["1e300", "1e6"]);
}

#[test]
fn plant_without_a_scenario_runs_each_shipped_arms_own() {
    // Rows at 0 and 0.2 s of zero torque: the arm sags under gravity against its friction.
    for (robot, dof) in [("panda", 7), ("ur5", 6), ("planar2", 2)] {
        let row = |t: f64| format!("{t}{}\n", " 0".repeat(dof));
        let output = hya(&["plant", "--robot", robot, "--dt", "0.01"], &(row(0.0) + &row(0.2)));
        assert_eq!(output.status.code(), Some(0), "{robot}: {}", stderr(&output));
        assert_all_finite(&output.stdout);
        let text = String::from_utf8(output.stdout).unwrap();
        let rows = crate::common::data_rows(&text);
        assert_eq!(rows.len(), 21, "{robot}: rows every 10 ms from 0 to 0.2 s");
        assert!(rows.iter().all(|r| r.len() == 1 + 2 * dof), "{robot}");
    }
    // A URDF of one's own has no built-in plant.
    let urdf = concat!(env!("CARGO_MANIFEST_DIR"), "/../robots/urdf/planar2.urdf");
    assert_rejected(&["plant", "--robot", urdf], "0 0 0\n", &["--scenario", "--ideal"]);
    let output = hya(&["plant", "--robot", urdf, "--ideal", "--dt", "0.1"], "0 0 0\n1 0 0\n");
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
}

#[test]
fn absurd_start_poses_are_refused_naming_the_joint() {
    let args = |q0: &'static str| ["plant", "--robot", "hya", "--ideal", "--q0", q0];
    let torque = "0 0 0 0 0 0 0\n";
    assert_rejected(&args("1e300 0 0 0 0 0"), torque, &["--q0", "1e300", "outside its range"]);
    // Within ±100 rad but beyond a joint's limits: the message names that joint.
    let output = hya(&args("0 0 0 0 0 50"), torque);
    assert_eq!(output.status.code(), Some(2));
    let message = stderr(&output);
    assert!(message.contains("WFE") && message.contains("at 50"), "{message}");
}

#[test]
fn results_that_overflow_are_never_written() {
    // Finite input, infinite result: inverse dynamics at 1e308 everywhere.
    let huge = "1e308 ".repeat(18) + "\n";
    for command in ["id", "fd"] {
        let output = hya(&[command, "--robot", "hya"], &("0 ".repeat(18) + "\n" + &huge));
        assert_eq!(output.status.code(), Some(2), "{command}");
        assert_all_finite(&output.stdout);
        let message = stderr(&output);
        assert!(message.contains("line 2") && message.len() < 300, "{command}: {message}");
    }
    // The plant under 1e308 N·m leaves the finite numbers at once; the failure names the time.
    let torque = "0 1e308 1e308 1e308 1e308 1e308 1e308\n0.01 0 0 0 0 0 0\n";
    let output = hya(&["plant", "--robot", "hya", "--ideal"], torque);
    assert_eq!(output.status.code(), Some(2));
    assert_all_finite(&output.stdout);
    let message = stderr(&output);
    assert!(message.contains("t = ") && message.len() < 300, "{message}");
}

#[test]
fn long_fields_are_echoed_cut() {
    let field = "x".repeat(100_000);
    let output = hya(&["filter"], &format!("0 {field}\n"));
    assert_eq!(output.status.code(), Some(2));
    let message = stderr(&output);
    assert!(message.contains("line 1, column 2") && message.contains('…') && message.len() < 200, "{message}");
}

#[test]
fn an_empty_cell_is_refused_not_skipped() {
    // Skipping the empty q2 cell once moved tau1 under q2 and gave d̂ = −7.18 instead of −21.83.
    let log = "t,q1,q2,tau1,tau2,current\n0,0.1,0.2,1,2,5\n0.001,0.1,,1,2,5\n";
    let args = ["estimate", "--robot", "planar2", "--timestamps", "--columns", "t,q1-q2,tau1-tau2"];
    assert_rejected(&args, log, &["line 3, column 3: an empty cell"]);
    // Without --columns, and in a command that reads bare rows, the same.
    assert_rejected(&["gravity", "--robot", "planar2"], "0.1,\n", &["line 1, column 2: an empty cell"]);
}

#[test]
fn a_row_narrower_or_wider_than_the_header_is_refused() {
    let args = ["estimate", "--robot", "planar2", "--timestamps", "--columns", "t,q1-q2,tau1-tau2"];
    let short = "t,q1,q2,tau1,tau2,current\n0,0.1,0.2,1,2,5\n0.001,0.1,0.2,1,2\n";
    assert_rejected(&args, short, &["line 3: 5 values, but the header on line 1 names 6"]);
    let long = "t,q1,q2,tau1,tau2\n0,0.1,0.2,1,2,5\n";
    assert_rejected(&args, long, &["line 2: 6 values, but the header on line 1 names 5"]);
}
