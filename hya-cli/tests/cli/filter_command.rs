//! `hya filter` end to end: the binary on sinusoids against the closed-form `H(jω)`, and its
//! answers to bad input.

use crate::common::{assert_rejected, hya};
use nalgebra::{Complex, ComplexField};

/// `[H, jωH, (jω)²H]` of the paper's filter, ζ = 0.8, ω1 = ω2 = 50 rad/s.
fn paper_response(omega: f64) -> [Complex<f64>; 3] {
    let s = Complex::new(0.0, omega);
    let h = Complex::new(50.0 * 2500.0, 0.0) / ((s + 50.0) * (s * s + s * 80.0 + 2500.0));
    [h, s * h, s * s * h]
}

#[test]
fn sinusoids_come_out_scaled_and_shifted_by_h() {
    let dt = 1e-3;
    let omegas = [2.0 * std::f64::consts::PI, 2.0 * std::f64::consts::PI * 8.0, 60.0];
    let steps = 3000;
    let input: String = (0..=steps)
        .map(|k| {
            let t = k as f64 * dt;
            let row: Vec<String> = omegas.iter().map(|w| format!("{}", (w * t).sin())).collect();
            row.join(",") + "\n"
        })
        .collect();
    let output = hya(&["filter", "--zeta", "0.8", "--omega1", "50", "--omega2", "50", "--dt", "0.001"], &input);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let text = String::from_utf8(output.stdout).unwrap();
    assert_eq!(text.lines().next(), Some("x1_u1,x1_u2,x1_u3,x2_u1,x2_u2,x2_u3,x3_u1,x3_u2,x3_u3"));
    let rows = crate::common::data_rows(&text);
    assert_eq!(rows.len(), steps + 1);
    assert!(rows.iter().all(|row| row.len() == 3 * omegas.len()));
    // After 2 s (40 group delays), each state is Im(H_i(jω) e^{jωt}) to 1 % of |H_i|: that bounds
    // the gain error by 1 % and the phase error by 0.6°.
    for (k, row) in rows.iter().enumerate().skip(2000) {
        let t = k as f64 * dt;
        for (channel, &omega) in omegas.iter().enumerate() {
            for (state, expected) in paper_response(omega).into_iter().enumerate() {
                let value = row[state * omegas.len() + channel];
                let ideal = (expected * Complex::new(0.0, omega * t).exp()).im;
                assert!(
                    (value - ideal).abs() <= 0.01 * expected.modulus(),
                    "t = {t}, ω = {omega}, x{}: {value} vs {ideal}",
                    state + 1
                );
            }
        }
    }
}

#[test]
fn first_row_sets_the_state_at_rest() {
    let output = hya(&["filter"], "1.5 -2\n");
    assert!(output.status.success());
    assert_eq!(
        String::from_utf8(output.stdout).unwrap(),
        "x1_u1,x1_u2,x2_u1,x2_u2,x3_u1,x3_u2\n1.5,-2.0,0.0,0.0,0.0,0.0\n"
    );
}

#[test]
fn bad_input_names_the_line_and_exits_with_2() {
    assert_rejected(&["filter"], "0 0\n1 1\n1 x\n", &["line 3", "column 2", "not a number"]);
    assert_rejected(&["filter"], "0 0\n# comment\n\n1\n", &["line 4: 1 values, but the first row, line 1, has 2"]);
    assert_rejected(&["filter"], "0\nnan\n", &["line 2", "non-finite"]);
    assert_rejected(&["filter"], "0\n1e999\n", &["line 2", "non-finite"]);
}

#[test]
fn bad_parameters_are_named() {
    assert_rejected(&["filter", "--zeta", "-0.5"], "0\n", &["zeta", "-0.5"]);
    assert_rejected(&["filter", "--omega1", "0"], "0\n", &["--omega1 0"]);
    assert_rejected(&["filter", "--dt", "inf"], "0\n", &["--dt inf", "between"]);
}

#[test]
fn absurd_rates_and_huge_samples_are_refused_at_once() {
    // ω·dt far beyond the discretisable range once looped for minutes in the matrix exponential.
    assert_rejected(&["filter", "--omega1", "1e200"], "0\n", &["--omega1 1e200", "100"]);
    assert_rejected(&["filter", "--dt", "1e304"], "0\n", &["--dt 1e304", "between"]);
    assert_rejected(&["filter", "--zeta", "1e200"], "0\n", &["zeta"]);
    // A finite sample that would overflow the state is refused with its line, never printed as inf.
    let output = hya(&["filter"], "0\n1e308\n");
    assert_eq!(output.status.code(), Some(2));
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(!stdout.contains("inf") && !stdout.contains("NaN"), "{stdout}");
    let message = String::from_utf8_lossy(&output.stderr);
    assert!(message.contains("line 2") && message.contains("too large"), "{message}");
    // With ω = 1e8 at 1 kHz (ω·dt = 1e5) the filter is refused, not run to NaN.
    assert_rejected(&["filter", "--omega1", "1e8", "--omega2", "1e8"], "0\n1\n", &["--omega1 1e8"]);
}
