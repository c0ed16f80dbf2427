//! Settings and numbers as report text: task, loads, noise, lists, table rows.

use hya_core::Short;

use crate::config::scenario::{LoadConfig, Noise, Task};

pub(super) fn noise_text(noise: &Noise) -> String {
    match noise {
        Noise::Off {} => "off".into(),
        Noise::Uniform { bound } => format!("uniform ±{}", Short(*bound)),
        Noise::Gaussian { sigma } => format!("Gaussian σ = {}", Short(*sigma)),
    }
}

pub(super) fn task_text(task: &Task) -> String {
    match task {
        Task::Hold {} => "hold the start pose".into(),
        Task::Goto { start_s, transition_s, delta_rad } => {
            format!(
                "goto start + ({}) rad at {} s, minimum-jerk over {} s",
                list(delta_rad),
                Short(*start_s),
                Short(*transition_s)
            )
        }
        Task::Sine { amplitude_rad, frequency_hz, ramp_s } => {
            format!(
                "sine, amplitudes ({}) rad, {} Hz, ramped in over {} s",
                list(amplitude_rad),
                Short(*frequency_hz),
                Short(*ramp_s)
            )
        }
        Task::Cartesian { start_s, transition_s, offset_m, rotation_rad } => {
            format!(
                "move the controlled frame by ({}) m and turn it by ({}) rad (rotation vector, base axes) at {} s, \
                 minimum-jerk over {} s",
                list(offset_m),
                list(rotation_rad),
                Short(*start_s),
                Short(*transition_s)
            )
        }
    }
}

pub(super) fn loads_text(loads: &LoadConfig) -> String {
    let mut parts = Vec::new();
    if let Some(s) = &loads.sinusoid {
        parts.push(format!(
            "sinusoidal torques ({}) N·m at {} Hz, phase i·60°",
            list(&s.amplitude_nm),
            Short(s.frequency_hz)
        ));
    }
    if let Some(d) = &loads.weight_drop {
        parts.push(format!(
            "{} kg dropped on `{}` at {} s from {} m (impact pulse {} s), {}",
            Short(d.mass_kg),
            d.frame,
            Short(d.drop_s),
            Short(d.fall_height_m),
            Short(d.impact_s),
            d.remove_s.map_or("never removed".into(), |r| format!("removed at {} s", Short(r)))
        ));
    }
    if parts.is_empty() {
        "none".into()
    } else {
        parts.join("; ")
    }
}

/// A markdown table row; `|` inside a cell is escaped.
pub(super) fn table_row(cells: impl IntoIterator<Item = String>) -> String {
    let cells: Vec<String> = cells.into_iter().map(|c| c.replace('|', "\\|")).collect();
    format!("| {} |\n", cells.join(" | "))
}

/// Joints (from 1) as a list, or "none".
pub(super) fn joints_text(joints: &[usize]) -> String {
    match joints.is_empty() {
        true => "none".into(),
        false => joints.iter().map(usize::to_string).collect::<Vec<_>>().join(", "),
    }
}

/// `values` with three decimals, comma-separated.
pub(super) fn list(values: &[f64]) -> String {
    values.iter().map(|v| format!("{v:.3}")).collect::<Vec<_>>().join(", ")
}

/// `mean ± half-width`; a single seed has no interval: `n/a`, not `± inf`.
pub(super) fn interval(mean: f64, half_width: f64) -> String {
    let half_width = if half_width.is_finite() { figure(half_width) } else { "n/a".into() };
    format!("{} ± {half_width}", figure(mean))
}

/// A number with three decimals, or three significant digits in scientific notation outside
/// `[0.01, 10⁴)`.
pub(super) fn figure(x: f64) -> String {
    if x == 0.0 || !x.is_finite() || (1e-2..1e4).contains(&x.abs()) {
        format!("{x:.3}")
    } else {
        format!("{x:.2e}")
    }
}
