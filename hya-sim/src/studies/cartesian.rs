//! A task-space scenario's study: every method over seeds under the Cartesian impedance
//! controller ([`crate::run::cartesian`]), measured where the task is set, at the controlled
//! frame: the distance of its origin from the reference and the angle between its axes and the
//! reference's, `‖p_des − p‖` and `‖log(R_des Rᵀ)‖`, from the plant's true joint angles.
//!
//! Per run, each over the ticks its trace keeps (every tick up to 30 s of control):
//! - RMS after the metrics' warm-up;
//! - the peak during the move and the half second after it (`[t_s, t_s + T + 0.5]`);
//! - the mean over the run's final window (its last [`SETTLED_WINDOW_S`], or the last fifth of
//!   what follows the warm-up, as the joint-space metrics take it), starting no earlier than 1 s
//!   after the move: where the arm holds the moved pose, under the payload if one rests there;
//! - the mean over the hold before the move once a payload set down before it has rested
//!   half a second (`None` without one).

use crate::analysis::metrics::{SETTLED_WINDOW_S, WARM_UP_S};
use crate::analysis::seeds::{lockstep_groups, parallel_map};
use crate::config::scenario::{Method, Scenario};
use crate::config::settings::{Setup, TaskSetup, TaskTimes};
use crate::error::SimError;
use crate::robot::Robot;
use crate::run::cartesian::CartesianLaw;
use crate::run::model::LoopModel;
use crate::run::trace::{Recording, Trace};
use crate::run::RunSetup;
use hya_core::cartesian::Vector6;

/// The controlled frame's errors in one run (m and rad; see the module's notes).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct ToolErrors {
    /// RMS of `‖p_des − p‖` after the warm-up, m.
    pub position_rms_m: f64,
    /// Peak of `‖p_des − p‖` over the move and the half second after it, m.
    pub position_peak_m: f64,
    /// Mean of `‖p_des − p‖` over the final window, m.
    pub position_final_m: f64,
    /// Mean of `‖p_des − p‖` over the loaded hold before the move, m.
    pub position_loaded_hold_m: Option<f64>,
    /// RMS of the orientation error's angle after the warm-up, rad.
    pub orientation_rms_rad: f64,
    /// Its peak over the move and the half second after it, rad.
    pub orientation_peak_rad: f64,
    /// Its mean over the final window, rad.
    pub orientation_final_rad: f64,
}

/// One run of the study.
#[derive(Debug, Clone, serde::Serialize)]
pub struct CartesianRun {
    /// Its method.
    pub method: Method,
    /// Its seed.
    pub seed: u64,
    /// The controlled frame's errors.
    pub tool: ToolErrors,
    /// `√(Σ_j RMSE(d̂_j − d_j)²)` after the warm-up, N·m (`None` without an estimate).
    pub disturbance_error_nm: Option<f64>,
    /// `√(Σ_j σ_j²)` of the joints' command noise (the RMS of the command's first difference
    /// over √2), N·m.
    pub command_noise_nm: f64,
}

/// The controlled frame's error over time in one run, for the figure and the CSV file.
#[derive(Debug, Clone, Default)]
pub struct ToolSeries {
    /// Time, s.
    pub time: Vec<f64>,
    /// `(p_des − p, log(R_des Rᵀ))` in base axes, m and rad.
    pub error: Vec<[f64; 6]>,
    /// `‖p_des − p‖`, m.
    pub position_m: Vec<f64>,
    /// `‖log(R_des Rᵀ)‖`, rad.
    pub orientation_rad: Vec<f64>,
}

/// What the loop's design says the frame's errors cannot go below, at the start pose.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Floors {
    /// How far the frame's origin moves for half an encoder count on every joint at once,
    /// `Σ_j ‖J_v,j‖ π / counts`, m: position errors below it are below what the loop measures.
    pub resolution_m: f64,
    /// How far the spring lets the origin trail at the reference's peak acceleration, without an
    /// acceleration feed-forward in the law: `‖(Λ_ii a_i / K_i)_{i = x, y, z}‖`, m, with `Λ` the
    /// task-space inertia `(J M⁻¹ Jᵀ)⁻¹` of the loop's model (no payload) and `a` the
    /// minimum-jerk peak `10/√3 Δp / T²` (`None` where `Λ` is singular).
    pub trailing_m: Option<f64>,
}

/// What the study found.
#[derive(Debug, Clone)]
pub struct CartesianStudy {
    /// The scenario, as run.
    pub scenario: Scenario,
    /// The controlled frame.
    pub frame: String,
    /// The floors of the errors at the start pose.
    pub floors: Floors,
    /// Seeds per method.
    pub seeds: usize,
    /// Every run, method by method, seed by seed.
    pub runs: Vec<CartesianRun>,
    /// The first seed's error norms per method, in the scenario's order.
    pub first: Vec<(Method, ToolSeries)>,
}

impl CartesianStudy {
    /// `method`'s runs, seed by seed.
    pub fn of(&self, method: Method) -> impl Iterator<Item = &CartesianRun> {
        self.runs.iter().filter(move |r| r.method == method)
    }
}

/// Runs every method of `scenario` (a task-space one) over `seeds` seeds (the scenario's seed
/// and the next ones) on every core; `progress` is told each finished run's simulated seconds.
pub fn run<const N: usize>(
    robot: &Robot<N>,
    scenario: &Scenario,
    seeds: usize,
    progress: &(dyn Fn(f64) + Sync),
) -> Result<CartesianStudy, SimError> {
    let settings = Setup::<N>::for_arm(scenario, &robot.model)?;
    let Some(setup) = &settings.cartesian else {
        return Err(SimError::Scenario {
            origin: scenario.name.clone(),
            message: "its task is set in joint space: `hya run` reports it as the paper's experiments".into(),
        });
    };
    let model = LoopModel::of(&settings.loop_model, robot)?;
    let q0 = settings.initial_position;
    let law = CartesianLaw::new((setup, &settings.task), model.dynamics(), &robot.model, (&q0, settings.torque_limit))?
        .ok_or(SimError::Nothing(
            "a Cartesian controller without a Cartesian task (refused by the scenario's check)",
        ))?;
    let drop_s = settings.plant.loads.weight_drop.as_ref().map(|d| d.drop_s);
    let setups = scenario
        .methods
        .iter()
        .map(|&method| RunSetup::task_space(Setup::for_run(scenario, method, &robot.model)?, method, robot))
        .collect::<Result<Vec<_>, _>>()?;
    let jobs: Vec<(usize, usize)> = (0..setups.len()).flat_map(|m| (0..seeds).map(move |k| (m, k))).collect();
    let seed = |k: usize| scenario.seed.wrapping_add(k as u64);
    // Each method's seeds step together (`RunSetup::run_together`).
    let groups = parallel_map(&lockstep_groups(&jobs, |&(m, _)| m), |group| {
        let (m, method) = (group[0].0, scenario.methods[group[0].0]);
        let runs =
            setups[m].run_together(&group.iter().map(|&(_, k)| (seed(k), Recording::Bounded)).collect::<Vec<_>>());
        group
            .iter()
            .zip(runs)
            .map(|(&(_, k), run)| {
                let failed = |e: SimError| SimError::Run {
                    run: format!("{} / {} / seed {}", scenario.name, method.name(), seed(k)),
                    source: Box::new(e),
                };
                let run = run.map_err(failed)?;
                progress(scenario.duration_s);
                let series = series(law.clone(), &run.trace);
                let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
                let record = CartesianRun {
                    method,
                    seed: seed(k),
                    tool: errors(&series, settings.task.times(), drop_s),
                    disturbance_error_nm: run.metrics.rmse_d.as_deref().map(norm),
                    command_noise_nm: norm(&run.metrics.tau_cmd_noise),
                };
                Ok((record, (k == 0).then_some((method, series))))
            })
            .collect::<Vec<Result<_, SimError>>>()
    });
    let results = groups.into_iter().flatten();
    let mut study = CartesianStudy {
        scenario: scenario.clone(),
        frame: law.frame().to_owned(),
        floors: floors(law.clone(), model.dynamics(), &settings),
        seeds,
        runs: vec![],
        first: vec![],
    };
    for result in results {
        let (run, first) = result?;
        study.runs.push(run);
        study.first.extend(first);
    }
    Ok(study)
}

/// The [`Floors`] of the loop `law` on its model `dynamics` at the start pose.
fn floors<const N: usize>(
    mut law: CartesianLaw<'_, N>,
    dynamics: &dyn hya_core::Dynamics<N>,
    settings: &Setup<N>,
) -> Floors {
    let q0 = settings.initial_position;
    let jacobian = law.frame_state(&q0).jacobian;
    let quantum = std::f64::consts::PI / settings.sensors.encoder_counts_per_rev as f64;
    let resolution_m = (0..N).map(|j| jacobian.fixed_view::<3, 1>(0, j).norm() * quantum).sum();
    let TaskSetup::Cartesian { transition_s, offset, rotation, .. } = settings.task else {
        return Floors { resolution_m, trailing_m: None };
    };
    // Quasi-static at the reference's peak acceleration: K e = Λ a, every spring needed.
    let stiffness = law.stiffness();
    let peak = 10.0 / 3f64.sqrt() / (transition_s * transition_s);
    let acceleration = Vector6::from_iterator(offset.iter().chain(&rotation).map(|v| v * peak));
    let inverse_mass = dynamics.mass_matrix(&q0).try_inverse();
    let task_inertia = inverse_mass.and_then(|m| (jacobian * m * jacobian.transpose()).try_inverse());
    let trailing_m = task_inertia.filter(|_| stiffness.iter().all(|k| *k > 0.0)).map(|inertia| {
        let error = (inertia * acceleration).component_div(&stiffness);
        error.fixed_rows::<3>(0).norm()
    });
    Floors { resolution_m, trailing_m }
}

/// The error norms of the ticks `trace` kept.
fn series<const N: usize>(mut law: CartesianLaw<'_, N>, trace: &Trace<N>) -> ToolSeries {
    let mut series = ToolSeries::default();
    for (&t, q) in trace.time.iter().zip(&trace.q) {
        let error = law.pose_error(t, q);
        series.time.push(t);
        series.error.push(error.into());
        series.position_m.push(error.fixed_rows::<3>(0).norm());
        series.orientation_rad.push(error.fixed_rows::<3>(3).norm());
    }
    series
}

/// The windows of the module's notes on `series`, for a move at `times` and a payload set down
/// at `drop_s`.
fn errors(series: &ToolSeries, times: TaskTimes, drop_s: Option<f64>) -> ToolErrors {
    let end = series.time.last().copied().unwrap_or(0.0);
    let (start_s, transition_s) = match times {
        TaskTimes::Goto { start_s, transition_s } => (start_s, transition_s),
        _ => (end, 0.0),
    };
    let final_from = (end - SETTLED_WINDOW_S.min(0.2 * (end - WARM_UP_S))).max(start_s + transition_s + 1.0).min(end);
    let loaded_from = drop_s.map(|d| d + 0.5).filter(|&from| from < start_s);
    let window = |values: &[f64], from: f64, to: f64| -> Vec<f64> {
        series.time.iter().zip(values).filter(|(t, _)| (from..=to).contains(*t)).map(|(_, v)| *v).collect()
    };
    let rms = |v: Vec<f64>| (v.iter().map(|x| x * x).sum::<f64>() / v.len().max(1) as f64).sqrt();
    let mean = |v: Vec<f64>| v.iter().sum::<f64>() / v.len().max(1) as f64;
    let peak = |v: Vec<f64>| v.into_iter().fold(0.0, f64::max);
    let move_end = start_s + transition_s + 0.5;
    let (p, r) = (&series.position_m, &series.orientation_rad);
    ToolErrors {
        position_rms_m: rms(window(p, WARM_UP_S, end)),
        position_peak_m: peak(window(p, start_s, move_end)),
        position_final_m: mean(window(p, final_from, end)),
        position_loaded_hold_m: loaded_from.map(|from| mean(window(p, from, start_s))),
        orientation_rms_rad: rms(window(r, WARM_UP_S, end)),
        orientation_peak_rad: peak(window(r, start_s, move_end)),
        orientation_final_rad: mean(window(r, final_from, end)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_windows_take_what_the_notes_say() {
        // 0.1 s ticks over 10 s; the position error is t itself, the orientation error 1.
        // A spike of 100 at 4 s, before the move, which no window of the move or the end takes;
        // the orientation error 1 but 3 at 8 s.
        let time: Vec<f64> = (0..=100).map(|k| k as f64 * 0.1).collect();
        let position_m = time.iter().map(|&t| if (t - 4.0).abs() < 1e-9 { 100.0 } else { t }).collect();
        let orientation_rad = time.iter().map(|&t| if (t - 8.0).abs() < 1e-9 { 3.0 } else { 1.0 }).collect();
        let series = ToolSeries { position_m, orientation_rad, time, error: vec![] };
        let times = TaskTimes::Goto { start_s: 5.0, transition_s: 1.0 };
        let e = errors(&series, times, Some(1.5));
        // The move's window ends at 6.5 s; the final window is the last fifth after the warm-up,
        // [8.1, 10].
        assert!((e.position_peak_m - 6.5).abs() < 1e-9, "{e:?}");
        let mean_from = |from: f64| {
            let kept: Vec<f64> = series.time.iter().copied().filter(|t| (from..=10.0).contains(t)).collect();
            kept.iter().sum::<f64>() / kept.len() as f64
        };
        assert!((e.position_final_m - mean_from(8.1)).abs() < 1e-9, "{e:?}");
        // A move that ends late pushes the final window to 1 s after it.
        let late = errors(&series, TaskTimes::Goto { start_s: 8.0, transition_s: 0.5 }, None);
        assert!((late.position_final_m - mean_from(9.5)).abs() < 1e-9, "{late:?}");
        // The loaded hold: [2, 5], the spike at 4 s in it.
        let hold: Vec<f64> = series
            .time
            .iter()
            .zip(&series.position_m)
            .filter(|(t, _)| (2.0..=5.0).contains(*t))
            .map(|(_, v)| *v)
            .collect();
        assert!((e.position_loaded_hold_m.unwrap() - hold.iter().sum::<f64>() / hold.len() as f64).abs() < 1e-9);
        // The orientation's peak over the move is 1, and its final mean too: the final window
        // starts at 8.1 s, after the 3 at 8 s.
        assert!((e.orientation_peak_rad - 1.0).abs() < 1e-12 && (e.orientation_final_rad - 1.0).abs() < 1e-12);
        // RMS over [0.5, 10] on the 0.1 s grid, the spike and the 3 included.
        let kept: Vec<f64> =
            series.time.iter().zip(&series.position_m).filter(|(t, _)| **t >= 0.5).map(|(_, v)| *v).collect();
        let rms = (kept.iter().map(|v| v * v).sum::<f64>() / kept.len() as f64).sqrt();
        assert!((e.position_rms_m - rms).abs() < 1e-9 && rms > 10.0);
        let turned: Vec<f64> =
            series.time.iter().zip(&series.orientation_rad).filter(|(t, _)| **t >= 0.5).map(|(_, v)| *v).collect();
        let rms = (turned.iter().map(|v| v * v).sum::<f64>() / turned.len() as f64).sqrt();
        assert!((e.orientation_rms_rad - rms).abs() < 1e-12 && rms > 1.0);
        assert_eq!(errors(&series, times, None).position_loaded_hold_m, None);
    }
}
