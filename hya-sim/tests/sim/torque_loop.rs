//! The hydraulic actuators' sampled inner torque loop on one joint turning about the vertical
//! (no gravity torque, no friction): a torque step on a locked joint (a load of 1e4 kg·m², which
//! moves by nanoradians during the step) and on a free light one, at a loop rate fast enough to
//! approach the continuous loop and at HyQ's 1 kHz; pressure noise reaching the torque; the
//! derived velocity; the dead band; and the loop's settings refused with their key.

use hya_core::JointVector;
use hya_sim::config::plant::{HydraulicSetup, PlantSetup};
use hya_sim::plant::hydraulic::{HydraulicActuators, HydraulicState};
use hya_sim::plant::{Actuators, Plant};
use hya_sim::scenario::{ActuatorKind, FrictionKind, HydraulicConfig, LoadConfig, PlantConfig};
use rand::SeedableRng;

/// The load of a locked joint, kg·m².
const LOCKED: f64 = 1e4;
/// The load of a light free joint, kg·m² (a wrist's order of magnitude; at 0.01 kg·m² the
/// joint outruns the valve's flow and the step never reaches 90 %).
const LIGHT: f64 = 0.05;
/// The torque step, N·m.
const STEP: f64 = 2.0;
/// When the step comes, s (a sample instant at every rate used here).
const STEP_AT: f64 = 0.02;
/// The physics step, s.
const H: f64 = 1e-5;

/// HyA's third joint's actuator (the default figures), its inner loop at `rate` Hz with
/// noise-free pressure sensors and an ideal encoder (2^53 counts, no velocity filter): the loop's
/// velocity is then `q̇` half a period ago.
fn ideal_sensing(rate: f64) -> HydraulicConfig {
    HydraulicConfig {
        torque_loop_rate_hz: rate,
        torque_loop_pressure_noise_pa: 0.0,
        torque_loop_pressure_offset_pa: 0.0,
        torque_loop_encoder_counts_per_rev: hya_sim::config::plant::MAX_ENCODER_COUNTS,
        torque_loop_velocity_filter_hz: 0.0,
        ..super::plant::one_joint_hydraulics()
    }
}

fn plant(hydraulic: HydraulicConfig, inertia: f64) -> Plant<1> {
    let config = PlantConfig {
        parameter_spread: 0.0,
        friction: FrictionKind::Off,
        actuator: ActuatorKind::Hydraulic,
        hydraulic,
        ..PlantConfig::default()
    };
    let loads = LoadConfig::default();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
    Plant::new(
        super::plant::turntable_of(inertia),
        &hya_sim::plant::generic_dynamics,
        &PlantSetup::of(&config, &loads).unwrap(),
        (JointVector::zeros(), JointVector::zeros()),
        &mut rng,
    )
    .unwrap()
}

fn actuators(plant: &Plant<1>) -> HydraulicActuators<1> {
    match plant.actuators() {
        Actuators::Hydraulic(h) => h.as_ref().clone(),
        _ => unreachable!("a hydraulic plant"),
    }
}

/// The actuator torque every `H` from `STEP_AT` on, for `seconds`, after a step of `STEP`
/// at `STEP_AT` from a command of 0.
fn step_response(plant: &mut Plant<1>, seconds: f64) -> Vec<f64> {
    let h = actuators(plant);
    let torque = |p: &Plant<1>| h.torque(&p.state.hydraulic.pressure_a, &p.state.hydraulic.pressure_b)[0];
    for _ in 0..(STEP_AT / H).round() as usize {
        plant.step(H, &JointVector::zeros()).unwrap();
    }
    let before = torque(plant);
    let mut series = vec![0.0];
    for _ in 0..(seconds / H).round() as usize {
        plant.step(H, &JointVector::from([STEP])).unwrap();
        series.push(torque(plant) - before);
    }
    series
}

/// The same step on a locked joint under the continuous loop
/// ([`HydraulicActuators::derivative`]), integrated by RK4 at `H`.
fn continuous_step_response(config: &HydraulicConfig, seconds: f64) -> Vec<f64> {
    let h = HydraulicActuators::<1>::new(&HydraulicSetup::of(config).unwrap(), [(-1.5, 1.5)]);
    let (q, qd) = (JointVector::zeros(), JointVector::zeros());
    let rate = |s: &HydraulicState<1>| h.derivative(&JointVector::from([STEP]), &q, &qd, s);
    let mut s = h.holding(&JointVector::zeros());
    let torque = |s: &HydraulicState<1>| h.torque(&s.pressure_a, &s.pressure_b)[0];
    let before = torque(&s);
    let mut series = vec![0.0];
    for _ in 0..(seconds / H).round() as usize {
        let k1 = rate(&s);
        let k2 = rate(&s.along(&k1, H / 2.0));
        let k3 = rate(&s.along(&k2, H / 2.0));
        let k4 = rate(&s.along(&k3, H));
        s = s.along(&k1, H / 6.0).along(&k2, H / 3.0).along(&k3, H / 3.0).along(&k4, H / 6.0);
        series.push(torque(&s) - before);
    }
    series
}

/// A step response's figures: the times of its 10 % and 90 % crossings and its 10–90 % rise
/// time, ms, and its overshoot over the step, fraction.
#[derive(Debug, Clone, Copy)]
struct Figures {
    at_10: f64,
    rise: f64,
    overshoot: f64,
}

fn figures(series: &[f64]) -> Figures {
    let crossing = |level: f64| series.iter().position(|y| *y >= level * STEP).map_or(f64::NAN, |k| k as f64 * H * 1e3);
    let (at_10, at_90) = (crossing(0.1), crossing(0.9));
    let peak = series.iter().copied().fold(f64::MIN, f64::max);
    Figures { at_10, rise: at_90 - at_10, overshoot: peak / STEP - 1.0 }
}

/// `2.2 / ω_τ`, ms: a first-order loop's 10–90 % rise at the design bandwidth.
fn design_rise(config: &HydraulicConfig) -> f64 {
    2.2 / (std::f64::consts::TAU * config.torque_bandwidth_hz[0]) * 1e3
}

#[test]
fn a_fast_loop_approaches_the_continuous_one_on_a_locked_joint() {
    let fast = ideal_sensing(1e5);
    let sampled = figures(&step_response(&mut plant(fast.clone(), LOCKED), 0.06));
    let continuous = figures(&continuous_step_response(&fast, 0.06));
    // The design K_τ = ω_τ / K_lock is a proportional loop's: with the integral off, the rise is
    // first order's 2.2 / ω_τ but for the valve's lag and the leakage's steady error. The
    // integral's zero (at 0.2 ω_τ) makes the default loop rise faster, with overshoot.
    let mut proportional = fast.clone();
    proportional.torque_integral_ratio = 0.0;
    let p_sampled = figures(&step_response(&mut plant(proportional.clone(), LOCKED), 0.06));
    let p_continuous = figures(&continuous_step_response(&proportional, 0.06));
    let design = design_rise(&fast);
    eprintln!(
        "locked joint: continuous loop {continuous:?}; 100 kHz loop {sampled:?}; without the integral, continuous \
         {p_continuous:?}, 100 kHz {p_sampled:?}; first order at the design bandwidth {design:.2} ms"
    );
    assert!(
        (sampled.rise - continuous.rise).abs() < 0.02 * continuous.rise,
        "100 kHz rise {} ms against the continuous {} ms",
        sampled.rise,
        continuous.rise
    );
    assert!((sampled.at_10 - continuous.at_10).abs() < 0.05, "10 % crossings {sampled:?} against {continuous:?}");
    assert!((sampled.overshoot - continuous.overshoot).abs() < 0.01, "overshoot {sampled:?} against {continuous:?}");
    assert!(
        (p_sampled.rise - p_continuous.rise).abs() < 0.02 * p_continuous.rise,
        "without the integral, 100 kHz {p_sampled:?} against the continuous {p_continuous:?}"
    );
    assert!(
        (p_sampled.rise - design).abs() < 0.2 * design,
        "without the integral, the 100 kHz rise {} ms against the design's {design} ms",
        p_sampled.rise
    );
}

#[test]
fn a_1_khz_loop_lags_the_continuous_one() {
    let slow = figures(&step_response(&mut plant(ideal_sensing(1e3), LOCKED), 0.06));
    let fast = figures(&step_response(&mut plant(ideal_sensing(1e5), LOCKED), 0.06));
    eprintln!("locked joint: 1 kHz loop {slow:?}; 100 kHz loop {fast:?}");
    // The zero-order hold delays the loop by about T_s / 2 = 0.5 ms. The step arrives at a
    // sample instant, so the response starts as soon; but with less phase margin the loop is
    // less damped: it rises faster and overshoots more.
    assert!(slow.rise < 0.9 * fast.rise, "rise {} ms (1 kHz) against {} ms (100 kHz)", slow.rise, fast.rise);
    assert!(
        slow.overshoot > fast.overshoot + 0.01,
        "overshoot {} (1 kHz) against {} (100 kHz)",
        slow.overshoot,
        fast.overshoot
    );
}

#[test]
fn a_light_free_joint_tracks_torque_differently_from_a_locked_one() {
    for rate in [1e5, 1e3] {
        let locked = figures(&step_response(&mut plant(ideal_sensing(rate), LOCKED), 0.06));
        let free = figures(&step_response(&mut plant(ideal_sensing(rate), LIGHT), 0.06));
        eprintln!("{rate} Hz loop: locked joint {locked:?}; free joint of {LIGHT} kg·m² {free:?}");
        // What the model guarantees: the load's motion feeds back on the pressures, so the
        // responses differ (by how much, and in which direction, the load and the loop decide).
        assert!(free.rise.is_finite(), "the free joint never reached 90 %: {free:?}");
        assert!(
            (free.rise - locked.rise).abs() > 0.1 * locked.rise,
            "the free joint's step {free:?} is the locked joint's {locked:?}"
        );
    }
}

/// Mean and standard deviation of the locked joint's actuator torque, N·m, held at `TAU` by a
/// 1 kHz loop whose transducers have `noise` and `offset` (Pa): every `H` over 0.4 s after 0.4 s
/// (the step from rest settles in that).
fn held_torque(noise: f64, offset: f64) -> (f64, f64, Plant<1>) {
    let config = HydraulicConfig {
        torque_loop_pressure_noise_pa: noise,
        torque_loop_pressure_offset_pa: offset,
        ..ideal_sensing(1e3)
    };
    let mut p = plant(config, LOCKED);
    let h = actuators(&p);
    let tau = JointVector::from([TAU]);
    for _ in 0..(0.4 / H).round() as usize {
        p.step(H, &tau).unwrap();
    }
    let mut samples = Vec::new();
    for _ in 0..(0.4 / H).round() as usize {
        p.step(H, &tau).unwrap();
        samples.push(h.torque(&p.state.hydraulic.pressure_a, &p.state.hydraulic.pressure_b)[0]);
    }
    let mean = samples.iter().sum::<f64>() / samples.len() as f64;
    let variance = samples.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / samples.len() as f64;
    (mean, variance.sqrt(), p)
}

/// The torque the locked joint holds in [`held_torque`], N·m.
const TAU: f64 = 5.0;

#[test]
fn pressure_noise_reaches_the_torque_in_proportion() {
    let (_, quiet, _) = held_torque(0.0, 0.0);
    let (_, low, _) = held_torque(1e4, 0.0);
    let (_, high, _) = held_torque(4e4, 0.0);
    eprintln!("locked joint at {TAU} N·m, 1 kHz loop: torque std {quiet:.2e} (no noise), {low:.4} (1e4 Pa), {high:.4} N·m (4e4 Pa)");
    assert!(quiet < 0.01 * low, "no noise, yet the torque varies by {quiet} N·m ({low} with noise)");
    assert!(low > 1e-3, "1e4 Pa of pressure noise leaves the torque still ({low} N·m)");
    // The loop is linear about the held point: four times the noise, four times the spread.
    assert!((high / low - 4.0).abs() < 0.4, "std {high} at 4e4 Pa against {low} at 1e4 Pa");
}

#[test]
fn the_loop_regulates_the_measured_torque_so_offsets_shift_the_true_one() {
    let (mean, _, p) = held_torque(0.0, 2.5e4);
    let h = actuators(&p);
    let (offset_a, offset_b) = h.pressure_offsets();
    // What the transducers add to the torque the loop reads.
    let bias = h.torque(&offset_a, &offset_b)[0];
    eprintln!("offsets {offset_a:?} {offset_b:?} Pa: true torque {mean:.5} N·m, the loop's bias {bias:.5} N·m");
    assert!(bias.abs() > 1e-3, "the seeded offsets add no torque ({bias} N·m)");
    assert!(offset_a[0].abs() <= 2.5e4 && offset_b[0].abs() <= 2.5e4, "offsets beyond their bound");
    assert!((mean - (TAU - bias)).abs() < 1e-3 * TAU, "true torque {mean} N·m, expected {TAU} − {bias}");
}

#[test]
fn the_loop_derives_its_velocity_from_its_encoder() {
    // A free light joint accelerating under a torque step, the loop at 1 kHz with HyA's 2^19
    // counts, with and without a 100 Hz low-pass: after every 1 ms tick, the loop's velocity
    // is the recursion on the rounded angles at the tick's start, and near the true q̇.
    for filter_hz in [0.0, 100.0] {
        let config = HydraulicConfig {
            torque_loop_encoder_counts_per_rev: 1 << 19,
            torque_loop_velocity_filter_hz: filter_hz,
            ..ideal_sensing(1e3)
        };
        let mut p = plant(config, LIGHT);
        let (period, resolution) = (1e-3, std::f64::consts::TAU / (1u64 << 19) as f64);
        let a = if filter_hz > 0.0 { (-std::f64::consts::TAU * filter_hz * period).exp() } else { 0.0 };
        let round = |q: f64| (q / resolution).round() * resolution;
        let (mut angle, mut velocity) = (round(p.state.q[0]), 0.0);
        let mut worst_gap: f64 = 0.0;
        for _ in 0..40 {
            let (q, qd) = (p.state.q[0], p.state.qd[0]);
            p.advance(period, 100, &JointVector::from([STEP])).unwrap();
            // The tick's first sub-step ran the loop on the state at its start.
            velocity = a * velocity + (1.0 - a) * (round(q) - angle) / period;
            angle = round(q);
            let s = &p.state.hydraulic;
            assert!((s.loop_angle[0] - angle).abs() < 1e-15, "encoder {} against {angle}", s.loop_angle[0]);
            assert!((s.loop_velocity[0] - velocity).abs() < 1e-9, "velocity {} against {velocity}", s.loop_velocity[0]);
            worst_gap = worst_gap.max((velocity - qd).abs());
        }
        eprintln!(
            "free joint at 1 kHz, 2^19 counts, filter {filter_hz} Hz: q̇ = {:.3} rad/s after 40 ms; the loop's velocity \
             within {worst_gap:.4} rad/s of the true one at each sample",
            p.state.qd[0]
        );
        // Half a period's lag at q̈ ≈ 40 rad/s², and a count per period (0.012 rad/s); the filter
        // adds 1/(2π 100 Hz) = 1.6 ms of lag (0.064 rad/s).
        let bound = if filter_hz > 0.0 { 0.1 } else { 0.04 };
        assert!(worst_gap < bound, "the loop's velocity strays {worst_gap} rad/s from q̇");
    }
}

#[test]
fn a_dead_band_delays_the_response_but_the_integral_crosses_it() {
    let plain = step_response(&mut plant(ideal_sensing(1e3), LOCKED), 0.3);
    let banded =
        step_response(&mut plant(HydraulicConfig { valve_dead_band: 0.005, ..ideal_sensing(1e3) }, LOCKED), 0.3);
    let (f_plain, f_banded) = (figures(&plain), figures(&banded));
    let settled = |series: &[f64]| series.last().copied().unwrap_or(f64::NAN);
    eprintln!(
        "locked joint, 1 kHz loop: no dead band {f_plain:?}, dead band 0.5 % of full opening {f_banded:?}; after \
         0.3 s {:.4} and {:.4} N·m",
        settled(&plain),
        settled(&banded)
    );
    // K_τ e is 0.014 of full opening for this 2 N·m step: the band eats a third of it, and the
    // integral has to wind the rest across it.
    assert!(
        f_banded.at_10 > f_plain.at_10,
        "10 % at {} ms with the band, {} ms without",
        f_banded.at_10,
        f_plain.at_10
    );
    assert!(f_banded.rise > 2.0 * f_plain.rise, "rise {} ms with the band, {} ms without", f_banded.rise, f_plain.rise);
    assert!((settled(&banded) - STEP).abs() < 0.01 * STEP, "with the band the step settles at {}", settled(&banded));
}

#[test]
fn the_loop_settings_are_refused_with_their_key() {
    type Change = fn(&mut HydraulicConfig);
    let cases: &[(&str, Change)] = &[
        ("torque_loop_rate_hz", |h| h.torque_loop_rate_hz = -1000.0),
        ("torque_loop_rate_hz", |h| h.torque_loop_rate_hz = 0.0),
        ("torque_loop_rate_hz", |h| h.torque_loop_rate_hz = f64::NAN),
        ("torque_loop_rate_hz", |h| h.torque_loop_rate_hz = 1e9),
        ("torque_loop_pressure_noise_pa", |h| h.torque_loop_pressure_noise_pa = f64::NAN),
        ("torque_loop_pressure_noise_pa", |h| h.torque_loop_pressure_noise_pa = -1.0),
        ("torque_loop_pressure_offset_pa", |h| h.torque_loop_pressure_offset_pa = f64::INFINITY),
        ("torque_loop_encoder_counts_per_rev", |h| h.torque_loop_encoder_counts_per_rev = 0),
        ("torque_loop_encoder_counts_per_rev", |h| h.torque_loop_encoder_counts_per_rev = u64::MAX),
        ("torque_loop_velocity_filter_hz", |h| h.torque_loop_velocity_filter_hz = -5.0),
        ("torque_loop_velocity_filter_hz", |h| h.torque_loop_velocity_filter_hz = f64::NAN),
        ("valve_dead_band", |h| h.valve_dead_band = 1.0),
        ("valve_dead_band", |h| h.valve_dead_band = 1.5),
        ("valve_dead_band", |h| h.valve_dead_band = -0.1),
        ("valve_dead_band", |h| h.valve_dead_band = f64::NAN),
        // The actuators' scalars, checked with the lists before a plant is built.
        ("supply_pressure_pa", |h| h.supply_pressure_pa = 0.0),
        ("tank_pressure_pa", |h| h.tank_pressure_pa = h.supply_pressure_pa),
        ("tank_pressure_pa", |h| h.tank_pressure_pa = -1.0),
        ("bulk_modulus_pa", |h| h.bulk_modulus_pa = f64::NAN),
        ("valve_rated_drop_pa", |h| h.valve_rated_drop_pa = -1.0),
        ("valve_damping_ratio", |h| h.valve_damping_ratio = 0.0),
        ("torque_integral_ratio", |h| h.torque_integral_ratio = 1.5),
        ("velocity_compensation", |h| h.velocity_compensation = 2.5),
    ];
    for (key, change) in cases {
        let mut config = ideal_sensing(1e3);
        change(&mut config);
        let error = HydraulicSetup::<1>::of(&config).unwrap_err().to_string();
        assert!(error.contains(&format!("`plant.hydraulic.{key}`")), "the refusal does not name {key}: {error}");
        // And a scenario's per-joint settings, checked before a run, refuse it too.
        let mut scenario = hya_sim::Scenario::builtin("goto_internal").unwrap();
        change(&mut scenario.plant.hydraulic);
        let error = hya_sim::settings::Setup::<6>::of(&scenario).unwrap_err().to_string();
        assert!(error.contains(key), "the scenario's refusal does not name {key}: {error}");
    }
    assert!(HydraulicSetup::<1>::of(&ideal_sensing(1e6)).is_ok());
}

#[test]
fn the_loop_keeps_step_with_the_control_ticks() {
    // 1 ms ticks of 4 sub-steps from t = 1e4 s (where the clock's rounding is coarser): after
    // every tick the loop's next sample is the next tick's start, so every new command is read
    // at once; the command alternates, and the held valve command follows it every tick.
    let mut p = plant(ideal_sensing(1e3), LOCKED);
    p.time = 1e4;
    let h = actuators(&p);
    let mut previous = f64::NAN;
    for k in 0..5000 {
        let tau = if k % 2 == 0 { 1.0 } else { -1.0 };
        p.advance(1e-3, 4, &JointVector::from([tau])).unwrap();
        let command = p.state.hydraulic.command[0];
        assert!(command != previous, "tick {k}: the command {command} did not follow the reference");
        previous = command;
        let next = match p.actuators() {
            Actuators::Hydraulic(a) => a.next_sample_time(),
            _ => unreachable!(),
        };
        assert!((next - p.time).abs() < 1e-6 * h.sample_period(), "tick {k}: next sample at {next}, time {}", p.time);
    }
}
