//! One closed-loop run: the controller at the control rate with its command held, the plant
//! integrated at `substeps` times that rate, and the true disturbance recorded.
//!
//! The true disturbance is everything the loop's model (the nominal one, or the one the scenario
//! names: [`model::LoopModel`]) does not explain, seen from the torque the controller measures,
//! noise aside: `d = ID_model(q, q̇, q̈_true) − τ_act − τ_o`, with `τ_o` the constant error of
//! that measurement (its pressure transducers' offsets, [`Sensors::offset_torque`](sensors::Sensors::offset_torque)). It includes
//! friction, parameter error, payload, external loads and the sensors' offsets, so estimate
//! errors are measured, not guessed, and an estimator is not charged for an offset that the
//! compensation needs it to take up.

use hya_core::{BoxedObserver, Dynamics, Gains, JointVector, Measurement, NonlinearGain, ObserverDesign};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::config::scenario::{ChenGain, IntegralRule, Method};
use crate::config::settings::{Setup, TaskSetup};
use crate::error::SimError;
use crate::plant::lockstep::{Failure, Lockstep};
use crate::plant::{perturbed, PlantState};
use crate::robot::Robot;
use hya_core::model::TreeModel;
use seed_loop::SeedLoop;
use task::Trajectory;
use trace::{Recording, Trace};

pub mod cartesian;
pub mod model;
pub mod rollout;
mod seed_loop;
pub mod sensors;
pub mod task;
pub mod trace;

/// The observer design of `method` at pole magnitude `bandwidth` (rad/s) and control period
/// `dt` (s), Chen's by the gain design `chen`; `None` for the methods without an observer.
pub fn observer_design(
    method: Method,
    (bandwidth, dt, chen): (f64, f64, ChenGain),
) -> Result<Option<ObserverDesign>, SimError> {
    let (bandwidth_rad_s, dt_s) = (bandwidth, dt);
    Ok(match method {
        Method::None | Method::Pid => None,
        Method::Lu => Some(
            ObserverDesign::paper_at(bandwidth, dt)
                .map_err(|source| SimError::Setup { setting: method.name().into(), source })?,
        ),
        Method::Chen => {
            let gain = match chen {
                ChenGain::Inertia => NonlinearGain::Inertia,
                ChenGain::Scalar => NonlinearGain::Scalar,
            };
            Some(ObserverDesign::Nonlinear { bandwidth_rad_s, dt_s, gain })
        }
        Method::Momentum => Some(ObserverDesign::Momentum { bandwidth_rad_s, dt_s }),
        Method::Eso => Some(ObserverDesign::ExtendedState { bandwidth_rad_s, dt_s }),
    })
}

/// The observer of `method` ([`observer_design`]) on the model `nominal`, started on the first
/// measurement, with its rates at the start pose (1/s) from its design; `None` for the methods
/// without one.
pub fn observer_designed<'a, const N: usize, D: Dynamics<N> + Send + 'a>(
    method: Method,
    nominal: D,
    design: (f64, f64, ChenGain),
    first: &Measurement<N>,
) -> Result<Option<(BoxedObserver<'a, N>, Vec<f64>)>, SimError> {
    let Some(design) = observer_design(method, design)? else { return Ok(None) };
    let (observer, rates) =
        design.build(nominal, first).map_err(|source| SimError::Setup { setting: method.name().into(), source })?;
    Ok(Some((observer, rates.as_slice().to_vec())))
}

/// Computed-torque gains by one rule for every method. Per joint, the natural frequency `ω_n`
/// with damping ratio `ζ` on the loop model's `M_ii(q0)`, stiffened where needed so that the PD's
/// torque at the error `e_f` reaches the joint's nominal static friction `F_s`, but to no more
/// than `ω_max` (the actuators' and the delay's limit):
///
/// ```text
/// K_P = clamp(F_s / e_f, M_ii ω_n², M_ii ω_max²),   K_D = 2 ζ √(K_P M_ii)
/// ```
pub fn gains<const N: usize>(nominal: &dyn Dynamics<N>, joints: &Setup<N>) -> Result<Gains<N>, SimError> {
    let c = &joints.control;
    let (omega, friction) = (&joints.natural_frequency, &joints.static_friction);
    let inertia = nominal.mass_matrix(&joints.initial_position).diagonal();
    let kp: [f64; N] = core::array::from_fn(|i| {
        let floor = inertia[i] * omega[i] * omega[i];
        let ceiling = (inertia[i] * c.max_natural_frequency_rad_s.powi(2)).max(floor);
        (friction[i] / c.friction_error_rad).clamp(floor, ceiling)
    });
    let kd: [f64; N] = core::array::from_fn(|i| 2.0 * c.damping_ratio * (kp[i] * inertia[i]).sqrt());
    Gains::diagonal(kp, kd).map_err(|source| SimError::Setup { setting: "controller".into(), source })
}

/// The PID baseline's `K_D` and `K_I` per joint, N·m·s/rad and N·m/(rad·s), by the controller's
/// [`IntegralRule`] (`K_D` is the common rule's but for [`IntegralRule::PolePlacement`]);
/// `inertia` is the loop model's `M_ii(q0)`; and whether each joint's `K_I` was capped by the
/// stability bound.
pub fn pid_gains<const N: usize>(
    gains: &Gains<N>,
    inertia: &JointVector<N>,
    joints: &Setup<N>,
) -> (JointVector<N>, JointVector<N>, [bool; N]) {
    let c = &joints.control;
    let (kp, kd) = (gains.kp().diagonal(), gains.kd().diagonal());
    match c.integral_rule {
        IntegralRule::ZeroRatio => {
            (kd, kp.component_mul(&joints.natural_frequency) * c.integral_zero_ratio, [false; N])
        }
        IntegralRule::MatchEstimator => {
            let delay = crate::linear::paper_delay(c.observer_bandwidth_rad_s);
            let capped: [bool; N] = core::array::from_fn(|i| kp[i] / delay > 0.5 * kd[i] * kp[i] / inertia[i]);
            let gain = JointVector::from_fn(|i, _| (kp[i] / delay).min(0.5 * kd[i] * kp[i] / inertia[i]));
            (kd, gain, capped)
        }
        IntegralRule::PolePlacement => {
            let omega = JointVector::<N>::from_fn(|i, _| (kp[i] / (3.0 * inertia[i])).sqrt());
            let kd = JointVector::from_fn(|i, _| 3.0 * inertia[i] * omega[i]);
            let ki = JointVector::from_fn(|i, _| inertia[i] * omega[i].powi(3));
            (kd, ki, [false; N])
        }
    }
}

/// The integral term of the PID baseline, `K_I ∫ e dt` ([`pid_gains`]), its torque clamped
/// to `± limit` (anti-windup: the integral stops growing at the clamp).
#[derive(Debug, Clone)]
struct IntegralAction<const N: usize> {
    gain: JointVector<N>,
    limit: JointVector<N>,
    torque: JointVector<N>,
    dt: f64,
}

impl<const N: usize> IntegralAction<N> {
    fn new(gain: JointVector<N>, joints: &Setup<N>) -> Result<Self, SimError> {
        Ok(Self { gain, limit: joints.pid_integral_limit()?, torque: JointVector::zeros(), dt: joints.timing.dt_s })
    }

    /// Adds `K_I e T` and returns the clamped integral torque, N·m.
    fn step(&mut self, error: &JointVector<N>) -> JointVector<N> {
        self.torque = JointVector::from_fn(|i, _| {
            (self.torque[i] + self.gain[i] * error[i] * self.dt).clamp(-self.limit[i], self.limit[i])
        });
        self.torque
    }
}

/// The record of one closed-loop run.
#[derive(Debug, Clone)]
pub struct ClosedLoop<const N: usize> {
    /// Its time series, as far as `Recording` kept them.
    pub trace: Trace<N>,
    /// Its metrics, from every tick.
    pub metrics: crate::analysis::metrics::Metrics,
    /// The observer's rates at the start pose, 1/s, from its design (ascending eigenvalues of
    /// `L` for Chen's observer); `None` without an observer.
    pub bandwidth_rad_s: Option<Vec<f64>>,
}

/// One scenario's loop under one method, set up once (its settings checked, its loop model
/// loaded, its reference built) and shared by its seeds: each [`run`](Self::run) differs only by
/// the seed, which draws the plant's perturbation, friction profiles and noise.
pub struct RunSetup<'a, const N: usize> {
    method: Method,
    settings: Setup<N>,
    model: model::LoopModel<'a, N>,
    trajectory: Trajectory<N>,
    robot: &'a Robot<N>,
}

impl<'a, const N: usize> RunSetup<'a, N> {
    /// The loop of `settings` (a scenario's, [`Setup::for_run`] of `method`) under
    /// `method` on `robot`: the controller and observers on its nominal dynamics or the model the
    /// settings name ([`model::LoopModel`]).
    pub fn new(settings: Setup<N>, method: Method, robot: &'a Robot<N>) -> Result<Self, SimError> {
        if let TaskSetup::Cartesian { .. } = settings.task {
            return Err(SimError::Scenario {
                origin: settings.name.clone(),
                message: "a task set in task space is measured at its frame (studies::cartesian, `hya run` on it \
                          alone), not by the joint-space runs"
                    .into(),
            });
        }
        Self::task_space(settings, method, robot)
    }

    /// [`Self::new`] for a task of either kind: the Cartesian study's runs, which it measures at
    /// the frame ([`crate::studies::cartesian`]).
    pub fn task_space(settings: Setup<N>, method: Method, robot: &'a Robot<N>) -> Result<Self, SimError> {
        let trajectory = Trajectory::new(settings.task, settings.initial_position);
        trajectory.within_limits(&robot.model)?;
        let model = model::LoopModel::of(&settings.loop_model, robot)?;
        Ok(Self { method, settings, model, trajectory, robot })
    }

    /// The run of `seed`, the plant on the robot's model perturbed by it; its trace kept as
    /// `recording` says.
    pub fn run(&self, seed: u64, recording: Recording) -> Result<ClosedLoop<N>, SimError> {
        let on = (&self.trajectory, recording);
        run_loop((&self.settings, &self.model, seed), self.method, self.robot, on, |_, _| {})
    }

    /// The runs of `seeds` (each with how its trace is kept), each what [`Self::run`] gives it,
    /// bit for bit: stepped together, their plants' rigid bodies one per vector lane, where the
    /// robot's plant is generated code ([`Robot::bodies`]); one by one otherwise. Each run
    /// fails alone, with its own error.
    pub fn run_together(&self, seeds: &[(u64, Recording)]) -> Vec<Result<ClosedLoop<N>, SimError>> {
        match self.robot.bodies {
            Some(kernel) if seeds.len() > 1 => self.lockstep(kernel, seeds),
            _ => seeds.iter().map(|&(seed, recording)| self.run(seed, recording)).collect(),
        }
    }

    /// [`Self::run_together`] in lockstep on `kernel`.
    fn lockstep(
        &self,
        kernel: &(dyn hya_core::BodiesBatch<N> + Send + Sync),
        seeds: &[(u64, Recording)],
    ) -> Vec<Result<ClosedLoop<N>, SimError>> {
        let (mut loops, mut plants) = (Vec::with_capacity(seeds.len()), Vec::with_capacity(seeds.len()));
        for &(seed, recording) in seeds {
            let on = (&self.trajectory, recording);
            match SeedLoop::new((&self.settings, &self.model, seed), self.method, self.robot, on) {
                Ok((seed_loop, plant)) => {
                    loops.push(seed_loop);
                    plants.push(plant);
                }
                // A seed that cannot start: every seed alone, each with its own outcome.
                Err(_) => return seeds.iter().map(|&(seed, recording)| self.run(seed, recording)).collect(),
            }
        }
        let count = plants.len();
        let mut lockstep = Lockstep::new(kernel, count);
        let mut failed: Vec<Failure> = (0..count).map(|_| None).collect();
        let (mut commands, mut accelerations) = (vec![JointVector::zeros(); count], vec![JointVector::zeros(); count]);
        let mut states = vec![PlantState::zeros(); count];
        let timing = &self.settings.timing;
        for k in 0..timing.steps {
            if failed.iter().all(Option::is_some) {
                break;
            }
            for j in 0..count {
                if failed[j].is_none() {
                    match loops[j].command(k, &plants[j], &mut |_, _| {}) {
                        Ok(command) => commands[j] = command,
                        Err(e) => failed[j] = Some(e),
                    }
                    states[j] = plants[j].state;
                }
            }
            lockstep.advance(&mut plants, (timing.dt_s, timing.substeps), &commands, (&mut accelerations, &mut failed));
            for j in 0..count {
                if failed[j].is_none() {
                    loops[j].record(k, &plants[j], (&states[j], &accelerations[j]));
                }
            }
        }
        loops
            .into_iter()
            .zip(failed)
            .map(|(seed_loop, failure)| match failure {
                Some(e) => Err(e),
                None => Ok(seed_loop.finish()),
            })
            .collect()
    }
}

/// Runs the loop of `settings` with `method` on `robot` ([`RunSetup`]) from the settings' seed;
/// its trace kept as `recording` says.
pub fn closed_loop<const N: usize>(
    settings: Setup<N>,
    method: Method,
    robot: &Robot<N>,
    recording: Recording,
) -> Result<ClosedLoop<N>, SimError> {
    let seed = settings.seed;
    RunSetup::new(settings, method, robot)?.run(seed, recording)
}

/// The plant's true rigid body: `model` perturbed by the relative parameter spread `spread`,
/// drawn from `seed`, with the random stream that then draws the friction profiles.
pub fn true_model(model: &TreeModel, spread: f64, seed: u64) -> (TreeModel, ChaCha8Rng) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let model = perturbed(model, spread, &mut rng);
    (model, rng)
}

/// [`closed_loop`] following `trajectory` instead of the settings' task, handing every
/// measurement the controller reads, with its time, to `log`: the log a real arm would record.
pub fn closed_loop_on<const N: usize>(
    settings: &Setup<N>,
    method: Method,
    robot: &Robot<N>,
    (trajectory, recording): (&Trajectory<N>, Recording),
    log: impl FnMut(f64, &Measurement<N>),
) -> Result<ClosedLoop<N>, SimError> {
    trajectory.within_limits(&robot.model)?;
    let model = model::LoopModel::of(&settings.loop_model, robot)?;
    run_loop((settings, &model, settings.seed), method, robot, (trajectory, recording), log)
}

/// The closed loop under `joints` (a scenario's checked settings) on the loop model `model`,
/// its plant drawn from `seed`.
fn run_loop<const N: usize>(
    (joints, model, seed): (&Setup<N>, &model::LoopModel<'_, N>, u64),
    method: Method,
    robot: &Robot<N>,
    (trajectory, recording): (&Trajectory<N>, Recording),
    mut log: impl FnMut(f64, &Measurement<N>),
) -> Result<ClosedLoop<N>, SimError> {
    let (mut seed_loop, mut plant) = SeedLoop::new((joints, model, seed), method, robot, (trajectory, recording))?;
    let (steps, substeps) = (joints.timing.steps, joints.timing.substeps);
    for k in 0..steps {
        let applied = seed_loop.command(k, &plant, &mut log)?;
        let state = plant.state;
        let acceleration = plant.advance(joints.timing.dt_s, substeps, &applied)?;
        seed_loop.record(k, &plant, (&state, &acceleration));
    }
    Ok(seed_loop.finish())
}
