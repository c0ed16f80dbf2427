//! The reproduction report: `summary.json`, `report.md`, CSV time series and SVG figures.
//!
//! Each of the paper's claims is judged by a rule fixed here, before any run: the verdict is the
//! rule applied to the numbers, and the deciding numbers are printed next to it.

mod plant;

use std::fmt::Write as _;
use std::path::Path;

use serde::Serialize;

use hya_core::JointVector;

use crate::run::{gains, RunOutcome, Trace, WARM_UP_S};
use crate::scenario::{LoadConfig, Method, Noise, Scenario, Task};
use crate::svg::{bar_chart, line_grid, Panel, Series, PALETTE};

use crate::{SimError, JOINTS};

/// One run's line in `summary.json`.
#[derive(Debug, Clone, Serialize)]
pub struct RunSummary {
    /// Scenario name.
    pub scenario: String,
    /// Method name.
    pub method: &'static str,
    /// Tracking RMSE per joint, rad.
    pub rmse_q: Vec<f64>,
    /// Estimate RMSE per joint, N·m; `null` without an estimator.
    pub rmse_d: Option<Vec<f64>>,
    /// Command-torque noise per joint, N·m.
    pub tau_cmd_noise: Vec<f64>,
    /// Largest tracking error per joint, rad.
    pub max_abs_error_q: Vec<f64>,
}

/// A claim of the paper and whether the simulation reproduces it.
#[derive(Debug, Clone, Serialize)]
pub struct Claim {
    /// The claim, as the paper makes it.
    pub claim: String,
    /// The rule that decides it.
    pub rule: String,
    /// The rule's verdict; `None` when a scenario it needs was not run.
    pub reproduced: Option<bool>,
    /// The numbers that decide it.
    pub evidence: String,
}

/// `summary.json`.
#[derive(Debug, Clone, Serialize)]
pub struct Summary {
    /// The robot.
    pub robot: String,
    /// Whether scenarios were shortened (`--quick`).
    pub quick: bool,
    /// Every run.
    pub runs: Vec<RunSummary>,
    /// The paper's claims, judged.
    pub claims: Vec<Claim>,
}

fn find<'a>(outcomes: &'a [RunOutcome<JOINTS>], scenario: &str, method: Method) -> Option<&'a RunOutcome<JOINTS>> {
    outcomes.iter().find(|o| o.scenario == scenario && o.method == method)
}

fn mean(values: &[f64]) -> f64 {
    values.iter().sum::<f64>() / values.len().max(1) as f64
}

fn list(values: &[f64]) -> String {
    values.iter().map(|v| format!("{v:.3}")).collect::<Vec<_>>().join(", ")
}

/// Judges the paper's claims on the outcomes.
pub fn claims(outcomes: &[RunOutcome<JOINTS>], scenarios: &[Scenario]) -> Vec<Claim> {
    let mut claims = Vec::new();
    for experiment in ["goto_internal", "sine_internal", "goto_weight", "sine_weight"] {
        let pair = find(outcomes, experiment, Method::None).zip(find(outcomes, experiment, Method::Lu));
        let (reproduced, evidence) = match pair {
            Some((none, lu)) => {
                let ratios: Vec<f64> = lu.metrics.rmse_q.iter().zip(&none.metrics.rmse_q).map(|(l, n)| l / n).collect();
                (Some(ratios.iter().all(|r| *r < 1.0)), format!("RMSE(lu) / RMSE(none) per joint: {}", list(&ratios)))
            }
            None => (None, "not run".into()),
        };
        claims.push(Claim {
            claim: format!("{experiment}: compensation lowers the tracking RMSE on every joint"),
            rule: "RMSE(lu) < RMSE(none) on all six joints".into(),
            reproduced,
            evidence,
        });
    }
    let noise = |method| {
        let low = find(outcomes, "estimator_noise_low", method)?.metrics.rmse_d.clone()?;
        let high = find(outcomes, "estimator_noise_high", method)?.metrics.rmse_d.clone()?;
        Some((low, high))
    };
    let (lu_noise, chen_noise) = (noise(Method::Lu), noise(Method::Chen));
    let growth = |(low, high): &(Vec<f64>, Vec<f64>)| mean(high) / mean(low);
    claims.push(match &lu_noise {
        Some(pair) => Claim {
            claim: "the paper's estimate is not affected by velocity-sensor noise (it does not use q̇_m)".into(),
            rule: "mean RMSE(d̂ − d) grows by less than 25 % from σ_q̇ = 0.01 to 0.1 rad/s".into(),
            reproduced: Some(growth(pair) < 1.25),
            evidence: format!("lu: mean RMSE {:.3} → {:.3} N·m (× {:.2})", mean(&pair.0), mean(&pair.1), growth(pair)),
        },
        None => Claim {
            claim: "lu is insensitive to velocity noise".into(),
            rule: String::new(),
            reproduced: None,
            evidence: "not run".into(),
        },
    });
    claims.push(match &chen_noise {
        Some(pair) => Claim {
            claim: "Chen's observer is sensitive to velocity noise".into(),
            rule: "mean RMSE(d̂ − d) at least doubles from σ_q̇ = 0.01 to 0.1 rad/s".into(),
            reproduced: Some(growth(pair) >= 2.0),
            evidence: format!(
                "chen: mean RMSE {:.3} → {:.3} N·m (× {:.2})",
                mean(&pair.0),
                mean(&pair.1),
                growth(pair)
            ),
        },
        None => Claim {
            claim: "chen is sensitive to velocity noise".into(),
            rule: String::new(),
            reproduced: None,
            evidence: "not run".into(),
        },
    });
    claims.push(match lu_noise.as_ref().zip(chen_noise.as_ref()) {
        Some((lu, chen)) => Claim {
            claim: "under high velocity noise the paper's estimate is more accurate than Chen's".into(),
            rule: "RMSE(d̂ − d) of lu < chen on every joint at σ_q̇ = 0.1 rad/s".into(),
            reproduced: Some(lu.1.iter().zip(&chen.1).all(|(l, c)| l < c)),
            evidence: format!("lu: {} N·m; chen: {} N·m", list(&lu.1), list(&chen.1)),
        },
        None => Claim {
            claim: "lu beats chen under noise".into(),
            rule: String::new(),
            reproduced: None,
            evidence: "not run".into(),
        },
    });
    for experiment in ["goto_weight", "sine_weight"] {
        let drop = scenarios.iter().find(|s| s.name == experiment).and_then(|s| s.loads.weight_drop.clone());
        let pair = find(outcomes, experiment, Method::None).zip(find(outcomes, experiment, Method::Lu));
        let (reproduced, evidence) = match (pair, drop) {
            (Some((none, lu)), Some(drop)) => {
                // Mean |q − q_des| of joints 2 and 4 (SFE, EFE) while the weight rests on the arm.
                let window_error = |o: &RunOutcome<JOINTS>, joint: usize| {
                    let errors: Vec<f64> = o
                        .trace
                        .time
                        .iter()
                        .enumerate()
                        .filter(|(_, t)| **t >= drop.drop_s + 0.5 && drop.remove_s.is_none_or(|r| **t < r))
                        .map(|(k, _)| (o.trace.q[k][joint] - o.trace.q_des[k][joint]).abs())
                        .collect();
                    mean(&errors)
                };
                let rows: Vec<(f64, f64)> =
                    [1, 3].iter().map(|&j| (window_error(none, j), window_error(lu, j))).collect();
                (
                    Some(rows.iter().all(|(n, l)| l < n)),
                    format!(
                        "mean |e| with the weight on, joint 2: none {:.4} rad, lu {:.4} rad; joint 4: none {:.4} rad, lu {:.4} rad",
                        rows[0].0, rows[0].1, rows[1].0, rows[1].1
                    ),
                )
            }
            _ => (None, "not run".into()),
        };
        claims.push(Claim {
            claim: format!("{experiment}: with the weight on, compensation keeps joints 2 and 4 near their reference"),
            rule: "mean |q − q_des| of joints 2 and 4 while the weight rests (from 0.5 s after the drop): lu < none"
                .into(),
            reproduced,
            evidence,
        });
    }
    claims
}

/// Writes the whole report into `dir`, which [`crate::output::prepare`] has made ready.
pub fn write(
    dir: &Path,
    scenarios: &[Scenario],
    outcomes: &[RunOutcome<JOINTS>],
    quick: bool,
) -> Result<Summary, SimError> {
    let save = |name: &str, text: &str| crate::output::save(dir, name, text);
    let robot = scenarios.first().map_or("hya".into(), |s| s.robot.clone());
    let summary = Summary {
        robot,
        quick,
        runs: outcomes
            .iter()
            .map(|o| RunSummary {
                scenario: o.scenario.clone(),
                method: o.method.name(),
                rmse_q: o.metrics.rmse_q.clone(),
                rmse_d: o.metrics.rmse_d.clone(),
                tau_cmd_noise: o.metrics.tau_cmd_noise.clone(),
                max_abs_error_q: o.metrics.max_abs_error_q.clone(),
            })
            .collect(),
        claims: claims(outcomes, scenarios),
    };
    let json = serde_json::to_string_pretty(&summary).map_err(|e| SimError::Config(e.to_string()))?;
    save("summary.json", &json)?;
    for o in outcomes {
        save(&format!("{}_{}.csv", o.scenario, o.method.name()), &csv(o))?;
    }
    for s in scenarios {
        let runs: Vec<&RunOutcome<JOINTS>> = outcomes.iter().filter(|o| o.scenario == s.name).collect();
        if runs.is_empty() {
            continue;
        }
        save(&format!("{}_joints.svg", s.name), &joints_figure(s, &runs))?;
        save(&format!("{}_disturbance.svg", s.name), &disturbance_figure(s, &runs))?;
        save(&format!("{}_rmse.svg", s.name), &rmse_figure(s, &runs))?;
    }
    let (plant_section, figures) = plant::section(scenarios, outcomes)?;
    for (name, svg) in &figures {
        save(name, svg)?;
    }
    save("report.md", &markdown(scenarios, outcomes, &summary, quick, &plant_section)?)?;
    Ok(summary)
}

fn csv(o: &RunOutcome<JOINTS>) -> String {
    let mut text = String::from("t");
    for name in ["q", "q_des", "d_true", "d_hat", "tau_cmd"] {
        for j in 1..=JOINTS {
            let _ = write!(text, ",{name}{j}");
        }
    }
    text.push('\n');
    let t = &o.trace;
    for k in 0..t.time.len() {
        let _ = write!(text, "{:?}", t.time[k]);
        for v in [&t.q[k], &t.q_des[k], &t.d_true[k], &t.d_hat[k], &t.tau_cmd[k]] {
            for x in v.iter() {
                let _ = write!(text, ",{x:?}");
            }
        }
        text.push('\n');
    }
    text
}

/// Which runs a figure shows: `none` and `lu` where both ran, else every method.
fn featured<'a>(runs: &[&'a RunOutcome<JOINTS>]) -> Vec<&'a RunOutcome<JOINTS>> {
    let paper: Vec<&RunOutcome<JOINTS>> =
        runs.iter().copied().filter(|o| matches!(o.method, Method::None | Method::Lu)).collect();
    if paper.len() == 2 {
        paper
    } else {
        runs.to_vec()
    }
}

fn series(
    o: &RunOutcome<JOINTS>,
    joint: usize,
    values: &[hya_core::JointVector<JOINTS>],
    label: String,
    color: &'static str,
    dashed: bool,
) -> Series {
    Series {
        label,
        points: o.trace.time.iter().zip(values).map(|(t, v)| (*t, v[joint])).collect(),
        color,
        dashed,
        markers: false,
    }
}

/// One panel per joint: `reference` of the first run, dashed, against `estimate` of every run.
fn per_joint_figure(
    title: String,
    y_label: &str,
    shown: &[&RunOutcome<JOINTS>],
    reference: (&str, fn(&Trace<JOINTS>) -> &[JointVector<JOINTS>]),
    estimate: (&str, fn(&Trace<JOINTS>) -> &[JointVector<JOINTS>]),
) -> String {
    let panels: Vec<Panel> = (0..JOINTS)
        .map(|j| {
            let mut lines = Vec::new();
            if let Some(first) = shown.first() {
                lines.push(series(first, j, reference.1(&first.trace), reference.0.into(), PALETTE[0], true));
            }
            for (k, o) in shown.iter().enumerate() {
                let label = format!("{} ({})", estimate.0, o.method.name());
                lines.push(series(o, j, estimate.1(&o.trace), label, PALETTE[(k + 1) % PALETTE.len()], false));
            }
            Panel { title: format!("joint {}", j + 1), y_label: y_label.into(), series: lines }
        })
        .collect();
    line_grid(&title, "t [s]", &panels, 3)
}

fn joints_figure(s: &Scenario, runs: &[&RunOutcome<JOINTS>]) -> String {
    per_joint_figure(
        format!("{}: joint angles against the reference", s.name),
        "rad",
        &featured(runs),
        ("q_des", |t| &t.q_des),
        ("q", |t| &t.q),
    )
}

fn disturbance_figure(s: &Scenario, runs: &[&RunOutcome<JOINTS>]) -> String {
    let estimating: Vec<&RunOutcome<JOINTS>> = runs.iter().copied().filter(|o| o.method != Method::None).collect();
    // The noise comparisons show every observer; the experiments show the paper's.
    let shown: Vec<&RunOutcome<JOINTS>> = if s.name.starts_with("estimator") {
        estimating
    } else {
        estimating.into_iter().filter(|o| o.method == Method::Lu).collect()
    };
    per_joint_figure(
        format!("{}: estimated against true disturbance", s.name),
        "N·m",
        &shown,
        ("d (true)", |t| &t.d_true),
        ("d̂", |t| &t.d_hat),
    )
}

fn rmse_figure(s: &Scenario, runs: &[&RunOutcome<JOINTS>]) -> String {
    let joints: Vec<String> = (1..=JOINTS).map(|j| format!("joint {j}")).collect();
    let bars: Vec<(String, Vec<f64>)> =
        runs.iter().map(|o| (o.method.name().to_owned(), o.metrics.rmse_q.clone())).collect();
    bar_chart(&format!("{}: tracking RMSE", s.name), "RMSE [rad]", &joints, &bars)
}

fn noise_text(noise: &Noise) -> String {
    match noise {
        Noise::Off => "off".into(),
        Noise::Uniform { bound } => format!("uniform ±{bound}"),
        Noise::Gaussian { sigma } => format!("Gaussian σ = {sigma}"),
    }
}

fn task_text(task: &Task) -> String {
    match task {
        Task::Hold => "hold the start pose".into(),
        Task::Goto { start_s, transition_s, delta_rad } => {
            format!("goto start + ({}) rad at {start_s} s, minimum-jerk over {transition_s} s", list(delta_rad))
        }
        Task::Sine { amplitude_rad, frequency_hz, ramp_s } => {
            format!("sine, amplitudes ({}) rad, {frequency_hz} Hz, ramped in over {ramp_s} s", list(amplitude_rad))
        }
    }
}

fn loads_text(loads: &LoadConfig) -> String {
    let mut parts = Vec::new();
    if let Some(s) = &loads.sinusoid {
        parts.push(format!("sinusoidal torques ({}) N·m at {} Hz, phase i·60°", list(&s.amplitude_nm), s.frequency_hz));
    }
    if let Some(d) = &loads.weight_drop {
        parts.push(format!(
            "{} kg dropped on `{}` at {} s from {} m (impact pulse {} s), {}",
            d.mass_kg,
            d.frame,
            d.drop_s,
            d.fall_height_m,
            d.impact_s,
            d.remove_s.map_or("never removed".into(), |r| format!("removed at {r} s"))
        ));
    }
    if parts.is_empty() {
        "none".into()
    } else {
        parts.join("; ")
    }
}

/// A markdown table row; `|` inside a cell is escaped.
fn table_row(cells: impl IntoIterator<Item = String>) -> String {
    let cells: Vec<String> = cells.into_iter().map(|c| c.replace('|', "\\|")).collect();
    format!("| {} |\n", cells.join(" | "))
}

fn markdown(
    scenarios: &[Scenario],
    outcomes: &[RunOutcome<JOINTS>],
    summary: &Summary,
    quick: bool,
    plant_section: &str,
) -> Result<String, SimError> {
    let mut md = String::new();
    let reproduced = summary.claims.iter().filter(|c| c.reproduced == Some(true)).count();
    let robot = if summary.robot == "hya" { "HyA" } else { summary.robot.as_str() };
    let _ = writeln!(md, "# Reproducing Lu, Sandy & Buchli on a simulated {robot}\n");
    let _ = writeln!(
        md,
        "Mode: {}. Generated by `hya reproduce`; every figure below comes from the runs in `summary.json`, and every run is reproducible bit for bit from its seed.\n",
        if quick { "**quick** (event times and durations scaled down; see each scenario)" } else { "full" }
    );
    let _ = writeln!(md, "## The paper's claims\n\n{reproduced} of {} claims reproduced.\n", summary.claims.len());
    md.push_str("| claim | rule | verdict | deciding figures |\n|---|---|---|---|\n");
    for c in &summary.claims {
        let verdict = match c.reproduced {
            Some(true) => "reproduced",
            Some(false) => "**not reproduced**",
            None => "not run",
        };
        md.push_str(&table_row([c.claim.clone(), c.rule.clone(), verdict.into(), c.evidence.clone()]));
    }
    md.push_str(&observations(outcomes));
    md.push_str(&lagged_cancellation(scenarios)?);
    md.push_str(plant_section);
    md.push_str(&parameters(scenarios)?);
    md.push_str("\n## Results\n\nMetrics per joint after the first ");
    let _ = writeln!(md, "{WARM_UP_S} s: tracking RMSE of the true `q − q_des` (rad), RMSE of `d̂ − d` against the recorded true disturbance (N·m), and the command-torque noise, the RMS of the command's first difference over √2 (N·m; white noise of deviation σ gives σ).\n");
    for s in scenarios {
        let runs: Vec<&RunOutcome<JOINTS>> = outcomes.iter().filter(|o| o.scenario == s.name).collect();
        if runs.is_empty() {
            continue;
        }
        let _ = writeln!(
            md,
            "### {}\n\n{}. Task: {}. Loads: {}. Duration {} s.\n",
            s.name,
            s.description,
            task_text(&s.task),
            loads_text(&s.loads),
            s.duration_s
        );
        let header = table_row(
            ["method".to_string(), "quantity".into()].into_iter().chain((1..=JOINTS).map(|j| format!("j{j}"))),
        );
        md.push_str(&header);
        md.push_str(&table_row(std::iter::repeat_n("---".to_string(), JOINTS + 2)));
        for o in &runs {
            let row = |name: &str, values: &[f64], digits: usize| {
                table_row(
                    [o.method.name().to_string(), name.into()]
                        .into_iter()
                        .chain(values.iter().map(|v| format!("{v:.digits$}"))),
                )
            };
            md.push_str(&row("RMSE q [rad]", &o.metrics.rmse_q, 5));
            if let Some(d) = &o.metrics.rmse_d {
                md.push_str(&row("RMSE d̂ [N·m]", d, 3));
            }
            md.push_str(&row("τ_cmd noise [N·m]", &o.metrics.tau_cmd_noise, 3));
        }
        let _ = writeln!(
            md,
            "\n![joints]({0}_joints.svg) ![disturbance]({0}_disturbance.svg) ![rmse]({0}_rmse.svg)\n\nTime series: `{0}_<method>.csv`.\n",
            s.name
        );
    }
    Ok(md)
}

/// Where a baseline beats the paper's method, said plainly.
fn observations(outcomes: &[RunOutcome<JOINTS>]) -> String {
    let mut md = String::from("\n## Where the baselines stand\n\n");
    let mut any = false;
    for o in outcomes.iter().filter(|o| matches!(o.method, Method::Chen | Method::Momentum | Method::Eso)) {
        let Some(lu) = find(outcomes, &o.scenario, Method::Lu) else { continue };
        let better_tracking = o.metrics.rmse_q.iter().zip(&lu.metrics.rmse_q).filter(|(b, l)| b < l).count();
        let (Some(d_b), Some(d_l)) = (&o.metrics.rmse_d, &lu.metrics.rmse_d) else { continue };
        let better_estimate = d_b.iter().zip(d_l).filter(|(b, l)| b < l).count();
        let noise_ratio = mean(&o.metrics.tau_cmd_noise) / mean(&lu.metrics.tau_cmd_noise);
        if better_tracking > 0 || better_estimate > 0 {
            any = true;
            let _ = writeln!(
                md,
                "- {} / {}: tracks better than lu on {better_tracking} of {JOINTS} joints, estimates better on {better_estimate} of {JOINTS}; its command is {noise_ratio:.1}× as noisy.",
                o.scenario,
                o.method.name()
            );
        }
    }
    if !any {
        md.push_str("No baseline beats the paper's method on any joint in any scenario.\n");
    }
    md.push_str("\nObservers that use the measured velocity (chen, momentum) feed its noise straight into `d̂` and so into the command; a stiffer loop can then track better in closed loop while estimating worse. Tracking RMSE alone does not settle which method is better on a real hydraulic arm, where command noise excites the valves.\n");
    md
}

/// Cancelling viscous friction `−F_v q̇` with an estimate that lags by `τ_d` leaves
/// `≈ F_v τ_d q̈`: the loop sees its inertia reduced by `F_v τ_d`. Where that exceeds the joint's
/// inertia, the compensated joint is destabilised and only friction's nonlinearity bounds it.
fn lagged_cancellation(scenarios: &[Scenario]) -> Result<String, SimError> {
    let Some(first) = scenarios.first() else { return Ok(String::new()) };
    let nominal =
        crate::nominal_dynamics(&first.robot).ok_or_else(|| SimError::Config("no nominal dynamics".into()))?;
    let q0 = hya_core::JointVector::<JOINTS>::from_column_slice(&crate::initial_position(first, JOINTS));
    let inertia = nominal.mass_matrix(&q0).diagonal();
    let w = first.controller.observer_bandwidth_rad_s;
    let delay = 1.0 / w + 2.0 * 0.8 / w;
    let mut md = format!(
        "\n### Lagged cancellation of viscous friction\n\nThe estimate lags the disturbance by about τ_d = 1/ω1 + 2ζ/ω2 = {delay:.3} s. Cancelling viscous friction `−F_v q̇` with it leaves roughly `F_v τ_d q̈` uncancelled, as if the joint's inertia were reduced by `F_v τ_d`. Where that exceeds the joint's inertia, the compensated joint oscillates slowly, bounded only by friction's nonlinearity (the paper, too, reports residual oscillations on joints 3, 5 and 6):\n\n| joint | F_v [N·m·s/rad] | F_v τ_d [kg·m²] | M_ii(q0) [kg·m²] | F_v τ_d > M_ii |\n|---|---|---|---|---|\n"
    );
    for j in 0..JOINTS {
        let fv = first.plant.viscous_nm_s.get(j).copied().unwrap_or(0.0);
        md.push_str(&table_row([
            format!("{}", j + 1),
            format!("{fv}"),
            format!("{:.4}", fv * delay),
            format!("{:.4}", inertia[j]),
            (if fv * delay > inertia[j] { "yes" } else { "no" }).into(),
        ]));
    }
    Ok(md)
}

fn parameters(scenarios: &[Scenario]) -> Result<String, SimError> {
    let mut md = String::from("\n## Every parameter\n\n");
    let Some(first) = scenarios.first() else { return Ok(md) };
    let robot =
        hya_robots::find(&first.robot).ok_or_else(|| SimError::Config(format!("unknown robot {}", first.robot)))?;
    let model = hya_codegen::load_str(robot.urdf, robot.name).map_err(|e| SimError::Config(e.to_string()))?.model;
    let _ = writeln!(
        md,
        "### Nominal rigid-body model (`robots/urdf/{}.urdf`), used by the controller and observers\n",
        robot.name
    );
    md.push_str("| body (joint) | mass [kg] | centre of mass in body frame [m] | rotational inertia about the body origin [kg·m²] (xx, yy, zz, xy, xz, yz) |\n|---|---|---|---|\n");
    for b in model.bodies() {
        let i = &b.inertia;
        let com = i.centre_of_mass_form().map_or(i.first_moment, |(_, com, _)| com);
        let r = &i.rotational;
        md.push_str(&table_row([
            format!("{} ({})", b.link, b.joint),
            format!("{:.6}", i.mass),
            format!("{:.6}, {:.6}, {:.6}", com.x, com.y, com.z),
            format!(
                "{:.6}, {:.6}, {:.6}, {:.6}, {:.6}, {:.6}",
                r[(0, 0)],
                r[(1, 1)],
                r[(2, 2)],
                r[(0, 1)],
                r[(0, 2)],
                r[(1, 2)]
            ),
        ]));
    }
    let c = &first.controller;
    let nominal =
        crate::nominal_dynamics(&first.robot).ok_or_else(|| SimError::Config("no nominal dynamics".into()))?;
    let q0 = hya_core::JointVector::<JOINTS>::from_column_slice(&crate::initial_position(first, JOINTS));
    let gains = gains(nominal, first, &q0)?;
    let _ = writeln!(
        md,
        "\n### Controller and observers\n\n- Computed torque, the paper's form `τ = M q̈_des + C + G − K_D ė − K_P e (− d̂)` with `M`, `C`, `G` from the nominal generated model at the measured `q`, at {} s per tick; velocity from the {} source; torque limits ({}) N·m.\n- Gains from natural frequencies ({}) rad/s and damping {} on the nominal `M(q0)` diagonal: K_P = ({}) N·m/rad, K_D = ({}) N·m·s/rad.\n- lu: the paper's filters, ζ = 0.8, ω1 = ω2 = {b} rad/s. chen: gain y = ½(ξ + 2βσ) with β = {b}/s, σ = 1.2 λmax(M(q0)), ξ = 0. momentum: K_O = {b}/s per joint. eso: ω_o = {b} rad/s, model-assisted. All four at the same bandwidth, {b} rad/s.\n- Start pose ({}) rad; the actuators start holding the nominal gravity torque.",
        c.dt_s,
        match first.sensors.velocity {
            crate::scenario::VelocitySource::Difference => "encoder difference (low-passed)",
            crate::scenario::VelocitySource::Filter => "filtered (q̂̇ of the paper's filter)",
            crate::scenario::VelocitySource::Sensor => "velocity sensor",
        },
        list(&c.torque_limit_nm),
        list(&c.natural_frequency_rad_s),
        c.damping_ratio,
        list(gains.kp().diagonal().as_slice()),
        list(gains.kd().diagonal().as_slice()),
        list(q0.as_slice()),
        b = c.observer_bandwidth_rad_s,
    );
    md.push_str("\n### Scenarios\n\n| scenario | duration [s] | task | loads | noise q / q̇ / τ | methods | seed |\n|---|---|---|---|---|---|---|\n");
    for s in scenarios {
        md.push_str(&table_row([
            s.name.clone(),
            format!("{}", s.duration_s),
            task_text(&s.task),
            loads_text(&s.loads),
            format!(
                "{} / {} / {}",
                noise_text(&s.noise.position),
                noise_text(&s.noise.velocity),
                noise_text(&s.noise.torque)
            ),
            s.methods.iter().map(|m| m.name()).collect::<Vec<_>>().join(", "),
            format!("{}", s.seed),
        ]));
    }
    md.push_str("\nDefault sensor noise: one count of HyA's 19-bit encoders on the angle; where a scenario defines a velocity sensor or a load cell, the uniform bounds measured on hydraulic joints (velocity 0.055 rad/s, torque 0.073 N·m; Vorndamme et al.). The weight: 2 kg, sized so that it shifts joint 2's disturbance by about 10 N·m, as the paper's weight-drop figure shows (≈ +5 N·m before, ≈ −5 N·m with the weight on). Each scenario's description names the paper times it follows. Sine amplitudes and frequency, the goto transition and the controller's natural frequencies are not given in the paper; they are our choices, fixed before any comparison was run.\n");
    Ok(md)
}
