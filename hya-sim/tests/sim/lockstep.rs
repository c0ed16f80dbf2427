//! Plants stepped in lockstep ([`hya_sim::plant::lockstep`]) end where each would have ended
//! stepped alone, bit for bit: on HyA's hydraulic plant with LuGre friction (sub-cycles and
//! sample instants), on lag and ideal actuators, through a payload's drop and removal, and with
//! a plant that fails among plants that do not; and whole closed loops run together
//! ([`RunSetup::run_together`]) equal the same runs alone.

use hya_core::model::TreeModel;
use hya_core::spatial::RigidBodyInertia;
use hya_core::{Dynamics, JointVector};
use hya_robots::HyaParametric;
use hya_sim::config::plant::PlantSetup;
use std::sync::atomic::{AtomicUsize, Ordering};

use hya_core::BodiesBatch;
use hya_sim::plant::lockstep::{Failure, Lockstep, Steps};
use hya_sim::plant::{perturbed, Plant};
use hya_sim::run::trace::Recording;
use hya_sim::run::RunSetup;
use hya_sim::scenario::{ActuatorKind, FrictionKind};
use hya_sim::settings::Setup;
use hya_sim::{with_robot, ForRobot, Method, Robot, Scenario, SimError};
use rand::SeedableRng;

/// HyA's parametric twin of `model`, as the simulator builds a shipped arm's plant.
fn twin(model: &TreeModel) -> Result<Box<dyn Dynamics<6>>, SimError> {
    let inertias: [RigidBodyInertia; 6] = core::array::from_fn(|i| model.bodies()[i].inertia);
    Ok(Box::new(HyaParametric::new(&inertias)))
}

/// The plant of `scenario` drawn from `seed`, at rest at the scenario's start pose.
fn plant(scenario: &Scenario, seed: u64) -> Plant<6> {
    let nominal = hya_urdf::load_str(hya_robots::find("hya").unwrap().urdf, "hya").unwrap().model;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let model = perturbed(&nominal, scenario.plant.parameter_spread, &mut rng);
    let q0 = JointVector::from_column_slice(scenario.initial_position_rad.as_deref().unwrap_or(&hya_robots::hya::HOME));
    let hold = hya_robots::Hya.gravity(&q0);
    let setup = PlantSetup::of(&scenario.plant, &scenario.loads).unwrap();
    Plant::new(model, &twin, &setup, (q0, hold), &mut rng).unwrap()
}

/// A command that moves the arm: gravity at the start pose plus a swing that differs by seed
/// (`scale` times larger for a plant meant to run away).
fn command(plant: &Plant<6>, k: usize, j: usize, scale: f64) -> JointVector<6> {
    let t = k as f64 * 1e-3;
    let hold = hya_robots::Hya.gravity(&plant.state.q);
    hold + JointVector::from_fn(|i, _| scale * 20.0 * (6.0 * t + i as f64 + j as f64).sin())
}

/// HyA's twin, refusing every `every`-th batch (from the `first`) as if a state were singular:
/// the lockstep's fallbacks, where each plant steps alone.
struct Refusing {
    calls: AtomicUsize,
    first: usize,
    every: usize,
}

impl BodiesBatch<6> for Refusing {
    fn forward_dynamics_of_bodies_batch(
        &self,
        bodies: hya_core::BodyColumns<'_, 6>,
        q: &[JointVector<6>],
        qd: &[JointVector<6>],
        tau: &[JointVector<6>],
        qdd: &mut [JointVector<6>],
    ) -> Result<(), hya_core::Error> {
        let call = self.calls.fetch_add(1, Ordering::Relaxed);
        if call >= self.first && (call - self.first).is_multiple_of(self.every) {
            return Err(hya_core::Error::SingularMassMatrix);
        }
        HyaParametric([[0.0; 10]; 6]).forward_dynamics_of_bodies_batch(bodies, q, qd, tau, qdd)
    }
}

/// Steps `count` plants of `scenario` in lockstep and alone for `ticks` periods, the plant
/// `runaway` (if any) under a command far beyond the arm's; checks every state, time,
/// acceleration and failure for equality.
fn check(scenario: &Scenario, count: usize, ticks: usize, runaway: Option<usize>) {
    let steps = check_on(&HyaParametric([[0.0; 10]; 6]), scenario, (count, ticks), runaway);
    assert!(steps.together > 4 * steps.alone, "most steps should be taken together: {steps:?}");
}

/// [`check`] with the plants' rigid bodies batched on `kernel`; the lockstep's step counts.
fn check_on(
    kernel: &(dyn BodiesBatch<6> + Send + Sync),
    scenario: &Scenario,
    (count, ticks): (usize, usize),
    runaway: Option<usize>,
) -> Steps {
    let scale = |j: usize| if Some(j) == runaway { 1e6 } else { 1.0 };
    let (dt, substeps) = (1e-3, scenario.plant.substeps.unwrap_or(4));
    let seeds: Vec<u64> = (0..count as u64).map(|k| scenario.seed + k).collect();
    let mut together: Vec<Plant<6>> = seeds.iter().map(|&s| plant(scenario, s)).collect();
    let mut alone: Vec<Plant<6>> = seeds.iter().map(|&s| plant(scenario, s)).collect();
    let mut alone_failed: Vec<Option<String>> = vec![None; count];
    let mut lockstep = Lockstep::new(kernel, count);
    let (mut accelerations, mut failed) =
        (vec![JointVector::zeros(); count], (0..count).map(|_| Failure::None).collect::<Vec<_>>());
    for k in 0..ticks {
        let commands: Vec<_> = together.iter().enumerate().map(|(j, p)| command(p, k, j, scale(j))).collect();
        lockstep.advance(&mut together, (dt, substeps), &commands, (&mut accelerations, &mut failed));
        for (j, plant) in alone.iter_mut().enumerate() {
            if alone_failed[j].is_some() {
                continue;
            }
            match plant.advance(dt, substeps, &commands[j]) {
                Ok(acceleration) => {
                    assert!(failed[j].is_none(), "plant {j} failed in lockstep only, tick {k}: {:?}", failed[j]);
                    assert_eq!(acceleration, accelerations[j], "plant {j}'s acceleration, tick {k}");
                }
                Err(e) => {
                    let lockstep_error = failed[j].as_ref().map(ToString::to_string);
                    assert_eq!(lockstep_error, Some(e.to_string()), "plant {j}'s failure, tick {k}");
                    alone_failed[j] = Some(e.to_string());
                }
            }
            assert_eq!(plant.state, together[j].state, "plant {j}'s state, tick {k}");
            assert_eq!(plant.time, together[j].time, "plant {j}'s clock, tick {k}");
        }
    }
    let steps = lockstep.steps();
    eprintln!("{}: {steps:?}", scenario.name);
    if let Some(j) = runaway {
        assert!(alone_failed[j].is_some(), "the runaway plant {j} should fail");
    }
    assert!(alone_failed.iter().enumerate().all(|(j, f)| f.is_none() || Some(j) == runaway));
    steps
}

#[test]
fn inner_loops_sampled_within_a_step_split_every_plants_step_alike() {
    // 3 kHz against RK4 steps of 0.25 ms: sample instants fall inside steps, which split there.
    let mut scenario = Scenario::builtin("goto_internal").unwrap();
    scenario.plant.hydraulic.torque_loop_rate_hz = 3000.0;
    check(&scenario, 3, 200, None);
}

#[test]
fn plants_whose_batch_is_refused_step_alone_and_alike() {
    let scenario = Scenario::builtin("goto_internal").unwrap();
    // Refused now and then: at a period's first stage and at later ones alike.
    let kernel = Refusing { calls: AtomicUsize::new(0), first: 0, every: 13 };
    let steps = check_on(&kernel, &scenario, (3, 200), None);
    assert!(steps.alone > 0 && steps.together > 0, "both paths ran: {steps:?}");
}

#[test]
fn the_hydraulic_plant_with_lugre_friction_steps_alone_and_together_alike() {
    let scenario = Scenario::builtin("goto_internal").unwrap();
    check(&scenario, 5, 400, None);
}

#[test]
fn lag_and_ideal_actuators_and_a_payload_step_alike() {
    let mut scenario = Scenario::builtin("goto_weight").unwrap();
    if let Some(drop) = &mut scenario.loads.weight_drop {
        (drop.drop_s, drop.remove_s) = (0.1, Some(0.25));
    }
    for actuator in [ActuatorKind::Lag, ActuatorKind::Ideal] {
        scenario.plant.actuator = actuator;
        check(&scenario, 3, 300, None);
    }
    scenario.plant.friction = FrictionKind::Smooth;
    check(&scenario, 2, 100, None);
}

#[test]
fn a_plant_that_fails_stops_alone_with_its_own_error() {
    let mut scenario = Scenario::builtin("goto_internal").unwrap();
    scenario.plant.actuator = ActuatorKind::Ideal;
    check(&scenario, 4, 300, Some(2));
}

/// Runs of a scenario under a method, some seeds: together, then each alone; equal bit for bit.
struct TogetherAndAlone<'a>(&'a Scenario, Method, u64);

impl ForRobot for TogetherAndAlone<'_> {
    type Output = ();
    fn call<const N: usize>(self, robot: Robot<N>) -> Result<(), SimError> {
        let TogetherAndAlone(scenario, method, count) = self;
        assert!(robot.bodies.is_some(), "a shipped arm's plant runs in lockstep");
        let setup = RunSetup::task_space(Setup::for_run(scenario, method, &robot.model)?, method, &robot)?;
        let seeds: Vec<(u64, Recording)> = (0..count).map(|k| (scenario.seed + k, Recording::Bounded)).collect();
        let together = setup.run_together(&seeds);
        for (&(seed, recording), together) in seeds.iter().zip(together) {
            let (alone, together) = (setup.run(seed, recording)?, together?);
            let what = format!("{} / {} / seed {seed}", scenario.name, method.name());
            // Debug text: every number in its shortest exact form, NaN equal to NaN.
            assert_eq!(format!("{:?}", alone.metrics), format!("{:?}", together.metrics), "{what}: metrics");
            assert_eq!(alone.trace.q, together.trace.q, "{what}: q");
            assert_eq!(alone.trace.d_hat, together.trace.d_hat, "{what}: d̂");
            assert_eq!(alone.trace.tau_cmd, together.trace.tau_cmd, "{what}: τ_cmd");
        }
        Ok(())
    }
}

/// `name`'s quick scenario, cut to `seconds`.
fn quick(name: &str, seconds: f64) -> Scenario {
    let mut scenario = Scenario::builtin(name).unwrap().quick();
    scenario.duration_s = seconds;
    scenario
}

#[test]
fn closed_loops_run_together_as_they_run_alone() {
    let mut weight = quick("goto_weight", 2.0);
    if let Some(drop) = &mut weight.loads.weight_drop {
        drop.drop_s = 1.0;
    }
    let cases = [
        (quick("goto_internal", 1.5), Method::Lu, 5),
        (quick("goto_internal", 1.0), Method::Pid, 3),
        (weight, Method::Chen, 4),
        (quick("sine_internal", 1.0), Method::Momentum, 2),
        (quick("panda_cartesian", 2.0), Method::Eso, 3),
    ];
    for (scenario, method, count) in &cases {
        with_robot(&scenario.robot, TogetherAndAlone(scenario, *method, *count)).unwrap();
    }
}
