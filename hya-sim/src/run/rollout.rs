//! Open-loop rollouts: the plant under a recorded torque sequence, sampled at a fixed interval,
//! so that anyone can hold it against another simulator.

use hya_core::model::TreeModel;
use hya_core::JointVector;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::config::plant::PlantSetup;
use crate::config::settings::Setup;
use crate::error::SimError;
use crate::plant::{generic_dynamics, Plant, PlantState};

/// A torque command, N·m, held from `time` (s) until the next one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TorqueCommand<const N: usize> {
    /// When it starts to act, s.
    pub time: f64,
    /// The joint torques, N·m.
    pub torque: JointVector<N>,
}

/// The plant of `settings` (its seeded parameter perturbation, friction, actuators and loads)
/// for `model`, at rest at `q0` with its actuators holding `tau0`, and its physics step, s.
pub fn scenario_plant<const N: usize>(
    model: &TreeModel,
    settings: &Setup<N>,
    q0: JointVector<N>,
    tau0: JointVector<N>,
) -> Result<(Plant<N>, f64), SimError> {
    let plant = seeded_plant(model, &settings.plant, (settings.parameter_spread, settings.seed), (q0, tau0))?;
    Ok((plant, settings.timing.physics_step_s()))
}

/// The plant of `setup` for `model`, its rigid body perturbed by the relative spread `spread`
/// and its friction profiles drawn from `seed` ([`crate::run::true_model`]), at rest at `q0`
/// with its actuators holding `tau0`.
pub fn seeded_plant<const N: usize>(
    model: &TreeModel,
    setup: &PlantSetup<N>,
    (spread, seed): (f64, u64),
    (q0, tau0): (JointVector<N>, JointVector<N>),
) -> Result<Plant<N>, SimError> {
    setup.check_against(model)?;
    let (true_model, mut rng) = crate::run::true_model(model, spread, seed);
    Plant::new(true_model, &generic_dynamics::<N>, setup, (q0, tau0), &mut rng)
}

/// The rigid body of `model` alone ([`PlantSetup::rigid_body`]: nominal parameters, no
/// friction, ideal actuators, no loads), at rest at `q0`.
pub fn ideal_plant<const N: usize>(model: &TreeModel, q0: JointVector<N>) -> Result<Plant<N>, SimError> {
    let mut rng = ChaCha8Rng::seed_from_u64(0);
    Plant::new(model.clone(), &generic_dynamics::<N>, &PlantSetup::rigid_body(), (q0, JointVector::zeros()), &mut rng)
}

/// Runs `plant` from its current state under `commands` (increasing times, the first at the
/// plant's time) until `until`, with physics steps of at most `max_step`, and calls `sample`
/// with the time and state at every multiple of `interval` (the start included).
pub fn open_loop<const N: usize, E: From<SimError>>(
    plant: &mut Plant<N>,
    commands: &[TorqueCommand<N>],
    max_step: f64,
    interval: f64,
    until: f64,
    mut sample: impl FnMut(f64, &PlantState<N>) -> Result<(), E>,
) -> Result<(), E> {
    let Some(first) = commands.first() else { return Ok(()) };
    let start = plant.time;
    let mut command = first.torque;
    let mut next_command = 1;
    let mut next_sample = 0usize;
    loop {
        let now = plant.time;
        let sample_time = start + next_sample as f64 * interval;
        if sample_time <= now + 1e-12 * interval {
            sample(sample_time, &plant.state)?;
            next_sample += 1;
            continue;
        }
        while next_command < commands.len() && commands[next_command].time <= now + 1e-12 * interval {
            command = commands[next_command].torque;
            next_command += 1;
        }
        if now >= until - 1e-12 * interval {
            return Ok(());
        }
        let change = commands.get(next_command).map_or(f64::INFINITY, |c| c.time);
        let target = sample_time.min(change).min(until);
        let span = target - now;
        let steps = (span / max_step).ceil().max(1.0) as usize;
        for _ in 0..steps {
            plant.step(span / steps as f64, &command).map_err(E::from)?;
        }
        // Land exactly on the event, not on the sum of the sub-steps.
        plant.time = target;
    }
}

/// MuJoCo's rollout of HyA under a recorded torque sequence (`tools/mujoco_rollout.py`): the
/// torque rows `t τ1 … τ6`, and the state rows `t q1 … q6 q̇1 … q̇6` every millisecond for 1 s.
pub const MUJOCO_HYA: (&str, &str) =
    (include_str!("../../tests/data/mujoco_hya_torque.csv"), include_str!("../../tests/data/mujoco_hya_rollout.csv"));

/// The numeric rows of a CSV whose comment lines start with `#`.
pub fn csv_rows(text: &str) -> Result<Vec<Vec<f64>>, SimError> {
    text.lines()
        .enumerate()
        .filter(|(_, l)| !l.starts_with('#') && !l.trim().is_empty())
        .map(|(k, l)| {
            l.split(',')
                .map(|x| {
                    x.trim().parse::<f64>().map_err(|e| SimError::ReferenceData(format!("line {}: {x:?}: {e}", k + 1)))
                })
                .collect()
        })
        .collect()
}

/// The ideal plant of `model` run under `torque` (rows `t τ`), against the reference `states`
/// (rows `t q q̇` every millisecond, starting at rest): the worst `|Δq|` (rad) and `|Δq̇|`
/// (rad/s) over the reference's span.
pub fn reference_gap<const N: usize>(model: &TreeModel, torque: &str, states: &str) -> Result<(f64, f64), SimError> {
    let commands: Vec<TorqueCommand<N>> = csv_rows(torque)?
        .iter()
        .map(|r| match r.len() == N + 1 {
            true => Ok(TorqueCommand { time: r[0], torque: JointVector::from_column_slice(&r[1..]) }),
            false => Err(SimError::ReferenceData(format!("torque rows need {} columns, found {}", N + 1, r.len()))),
        })
        .collect::<Result<_, _>>()?;
    let reference = csv_rows(states)?;
    if reference.len() < 2 || reference.iter().any(|r| r.len() != 2 * N + 1) {
        return Err(SimError::ReferenceData(format!("state rows need {} columns", 2 * N + 1)));
    }
    let q0 = JointVector::<N>::from_column_slice(&reference[0][1..=N]);
    let mut plant = ideal_plant(model, q0)?;
    let until = reference[reference.len() - 1][0];
    let interval = reference[1][0] - reference[0][0];
    let (mut q_gap, mut qd_gap, mut row) = (0.0_f64, 0.0_f64, 0);
    open_loop(&mut plant, &commands, 1e-4, interval, until, |t, s| {
        let theirs =
            reference.get(row).ok_or_else(|| SimError::ReferenceData(format!("no reference row at t = {t}")))?;
        row += 1;
        q_gap = q_gap.max((s.q - JointVector::<N>::from_column_slice(&theirs[1..=N])).amax());
        qd_gap = qd_gap.max((s.qd - JointVector::<N>::from_column_slice(&theirs[N + 1..])).amax());
        Ok::<(), SimError>(())
    })?;
    Ok((q_gap, qd_gap))
}
