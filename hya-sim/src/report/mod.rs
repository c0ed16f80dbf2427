//! The reproduction report: `summary.json`, `report.md`, CSV time series and SVG figures.
//!
//! Each of the paper's claims is judged by a rule fixed here, before any run: the verdict is the
//! rule applied to the numbers, and the deciding numbers are printed next to it.

mod figures;
mod plant;
mod viscous;

use std::fmt::Write as _;
use std::path::Path;

use serde::Serialize;

use crate::claims::{judge_all, Judgement, Verdict, RULES};
use crate::metrics::WARM_UP_S;
use crate::run::{gains, RunOutcome};
use crate::scenario::{LoadConfig, Method, Noise, Scenario, Task};
use crate::seeds::{per_joint_mean_ci95, MetricTable};

use crate::SimError;

/// One scenario and method's line in `summary.json`: per-joint means over the seeds, each with
/// the half-width of its 95 % interval (`…_ci95`).
#[derive(Debug, Clone, Serialize)]
pub struct RunSummary {
    /// Scenario name.
    pub scenario: String,
    /// Method name.
    pub method: &'static str,
    /// How many seeds.
    pub seeds: usize,
    /// Tracking RMSE per joint, rad.
    pub rmse_q: Vec<f64>,
    /// Its 95 % half-width.
    pub rmse_q_ci95: Vec<f64>,
    /// Estimate RMSE per joint, N·m; `null` without an estimator.
    pub rmse_d: Option<Vec<f64>>,
    /// Its 95 % half-width.
    pub rmse_d_ci95: Option<Vec<f64>>,
    /// Command-torque noise per joint, N·m.
    pub tau_cmd_noise: Vec<f64>,
    /// Its 95 % half-width.
    pub tau_cmd_noise_ci95: Vec<f64>,
    /// Largest tracking error per joint, rad.
    pub max_abs_error_q: Vec<f64>,
    /// Its 95 % half-width.
    pub max_abs_error_q_ci95: Vec<f64>,
    /// Mean |e| over the final 5 s, rad.
    pub steady_error_q: Vec<f64>,
    /// Its 95 % half-width.
    pub steady_error_q_ci95: Vec<f64>,
    /// Peak-to-peak error over the final 5 s, rad.
    pub limit_cycle_q: Vec<f64>,
    /// Its 95 % half-width.
    pub limit_cycle_q_ci95: Vec<f64>,
    /// The observer's rates at the start pose from its design, 1/s; absent without an observer.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bandwidth_rad_s: Option<Vec<f64>>,
}

/// `summary.json`.
#[derive(Debug, Clone, Serialize)]
pub struct Summary {
    /// The robot.
    pub robot: String,
    /// Whether scenarios were shortened (`--quick`).
    pub quick: bool,
    /// Seeds per scenario and method.
    pub seeds: usize,
    /// Every scenario and method.
    pub runs: Vec<RunSummary>,
    /// The paper's claims, judged over the seeds.
    pub claims: Vec<Judgement>,
}

fn mean(values: &[f64]) -> f64 {
    values.iter().sum::<f64>() / values.len().max(1) as f64
}

fn list(values: &[f64]) -> String {
    values.iter().map(|v| format!("{v:.3}")).collect::<Vec<_>>().join(", ")
}

/// The mean and 95 % half-width over seeds of `metric` for one scenario and method.
fn aggregate(table: &MetricTable, scenario: &str, method: Method, metric: &str) -> Option<(Vec<f64>, Vec<f64>)> {
    table.values(scenario, method, metric).filter(|v| !v.is_empty()).map(|v| per_joint_mean_ci95(&v))
}

fn run_summary(table: &MetricTable, scenario: &str, method: Method, bandwidth: Option<Vec<f64>>) -> RunSummary {
    let get = |metric: &str| aggregate(table, scenario, method, metric).unwrap_or_default();
    let (rmse_q, rmse_q_ci95) = get("rmse_q");
    let rmse_d = aggregate(table, scenario, method, "rmse_d");
    let (tau_cmd_noise, tau_cmd_noise_ci95) = get("tau_cmd_noise");
    let (max_abs_error_q, max_abs_error_q_ci95) = get("max_abs_error_q");
    let (steady_error_q, steady_error_q_ci95) = get("steady_error_q");
    let (limit_cycle_q, limit_cycle_q_ci95) = get("limit_cycle_q");
    RunSummary {
        scenario: scenario.to_owned(),
        method: method.name(),
        seeds: table.seeds(scenario, method),
        rmse_q,
        rmse_q_ci95,
        rmse_d_ci95: rmse_d.as_ref().map(|(_, ci)| ci.clone()),
        rmse_d: rmse_d.map(|(m, _)| m),
        tau_cmd_noise,
        tau_cmd_noise_ci95,
        max_abs_error_q,
        max_abs_error_q_ci95,
        steady_error_q,
        steady_error_q_ci95,
        limit_cycle_q,
        limit_cycle_q_ci95,
        bandwidth_rad_s: bandwidth,
    }
}

/// Writes the whole report into `dir`, which [`crate::output::prepare`] has made ready:
/// `outcomes` are the first seed's runs (with traces, for figures), `table` every seed's metrics.
pub fn write<const N: usize>(
    dir: &Path,
    scenarios: &[Scenario],
    outcomes: &[RunOutcome<N>],
    table: &MetricTable,
    quick: bool,
    generated_by: &str,
) -> Result<Summary, SimError> {
    let save = |name: &str, text: &str| crate::output::save(dir, name, text);
    let robot = scenarios.first().map_or("hya".into(), |s| s.robot.clone());
    let summary = Summary {
        robot,
        quick,
        seeds: outcomes.first().map_or(0, |o| table.seeds(&o.scenario, o.method)),
        runs: outcomes.iter().map(|o| run_summary(table, &o.scenario, o.method, o.bandwidth_rad_s.clone())).collect(),
        claims: judge_all(table),
    };
    let json = serde_json::to_string_pretty(&summary)?;
    save("summary.json", &json)?;
    for o in outcomes {
        save(&format!("{}_{}.csv", o.scenario, o.method.name()), &csv(o))?;
    }
    let mut figure_names = std::collections::BTreeMap::new();
    for s in scenarios {
        let runs: Vec<&RunOutcome<N>> = outcomes.iter().filter(|o| o.scenario == s.name).collect();
        if runs.is_empty() {
            continue;
        }
        let mut names = Vec::new();
        for (name, svg) in figures::scenario_figures(s, &runs, table) {
            save(&name, &svg)?;
            names.push(name);
        }
        figure_names.insert(s.name.clone(), names);
    }
    let (mut plant_section, figures) = plant::section(scenarios, outcomes)?;
    for (name, svg) in &figures {
        save(name, svg)?;
    }
    let viscous_section = match scenarios.iter().find(|s| s.name == "goto_internal") {
        Some(base) => viscous::section(base)?,
        None => String::new(),
    };
    if let Some(base) = scenarios.iter().find(|s| s.name.starts_with("estimator_noise")) {
        let points = crate::frequency::measure(base, &crate::frequency::FREQUENCIES_HZ)?;
        save("frequency.svg", &crate::frequency::figure(&points))?;
        plant_section.push_str(&frequency_section(&points));
    }
    save(
        "report.md",
        &markdown(
            scenarios,
            outcomes,
            table,
            &summary,
            (quick, generated_by),
            (&plant_section, &figure_names, &viscous_section),
        )?,
    )?;
    Ok(summary)
}

fn csv<const N: usize>(o: &RunOutcome<N>) -> String {
    let mut text = String::from("t");
    for name in ["q", "q_des", "d_true", "d_hat", "tau_cmd"] {
        for j in 1..=N {
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

fn noise_text(noise: &Noise) -> String {
    match noise {
        Noise::Off {} => "off".into(),
        Noise::Uniform { bound } => format!("uniform ±{bound}"),
        Noise::Gaussian { sigma } => format!("Gaussian σ = {sigma}"),
    }
}

fn task_text(task: &Task) -> String {
    match task {
        Task::Hold {} => "hold the start pose".into(),
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

fn markdown<const N: usize>(
    scenarios: &[Scenario],
    outcomes: &[RunOutcome<N>],
    table: &MetricTable,
    summary: &Summary,
    (quick, generated_by): (bool, &str),
    (plant_section, figure_names, viscous_section): (&str, &std::collections::BTreeMap<String, Vec<String>>, &str),
) -> Result<String, SimError> {
    let mut md = String::new();
    let robot = if summary.robot == "hya" { "HyA" } else { summary.robot.as_str() };
    let _ = writeln!(md, "# Lu, Sandy & Buchli on a simulated {robot}\n");
    let _ = writeln!(
        md,
        "Generated by `{generated_by}`. Mode: {}; {} seeds per scenario and method (each seed draws the model error, the friction profile and the noise). Every figure comes from the runs in `summary.json`; every run repeats bit for bit from its seed. Means are over seeds, ± the half-width of the 95 % interval (Student's t).\n",
        if quick { "**quick** (event times and durations scaled down; see each scenario)" } else { "full" },
        summary.seeds
    );
    md.push_str(&claims_table(&summary.claims));
    md.push_str(&baselines_doing_better(scenarios, table));
    md.push_str(&observations(outcomes));
    md.push_str(&lagged_cancellation::<N>(scenarios)?);
    md.push_str(viscous_section);
    md.push_str(plant_section);
    md.push_str(&parameters::<N>(scenarios)?);
    md.push_str("\n## Results\n\nMetrics per joint after the first ");
    let _ = writeln!(md, "{WARM_UP_S} s: tracking RMSE of the true `q − q_des` (rad), RMSE of `d̂ − d` against the recorded true disturbance (N·m), and the command-torque noise, the RMS of the command's first difference over √2 (N·m; white noise of deviation σ gives σ).\n");
    for s in scenarios {
        let runs: Vec<&RunOutcome<N>> = outcomes.iter().filter(|o| o.scenario == s.name).collect();
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
        let header =
            table_row(["method".to_string(), "quantity".into()].into_iter().chain((1..=N).map(|j| format!("j{j}"))));
        md.push_str(&header);
        md.push_str(&table_row(std::iter::repeat_n("---".to_string(), N + 2)));
        for o in &runs {
            // Mean ± 95 % half-width over the seeds.
            for (name, metric) in
                [("RMSE q [rad]", "rmse_q"), ("RMSE d̂ [N·m]", "rmse_d"), ("τ_cmd noise [N·m]", "tau_cmd_noise")]
            {
                let Some((mean, ci)) = aggregate(table, &s.name, o.method, metric) else { continue };
                md.push_str(&table_row(
                    [o.method.name().to_string(), name.into()]
                        .into_iter()
                        .chain(mean.iter().zip(&ci).map(|(m, c)| format!("{} ± {}", figure(*m), figure(*c)))),
                ));
            }
        }
        let _ = writeln!(
            md,
            "\n{}\n\nTime series: `{}_<method>.csv` (first seed).\n",
            figure_names
                .get(&s.name)
                .map_or(&[][..], |n| n.as_slice())
                .iter()
                .map(|n| format!("![{n}]({n})"))
                .collect::<Vec<_>>()
                .join(" "),
            s.name
        );
    }
    Ok(md)
}

/// The claims, leading the report: what the paper says, what we measure, the verdict.
fn claims_table(claims: &[Judgement]) -> String {
    let count = |v: Verdict| claims.iter().filter(|c| c.verdict == v).count();
    if count(Verdict::NotRun) == claims.len() {
        return "## The paper's claims\n\nNone of the paper's experiments was run, so no claim is judged (`hya reproduce` runs them).\n".into();
    }
    let mut md = format!(
        "## The paper's claims\n\n{} reproduced, {} partly, {} not reproduced, {} not run (of {}). Each rule is fixed in `hya-sim/src/claims.rs` before any run: at a joint it holds when the whole 95 % interval clears its threshold by the margin.\n\n| claim | section | paper | ours: per joint, mean ± 95 % | verdict |\n|---|---|---|---|---|\n",
        count(Verdict::Reproduced),
        count(Verdict::Partly),
        count(Verdict::NotReproduced),
        count(Verdict::NotRun),
        claims.len()
    );
    for (c, rule) in claims.iter().zip(RULES) {
        let ours = if c.numbers.is_empty() {
            "not run".to_owned()
        } else {
            c.numbers
                .iter()
                .map(|f| {
                    format!("j{}: {} ± {}{}", f.joint, figure(f.mean), figure(f.ci95), if f.holds { "" } else { " ✗" })
                })
                .collect::<Vec<_>>()
                .join("; ")
        };
        let verdict = match c.verdict {
            Verdict::Partly | Verdict::NotReproduced => format!("**{}**", c.verdict.name()),
            other => other.name().to_owned(),
        };
        md.push_str(&table_row([
            c.statement.to_owned(),
            c.section.to_owned(),
            rule.paper.to_owned(),
            ours,
            verdict.to_owned(),
        ]));
    }
    md.push_str("\n✗ marks a joint where the rule does not hold.\n");
    md
}

/// The observers' measured responses against their designs.
fn frequency_section(points: &[crate::frequency::Point]) -> String {
    let mut md = format!(
        "\n## Frequency response of the estimates\n\n![frequency](frequency.svg)\n\nA sinusoidal torque from {} to {} Hz on a clean plant (the rigid body alone, no friction, ideal actuators, exact sensors, a velocity sensor for the observers that read one), each observer in closed loop; `d̂/d` on joint {} is measured from whole periods after 2 s and set against each design's transfer function.\n\n| method | largest gain error | largest phase error [deg] | at |\n|---|---|---|---|\n",
        crate::frequency::FREQUENCIES_HZ[0],
        crate::frequency::FREQUENCIES_HZ[crate::frequency::FREQUENCIES_HZ.len() - 1],
        crate::frequency::JOINT + 1
    );
    for method in [Method::Lu, Method::Chen, Method::Momentum, Method::Eso] {
        let mine: Vec<_> = points.iter().filter(|p| p.method == method).collect();
        let gain = |p: &&crate::frequency::Point| (p.measured.norm() / p.design.norm() - 1.0).abs();
        let phase = |p: &&crate::frequency::Point| (p.measured / p.design).arg().to_degrees().abs();
        let worst_gain = mine.iter().max_by(|a, b| gain(a).total_cmp(&gain(b)));
        let worst_phase = mine.iter().map(phase).fold(0.0, f64::max);
        if let Some(w) = worst_gain {
            md.push_str(&table_row([
                method.name().to_owned(),
                format!("{:.1} %", 100.0 * gain(w)),
                format!("{worst_phase:.1}"),
                format!("gain error at {} Hz", w.frequency_hz),
            ]));
        }
    }
    md
}

/// A number with three significant digits.
fn figure(x: f64) -> String {
    if x == 0.0 || !x.is_finite() || (1e-2..1e4).contains(&x.abs()) {
        format!("{x:.3}")
    } else {
        format!("{x:.2e}")
    }
}

/// Every scenario, joint and figure where a baseline is better than the paper's method by more
/// than both 95 % intervals.
fn baselines_doing_better(scenarios: &[Scenario], table: &MetricTable) -> String {
    let mut md = String::from("\n## Where a baseline does better\n\n");
    let mut rows = Vec::new();
    for s in scenarios {
        for metric in ["rmse_q", "rmse_d"] {
            let Some((lu, lu_ci)) = aggregate(table, &s.name, Method::Lu, metric) else { continue };
            for &method in s.methods.iter().filter(|m| **m != Method::Lu) {
                let Some((other, other_ci)) = aggregate(table, &s.name, method, metric) else { continue };
                let better: Vec<String> = (0..lu.len())
                    .filter(|&j| other[j] + other_ci[j] < lu[j] - lu_ci[j])
                    .map(|j| format!("j{}: {} vs {}", j + 1, figure(other[j]), figure(lu[j])))
                    .collect();
                if !better.is_empty() {
                    rows.push(table_row([
                        s.name.clone(),
                        method.name().to_owned(),
                        metric.to_owned(),
                        better.join("; "),
                    ]));
                }
            }
        }
    }
    if rows.is_empty() {
        md.push_str("No baseline is better than the paper's method beyond the 95 % intervals on any joint.\n");
    } else {
        md.push_str(
            "| scenario | method | metric | joints where it is lower than lu (its mean vs lu's) |\n|---|---|---|---|\n",
        );
        md.extend(rows);
    }
    md
}

/// What the first seed's runs show about command noise, said plainly.
fn observations<const N: usize>(outcomes: &[RunOutcome<N>]) -> String {
    let mut md = String::from("\n");
    for o in outcomes.iter().filter(|o| matches!(o.method, Method::Chen | Method::Momentum)) {
        let Some(lu) = outcomes.iter().find(|l| l.scenario == o.scenario && l.method == Method::Lu) else { continue };
        let ratio = mean(&o.metrics.tau_cmd_noise) / mean(&lu.metrics.tau_cmd_noise);
        let _ = writeln!(
            md,
            "- {} / {}: its command is {ratio:.1}× as noisy as lu's (first seed).",
            o.scenario,
            o.method.name()
        );
    }
    md.push_str("\nObservers that use the measured velocity (chen, momentum) feed its noise into `d̂` and so into the command; a stiffer loop can then track better in closed loop while estimating worse. Tracking RMSE alone does not settle which method is better on a real arm, where command noise excites the actuators (a hydraulic arm's valves most of all).\n");
    md
}

/// Cancelling viscous friction `−F_v q̇` with an estimate that lags by `τ_d` leaves
/// `≈ F_v τ_d q̈`: the loop sees its inertia reduced by `F_v τ_d`. Where that exceeds the joint's
/// inertia, the compensated joint is destabilised and only friction's nonlinearity bounds it.
fn lagged_cancellation<const N: usize>(scenarios: &[Scenario]) -> Result<String, SimError> {
    let Some(first) = scenarios.first() else { return Ok(String::new()) };
    let nominal = crate::nominal_dynamics::<N>(&first.robot)?;
    let nominal = nominal.as_ref();
    let q0 = hya_core::JointVector::<N>::from_column_slice(&crate::initial_position(first, N));
    let inertia = nominal.mass_matrix(&q0).diagonal();
    let w = first.controller.observer_bandwidth_rad_s;
    let delay = 1.0 / w + 2.0 * hya_core::filter::PAPER_ZETA / w;
    let mut md = format!(
        "\n### Lagged cancellation of viscous friction\n\nThe estimate lags the disturbance by about τ_d = 1/ω1 + 2ζ/ω2 = {delay:.3} s. Cancelling viscous friction `−F_v q̇` with it leaves roughly `F_v τ_d q̈` uncancelled, as if the joint's inertia were reduced by `F_v τ_d`. Where that exceeds the joint's inertia, this simple rule predicts that the compensated joint oscillates slowly, bounded only by friction's nonlinearity{}:\n\n| joint | F_v [N·m·s/rad] | F_v τ_d [kg·m²] | M_ii(q0) [kg·m²] | F_v τ_d > M_ii |\n|---|---|---|---|---|\n",
        if first.robot == "hya" { " (the paper reports residual oscillations on HyA's joints 3, 5 and 6); the sweep below measures it" } else { "" }
    );
    for j in 0..N {
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

fn parameters<const N: usize>(scenarios: &[Scenario]) -> Result<String, SimError> {
    let mut md = String::from("\n## Every parameter\n\n");
    let Some(first) = scenarios.first() else { return Ok(md) };
    let model = crate::robot_model(&first.robot)?;
    let description = match hya_robots::find(&first.robot) {
        Some(robot) => format!("`robots/urdf/{}.urdf`, generated code", robot.name),
        None => format!("`{}`, the run-time model", first.robot),
    };
    let _ = writeln!(md, "### Nominal rigid-body model ({description}), used by the controller and observers\n");
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
    let nominal = crate::nominal_dynamics::<N>(&first.robot)?;
    let nominal = nominal.as_ref();
    let q0 = hya_core::JointVector::<N>::from_column_slice(&crate::initial_position(first, N));
    let gains = gains(nominal, first, &q0)?;
    let _ = writeln!(
        md,
        "\n### Controller and observers\n\n- Computed torque, the paper's form `τ = M q̈_des + C + G − K_D ė − K_P e (− d̂)` with `M`, `C`, `G` from the nominal generated model at the measured `q`, at {} s per tick; velocity from the {} source; torque limits ({}) N·m.\n- Gains, one rule for every method: per joint the natural frequency ({}) rad/s with damping ratio {} on the nominal `M(q0)` diagonal, stiffened where needed so that the PD's torque at {} rad of error reaches the joint's nominal static friction, but to no more than {} rad/s (the actuators and the delay); `K_P = clamp(F_s / e_f, M_ii ω_n², M_ii ω_max²)`, `K_D = 2ζ √(K_P M_ii)`: K_P = ({}) N·m/rad, K_D = ({}) N·m·s/rad.\n- pid: the same PD plus `K_I ∫e`, `K_I = K_P ω_n · {}`, its torque clamped to ± ({}) N·m (anti-windup). At low frequency the paper's estimator acts like this integral: pid is the honest baseline for it.\n- Observers, all with rates of {b}/s at the start pose (`bandwidth_rad_s` in `summary.json`, computed from each design): lu, the paper's filters, ζ = 0.8, ω1 = ω2 = {b} rad/s (poles of magnitude {b}; −3 dB near 0.64·{b} rad/s); chen, `Y = β M(q0)` with β = {b}/s, so that `L = Y M⁻¹ = β I` at `q0` (Mohammadi's scalar `Y = y I` would spread the rates by the ratio of `M`'s largest to smallest eigenvalue); momentum, `K_O = {b}/s` per joint; eso, ω_o = {b} rad/s, model-assisted (−3 dB near 0.51·{b} rad/s). Chen and momentum read the same derived velocity as the controller.\n- Start pose ({}) rad; the actuators start holding the nominal gravity torque.",
        c.dt_s,
        match first.sensors.velocity {
            crate::scenario::VelocitySource::Difference => "encoder difference (low-passed)",
            crate::scenario::VelocitySource::Filter => "filtered (q̂̇ of the paper's filter)",
            crate::scenario::VelocitySource::Sensor => "velocity sensor",
        },
        list(&c.torque_limit_nm),
        list(&c.natural_frequency_rad_s),
        c.damping_ratio,
        c.friction_error_rad,
        c.max_natural_frequency_rad_s,
        list(gains.kp().diagonal().as_slice()),
        list(gains.kd().diagonal().as_slice()),
        c.integral_zero_ratio,
        list(&c.integral_limit_nm),
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
                match s.sensors.velocity {
                    crate::scenario::VelocitySource::Sensor => noise_text(&s.noise.velocity),
                    _ => "no sensor (from the encoders)".into(),
                },
                if s.plant.actuator == crate::scenario::ActuatorKind::Hydraulic
                    && s.sensors.torque == crate::scenario::TorqueSource::Pressure
                {
                    format!(
                        "from the chamber pressures (Gaussian σ = {} Pa, offsets within ±{} Pa)",
                        s.sensors.pressure_noise_pa, s.sensors.pressure_offset_pa
                    )
                } else {
                    noise_text(&s.noise.torque)
                }
            ),
            s.methods.iter().map(|m| m.name()).collect::<Vec<_>>().join(", "),
            format!("{}", s.seed),
        ]));
    }
    md.push_str("\nDefault sensor noise: one count of HyA's 19-bit encoders on the angle; where a scenario defines a velocity sensor or a load cell, the uniform bounds measured on hydraulic joints (velocity 0.055 rad/s, torque 0.073 N·m; Vorndamme et al.). The weight: 2 kg, our choice (the paper does not give its mass; its weight-drop figure shows joint 2's disturbance going from about +5 to about −5 N·m). Each scenario's description names the paper times it follows. Sine amplitudes and frequency, the goto transition and the controller's natural frequencies are not given in the paper; they are our choices, fixed before any comparison was run.\n");
    Ok(md)
}
