//! `hya bench`: in-process medians of the generated and generic dynamics, and of the HyA control
//! tick, over many calls with varied inputs.
//!
//! Each figure is the median over 31 rounds of the mean time of one call within a round of
//! 2000 calls that cycle through 64 pseudo-random states; inputs and outputs pass through
//! `black_box`, so nothing is folded at compile time. The machine's speed drifts: compare
//! figures from one run, side by side.

use std::hint::black_box;
use std::time::Instant;

use hya_core::model::TreeDynamics;
use hya_core::{
    ComputedTorque, DisturbanceAttenuation, DisturbanceEstimator, Dynamics, FilterParams, FrameJacobian,
    FrameKinematics, Gains, JointMatrix, JointVector, Reference,
};
use hya_robots::Hya;

use crate::CliError;

/// Parameters of `hya bench`.
#[derive(Debug, clap::Args)]
pub struct BenchArgs {
    /// One shipped robot (default: all).
    #[arg(long)]
    robot: Option<String>,
    /// Print JSON instead of a table.
    #[arg(long)]
    json: bool,
}

/// Medians for one robot, ns per call.
#[derive(Debug, Clone, serde::Serialize)]
struct Figures {
    robot: &'static str,
    generated_id_ns: f64,
    generic_id_ns: f64,
    generated_mass_ns: f64,
    generic_mass_ns: f64,
    generated_gravity_ns: f64,
    generated_fd_ns: f64,
    generic_fd_ns: f64,
    /// Generated inverse dynamics on [`BATCH`] states per call (`Dynamics::inverse_dynamics_batch`),
    /// ns per state.
    batch_id_ns_per_state: f64,
    /// The same for forward dynamics.
    batch_fd_ns_per_state: f64,
    /// The mass matrix and the inverse-dynamics derivatives on [`BATCH`] states per call, ns per
    /// state.
    batch_mass_ns_per_state: f64,
    batch_id_derivatives_ns_per_state: f64,
    /// `(∂q̈/∂q, ∂q̈/∂q̇, M⁻¹)` on [`BATCH`] states per call
    /// (`Dynamics::forward_dynamics_derivatives_batch`), ns per state.
    batch_fd_derivatives_ns_per_state: f64,
    /// The states per step of those batches on this CPU (`hya_core::lanes::batch_lanes`: 8 with
    /// AVX-512F, 4 with AVX2 and FMA, 1 without a vector unit).
    batch_lanes: usize,
    /// Where the batches take 8 lanes: the same batches held to 4 (AVX2,
    /// `hya_core::lanes::limit_batch_lanes`), measured beside them, ns per state (forward
    /// dynamics takes 4 either way: `hya_core::lanes::kernels::Width`).
    #[serde(skip_serializing_if = "Option::is_none")]
    batch_id_ns_per_state_4_lanes: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    batch_fd_ns_per_state_4_lanes: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    batch_mass_ns_per_state_4_lanes: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    batch_id_derivatives_ns_per_state_4_lanes: Option<f64>,
    /// `(∂τ/∂q, ∂τ/∂q̇)` of inverse dynamics (`Dynamics::inverse_dynamics_derivatives`).
    generated_id_derivatives_ns: f64,
    generic_id_derivatives_ns: f64,
    /// `(∂q̈/∂q, ∂q̈/∂q̇, M⁻¹)` (`Dynamics::forward_dynamics_derivatives`).
    generated_fd_derivatives_ns: f64,
    generic_fd_derivatives_ns: f64,
    /// The frame the kinematics figures are of: the last link (`FrameKinematics::frame_name`).
    frame: &'static str,
    /// The last link's world-aligned Jacobian, generated (`FrameKinematics::frame_jacobian`) and
    /// on the run-time tree (`TreeModel::frame_jacobian`, which allocates its result).
    generated_jacobian_ns: f64,
    generic_jacobian_ns: f64,
    /// The last link's `J̇ q̇`, generated (`FrameKinematics::frame_acceleration_bias`).
    generated_jacobian_bias_ns: f64,
    /// The generated Jacobian on [`BATCH`] states per call, ns per state, and held to four
    /// lanes where the CPU has eight.
    batch_jacobian_ns_per_state: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    batch_jacobian_ns_per_state_4_lanes: Option<f64>,
    /// The HyA control tick through `DisturbanceAttenuation::tick` (both inverse dynamics in one
    /// batch call).
    #[serde(skip_serializing_if = "Option::is_none")]
    tick_ns: Option<f64>,
    /// The same tick as `DisturbanceEstimator::update` then `ComputedTorque::command`.
    #[serde(skip_serializing_if = "Option::is_none")]
    tick_in_sequence_ns: Option<f64>,
    /// Seed-seconds simulated per wall-clock second on one core, `goto_internal` (method lu)
    /// on the simple plant (`actuator = "lag"`), its seeds in lockstep as `hya run` runs them.
    #[serde(skip_serializing_if = "Option::is_none")]
    sim_realtime_factor: Option<f64>,
    /// The same seeds run one by one.
    #[serde(skip_serializing_if = "Option::is_none")]
    sim_realtime_factor_one_by_one: Option<f64>,
    /// The same on the hydraulic plant (the scenario as built in), in lockstep.
    #[serde(skip_serializing_if = "Option::is_none")]
    sim_realtime_factor_hydraulic: Option<f64>,
    /// The hydraulic plant's seeds one by one.
    #[serde(skip_serializing_if = "Option::is_none")]
    sim_realtime_factor_hydraulic_one_by_one: Option<f64>,
    /// The same with ideal actuators (the commanded torque acts at once): the closed loop,
    /// estimators and controller included, on the rigid body and its friction alone; in lockstep.
    #[serde(skip_serializing_if = "Option::is_none")]
    sim_realtime_factor_ideal: Option<f64>,
    /// The ideal actuators' seeds one by one.
    #[serde(skip_serializing_if = "Option::is_none")]
    sim_realtime_factor_ideal_one_by_one: Option<f64>,
    /// The target features this binary was compiled for (`sse4.1 avx2 fma`, …).
    build: &'static str,
    /// Whether generated code ran its fused multiply-add variant: `compiled` (the target has
    /// FMA), `run time` (detected on this CPU) or `no …`.
    generated_fma: &'static str,
}

/// How generated code met fused multiply-add in this run (see `hya_core::with_fma`).
fn generated_fma() -> &'static str {
    use hya_core::FmaSupport;
    match (hya_core::FMA_SUPPORT, hya_core::with_fma(|| ()).is_some()) {
        (FmaSupport::Compiled, _) => "compiled",
        (FmaSupport::Detected, true) => "run time",
        (FmaSupport::Detected, false) => "no (this CPU lacks it)",
        (FmaSupport::Never, _) => "no",
    }
}

/// The CPU features the compiler could use in this build: what separates a plain
/// `cargo build --release` from `-C target-cpu=native`.
fn build_features() -> &'static str {
    const FEATURES: [(&str, bool); 8] = [
        ("sse2", cfg!(target_feature = "sse2")),
        ("sse4.1", cfg!(target_feature = "sse4.1")),
        ("avx", cfg!(target_feature = "avx")),
        ("avx2", cfg!(target_feature = "avx2")),
        ("fma", cfg!(target_feature = "fma")),
        ("avx512f", cfg!(target_feature = "avx512f")),
        ("neon", cfg!(target_feature = "neon")),
        ("crt-static", cfg!(target_feature = "crt-static")),
    ];
    static TEXT: std::sync::OnceLock<String> = std::sync::OnceLock::new();
    TEXT.get_or_init(|| {
        let on: Vec<&str> = FEATURES.iter().filter(|(_, on)| *on).map(|(name, _)| *name).collect();
        format!("{} {}", std::env::consts::ARCH, on.join(" "))
    })
}

const ROUNDS: usize = 31;
const CALLS: usize = 2000;
const STATES: usize = 64;
/// States per batch call.
const BATCH: usize = 1024;
/// Batch calls per round.
const BATCH_CALLS: usize = 8;

/// Median over rounds of the mean ns per state of `f()`, a batch of [`BATCH`] states.
fn median_batch_ns(mut f: impl FnMut()) -> f64 {
    median(
        (0..ROUNDS)
            .map(|_| {
                let start = Instant::now();
                for _ in 0..BATCH_CALLS {
                    f();
                }
                start.elapsed().as_secs_f64() * 1e9 / (BATCH_CALLS * BATCH) as f64
            })
            .collect(),
    )
}

/// The mean ns per call of `f(state index)` over one round of [`CALLS`] calls.
fn round_ns(f: &mut impl FnMut(usize)) -> f64 {
    let start = Instant::now();
    for k in 0..CALLS {
        f(k % STATES);
    }
    start.elapsed().as_secs_f64() * 1e9 / CALLS as f64
}

/// The median of per-round figures.
fn median(mut rounds: Vec<f64>) -> f64 {
    rounds.sort_by(f64::total_cmp);
    rounds[rounds.len() / 2]
}

/// Median over rounds of the mean ns per call of `f(state index)`.
fn median_ns(mut f: impl FnMut(usize)) -> f64 {
    median((0..ROUNDS).map(|_| round_ns(&mut f)).collect())
}

/// [`median_ns`] of `a` and of `b`, their rounds interleaved so that the machine's slow and
/// fast phases fall on both alike, and which goes first alternating from round to round.
fn interleaved_median_ns(mut a: impl FnMut(usize), mut b: impl FnMut(usize)) -> (f64, f64) {
    let (rounds_a, rounds_b) = (0..ROUNDS)
        .map(|round| {
            if round % 2 == 0 {
                let first = round_ns(&mut a);
                (first, round_ns(&mut b))
            } else {
                let first = round_ns(&mut b);
                (round_ns(&mut a), first)
            }
        })
        .unzip();
    (median(rounds_a), median(rounds_b))
}

/// The benchmark's varied states (see [`hya_core::sampling::varied_states`]).
fn states<const N: usize>() -> [[JointVector<N>; 3]; STATES] {
    hya_core::sampling::varied_states()
}

fn bench_robot<const N: usize, D: Dynamics<N> + FrameKinematics<N>>(
    name: &'static str,
    generated: D,
) -> Result<Figures, CliError> {
    let robot = hya_robots::find(name).ok_or_else(|| CliError::Input(format!("unknown robot {name}")))?;
    let generic: TreeDynamics<N> = hya_urdf::load_str(robot.urdf, name)
        .map_err(|e| CliError::Input(e.to_string()))?
        .model
        .into_dynamics()
        .map_err(|e| CliError::Input(e.to_string()))?;
    let states = states::<N>();
    let id = |d: &dyn Dynamics<N>| {
        median_ns(|k| {
            let [q, qd, qdd] = black_box(&states[k]);
            black_box(d.inverse_dynamics(q, qd, qdd));
        })
    };
    let mass = |d: &dyn Dynamics<N>| {
        median_ns(|k| {
            black_box(d.mass_matrix(black_box(&states[k][0])));
        })
    };
    let fd = |d: &dyn Dynamics<N>| {
        median_ns(|k| {
            let [q, qd, tau] = black_box(&states[k]);
            let _ = black_box(d.forward_dynamics(q, qd, tau));
        })
    };
    let id_derivatives = |d: &dyn Dynamics<N>| {
        median_ns(|k| {
            let [q, qd, qdd] = black_box(&states[k]);
            black_box(d.inverse_dynamics_derivatives(q, qd, qdd));
        })
    };
    let fd_derivatives = |d: &dyn Dynamics<N>| {
        median_ns(|k| {
            let [q, qd, tau] = black_box(&states[k]);
            let _ = black_box(d.forward_dynamics_derivatives(q, qd, tau));
        })
    };
    let tree = generic.model();
    let last = tree.frames().last().map(|f| f.name.clone()).unwrap_or_default();
    let (generated_jacobian_ns, generic_jacobian_ns) = interleaved_median_ns(
        |k| {
            black_box(generated.frame_jacobian(black_box(&states[k][0])));
        },
        |k| {
            let _ = black_box(tree.frame_jacobian(&last, black_box(states[k][0].as_slice())));
        },
    );
    let generated_jacobian_bias_ns = median_ns(|k| {
        let [q, qd, _] = black_box(&states[k]);
        black_box(generated.frame_acceleration_bias(q, qd));
    });
    let batch: Vec<[JointVector<N>; 3]> = hya_core::sampling::varied_states::<N, BATCH>().to_vec();
    let [q, qd, x]: [Vec<JointVector<N>>; 3] = core::array::from_fn(|i| batch.iter().map(|s| s[i]).collect());
    let (mut out, mut matrices) = (vec![JointVector::<N>::zeros(); BATCH], vec![JointMatrix::<N>::zeros(); BATCH]);
    let mut more_matrices = matrices.clone();
    let lanes = hya_core::lanes::batch_lanes();
    // Each batch on the CPU's lanes and, where those are eight, held to four just after it.
    let both_widths = |mut run: Box<dyn FnMut() + '_>| {
        let wide = median_batch_ns(&mut run);
        let narrow = (lanes == 8).then(|| {
            let _ = hya_core::lanes::limit_batch_lanes(4);
            let ns = median_batch_ns(&mut run);
            let _ = hya_core::lanes::limit_batch_lanes(8);
            ns
        });
        (wide, narrow)
    };
    let (batch_id_ns_per_state, batch_id_ns_per_state_4_lanes) = both_widths(Box::new(|| {
        let _ = black_box(generated.inverse_dynamics_batch(black_box(&q), &qd, &x, &mut out));
    }));
    let (batch_fd_ns_per_state, batch_fd_ns_per_state_4_lanes) = both_widths(Box::new(|| {
        let _ = black_box(generated.forward_dynamics_batch(black_box(&q), &qd, &x, &mut out));
    }));
    let (batch_mass_ns_per_state, batch_mass_ns_per_state_4_lanes) = both_widths(Box::new(|| {
        let _ = black_box(generated.mass_matrix_batch(black_box(&q), &mut matrices));
    }));
    let (batch_id_derivatives_ns_per_state, batch_id_derivatives_ns_per_state_4_lanes) = both_widths(Box::new(|| {
        let _ = black_box(generated.inverse_dynamics_derivatives_batch(
            black_box(&q),
            &qd,
            &x,
            &mut matrices,
            &mut more_matrices,
        ));
    }));
    let mut inverses = matrices.clone();
    let batch_fd_derivatives_ns_per_state = median_batch_ns(|| {
        let outputs = (&mut matrices[..], &mut more_matrices[..], &mut inverses[..]);
        let _ = black_box(generated.forward_dynamics_derivatives_batch(black_box(&q), &qd, &x, outputs));
    });
    let mut jacobians = vec![FrameJacobian::<N>::zeros(); BATCH];
    let (batch_jacobian_ns_per_state, batch_jacobian_ns_per_state_4_lanes) = both_widths(Box::new(|| {
        let _ = black_box(generated.frame_jacobian_batch(black_box(&q), &mut jacobians));
    }));
    // Generated and generic alternate, so slow phases of the machine hit both.
    Ok(Figures {
        robot: name,
        generated_id_ns: id(&generated),
        generic_id_ns: id(&generic),
        generated_mass_ns: mass(&generated),
        generic_mass_ns: mass(&generic),
        generated_gravity_ns: median_ns(|k| {
            black_box(generated.gravity(black_box(&states[k][0])));
        }),
        generated_fd_ns: fd(&generated),
        generic_fd_ns: fd(&generic),
        batch_id_ns_per_state,
        batch_fd_ns_per_state,
        batch_lanes: lanes,
        batch_id_ns_per_state_4_lanes,
        batch_fd_ns_per_state_4_lanes,
        batch_mass_ns_per_state,
        batch_mass_ns_per_state_4_lanes,
        batch_id_derivatives_ns_per_state,
        batch_id_derivatives_ns_per_state_4_lanes,
        batch_fd_derivatives_ns_per_state,
        generated_id_derivatives_ns: id_derivatives(&generated),
        generic_id_derivatives_ns: id_derivatives(&generic),
        generated_fd_derivatives_ns: fd_derivatives(&generated),
        generic_fd_derivatives_ns: fd_derivatives(&generic),
        frame: generated.frame_name(),
        generated_jacobian_ns,
        generic_jacobian_ns,
        generated_jacobian_bias_ns,
        batch_jacobian_ns_per_state,
        batch_jacobian_ns_per_state_4_lanes,
        tick_ns: None,
        tick_in_sequence_ns: None,
        sim_realtime_factor: None,
        sim_realtime_factor_one_by_one: None,
        sim_realtime_factor_hydraulic: None,
        sim_realtime_factor_hydraulic_one_by_one: None,
        sim_realtime_factor_ideal: None,
        sim_realtime_factor_ideal_one_by_one: None,
        build: build_features(),
        generated_fma: generated_fma(),
    })
}

/// One HyA control tick, the estimator's update (two filter steps, one ID) and the controller's
/// command (one ID): through [`DisturbanceAttenuation::tick`], both IDs in one batch call, and
/// as the two calls in sequence. Medians of interleaved rounds, ns per tick.
fn ticks_ns() -> Result<Ticks, CliError> {
    let core = |e: hya_core::Error| CliError::Input(e.to_string());
    let q0 = JointVector::<6>::from([0.0, 0.0, -0.78, 0.78, 0.78, 0.0]);
    let (params, gains) =
        (FilterParams::paper(1e-3).map_err(core)?, Gains::diagonal([300.0; 6], [30.0; 6]).map_err(core)?);
    let mut attenuation = DisturbanceAttenuation::new(Hya, params, gains, q0, Hya.gravity(&q0)).map_err(core)?;
    let mut estimator = DisturbanceEstimator::new(Hya, params, q0, Hya.gravity(&q0)).map_err(core)?;
    let controller = ComputedTorque::new(Hya, gains);
    let states = states::<6>();
    let reference = Reference::hold(q0);
    let measured = |k: usize| {
        let [dq, qd, tau] = black_box(&states[k]);
        (q0 + dq * 1e-3, qd, tau)
    };
    let (paired, in_sequence) = interleaved_median_ns(
        |k| {
            let (q, qd, tau) = measured(k);
            black_box(attenuation.tick(&q, qd, tau, &reference).map(|c| c.torque).unwrap_or_default());
        },
        |k| {
            let (q, qd, tau) = measured(k);
            let d_hat = estimator.update(&q, tau).unwrap_or_default();
            black_box(controller.command(&q, qd, &reference, Some(&d_hat)).map(|c| c.torque).unwrap_or_default());
        },
    );
    Ok(Ticks { paired, in_sequence })
}

/// [`ticks_ns`]'s two figures.
struct Ticks {
    paired: f64,
    in_sequence: f64,
}

/// Seed-seconds simulated per wall-clock second of `goto_internal` (method lu) on `actuator`,
/// over one lockstep's worth of seeds ([`hya_sim::seeds::LOCKSTEP_SEEDS`]), their traces off: the
/// seeds run together ([`RunSetup::run_together`](hya_sim::run::RunSetup::run_together), as
/// `hya run` and `hya reproduce` run them), and one by one on the same core, in alternating
/// order over [`SIMULATION_ROUNDS`] rounds; the medians.
fn simulation_speed(actuator: hya_sim::scenario::ActuatorKind) -> Result<SimulationSpeed, CliError> {
    let mut scenario = hya_sim::Scenario::builtin("goto_internal").map_err(|e| CliError::Input(e.to_string()))?;
    scenario.plant.actuator = actuator;
    /// The runs, timed on the robot [`hya_sim::with_robot`] hands over (loading it is not timed).
    struct Timed<'a>(&'a hya_sim::Scenario);
    impl hya_sim::ForRobot for Timed<'_> {
        type Output = SimulationSpeed;
        fn call<const N: usize>(self, robot: hya_sim::Robot<N>) -> Result<SimulationSpeed, hya_sim::SimError> {
            let setup = hya_sim::analysis::simulate::run_setup(self.0, hya_sim::Method::Lu, &robot)?;
            let seeds: Vec<(u64, hya_sim::run::trace::Recording)> = (0..hya_sim::seeds::LOCKSTEP_SEEDS as u64)
                .map(|k| (self.0.seed + k, hya_sim::run::trace::Recording::Off))
                .collect();
            let simulated = self.0.duration_s * seeds.len() as f64;
            let together = || -> Result<f64, hya_sim::SimError> {
                let start = Instant::now();
                for run in setup.run_together(&seeds) {
                    run?;
                }
                Ok(simulated / start.elapsed().as_secs_f64())
            };
            let alone = || -> Result<f64, hya_sim::SimError> {
                let start = Instant::now();
                for &(seed, recording) in &seeds {
                    setup.run(seed, recording)?;
                }
                Ok(simulated / start.elapsed().as_secs_f64())
            };
            // Rounds in turn, which goes first alternating, so both see the machine alike.
            let (mut with, mut without) = (Vec::new(), Vec::new());
            for round in 0..SIMULATION_ROUNDS {
                if round % 2 == 0 {
                    with.push(together()?);
                    without.push(alone()?);
                } else {
                    without.push(alone()?);
                    with.push(together()?);
                }
            }
            Ok(SimulationSpeed { together: median(with), alone: median(without) })
        }
    }
    hya_sim::with_robot(&scenario.robot, Timed(&scenario)).map_err(|e| CliError::Input(e.to_string()))
}

/// Rounds of [`simulation_speed`], each timing the seeds together and one by one.
const SIMULATION_ROUNDS: usize = 3;

/// [`simulation_speed`]'s figures: medians over its rounds.
struct SimulationSpeed {
    together: f64,
    alone: f64,
}

/// `hya bench`.
pub fn run(args: &BenchArgs, output: &mut impl std::io::Write) -> Result<(), CliError> {
    let wanted = |name: &str| args.robot.as_deref().is_none_or(|r| r == name);
    if let Some(name) = &args.robot {
        if hya_robots::find(name).is_none() {
            return Err(CliError::Input(format!("unknown robot `{name}` (see `hya robots`)")));
        }
    }
    let mut figures = Vec::new();
    macro_rules! bench_each {
        ($($module:ident $type:ident $parametric:ident $dof:literal [$($home:expr),*] $doc:literal;)*) => {$(
            if wanted(stringify!($module)) {
                figures.push(bench_robot::<$dof, _>(stringify!($module), hya_robots::$type)?);
            }
        )*};
    }
    hya_robots::for_each_robot!(bench_each);
    // The control tick and the simulator's speed are measured on HyA, the paper's arm.
    if let Some(hya) = figures.iter_mut().find(|f| f.robot == "hya") {
        let ticks = ticks_ns()?;
        (hya.tick_ns, hya.tick_in_sequence_ns) = (Some(ticks.paired), Some(ticks.in_sequence));
        use hya_sim::scenario::ActuatorKind;
        let lag = simulation_speed(ActuatorKind::Lag)?;
        (hya.sim_realtime_factor, hya.sim_realtime_factor_one_by_one) = (Some(lag.together), Some(lag.alone));
        let hydraulic = simulation_speed(ActuatorKind::Hydraulic)?;
        hya.sim_realtime_factor_hydraulic = Some(hydraulic.together);
        hya.sim_realtime_factor_hydraulic_one_by_one = Some(hydraulic.alone);
        let ideal = simulation_speed(ActuatorKind::Ideal)?;
        (hya.sim_realtime_factor_ideal, hya.sim_realtime_factor_ideal_one_by_one) =
            (Some(ideal.together), Some(ideal.alone));
    }
    if args.json {
        let text = if figures.len() == 1 {
            serde_json::to_string_pretty(&figures[0])
        } else {
            serde_json::to_string_pretty(&figures)
        };
        writeln!(output, "{}", text.map_err(|e| CliError::Input(e.to_string()))?)?;
        return Ok(());
    }
    writeln!(
        output,
        "{:<8} {:>9} {:>9} {:>9} {:>6} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9} {:>8} {:>8} {:>8} {:>8} {:>8}",
        "robot",
        "id gen",
        "id batch",
        "id gener",
        "ratio",
        "M gen",
        "M gener",
        "G gen",
        "FD gen",
        "FD batch",
        "FD gener",
        "dID gen",
        "dFD gen",
        "J gen",
        "tick",
        "tick seq",
        "sim x",
        "hydr x",
        "ideal x"
    )?;
    for f in &figures {
        writeln!(
            output,
            "{:<8} {:>9.1} {:>9.1} {:>9.1} {:>6.2} {:>9.1} {:>9.1} {:>9.1} {:>9.1} {:>9.1} {:>9.1} {:>9.1} {:>9.1} {:>9.1} {:>8} {:>8} {:>8} {:>8} {:>8}",
            f.robot,
            f.generated_id_ns,
            f.batch_id_ns_per_state,
            f.generic_id_ns,
            f.generic_id_ns / f.generated_id_ns,
            f.generated_mass_ns,
            f.generic_mass_ns,
            f.generated_gravity_ns,
            f.generated_fd_ns,
            f.batch_fd_ns_per_state,
            f.generic_fd_ns,
            f.generated_id_derivatives_ns,
            f.generated_fd_derivatives_ns,
            f.generated_jacobian_ns,
            f.tick_ns.map_or("-".into(), |t| format!("{t:.1}")),
            f.tick_in_sequence_ns.map_or("-".into(), |t| format!("{t:.1}")),
            f.sim_realtime_factor.map_or("-".into(), |x| format!("{x:.0}")),
            f.sim_realtime_factor_hydraulic.map_or("-".into(), |x| format!("{x:.0}")),
            f.sim_realtime_factor_ideal.map_or("-".into(), |x| format!("{x:.0}")),
        )?;
    }
    writeln!(
        output,
        "(ns per call, medians; gen = generated, batch = generated on 1024 states per call, ns per state, gener = generic tree model; dID, dFD = derivatives of inverse and forward dynamics; J = the last link's Jacobian; tick = HyA's control tick, both IDs in one batch call; tick seq = update then command; sim x = seed-seconds simulated per wall s on one core, seeds in lockstep, lag actuators; hydr x: hydraulic; ideal x: ideal actuators; build: {}; generated FMA: {})",
        build_features(),
        generated_fma()
    )?;
    Ok(())
}
