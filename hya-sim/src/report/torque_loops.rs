//! The Plant section's torque loops as measured ([`crate::torque_response`]): each joint's
//! `A(jω)` locked and with the position loop closed at three amplitudes, the fitted model
//! against the design bandwidth, what the amplitude changes, and the back-drive. Every comparative
//! sentence is computed from the table it follows.

use std::fmt::Write as _;

use crate::io::svg::{line_grid_scaled, Panel, Scale, Series, PALETTE};
use crate::torque_response::{Mounting, Response, TorqueResponses, AMPLITUDES_NM};

use super::text::{joints_text, table_row};

/// The frequency at which the table compares locked and held gains, Hz.
const COMPARED_AT_HZ: f64 = 20.0;

/// The frequency at which the table gives the back-drive, Hz (63 rad/s, at the upper end of the
/// position loops' crossovers in the margins table).
const BACK_DRIVE_AT_HZ: f64 = 10.0;

/// A held gain that differs from the locked one by more than this fraction is another actuator
/// than the loops model.
const GAIN_CHANGE: f64 = 0.2;

/// A response that moves by more than this (`|ΔA|`) between the smallest and largest amplitude
/// is amplitude-dependent.
const AMPLITUDE_CHANGE: f64 = 0.1;

/// The lowest frequency where `|A|` falls below `1/√2`, interpolated in `log f` (the lowest
/// frequency measured if it is below there already); `None` where it stays above over the
/// frequencies measured.
fn measured_3db(frequencies: &[f64], r: &Response) -> Option<f64> {
    let level = std::f64::consts::FRAC_1_SQRT_2;
    let points: Vec<(f64, f64)> = frequencies.iter().zip(&r.gain_phase).map(|(f, (g, _))| (*f, *g)).collect();
    if let Some((f, _)) = points.first().filter(|(_, g)| *g < level) {
        return Some(*f);
    }
    points.windows(2).find(|w| w[0].1 >= level && w[1].1 < level).map(|w| {
        let x = (w[0].1 - level) / (w[0].1 - w[1].1);
        (w[0].0.ln() + x * (w[1].0.ln() - w[0].0.ln())).exp()
    })
}

/// The largest `|A(a_max) − A(a_min)|` over the frequencies, for `mounting`.
fn amplitude_change(t: &TorqueResponses, mounting: Mounting, joint: usize) -> f64 {
    let (Some(small), Some(large)) = (
        t.response(mounting, AMPLITUDES_NM[0], joint),
        t.response(mounting, AMPLITUDES_NM[AMPLITUDES_NM.len() - 1], joint),
    ) else {
        return f64::NAN;
    };
    small.complex().iter().zip(large.complex()).map(|(a, b)| (a - b).norm()).fold(0.0, f64::max)
}

/// The figure: per joint, `|A|` against frequency, locked (dashed) and held (solid) at each
/// amplitude, and the fitted model (black dots).
fn figure(t: &TorqueResponses) -> String {
    let joints = t.fits.len();
    let panels: Vec<Panel> = (1..=joints)
        .map(|joint| {
            let mut series = Vec::new();
            for (k, &amplitude) in AMPLITUDES_NM.iter().enumerate() {
                for mounting in [Mounting::Held, Mounting::Locked] {
                    let Some(r) = t.response(mounting, amplitude, joint) else { continue };
                    series.push(Series {
                        label: format!("{}, {amplitude} N·m", mounting.name()),
                        points: t.frequencies_hz.iter().zip(&r.gain_phase).map(|(f, (g, _))| (*f, *g)).collect(),
                        color: PALETTE[k % PALETTE.len()],
                        dashed: mounting == Mounting::Locked,
                        markers: false,
                    });
                }
            }
            if let Some(model) = t.model(joint) {
                series.push(Series {
                    label: "fitted model".into(),
                    points: t
                        .frequencies_hz
                        .iter()
                        .map(|f| (*f, model.response(std::f64::consts::TAU * f).norm()))
                        .collect(),
                    color: "black",
                    dashed: false,
                    markers: true,
                });
            }
            Panel { title: format!("joint {joint}"), y_label: "|τ_act / τ_cmd|".into(), series }
        })
        .collect();
    line_grid_scaled("torque frequency responses", "frequency [Hz]", &panels, 3, Scale::Log)
}

/// The subsection and its figure `(name, svg)`; `design_hz` is each joint's design bandwidth,
/// `viscous` its viscous friction `F_v`.
pub fn section(t: &TorqueResponses, design_hz: &[f64], viscous: &[f64]) -> (String, (String, String)) {
    let name = "plant_torque_response.svg".to_owned();
    let frequencies = &t.frequencies_hz;
    let (first, last) = (frequencies.first().copied().unwrap_or(0.0), frequencies.last().copied().unwrap_or(0.0));
    let small = AMPLITUDES_NM[0];
    let large = AMPLITUDES_NM[AMPLITUDES_NM.len() - 1];
    let mut md = format!(
        "\n### The torque loops, measured as they are used\n\n![torque frequency responses]({name})\n\nEach joint's actuator torque over its command, `A(jω) = τ_act / τ_cmd`, from sinusoidal commands of {} N·m at {first} to {last} Hz on top of the holding torque: with the joint locked, and with the arm held at its start pose by the PD (`τ = g(q) − K_P (q − q0) − K_D q̇` plus the sine: the position loop closed, the joint free to move); pressure noise, transducer offsets, friction and the parameter spread off. The command is held over each control tick, and that hold is taken out (the linear loop has it apart). Fitted to the locked responses at {small} N·m (least squares on the complex responses), the model the linearised loops use: a second-order loop with a dead time, `A(s) = ω_n² e^{{−s T_a}} / (s² + 2ζ ω_n s + ω_n²)`. On the moving joint the load's motion changes the chambers' pressures too: `τ_act = A τ_cmd − B q̇`, and the held runs give that back-drive `B = (A τ_cmd − τ_act) / q̇` (damping where its real part is positive), which the linear loops leave out. Per-frequency gains, phases and `B` are in `summary.json`.\n\n",
        AMPLITUDES_NM.map(|a| a.to_string()).join(", "),
    );
    md.push_str(&table_row([
        "joint".to_owned(),
        "design bandwidth [Hz]".into(),
        format!("locked −3 dB, {small} N·m [Hz]"),
        "fitted ω_n / 2π [Hz]".into(),
        "fitted ζ".into(),
        "fitted T_a [ms]".into(),
        "fit residual (RMS of the complex error)".into(),
        format!("largest change of A from {small} to {large} N·m: locked / held"),
        format!("|A| at {COMPARED_AT_HZ} Hz, {small} N·m: locked / held"),
        format!("back-drive Re B at {BACK_DRIVE_AT_HZ} Hz, {large} N·m [N·m·s/rad]"),
        "F_v [N·m·s/rad]".into(),
    ]));
    md.push_str(&table_row(std::iter::repeat_n("---".to_owned(), 11)));
    let at = frequencies.iter().position(|f| *f == COMPARED_AT_HZ);
    let gain_at =
        |r: Option<&Response>, k: Option<usize>| k.and_then(|k| r.map(|r| r.gain_phase[k].0)).unwrap_or(f64::NAN);
    let back_at = frequencies.iter().position(|f| *f == BACK_DRIVE_AT_HZ);
    let (mut above, mut below, mut moved, mut damped) = (vec![], vec![], vec![], vec![]);
    let (mut other_gain, mut feeding) = (vec![], vec![]);
    let mut locked_change = 0.0_f64;
    for fit in &t.fits {
        let j = fit.joint;
        let design = design_hz.get(j - 1).copied().unwrap_or(f64::NAN);
        let fv = viscous.get(j - 1).copied().unwrap_or(f64::NAN);
        let locked = t.response(Mounting::Locked, small, j);
        let held = t.response(Mounting::Held, small, j);
        let corner = locked.and_then(|r| measured_3db(frequencies, r));
        match corner {
            Some(f) if f < design => below.push(j),
            _ => above.push(j),
        }
        let (change_locked, change_held) =
            (amplitude_change(t, Mounting::Locked, j), amplitude_change(t, Mounting::Held, j));
        locked_change = locked_change.max(change_locked);
        if change_held > AMPLITUDE_CHANGE {
            moved.push(j);
        }
        let back_drive = t
            .response(Mounting::Held, large, j)
            .and_then(|r| back_at.and_then(|k| r.back_drive.get(k)))
            .map_or(f64::NAN, |(m, p)| m * p.to_radians().cos());
        if back_drive.abs() > fv {
            damped.push(j);
        }
        if back_drive < 0.0 {
            feeding.push(j);
        }
        let (locked_gain, held_gain) = (gain_at(locked, at), gain_at(held, at));
        if (held_gain / locked_gain - 1.0).abs() > GAIN_CHANGE {
            other_gain.push(j);
        }
        md.push_str(&table_row([
            j.to_string(),
            format!("{design}"),
            corner.map_or(format!("above {last}"), |f| format!("{f:.1}")),
            format!("{:.1}", fit.natural_rad_s / std::f64::consts::TAU),
            format!("{:.2}", fit.damping),
            format!("{:.2}", fit.delay_s * 1e3),
            format!("{:.3}", fit.residual),
            format!("{change_locked:.3} / {change_held:.2}"),
            format!("{locked_gain:.2} / {held_gain:.2}"),
            format!("{back_drive:.2}"),
            format!("{fv}"),
        ]));
    }
    let _ = writeln!(
        md,
        "\nComputed from the table: locked, the measured −3 dB frequency is at or above the design bandwidth on joints {} and below it on {}; from {small} to {large} N·m the locked responses change by at most {locked_change:.3}{}, the held ones by more than {AMPLITUDE_CHANGE} on joints {}. On the moving joint the actuator's gain at {COMPARED_AT_HZ} Hz differs from the locked one by more than {:.0} % on joints {}, and the back-drive's real part at {BACK_DRIVE_AT_HZ} Hz is larger in magnitude than the joint's viscous friction on joints {}; that real part is negative (it feeds energy into the motion) on joints {}. The linearised loops' margins (\"Each joint's loop, linearised\") use the locked fit, not the design bandwidth, and leave the back-drive out: on the joints just named they are not to be relied on.",
        joints_text(&above),
        joints_text(&below),
        if locked_change <= AMPLITUDE_CHANGE { format!(" (below the change of {AMPLITUDE_CHANGE} counted next)") } else { String::new() },
        joints_text(&moved),
        GAIN_CHANGE * 100.0,
        joints_text(&other_gain),
        joints_text(&damped),
        joints_text(&feeding)
    );
    (md, (name, figure(t)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_3db_point_is_interpolated_between_the_frequencies_around_it() {
        let r = Response {
            mounting: Mounting::Held,
            amplitude_nm: 0.05,
            joint: 1,
            gain_phase: vec![(1.0, 0.0), (0.8, -30.0), (0.6, -60.0)],
            back_drive: Vec::new(),
        };
        let f = measured_3db(&[10.0, 20.0, 40.0], &r).unwrap_or(f64::NAN);
        // 0.8 → 0.6 crosses 0.7071 at x = 0.4645 of the way in log f from 20 to 40 Hz.
        let expected = (20f64.ln() + (0.8 - std::f64::consts::FRAC_1_SQRT_2) / 0.2 * 2f64.ln()).exp();
        assert!((f - expected).abs() < 1e-9, "{f}");
        let flat = Response { gain_phase: vec![(1.0, 0.0); 3], ..r };
        assert_eq!(measured_3db(&[10.0, 20.0, 40.0], &flat), None);
    }
}
