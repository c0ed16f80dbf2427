//! `hya estimate --timestamps`: against an independent NumPy/SciPy implementation
//! (`tools/timestamped_estimate_reference.py`), against the fixed-step estimator on a regular
//! log and on a fine grid, and its answers to hostile logs.

use crate::common::{assert_rejected, hya};

fn data(name: &str) -> String {
    std::fs::read_to_string(format!("{}/tests/data/{name}", env!("CARGO_MANIFEST_DIR"))).unwrap()
}

/// `hya ARGS` on `input`, which must succeed: its stdout as rows, and its stderr.
fn run(args: &[&str], input: &str) -> (Vec<Vec<f64>>, String) {
    let output = hya(args, input);
    let stderr = String::from_utf8(output.stderr).unwrap();
    assert!(output.status.success(), "{stderr}");
    (crate::common::data_rows(&String::from_utf8(output.stdout).unwrap()), stderr)
}

#[test]
fn a_jittered_log_with_gaps_matches_the_scipy_reference_to_1e_9() {
    let args = ["estimate", "--robot", "planar2", "--timestamps", "--dt", "0.01", "--columns", "t,q1-q2,tau1-tau2"];
    let (estimate, stderr) = run(&args, &data("timestamped_planar2_log.csv"));
    let reference = crate::common::data_rows(&data("timestamped_planar2_estimate.csv"));
    assert_eq!(estimate.len(), reference.len());
    assert_eq!(estimate.len(), 110);
    let mut worst = 0.0f64;
    for (row, expected) in estimate.iter().zip(&reference) {
        assert_eq!(row[0], expected[0], "the times are echoed as read");
        for j in 1..3 {
            worst = worst.max((row[j] - expected[j]).abs());
        }
    }
    eprintln!("largest |d̂ − reference|: {worst:e} N·m");
    assert!(worst < 1e-9, "{worst:e}");
    // Gaps of 30 to 45 ms (beyond 2.5 × 10 ms) are reported, bridged; the 2.5 s one restarts.
    assert!(stderr.contains("line 8: gap of 0.03833 s") && stderr.contains("bridged exactly"), "{stderr}");
    assert!(stderr.contains("line 83: gap of 2.5 s") && stderr.contains("restarted at rest"), "{stderr}");
    assert!(!stderr.contains("line 9:"), "a 10 ms step is no gap: {stderr}");
}

#[test]
fn timestamps_on_a_regular_log_equal_dt_mode_bit_for_bit() {
    // dt = 2⁻¹⁰ s: every t_k = 3 + k dt and every difference is exact in binary, so each step
    // is the fixed-step filter's own.
    let dt = 1.0 / 1024.0;
    let (mut plain, mut timed) = (String::new(), String::new());
    for k in 0..600 {
        let x = k as f64 * dt;
        let row = format!("{} {} {} {}", (3.0 * x).sin(), 0.5 + x, 4.0 * (2.0 * x).cos(), 1.0 - x * x);
        plain += &format!("{row}\n");
        timed += &format!("{},{}\n", 3.0 + x, row.replace(' ', ","));
    }
    let (fixed, _) = run(&["estimate", "--robot", "planar2", "--dt", &dt.to_string()], &plain);
    let (stamped, stderr) = run(&["estimate", "--robot", "planar2", "--timestamps", "--dt", &dt.to_string()], &timed);
    assert!(stderr.is_empty(), "{stderr}");
    assert_eq!(fixed.len(), 600);
    for (k, (a, b)) in fixed.iter().zip(&stamped).enumerate() {
        assert_eq!(b[0], 3.0 + k as f64 * dt);
        assert_eq!(a[..], b[1..], "row {k}");
    }
}

/// A small deterministic generator (64-bit LCG), for step lengths.
struct Lcg(u64);

impl Lcg {
    fn below(&mut self, n: u64) -> u64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (self.0 >> 33) % n
    }
}

#[test]
fn a_jittered_log_agrees_with_the_same_log_on_a_fine_regular_grid() {
    // A 1 kHz log whose steps jitter from 0.7 to 1.3 ms with gaps of 5 to 40 ms, its times on a
    // 0.1 ms grid (a logger's resolution), and the same signals on every point of that grid:
    // between two rows of the jittered log the fine log holds the straight line joining them.
    // The first-order hold is exact for such input, so both runs solve the same differential
    // equation exactly and may differ only by rounding: each of the 30 000 fine steps rounds
    // the states at about 1e-16 relative (|q̂̈| ≲ 10 rad/s², |τ̂| ≲ 10 N·m), the errors add up
    // to some 1e-11 to 1e-10 in the states, and ID multiplies them by gains of order one
    // (|M| < 1 kg m²). 1e-8 N·m bounds that with room (measured: 5e-10 N·m).
    let tick = 1e-4;
    let signal = |k: u64| {
        let t = k as f64 * tick;
        [-0.5 + 0.3 * (3.1 * t).sin(), 0.8 + 0.4 * (5.0 * t + 0.3).sin(), 8.0 * (2.0 * t).cos(), 1.5 + (7.0 * t).sin()]
    };
    let mut rng = Lcg(22);
    let mut samples = vec![0u64];
    while *samples.last().unwrap() < 30_000 {
        let step = if rng.below(20) == 0 { 50 + rng.below(350) } else { 7 + rng.below(7) };
        samples.push(samples.last().unwrap() + step);
    }
    let jittered: String = samples
        .iter()
        .map(|&k| {
            let s = signal(k);
            format!("{}\t{}\t{}\t{}\t{}\n", k as f64 * tick, s[0], s[1], s[2], s[3])
        })
        .collect();
    let mut fine = String::new();
    for pair in samples.windows(2) {
        let (a, b) = (signal(pair[0]), signal(pair[1]));
        for k in pair[0]..pair[1] {
            let w = (k - pair[0]) as f64 / (pair[1] - pair[0]) as f64;
            let row: Vec<String> = (0..4).map(|i| (a[i] + w * (b[i] - a[i])).to_string()).collect();
            fine += &(row.join(" ") + "\n");
        }
    }
    let last = signal(*samples.last().unwrap());
    fine += &format!("{} {} {} {}\n", last[0], last[1], last[2], last[3]);
    let (stamped, _) = run(&["estimate", "--robot", "planar2", "--timestamps", "--max-step", "1"], &jittered);
    let (gridded, _) = run(&["estimate", "--robot", "planar2", "--dt", "1e-4"], &fine);
    let mut worst = 0.0f64;
    for (row, &k) in stamped.iter().zip(&samples) {
        for j in 0..2 {
            worst = worst.max((row[1 + j] - gridded[k as usize][j]).abs());
        }
    }
    eprintln!("{} rows, largest |d̂_jittered − d̂_grid|: {worst:e} N·m", samples.len());
    assert!(worst < 1e-8, "{worst:e}");
}

#[test]
fn hostile_logs_are_named_by_line() {
    let timed = ["estimate", "--robot", "planar2", "--timestamps"];
    assert_rejected(
        &timed,
        "0 0 0 0 0\n0.001 0 0 0 0\n0.001 0 0 0 0\n",
        &["line 3", "t = 0.001 s", "strictly increase"],
    );
    assert_rejected(&timed, "0 0 0 0 0\n-1 0 0 0 0\n", &["line 2", "not after"]);
    assert_rejected(&timed, "0 0 0 0 0\nnan 0 0 0 0\n", &["line 2, column 1", "non-finite"]);
    assert_rejected(&timed, "0 0 0 0 0\n0.001 0 0 0\n", &["line 2: 4 values, but the first row, line 1, has 5"]);
    assert_rejected(&timed, "t q1 q2 tau1 tau2\n0 0 0 0 0\nt q1 q2 tau1 tau2\n", &["line 3, column 1", "not a number"]);
    let with = |spec: &'static str| {
        let mut args = timed.to_vec();
        args.extend(["--columns", spec]);
        args
    };
    let log = "t,q1,q2,qd1,qd2,tau1,tau2\n0,0,0,0,0,0,0\n0.001,0,0,0,0,0\n";
    assert_rejected(&with("t,q1-q2,tau1-tau2"), log, &["line 3: 6 values, but the header on line 1 names 7"]);
    // Without a header, rows are counted against the first.
    let headless = "0,0,0,0,0,0,0\n0.001,0,0,0,0,0\n";
    assert_rejected(&with("1,2-3,6-7"), headless, &["line 2: 6 values, but the first row, line 1, has 7"]);
    assert_rejected(&with("t,q1-q2,tau1-tau3"), log, &["selects 6 columns", "5 are read"]);
    assert_rejected(&with("t,q1-q2,tau1,torque2"), log, &["no column \"torque2\"", "line 1"]);
    assert_rejected(&with("t,q2-q1,tau1-tau2"), log, &["\"q2-q1\"", "ends before"]);
    assert_rejected(&with("0,2-3,6-7"), log, &["\"0\"", "count from 1"]);
    assert_rejected(&with("t,,q1"), log, &["empty item"]);
    assert_rejected(&with("1,2,2,6,7"), log, &["column 2 twice"]);
    assert_rejected(&with("t,q1-q2,tau1-tau2"), "0 0 0 0 0\n", &["no header"]);
    assert_rejected(&["estimate", "--robot", "planar2", "--max-step", "1"], "0 0 0 0\n", &["--timestamps"]);
    assert_rejected(&[&timed[..], &["--max-step", "-1"]].concat(), "0 0 0 0 0\n", &["--max-step", "> 0"]);
}

#[test]
fn columns_pick_q_and_tau_from_a_wider_log_by_position_too() {
    let log = data("timestamped_planar2_log.csv");
    let base = ["estimate", "--robot", "planar2", "--timestamps", "--dt", "0.01", "--columns"];
    let (by_name, _) = run(&[&base[..], &["t,q1-q2,tau1-tau2"]].concat(), &log);
    let (by_position, _) = run(&[&base[..], &["1,2-3,6-7"]].concat(), &log);
    assert_eq!(by_name, by_position);
    // The same columns alone, space-separated without a header, give the same rows.
    let narrow: String = crate::common::data_rows(&log.replace("t,q1", "#").replace(',', " "))
        .iter()
        .map(|r| format!("{} {} {} {} {}\n", r[0], r[1], r[2], r[5], r[6]))
        .collect();
    let (plain, _) = run(&base[..6], &narrow);
    assert_eq!(plain, by_name);
}

/// planar2's gravity torques in closed form (robots/urdf/planar2.urdf, g = 9.81 m/s²).
fn planar2_gravity(q: [f64; 2]) -> [f64; 2] {
    let (m1, m2, l1, c1, c2) = (3.0, 2.0, 0.5, 0.25, 0.2);
    let outer = m2 * c2 * (q[0] + q[1]).cos();
    [-9.81 * ((m1 * c1 + m2 * l1) * q[0].cos() + outer), -9.81 * outer]
}

#[test]
fn every_method_recovers_a_constant_disturbance_and_observers_read_velocity_columns() {
    // The arm held at q0 with τ = G(q0) − δ: every estimator must settle on d̂ = δ.
    let q0 = [0.4, -0.9];
    let delta = [1.5, -0.7];
    let g = planar2_gravity(q0);
    let tau = [g[0] - delta[0], g[1] - delta[1]];
    let mut narrow = String::new();
    let mut wide = String::from("q1,q2,tau1,tau2,current1,qd1,qd2\n");
    for _ in 0..1000 {
        narrow += &format!("{} {} 0 0 {} {}\n", q0[0], q0[1], tau[0], tau[1]);
        wide += &format!("{},{},{},{},9,0,0\n", q0[0], q0[1], tau[0], tau[1]);
    }
    let plain: String = narrow.lines().map(|l| l.replacen(" 0 0", "", 1) + "\n").collect();
    for method in ["lu", "chen", "momentum", "eso"] {
        let velocity = matches!(method, "chen" | "momentum");
        let base = ["estimate", "--robot", "planar2", "--method", method];
        let (rows, _) = run(&base, if velocity { &narrow } else { &plain });
        let last = rows.last().unwrap();
        for j in 0..2 {
            assert!((last[j] - delta[j]).abs() < 1e-6, "{method}: d̂ {last:?} after 1 s, δ = {delta:?}");
        }
        let spec = if velocity { "q1-q2,qd1-qd2,tau1-tau2" } else { "q1-q2,tau1-tau2" };
        let (picked, _) = run(&[&base[..], &["--columns", spec]].concat(), &wide);
        assert_eq!(picked, rows, "{method}: --columns picks the same q, q̇, τ");
    }
    assert_rejected(
        &["estimate", "--robot", "planar2", "--method", "chen"],
        &plain,
        &["line 1", "expected 6 values", "q̇"],
    );
    assert_rejected(
        &["estimate", "--robot", "planar2", "--method", "chen", "--bandwidth", "-1"],
        &narrow,
        &["--bandwidth -1"],
    );
    // A bandwidth beyond the sample rate: every observer names it, Chen's too (which once
    // printed rounding noise for it).
    for (method, log) in [("chen", &narrow), ("momentum", &narrow), ("eso", &plain)] {
        assert_rejected(
            &["estimate", "--robot", "planar2", "--method", method, "--bandwidth", "1e9"],
            log,
            &["= 1e9", "dt_s is at most 100"],
        );
    }
    assert_rejected(
        &["estimate", "--robot", "planar2", "--method", "eso", "--timestamps"],
        "0 0 0 0 0\n",
        &["--method eso with --timestamps", "only lu"],
    );
}

#[test]
fn restarts_are_reported_up_to_the_cap_then_counted() {
    // Every step of this log is a restart (10 s apart): 200 of them once meant 200 lines of stderr.
    let log: String = (0..201).map(|k| format!("{} 0.1 0.2 1 2\n", 10 * k)).collect();
    let output = hya(&["estimate", "--robot", "planar2", "--timestamps", "--dt", "0.01"], &log);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    assert_eq!(stderr.lines().filter(|l| l.contains("gap of")).count(), 20, "{stderr}");
    assert!(
        stderr.contains("200 gaps in all, 200 of them restarts of the estimator; the first 20 reported"),
        "{stderr}"
    );
}

#[test]
fn without_dt_the_nominal_step_is_the_log_s_median_step() {
    // A 100 Hz log: with the old fixed default of 1 ms, every step was reported as a gap.
    let log: String = (0..300).map(|k| format!("{} 0.1 0.2 1 2\n", k as f64 * 0.01)).collect();
    let (rows, stderr) = run(&["estimate", "--robot", "planar2", "--timestamps"], &log);
    assert_eq!(rows.len(), 300);
    assert!(stderr.contains("the log's median step, 0.01 s, is the nominal one"), "{stderr}");
    assert!(!stderr.contains("gap"), "{stderr}");
    // The same as giving it.
    let (given, _) = run(&["estimate", "--robot", "planar2", "--timestamps", "--dt", "0.01"], &log);
    assert_eq!(rows, given);
    let (one, stderr) = run(&["estimate", "--robot", "planar2", "--timestamps"], "0 0.1 0.2 1 2\n");
    assert_eq!(one.len(), 1);
    assert!(stderr.contains("no --dt, and no step in time order to take it from: 0.001 s"), "{stderr}");
}
