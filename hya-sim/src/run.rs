//! One closed-loop run: the controller at the control rate with its command held, the plant
//! integrated at `substeps` times that rate, and the true disturbance recorded.
//!
//! The true disturbance is everything the nominal model does not explain, seen from the
//! actuator torque: `d = ID_nominal(q, q̇, q̈_true) − τ_act`. It includes friction, parameter
//! error, payload and external loads, so estimate errors are measured, not guessed.

use hya_core::model::TreeModel;
use std::collections::VecDeque;

use hya_core::{
    ComputedTorque, DisturbanceEstimator, DisturbanceObserver, Dynamics, ExtendedStateObserver, FilterParams, Gains,
    JointVector, Measurement, MomentumObserver, NonlinearDisturbanceObserver,
};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::Serialize;

use crate::plant::{per_joint, perturbed, DynamicsFactory, Plant};
use crate::scenario::{Method, Scenario};
use crate::sensors::Sensors;
use crate::task::Trajectory;
use crate::SimError;

/// Metrics skip this start-up interval (observers and filters settling), s.
pub const WARM_UP_S: f64 = 0.5;

/// Time series of one run, one entry per control tick.
#[derive(Debug, Clone, Default)]
pub struct Trace<const N: usize> {
    /// Time, s.
    pub time: Vec<f64>,
    /// True joint positions, rad.
    pub q: Vec<JointVector<N>>,
    /// Reference positions, rad.
    pub q_des: Vec<JointVector<N>>,
    /// True disturbance, N·m.
    pub d_true: Vec<JointVector<N>>,
    /// Estimated disturbance, N·m (zeros for `none`).
    pub d_hat: Vec<JointVector<N>>,
    /// Commanded torque, N·m.
    pub tau_cmd: Vec<JointVector<N>>,
}

/// Per-joint figures of one run (after [`WARM_UP_S`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Metrics {
    /// RMSE of tracking, `q − q_des`, rad.
    pub rmse_q: Vec<f64>,
    /// RMSE of `d̂ − d`, N·m; `None` without an estimator.
    pub rmse_d: Option<Vec<f64>>,
    /// Noise in the commanded torque: RMS of its first difference over √2, N·m (white noise of
    /// standard deviation σ gives σ; a smooth command gives nearly 0).
    pub tau_cmd_noise: Vec<f64>,
    /// Largest `|q − q_des|`, rad.
    pub max_abs_error_q: Vec<f64>,
}

/// A finished run.
#[derive(Debug, Clone)]
pub struct RunOutcome<const N: usize> {
    /// The scenario's name.
    pub scenario: String,
    /// The method.
    pub method: Method,
    /// Its time series.
    pub trace: Trace<N>,
    /// Its metrics.
    pub metrics: Metrics,
}

type Observer<'a, const N: usize> = Box<dyn DisturbanceObserver<N> + 'a>;

/// The observer of `method`, started on the first measurement; `None` for [`Method::None`].
fn observer<'a, const N: usize>(
    method: Method,
    nominal: &'a dyn Dynamics<N>,
    scenario: &Scenario,
    first: &Measurement<N>,
) -> Result<Option<Observer<'a, N>>, SimError> {
    let (bandwidth, dt) = (scenario.controller.observer_bandwidth_rad_s, scenario.controller.dt_s);
    let q0 = first.position;
    let qd0 = first.velocity.unwrap_or_else(JointVector::zeros);
    let core = |e: hya_core::Error| SimError::Config(format!("{}: {e}", method.name()));
    Ok(match method {
        Method::None => None,
        Method::Lu => {
            let params = FilterParams::new(0.8, bandwidth, bandwidth, dt).map_err(core)?;
            Some(Box::new(DisturbanceEstimator::new(nominal, params, q0, first.torque).map_err(core)?))
        }
        Method::Chen => {
            // σ ≥ λmax(M): the largest eigenvalue at the start pose with a 20 % margin.
            let sigma = 1.2 * largest_eigenvalue(&nominal.mass_matrix(&q0));
            let gain = hya_core::observers::mohammadi_gain(bandwidth, sigma, 0.0).map_err(core)?;
            Some(Box::new(NonlinearDisturbanceObserver::new(nominal, gain, dt, qd0).map_err(core)?))
        }
        Method::Momentum => Some(Box::new(
            MomentumObserver::new(nominal, JointVector::repeat(bandwidth), dt, q0, qd0, first.torque).map_err(core)?,
        )),
        Method::Eso => Some(Box::new(ExtendedStateObserver::new(nominal, bandwidth, dt, q0).map_err(core)?)),
    })
}

/// The largest eigenvalue of a symmetric positive definite matrix, by power iteration.
fn largest_eigenvalue<const N: usize>(m: &hya_core::JointMatrix<N>) -> f64 {
    let mut v = JointVector::<N>::repeat(1.0).normalize();
    for _ in 0..200 {
        v = (m * v).normalize();
    }
    v.dot(&(m * v))
}

/// Computed-torque gains from a natural frequency and damping per joint: `K_P = M_ii ω²`,
/// `K_D = 2 ζ ω M_ii`, with `M` the nominal mass matrix at `q0`.
pub fn gains<const N: usize>(
    nominal: &dyn Dynamics<N>,
    scenario: &Scenario,
    q0: &JointVector<N>,
) -> Result<Gains<N>, SimError> {
    let omega = per_joint::<N>("controller.natural_frequency_rad_s", &scenario.controller.natural_frequency_rad_s)?;
    let zeta = scenario.controller.damping_ratio;
    let inertia = nominal.mass_matrix(q0).diagonal();
    let kp: [f64; N] = core::array::from_fn(|i| inertia[i] * omega[i] * omega[i]);
    let kd: [f64; N] = core::array::from_fn(|i| 2.0 * zeta * omega[i] * inertia[i]);
    Gains::diagonal(kp, kd).map_err(|e| SimError::Config(format!("controller: {e}")))
}

/// Runs `scenario` with `method` on a plant built from `nominal_model` (perturbed, seeded), whose
/// rigid body `plant_dynamics` builds.
pub fn simulate<const N: usize>(
    scenario: &Scenario,
    method: Method,
    nominal: &dyn Dynamics<N>,
    nominal_model: &TreeModel,
    plant_dynamics: &DynamicsFactory<N>,
) -> Result<RunOutcome<N>, SimError> {
    let dt = scenario.controller.dt_s;
    let q0 = per_joint::<N>("initial_position_rad", &crate::initial_position(scenario, N))?;
    // One stream draws the model perturbation, then the friction profiles.
    let mut rng = ChaCha8Rng::seed_from_u64(scenario.seed);
    let true_model = perturbed(nominal_model, scenario.plant.parameter_spread, &mut rng);
    let hold = nominal.gravity(&q0);
    let mut plant = Plant::new(true_model, plant_dynamics, &scenario.plant, &scenario.loads, q0, hold, &mut rng)?;
    let bandwidth = scenario.controller.observer_bandwidth_rad_s;
    let mut sensors =
        Sensors::new(scenario.sensors.clone(), scenario.noise.clone(), scenario.seed.wrapping_add(1), dt, bandwidth);
    let trajectory = Trajectory::new(&scenario.task, q0)?;
    let controller = ComputedTorque::new(nominal, gains(nominal, scenario, &q0)?)
        .with_torque_limit(per_joint("controller.torque_limit_nm", &scenario.controller.torque_limit_nm)?)
        .map_err(|e| SimError::Config(format!("controller: {e}")))?;

    // The delays: readings wait `measurement_delay_ticks` before the controller sees them, and
    // commands `command_delay_ticks` before the valves do (the actuators hold `G(q0)` until then).
    let (measurement_delay, command_delay) =
        (scenario.sensors.measurement_delay_ticks, scenario.sensors.command_delay_ticks);
    let mut readings: VecDeque<Measurement<N>> = VecDeque::with_capacity(measurement_delay + 1);
    let mut commands: VecDeque<JointVector<N>> = std::iter::repeat_n(hold, command_delay).collect();
    let mut applied = hold;
    readings.push_back(sensors.read(&plant, &applied)?);
    let mut estimator = observer(method, nominal, scenario, &readings[0])?;
    let steps = (scenario.duration_s / dt).round() as usize;
    let substep = dt / scenario.plant.substeps as f64;
    let mut trace = Trace::default();
    for k in 0..steps {
        let t = k as f64 * dt;
        if k > 0 {
            readings.push_back(sensors.read(&plant, &applied)?);
            if readings.len() > measurement_delay + 1 {
                readings.pop_front();
            }
        }
        let measurement = readings[0];
        let at = |e: hya_core::Error| SimError::Numerical(format!("t = {t:.3} s: {e}"));
        let d_hat = match estimator.as_mut() {
            Some(o) if k > 0 => o.update(&measurement).map_err(at)?,
            Some(o) => *o.disturbance(),
            None => JointVector::zeros(),
        };
        let velocity = measurement.velocity.unwrap_or_else(JointVector::zeros);
        let reference = trajectory.at(t);
        let compensation = (method != Method::None).then_some(&d_hat);
        let command =
            controller.command(&measurement.position, &velocity, &reference, compensation).map_err(at)?.torque;
        commands.push_back(command);
        applied = commands.pop_front().unwrap_or(command);
        let state = plant.state;
        let acceleration = plant.acceleration(t, &state, &applied)?;
        trace.time.push(t);
        trace.q.push(state.q);
        trace.q_des.push(reference.position);
        trace.d_true.push(
            nominal.inverse_dynamics(&state.q, &state.qd, &acceleration) - plant.actuator_torque(&state, &applied),
        );
        trace.d_hat.push(d_hat);
        trace.tau_cmd.push(command);
        for _ in 0..scenario.plant.substeps {
            plant.step(substep, &applied)?;
        }
    }
    let metrics = metrics(&trace, method != Method::None);
    Ok(RunOutcome { scenario: scenario.name.clone(), method, trace, metrics })
}

/// Per-joint `sqrt(mean(x²))` over the samples.
fn rms<const N: usize>(samples: impl Iterator<Item = JointVector<N>>) -> Vec<f64> {
    let (sum, count) = samples.fold((JointVector::<N>::zeros(), 0usize), |(s, n), x| (s + x.component_mul(&x), n + 1));
    (sum / count.max(1) as f64).map(f64::sqrt).as_slice().to_vec()
}

/// The metrics of a trace, after the warm-up.
pub fn metrics<const N: usize>(trace: &Trace<N>, has_estimate: bool) -> Metrics {
    let start = trace.time.iter().position(|t| *t >= WARM_UP_S).unwrap_or(0);
    let errors = || trace.q[start..].iter().zip(&trace.q_des[start..]).map(|(q, r)| q - r);
    let estimate_errors = trace.d_hat[start..].iter().zip(&trace.d_true[start..]).map(|(e, d)| e - d);
    let command_steps = trace.tau_cmd[start..].windows(2).map(|w| (w[1] - w[0]) / std::f64::consts::SQRT_2);
    Metrics {
        rmse_q: rms(errors()),
        rmse_d: has_estimate.then(|| rms(estimate_errors)),
        tau_cmd_noise: rms(command_steps),
        max_abs_error_q: (0..N).map(|i| errors().map(|e| e[i].abs()).fold(0.0, f64::max)).collect(),
    }
}
