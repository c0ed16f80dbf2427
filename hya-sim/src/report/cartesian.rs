//! The report of a task-space scenario ([`crate::studies::cartesian`]): `report.md` (the answer
//! first: what compensation changes at the controlled frame, computed from the paired runs),
//! `cartesian_runs.csv` (every run's figures), `tool_errors.svg` (the first seed's error norms)
//! and `summary.json`.

use std::fmt::Write as _;

use serde::Serialize;

use super::text::{figure, interval, list, table_row, task_text};
use super::Provenance;
use crate::analysis::seeds::{mean_ci95, PairedRatio};
use crate::config::scenario::Method;
use crate::error::SimError;
use crate::io::output::OutputDir;
use crate::io::svg::{line_grid, Panel, Series, PALETTE};
use crate::studies::cartesian::{CartesianRun, CartesianStudy, Floors};

/// One figure of a run, its name, unit and scale from SI.
struct Column {
    name: &'static str,
    unit: &'static str,
    scale: f64,
    of: fn(&CartesianRun) -> Option<f64>,
}

const COLUMNS: [Column; 9] = [
    Column { name: "final position error", unit: "mm", scale: 1e3, of: |r| Some(r.tool.position_final_m) },
    Column { name: "peak position error (move)", unit: "mm", scale: 1e3, of: |r| Some(r.tool.position_peak_m) },
    Column { name: "RMS position error", unit: "mm", scale: 1e3, of: |r| Some(r.tool.position_rms_m) },
    Column {
        name: "position error in the loaded hold before the move",
        unit: "mm",
        scale: 1e3,
        of: |r| r.tool.position_loaded_hold_m,
    },
    Column { name: "final orientation error", unit: "mrad", scale: 1e3, of: |r| Some(r.tool.orientation_final_rad) },
    Column {
        name: "peak orientation error (move)",
        unit: "mrad",
        scale: 1e3,
        of: |r| Some(r.tool.orientation_peak_rad),
    },
    Column { name: "RMS orientation error", unit: "mrad", scale: 1e3, of: |r| Some(r.tool.orientation_rms_rad) },
    Column { name: "RMSE d̂ − d (norm over joints)", unit: "N·m", scale: 1.0, of: |r| r.disturbance_error_nm },
    Column { name: "command noise (norm over joints)", unit: "N·m", scale: 1.0, of: |r| Some(r.command_noise_nm) },
];

/// The columns whose paired ratios against `none` say what compensation changes.
const COMPARED: [usize; 5] = [0, 1, 4, 5, 8];

/// What [`write()`] returns and keeps in `summary.json`.
#[derive(Debug, Clone, Serialize)]
pub struct CartesianSummary {
    /// The scenario's name.
    pub scenario: String,
    /// The controlled frame.
    pub frame: String,
    /// Seeds per method.
    pub seeds: usize,
    /// What the loop's design says the frame's errors cannot go below.
    pub floors: Floors,
    /// Per method with an estimate, what it changes against `none` (empty without `none`).
    pub changes: Vec<Change>,
    /// Every run.
    pub runs: Vec<CartesianRun>,
    /// Whether the scenario ran shortened (`--quick`).
    pub quick: bool,
    /// What wrote it.
    pub provenance: Provenance,
}

/// What one estimator's compensation changes against `none`, paired by seed.
#[derive(Debug, Clone, Serialize)]
pub struct Change {
    /// The method.
    pub method: Method,
    /// Per compared figure, its ratio to `none`'s.
    pub ratios: Vec<Ratio>,
}

/// One figure of a method against `none`'s on the same seeds.
#[derive(Debug, Clone, Serialize)]
pub struct Ratio {
    /// The figure's name.
    pub name: String,
    /// Its unit.
    pub unit: String,
    /// The method's mean over seeds, in that unit.
    pub mean: f64,
    /// `none`'s.
    pub none_mean: f64,
    /// The geometric mean of the per-seed ratios `method / none`, and its 95 % interval.
    pub ratio: f64,
    /// The interval's lower end.
    pub low: f64,
    /// Its upper end.
    pub high: f64,
    /// The seeds where the method's figure is lower.
    pub lower: usize,
}

impl Ratio {
    /// "lowers", "raises" or "does not change beyond the seeds' spread", by where the interval
    /// lies.
    pub fn direction(&self) -> &'static str {
        direction(self.low, self.high)
    }
}

/// The values of column `c` of `method`'s runs, in its unit, seed by seed (`None` if any run
/// lacks it).
fn values(study: &CartesianStudy, method: Method, c: &Column) -> Option<Vec<f64>> {
    study.of(method).map(|r| (c.of)(r).map(|v| v * c.scale)).collect()
}

/// Writes the report of `study` into `dir`; `quick` if its scenario ran shortened.
pub fn write(
    dir: &OutputDir,
    study: &CartesianStudy,
    (quick, provenance): (bool, &Provenance),
) -> Result<CartesianSummary, SimError> {
    let changes = changes(study);
    let summary = CartesianSummary {
        scenario: study.scenario.name.clone(),
        frame: study.frame.clone(),
        seeds: study.seeds,
        floors: study.floors,
        changes,
        quick,
        runs: study.runs.clone(),
        provenance: provenance.clone(),
    };
    dir.save("report.md", &markdown(study, &summary))?;
    dir.save("cartesian_runs.csv", &runs_csv(study))?;
    dir.save("tool_errors.svg", &errors_figure(study))?;
    for (method, series) in &study.first {
        dir.save(&format!("tool_error_{}.csv", method.name()), &series_csv(series))?;
    }
    dir.save("summary.json", &serde_json::to_string_pretty(&summary)?)?;
    Ok(summary)
}

/// Each estimating method's paired ratios against `none` on the compared figures.
fn changes(study: &CartesianStudy) -> Vec<Change> {
    let methods = &study.scenario.methods;
    if !methods.contains(&Method::None) {
        return Vec::new();
    }
    methods
        .iter()
        .filter(|m| m.estimates())
        .map(|&method| Change {
            method,
            ratios: COMPARED
                .iter()
                .filter_map(|&c| {
                    let column = &COLUMNS[c];
                    let (a, b) = (values(study, method, column)?, values(study, Method::None, column)?);
                    let paired = PairedRatio::of(&a, &b);
                    Some(Ratio {
                        name: column.name.to_owned(),
                        unit: column.unit.to_owned(),
                        mean: mean_ci95(&a).0,
                        none_mean: mean_ci95(&b).0,
                        ratio: paired.ratio,
                        low: paired.low,
                        high: paired.high,
                        lower: a.iter().zip(&b).filter(|(x, y)| x < y).count(),
                    })
                })
                .collect(),
        })
        .collect()
}

/// "lowers", "raises" or "does not change beyond the seeds' spread", by where the interval lies.
fn direction(low: f64, high: f64) -> &'static str {
    if high < 1.0 {
        "lowers"
    } else if low > 1.0 {
        "raises"
    } else {
        "does not change beyond the seeds' spread"
    }
}

fn markdown(study: &CartesianStudy, summary: &CartesianSummary) -> String {
    let s = &study.scenario;
    let mut md = String::new();
    let _ = writeln!(md, "# Cartesian impedance control with disturbance compensation: `{}`\n", s.name);
    md.push_str(&in_short(study, summary));
    let _ = writeln!(md, "## What ran\n\n{}\n", s.description);
    let gains = s.controller.cartesian.as_ref();
    let _ = writeln!(
        md,
        "- Robot `{}`, controlled frame `{}`; task: {}.\n- Controller: `τ = Jᵀ(K_x e − D_x (J q̇ − ẋ_des)) + C + G − d̂ + P(−K_n (q − q₀) − D_n q̇)` on the nominal model (hya_core::CartesianImpedance), `d̂` from the method's estimator (none: `d̂ = 0`), K_x = ({}), D_x = ({}), posture K_n = ({}) N·m/rad, D_n = ({}) N·m·s/rad, torque limits ({}) N·m; observers at {} rad/s, control period {} ms.\n- {} seeds per method (each seed draws the plant's inertial parameters, friction profile and noise); means ± the half-width of the 95 % interval (Student's t); ratios are paired by seed (geometric mean of the per-seed ratios, 95 % interval of its logarithm).\n- Windows: the RMS from the {} s warm-up to the end; the peak over the move and the half second after it; the final window is the run's last {} s, or the last fifth after the warm-up, from 1 s after the move at the earliest; the loaded hold runs from 0.5 s after the payload is set down to the move. Errors are norms over the three axes, from the plant's true joint angles. The command noise is the joints' RMS of the command's first difference over √2 after the warm-up (their norm), over the whole run: it holds the payload's step and the move too, not only noise.\n- Mode: {}.\n- Generated by {}.\n",
        s.robot,
        study.frame,
        task_text(&s.task),
        gains.map(|g| list(&g.stiffness)).unwrap_or_default(),
        gains.map(|g| list(&g.damping)).unwrap_or_default(),
        gains.map(|g| list(&g.posture_stiffness_nm_rad)).unwrap_or_default(),
        gains.map(|g| list(&g.posture_damping_nm_s_rad)).unwrap_or_default(),
        list(&s.controller.torque_limit_nm),
        figure(s.controller.observer_bandwidth_rad_s),
        figure(s.controller.dt_s * 1e3),
        study.seeds,
        figure(crate::analysis::metrics::WARM_UP_S),
        figure(crate::analysis::metrics::SETTLED_WINDOW_S),
        if summary.quick {
            format!(
                "**quick** (event times and the duration scaled by {}, the move's duration kept: the final window follows the move more closely than in the full run)",
                figure(s.quick_time_scale)
            )
        } else {
            "full".to_owned()
        },
        summary.provenance.described(),
    );
    md.push_str(&results_table(study));
    md.push_str(&changes_table(summary));
    md.push_str(
        "## What this scenario does not show\n\n\
         - Contact. `d̂` holds every torque the model does not explain, a payload's weight and a push at the frame alike, so with compensation the arm cancels a contact force as it cancels the payload, at the estimator's bandwidth: the impedance `K_x`, `D_x` then holds only for forces faster than the estimator follows. Against a stiff surface with the target behind it, the force is no longer `K_x e`: it grows until the torque limits at the estimator's rate. A task in contact needs `d̂` restricted (to the joints' friction, say) or a wrench sensor; neither is simulated here.\n\
         - The payload is a point mass at the frame's origin: it exerts no moment about it, so the orientation errors come from the joints' friction and the parameter spread against the rotational springs, not from the payload.\n\
         - A real Panda's torque control and friction: the plant is panda_goto's model (lags and LuGre friction of our choice), not identified on an arm.\n\
         - The frame's kinematics come from the run-time model at every tick (generated kinematics exist for the shipped arms' last link; the simulator does not use them yet).\n\n\
         Figure: `tool_errors.svg`, the first seed's error norms per method; their components: `tool_error_<method>.csv`. Every run's figures: `cartesian_runs.csv`.\n",
    );
    md
}

/// The answer first: which estimator leaves the frame closest to its target at the end, and
/// what each changes against no compensation, in the words of [`direction`].
fn in_short(study: &CartesianStudy, summary: &CartesianSummary) -> String {
    let mut md = String::from("## In short\n\n");
    let final_error = &COLUMNS[0];
    let means: Vec<(Method, f64)> = study
        .scenario
        .methods
        .iter()
        .filter_map(|&m| values(study, m, final_error).map(|v| (m, mean_ci95(&v).0)))
        .collect();
    if let Some(&(best, error)) = means.iter().min_by(|a, b| a.1.total_cmp(&b.1)) {
        // Those whose paired ratio to the best does not lie wholly above 1, or whose mean is within
        // the loop's resolution of the best's, are not told apart.
        let resolution_mm = summary.floors.resolution_m * 1e3;
        let best_values = values(study, best, final_error).unwrap_or_default();
        let alike: Vec<String> = means
            .iter()
            .filter(|&&(m, e)| {
                m != best
                    && (e - error < resolution_mm || {
                        values(study, m, final_error).is_some_and(|v| !PairedRatio::of(&v, &best_values).above_one())
                    })
            })
            .map(|(m, e)| format!("`{}` ({} mm)", m.name(), figure(*e)))
            .collect();
        let _ = write!(
            md,
            "At the end of the run (the final window, holding the moved pose), the frame's origin is closest to its target with `{}`: {} mm on average over {} seeds",
            best.name(),
            figure(error),
            study.seeds
        );
        if !alike.is_empty() {
            let _ = write!(
                md,
                ", not told apart from {} (their paired ratio's interval reaches 1, or their means differ by less than the resolution below)",
                alike.join(", ")
            );
        }
        match means.iter().find(|(m, _)| *m == Method::None) {
            Some(&(_, none)) if best != Method::None => {
                let _ = write!(md, "; without compensation, {} mm", figure(none));
            }
            _ => {}
        }
        let _ = writeln!(
            md,
            ". The loop resolves {} mm at the frame (half an encoder count on every joint at the start pose); {}.\n",
            figure(resolution_mm),
            if error < 10.0 * resolution_mm {
                "errors within ten times that are at the edge of what it measures"
            } else {
                "the errors above are well above it"
            }
        );
    }
    md.push_str(&trailing(study, summary.floors));
    for change in &summary.changes {
        let parts: Vec<String> = change
            .ratios
            .iter()
            .map(|r| {
                format!(
                    "{} the {} ({} → {} {}: × {} [{}, {}], lower in {} of {} seeds)",
                    r.direction(),
                    r.name,
                    figure(r.none_mean),
                    figure(r.mean),
                    r.unit,
                    figure(r.ratio),
                    figure(r.low),
                    figure(r.high),
                    r.lower,
                    study.seeds
                )
            })
            .collect();
        let _ = writeln!(md, "- `{}`'s compensation {}.", change.method.name(), parts.join("; "));
    }
    if summary.changes.is_empty() {
        md.push_str("- The scenario does not run `none`: nothing to compare compensation with.\n");
    }
    md.push('\n');
    md
}

/// The move's peak error with compensation beside what the spring lets the frame trail by at
/// the reference's peak acceleration, the law having no acceleration feed-forward.
fn trailing(study: &CartesianStudy, floors: Floors) -> String {
    let Some(trailing) = floors.trailing_m else { return String::new() };
    let peaks: Vec<f64> = study
        .scenario
        .methods
        .iter()
        .filter(|m| m.estimates())
        .filter_map(|&m| values(study, m, &COLUMNS[1]).map(|v| mean_ci95(&v).0))
        .collect();
    let (Some(low), Some(high)) = (peaks.iter().copied().reduce(f64::min), peaks.iter().copied().reduce(f64::max))
    else {
        return String::new();
    };
    format!(
        "During the move, the peak position error with compensation is {}–{} mm on average: the law has no acceleration feed-forward, and at the reference's peak acceleration the springs let the origin trail by about {} mm (`K⁻¹ Λ a`, quasi-static, with the task-space inertia `Λ` of the loop's model at the start pose, without the payload, and the reference's peak linear and angular acceleration `a`; the position rows; it leaves out what the dampers add), which no estimator removes.\n\n",
        figure(low),
        figure(high),
        figure(trailing * 1e3)
    )
}

fn results_table(study: &CartesianStudy) -> String {
    let mut md = String::from("## Results\n\nPer method, mean over seeds ± 95 %:\n\n");
    let header = std::iter::once("method".to_owned()).chain(COLUMNS.iter().map(|c| format!("{} [{}]", c.name, c.unit)));
    md.push_str(&table_row(header));
    md.push_str(&table_row(std::iter::repeat_n("---".to_owned(), COLUMNS.len() + 1)));
    for &method in &study.scenario.methods {
        let cells = COLUMNS.iter().map(|c| match values(study, method, c) {
            Some(v) => {
                let (mean, half) = mean_ci95(&v);
                interval(mean, half)
            }
            None => "—".into(),
        });
        md.push_str(&table_row(std::iter::once(format!("`{}`", method.name())).chain(cells)));
    }
    md.push('\n');
    md
}

fn changes_table(summary: &CartesianSummary) -> String {
    let Some(first) = summary.changes.first() else { return String::new() };
    let mut md = String::from(
        "## What compensation changes\n\nEach estimator's figure over `none`'s on the same seed: geometric mean [95 % interval], and the seeds where it is lower:\n\n",
    );
    let header = std::iter::once("method".to_owned()).chain(first.ratios.iter().map(|r| r.name.clone()));
    md.push_str(&table_row(header));
    md.push_str(&table_row(std::iter::repeat_n("---".to_owned(), first.ratios.len() + 1)));
    for change in &summary.changes {
        let cells = change.ratios.iter().map(|r| {
            format!("{} [{}, {}] ({}/{})", figure(r.ratio), figure(r.low), figure(r.high), r.lower, summary.seeds)
        });
        md.push_str(&table_row(std::iter::once(format!("`{}`", change.method.name())).chain(cells)));
    }
    md.push('\n');
    md
}

fn runs_csv(study: &CartesianStudy) -> String {
    let mut csv = String::from("method,seed");
    for c in &COLUMNS {
        let _ = write!(csv, ",{} [{}]", c.name, c.unit);
    }
    csv.push('\n');
    for run in &study.runs {
        let _ = write!(csv, "{},{}", run.method.name(), run.seed);
        for c in &COLUMNS {
            let _ = write!(csv, ",{}", (c.of)(run).map(|v| format!("{}", v * c.scale)).unwrap_or_default());
        }
        csv.push('\n');
    }
    csv
}

/// One run's error components over time: `t [s]`, the position error (mm) and the rotation
/// vector (mrad), in base axes.
fn series_csv(series: &crate::studies::cartesian::ToolSeries) -> String {
    let mut csv = String::from("t [s],e_x [mm],e_y [mm],e_z [mm],theta_x [mrad],theta_y [mrad],theta_z [mrad]\n");
    for (t, e) in series.time.iter().zip(&series.error) {
        let _ = write!(csv, "{t}");
        for v in e {
            let _ = write!(csv, ",{}", v * 1e3);
        }
        csv.push('\n');
    }
    csv
}

fn errors_figure(study: &CartesianStudy) -> String {
    let panel = |title: &str, y_label: &str, of: fn(&crate::studies::cartesian::ToolSeries) -> &[f64]| Panel {
        title: title.into(),
        y_label: y_label.into(),
        series: study
            .first
            .iter()
            .enumerate()
            .map(|(i, (method, series))| Series {
                label: method.name().into(),
                points: series.time.iter().zip(of(series)).map(|(t, v)| (*t, v * 1e3)).collect(),
                color: PALETTE[i % PALETTE.len()],
                dashed: false,
                markers: false,
            })
            .collect(),
    };
    let panels = [
        panel("position error ‖p_des − p‖", "mm", |s| &s.position_m),
        panel("orientation error ‖log(R_des Rᵀ)‖", "mrad", |s| &s.orientation_rad),
    ];
    line_grid(&format!("{}: the controlled frame's errors, first seed", study.scenario.name), "t [s]", &panels, 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_direction_follows_the_interval() {
        assert_eq!(direction(0.2, 0.9), "lowers");
        assert_eq!(direction(1.1, 3.0), "raises");
        assert_eq!(direction(0.5, 1.5), "does not change beyond the seeds' spread");
        // One seed has an infinite interval: no direction.
        assert_eq!(direction(0.0, f64::INFINITY), "does not change beyond the seeds' spread");
    }
}
