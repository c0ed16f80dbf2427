//! The report's "Plant" section: every parameter of the simulated arm with its value and source,
//! the friction-velocity curve against the estimated disturbance of the sine task, each joint's
//! actuator step response, and the rigid body against MuJoCo.

use std::fmt::Write as _;

use hya_core::JointVector;
use rand::SeedableRng;

use crate::analysis::simulate::RunOutcome;
use crate::config::scenario::Method;
use crate::config::scenario::{ActuatorKind, PlantConfig, Scenario, SensorConfig, TorqueSource, Transducers};
use crate::error::SimError;
use crate::io::svg::{line_grid, Panel, Series, PALETTE};
use crate::plant::friction::Friction;
use crate::plant::Actuators;
use crate::run::rollout::scenario_plant;
use crate::studies::step_responses::{OpenLoop, StepResponse, STEPS_NM};

use super::text::table_row;

/// A figure: file name and SVG text.
pub type Figure = (String, String);

fn numbers(values: &[f64]) -> String {
    values.iter().map(|v| format!("{v}")).collect::<Vec<_>>().join(", ")
}

/// `(parameter, value, unit, source)` for the settings of the plant and the sensors that act in
/// this configuration (no valve figures for lag actuators); a value other than the default
/// (HyA's, whose sources the table gives) is marked as the scenario's own.
fn parameter_rows(p: &PlantConfig, s: &SensorConfig) -> Vec<[String; 4]> {
    let hydraulic = p.actuator == ActuatorKind::Hydraulic;
    let acts = |name: &str| match name {
        "actuator_time_constant_s" => p.actuator == ActuatorKind::Lag,
        "pressure_noise_pa" | "transducers" => hydraulic && s.torque == TorqueSource::Pressure,
        "pressure_offset_pa" => {
            hydraulic && s.torque == TorqueSource::Pressure && s.transducers == Transducers::Independent
        }
        n if n.starts_with("bristle_") => p.friction == crate::config::scenario::FrictionKind::Lugre,
        n => hydraulic || !HYDRAULIC_ROWS.contains(&n),
    };
    let defaults = every_parameter_row(&PlantConfig::default(), &SensorConfig::default());
    every_parameter_row(p, s)
        .into_iter()
        .zip(defaults)
        .filter(|(row, _)| acts(&row[0]))
        .map(|(mut row, default)| {
            if row[1] != default[1] {
                row[3] = "this scenario's setting (the default differs)".into();
            }
            row
        })
        .collect()
}

/// The rows of the hydraulic actuators' settings.
const HYDRAULIC_ROWS: [&str; 21] = [
    "supply_pressure_pa",
    "tank_pressure_pa",
    "bulk_modulus_pa",
    "displacement_m3_rad",
    "area_ratio",
    "dead_volume_m3",
    "valve_rated_flow_m3_s",
    "valve_rated_drop_pa",
    "valve_natural_frequency_hz",
    "valve_damping_ratio",
    "valve_null_bias",
    "leakage_m3_s_pa",
    "torque_bandwidth_hz",
    "torque_integral_ratio",
    "velocity_compensation",
    "torque_loop_rate_hz",
    "torque_loop_pressure_noise_pa",
    "torque_loop_pressure_offset_pa",
    "torque_loop_encoder_counts_per_rev",
    "torque_loop_velocity_filter_hz",
    "valve_dead_band",
];

/// `(parameter, value, unit, source)` for every setting of the plant and the sensors, the
/// source being that of the default value.
fn every_parameter_row(p: &PlantConfig, s: &SensorConfig) -> Vec<[String; 4]> {
    let h = &p.hydraulic;
    let row = |name: &str, value: String, unit: &str, source: &str| [name.into(), value, unit.into(), source.into()];
    vec![
        row("parameter_spread", format!("{}", p.parameter_spread), "–", "our choice: every mass, centre-of-mass coordinate and rotational inertia scaled by a seeded uniform factor in 1 ± spread"),
        row("friction", format!("{:?}", p.friction).to_lowercase(), "–", "LuGre: Canudas de Wit, Olsson, Åström & Lischinsky, IEEE TAC 40(3), 1995"),
        row("coulomb_nm", numbers(&p.coulomb_nm), "N·m", "Coulomb 2–10 N·m identified on the hydraulic Atlas arm (Vorndamme et al., IROS 2016); ≈ 5 N·m seen on HyA's joint 2 (the paper, VI-A)"),
        row("static_nm", numbers(&p.static_nm), "N·m", "our choice: 1.3 × Coulomb"),
        row("viscous_nm_s (σ2)", numbers(&p.viscous_nm_s), "N·m·s/rad", "Vorndamme et al., IROS 2016 (0.9–2.7 N·m·s/rad)"),
        row("stribeck_velocity_rad_s", format!("{}", p.stribeck_velocity_rad_s), "rad/s", "our choice"),
        row("coulomb_position_variation", format!("{}", p.coulomb_position_variation), "–", "our choice: levels vary within 1 ± this over a seeded profile of 0.4–1.6 rad wavelengths (the paper, VI-A: static friction changes with position)"),
        row("bristle_stiffness_nm_rad (σ0)", numbers(&p.bristle_stiffness_nm_rad), "N·m/rad", "our choice: static level over a presliding deflection of 2e-4 rad"),
        row("bristle_damping_nm_s_rad (σ1)", numbers(&p.bristle_damping_nm_s_rad), "N·m·s/rad", "our choice: √(σ0 M_ii(q_home)), a bristle damping ratio of 0.5"),
        row("actuator", format!("{:?}", p.actuator).to_lowercase(), "–", "HyA: Moog E024 servo valve per joint; vanes on SAA, SFE, HR, WR, cylinders on EFE, WFE (Semini et al., SICFP 2015, Table 2)"),
        row("supply_pressure_pa", format!("{}", h.supply_pressure_pa), "Pa", "HyA's torques are rated at 20 MPa (Semini et al., SICFP 2015, Table 2)"),
        row("tank_pressure_pa", format!("{}", h.tank_pressure_pa), "Pa", "our choice (gauge)"),
        row("bulk_modulus_pa", format!("{}", h.bulk_modulus_pa), "Pa", "our choice, between 3e8 Pa identified on HyQ's leg with long hoses (Cunha et al., COBEM 2009) and 1.6e9 Pa of the oil: HyA's valves sit on the arm"),
        row("displacement_m3_rad", numbers(&h.displacement_m3_rad), "m³/rad", "HyA's maximum torques 126, 120, 120, 225, 60, 100 N·m (Rehman et al., ICRA 2016, Table I) over 20 MPa: vane displacement, or a 4 kN cylinder's area times its lever arm (56 mm EFE, 25 mm WFE)"),
        row("area_ratio", numbers(&h.area_ratio), "–", "vanes 1; cylinders 1.23/2.01 cm² (HyQ's 16/10 mm cylinder, Semini et al., JSCE 2011, Table II)"),
        row("dead_volume_m3", numbers(&h.dead_volume_m3), "m³", "our choice (valves mounted on the arm; HyA's not published)"),
        row("valve_rated_flow_m3_s", numbers(&h.valve_rated_flow_m3_s), "m³/s", "our choice: 2.5 l/min at the rated drop (the E024's rating was not found); ≈ 12 rad/s unloaded on a vane, HyA's velocity limit"),
        row("valve_rated_drop_pa", format!("{}", h.valve_rated_drop_pa), "Pa", "our choice (7 MPa, a common servo-valve rating)"),
        row("valve_natural_frequency_hz", numbers(&h.valve_natural_frequency_hz), "Hz", "E024 ≈ 250 Hz; spool identified as second order at 1600 rad/s (Boaventura et al., IROS 2012)"),
        row("valve_damping_ratio", format!("{}", h.valve_damping_ratio), "–", "Boaventura et al., IROS 2012"),
        row("valve_null_bias", numbers(&h.valve_null_bias), "of full opening", "our choice (none)"),
        row("leakage_m3_s_pa", numbers(&h.leakage_m3_s_pa), "m³/(s·Pa)", "our choice, small (HyQ's cylinder leakage is negligible, Boaventura et al., ICRA 2012)"),
        row("torque_bandwidth_hz", numbers(&h.torque_bandwidth_hz), "Hz", "≈ 40 Hz torque loop on HyQ (Boaventura et al., ICRA 2012; IROS 2013), here on a locked joint at mid-range"),
        row("torque_integral_ratio", format!("{}", h.torque_integral_ratio), "–", "our choice (HyQ runs a PI torque loop, Boaventura et al., IROS 2013)"),
        row("velocity_compensation", format!("{}", h.velocity_compensation), "–", "load-motion compensation (Boaventura et al., IROS 2012)"),
        row("torque_loop_rate_hz", format!("{}", h.torque_loop_rate_hz), "Hz", "HyQ's torque loops run at 1 kHz (Boaventura et al., IROS 2012); sampled, the valve command held between samples"),
        row("torque_loop_pressure_noise_pa", format!("{}", h.torque_loop_pressure_noise_pa), "Pa", "our choice: as the controller's pressure sensors (the inner loop reads its own draw)"),
        row("torque_loop_pressure_offset_pa", format!("{}", h.torque_loop_pressure_offset_pa), "Pa", "our choice: a fifth of the ±0.5 % FS accuracy of HyQ's 25 MPa transducers (Semini, PhD thesis, 2010), for sensors zeroed at start-up"),
        row("torque_loop_encoder_counts_per_rev", format!("{}", h.torque_loop_encoder_counts_per_rev), "counts", "HyA's 19-bit encoders; the loop's load-motion compensation differentiates them"),
        row("torque_loop_velocity_filter_hz", format!("{}", h.torque_loop_velocity_filter_hz), "Hz", "our choice: none (0)"),
        row("valve_dead_band", format!("{}", h.valve_dead_band), "of full opening", "our choice: none (0)"),
        row("actuator_time_constant_s", numbers(&p.actuator_time_constant_s), "s", "our choice (`actuator = \"lag\"` only)"),
        row("substeps", format!("{}", p.substeps()), "per tick", "measured: the fewest RK4 sub-steps per 1 ms tick within 1e-7 rad per tick of a ten times finer step along a goto move (an encoder count is 1.2e-5 rad): 2 on lag and ideal actuators (lag 1: 3.6e-7 rad, 2: 3.5e-8 rad; ideal 1: 3.7e-7 rad, 2: 2.6e-8 rad), and 2 on hydraulic ones (5.2e-8 rad; one sub-step measures the same, because the spool, ω_v h = 1.6 at h = 1 ms, cuts it into the same two RK4 steps), `cargo test --release -p hya-sim --test sim integration_step -- --ignored --nocapture`; each sub-step cut into equal RK4 cycles wherever the state's stiffest mode λ needs it to keep h·λ ≤ 1: sliding bristles (σ0|q̇|/g), a hydraulic spool (its faster pole) and a chamber whose valve is wide open near zero pressure drop (the orifice law's stiff mode, up to β K_v/(V √δ))"),
        row("encoder_counts_per_rev", format!("{}", s.encoder_counts_per_rev), "counts", "HyA's 19-bit absolute encoders (Semini et al., SICFP 2015)"),
        row("velocity", format!("{:?}", s.velocity).to_lowercase(), "–", "HyA has encoders only (the paper, III-B): velocity from their difference"),
        row("velocity_cutoff_rad_s", format!("{}", s.velocity_cutoff_rad_s), "rad/s", "our choice"),
        row("torque", format!("{:?}", s.torque).to_lowercase(), "–", "from the chamber pressures, so the actuators' own friction stays in the measured disturbance, as the paper observes (VI-A); HyA itself carries torque sensors and load cells (SICFP 2015)"),
        row("pressure_noise_pa", format!("{}", s.pressure_noise_pa), "Pa", "our choice"),
        row("transducers", format!("{:?}", s.transducers).to_lowercase(), "–", "HyA's: the controller reads the inner torque loops' pressure transducers (one set per joint), so their offsets are shared; the noise is drawn per reading (a simplification). `independent` (a second set with offsets of its own) is a variant in the sensitivity table"),
        row("pressure_offset_pa", format!("{}", s.pressure_offset_pa), "Pa", "our choice: as the torque loops' transducers (read with `transducers = \"independent\"` only)"),
        row("measurement_delay_ticks", format!("{}", s.measurement_delay_ticks), "ticks", "our choice"),
        row("command_delay_ticks", format!("{}", s.command_delay_ticks), "ticks", "our choice: one 1 ms tick (control at 1 kHz over EtherCAT)"),
    ]
}

/// The model's steady-sliding friction and the sine task's estimated disturbance against joint
/// velocity (the velocity from the true angles by central differences), one panel per joint.
fn friction_figure<const N: usize>(config: &PlantConfig, sine: &RunOutcome<N>) -> Result<Option<String>, SimError> {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(0);
    // Only the friction lists: the actuators' and the loads' do not enter the figure.
    let setup = crate::config::plant::FrictionSetup::<N>::of(config)?;
    let Friction::LuGre(lugre) = Friction::<N>::new(&setup, &mut rng) else {
        return Ok(None);
    };
    let trace = &sine.trace;
    let panels = (0..N)
        .map(|j| {
            let velocities: Vec<f64> = (1..trace.q.len().saturating_sub(1))
                .map(|k| (trace.q[k + 1][j] - trace.q[k - 1][j]) / (trace.time[k + 1] - trace.time[k - 1]))
                .collect();
            let estimate: Vec<(f64, f64)> = velocities
                .iter()
                .enumerate()
                .filter(|(k, _)| k % 5 == 0)
                .map(|(k, v)| (*v, trace.d_hat[k + 1][j]))
                .collect();
            let span = velocities.iter().fold(0.05_f64, |m, v| m.max(v.abs()));
            let curve: Vec<(f64, f64)> = (-200..=200)
                .filter(|k| *k != 0)
                .map(|k| {
                    let v = span * k as f64 / 200.0;
                    (v, lugre.nominal_steady_sliding_torque(j, v))
                })
                .collect();
            Panel {
                title: format!("joint {}", j + 1),
                y_label: "N·m".into(),
                series: vec![
                    Series {
                        label: "d̂ (lu)".into(),
                        points: estimate,
                        color: PALETTE[2],
                        dashed: false,
                        markers: true,
                    },
                    Series {
                        label: "LuGre, steady sliding".into(),
                        points: curve,
                        color: PALETTE[0],
                        dashed: false,
                        markers: false,
                    },
                ],
            }
        })
        .collect::<Vec<_>>();
    Ok(Some(line_grid(&format!("{}: friction against joint velocity", sine.scenario), "q̇ [rad/s]", &panels, 3)))
}

/// Whether the lightly loaded joints track torque worse (the paper, VI-A, explains the wrist's
/// oscillations so): the median rise time (of the small step) of the joints below the median
/// `M_ii` against the rest's, and the slowest joint.
fn load_and_torque_tracking(inertia: &[f64], rise_times: &[f64]) -> String {
    let middle = crate::analysis::seeds::median(inertia.to_vec());
    // A joint that never reached 90 % within the window is slower than every one that did.
    let rise = |r: f64| if r.is_finite() { r } else { f64::INFINITY };
    let rises = |light: bool| -> Vec<f64> {
        inertia.iter().zip(rise_times).filter(|(m, _)| (**m < middle) == light).map(|(_, r)| rise(*r)).collect()
    };
    let (light, heavy) = (rises(true), rises(false));
    let slowest = rise_times.iter().map(|r| rise(*r)).enumerate().max_by(|a, b| a.1.total_cmp(&b.1));
    let (Some((k, slowest_ms)), false, false) = (slowest, light.is_empty(), heavy.is_empty()) else {
        return String::new();
    };
    let (n_light, n_heavy) = (light.len(), heavy.len());
    let with_ms = |r: f64| if r.is_finite() { format!("{r:.1} ms") } else { "beyond the 90 ms window".to_owned() };
    // Each group's fastest and slowest: the medians rank the groups only where they do not overlap.
    let span = |r: &[f64]| r.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(*v), hi.max(*v)));
    let ((light_fastest, light_slowest), (heavy_fastest, heavy_slowest)) = (span(&light), span(&heavy));
    let (light, heavy) = (crate::analysis::seeds::median(light), crate::analysis::seeds::median(heavy));
    let verdict = match (light_fastest > heavy_slowest, light_slowest < heavy_fastest) {
        (true, _) => "slower: every one of them rises later than every heavier joint".to_owned(),
        (_, true) => "faster: every one of them rises sooner than every heavier joint".to_owned(),
        _ => format!(
            "{} by the medians only: the groups overlap (lighter {} to {}, heavier {} to {}), so the load does not order the rise times",
            if light > heavy { "slower" } else { "not slower" },
            with_ms(light_fastest),
            with_ms(light_slowest),
            with_ms(heavy_fastest),
            with_ms(heavy_slowest)
        ),
    };
    format!(
        "\nThe paper (VI-A) explains the wrist's oscillations by lightly loaded joints tracking torque worse. For the {} N·m step (one run per joint), the median rise time of the {n_light} joints below the median `M_ii` is {}, of the other {n_heavy} {}: the lightly loaded joints are {verdict} in this model; the slowest joint is {} ({}, `M_ii` = {:.4} kg·m²). The rise times need not be monotonic in `M_ii`: the joints differ in actuator too (vanes and cylinders). The {} N·m step is large: where a joint reaches its valve's flow limit within the step, its rise time measures that limit, not the small-signal loop; the frequency responses below are the small-signal measure.\n",
        STEPS_NM[0],
        with_ms(light),
        with_ms(heavy),
        k + 1,
        with_ms(slowest_ms),
        inertia[k],
        STEPS_NM[1]
    )
}

/// A rise time, ms, or that it was not reached within the window.
fn rise_text(rise_ms: f64) -> String {
    match rise_ms.is_finite() {
        true => format!("{rise_ms:.1}"),
        false => "not reached in 90 ms".into(),
    }
}

/// The step responses of one step size as a figure.
fn step_figure(response: &StepResponse) -> String {
    let series = response
        .points
        .iter()
        .enumerate()
        .map(|(j, points)| Series {
            label: format!("joint {}", j + 1),
            points: points.clone(),
            color: PALETTE[j % PALETTE.len()],
            dashed: j >= PALETTE.len(),
            markers: false,
        })
        .collect();
    let panel = Panel {
        title: format!("change of actuator torque after a {} N·m command step, over the step", response.step_nm),
        y_label: "Δτ_act / step".into(),
        series,
    };
    line_grid("torque step responses", "time after the step [ms]", &[panel], 1)
}

/// The "Plant" section and its figures.
pub fn section<const N: usize>(
    robot: &crate::robot::Robot<N>,
    scenarios: &[Scenario],
    outcomes: &[RunOutcome<N>],
    (torque, open_loop): (Option<&crate::torque_response::TorqueResponses>, Option<&OpenLoop>),
) -> Result<(String, Vec<Figure>), SimError> {
    let mut md = String::from("\n## Plant\n\n");
    let mut figures = Vec::new();
    let Some(first) = scenarios.first() else { return Ok((md, figures)) };
    let p = &first.plant;
    let friction = match p.friction {
        crate::config::scenario::FrictionKind::Lugre => "LuGre friction",
        crate::config::scenario::FrictionKind::Smooth => "smooth (tanh) friction without stiction",
        crate::config::scenario::FrictionKind::Off => "no friction",
    };
    let actuator = match p.actuator {
        ActuatorKind::Hydraulic => "hydraulic actuators with an inner PI torque loop",
        ActuatorKind::Lag => "first-order torque lags as actuators",
        ActuatorKind::Ideal => "ideal actuators",
    };
    let velocity = match first.sensors.velocity {
        crate::config::scenario::VelocitySource::Difference => "velocity from the encoders' difference",
        crate::config::scenario::VelocitySource::Filter => "velocity from the paper's filter",
        crate::config::scenario::VelocitySource::Sensor => "a velocity sensor",
    };
    let _ = writeln!(
        md,
        "The simulated arm (\"true\" plant) of `{}`, as the other scenarios use it unless they say otherwise: the nominal rigid body with seeded parameter errors, {friction}, {actuator}, encoders with {velocity}, and {} tick(s) of command delay. Gravity {} m/s² along −z.{}\n",
        first.name,
        first.sensors.command_delay_ticks,
        hya_core::STANDARD_GRAVITY,
        if first.robot == "hya" {
            " The first testbed's plant is one setting away: `friction = \"smooth\"`, `actuator = \"lag\"`, `[sensors] velocity = \"sensor\"`."
        } else {
            ""
        }
    );
    md.push_str("| parameter | value (per joint where a list) | unit | source (of the default, HyA's, unless marked) |\n|---|---|---|---|\n");
    for r in parameter_rows(p, &first.sensors) {
        md.push_str(&table_row(r));
    }
    let model = &robot.model;
    let nominal = robot.nominal.as_ref();
    if let Some(sine) = outcomes.iter().find(|o| o.scenario.starts_with("sine_internal") && o.method == Method::Lu) {
        if let Some(svg) = friction_figure(p, sine)? {
            let name = "plant_friction.svg".to_owned();
            let _ = writeln!(md, "\n### Friction against velocity\n\n![friction]({name})\n\nThe LuGre model's steady-sliding torque `−(g(q̇) sgn q̇ + σ2 q̇)` at the nominal levels (black; the seeded profile moves it within ±{} of that), and the paper's estimate `d̂` of the sine task against the joint's velocity (dots). The estimate also holds the rigid-body model error and the actuators' torque error, so it sits off the curve by a joint-dependent offset; it opposes the motion where the curve does.", p.coulomb_position_variation);
            figures.push((name, svg));
        }
    }
    if let Some([small, large]) = open_loop.map(|o| o.steps.as_slice()) {
        let (svg, rise_times, large_rise_times) = (step_figure(small), &small.rise_ms, &large.rise_ms);
        let name = "plant_step.svg".to_owned();
        let joints = crate::config::settings::Setup::<N>::of(first)?;
        let q0 = joints.initial_position;
        let (plant, _) = scenario_plant(model, &joints, q0, nominal.gravity(&q0))?;
        let natural = match plant.actuators() {
            Actuators::Hydraulic(h) => h.natural_frequency(&q0, &nominal.mass_matrix(&q0).diagonal()),
            _ => JointVector::zeros(),
        };
        let _ = writeln!(md, "\n### Actuators on the arm\n\n![step responses]({name})\n\nEach joint's actuator torque after a {} N·m step of its own command (the figure; the table has a {} N·m step too), 50 ms after the arm was released at the start pose with every actuator holding the gravity torque, friction off (a step below static friction would leave the joint stuck, as if locked), the parameter spread, pressure noise and transducer offsets off: the loops were designed for ({}) Hz on a locked joint at mid-range and run sampled, on measured pressures, with load-motion compensation from the encoders' difference. The oil-column natural frequency `√(β (D_a²/V_a + D_b²/V_b) / M_ii)` at the start pose, which the load sets, is in the table:\n", STEPS_NM[0], STEPS_NM[1], numbers(&p.hydraulic.torque_bandwidth_hz));
        let _ = writeln!(md, "| joint | M_ii(q0) [kg·m²] | hydraulic natural frequency [Hz] | 10–90 % rise time, {} N·m step [ms] | 10–90 % rise time, {} N·m step [ms] |\n|---|---|---|---|---|", STEPS_NM[0], STEPS_NM[1]);
        let inertia = nominal.mass_matrix(&q0).diagonal();
        for j in 0..N {
            md.push_str(&table_row([
                format!("{}", j + 1),
                format!("{:.4}", inertia[j]),
                format!("{:.0}", natural[j] / std::f64::consts::TAU),
                rise_text(rise_times[j]),
                rise_text(large_rise_times[j]),
            ]));
        }
        md.push_str(&load_and_torque_tracking(inertia.as_slice(), rise_times));
        figures.push((name, svg));
        if let Some(t) = torque {
            let (text, figure) = super::torque_loops::section(t, &p.hydraulic.torque_bandwidth_hz, &p.viscous_nm_s);
            md.push_str(&text);
            figures.push(figure);
        }
    }
    if let Some((q_gap, qd_gap)) = open_loop.and_then(|o| o.mujoco_gap) {
        let _ = writeln!(md, "\n### The rigid body against MuJoCo\n\nThe plant with friction, actuators, noise and parameter errors off (`hya plant --ideal`), under the torque sequence of `tools/mujoco_rollout.py`, against MuJoCo 4.0's rollout of the same URDF (RK4 at 0.1 ms both; gravity along −z, limits, contacts, damping and armature off in MuJoCo): the worst difference over 1 s is **{q_gap:.1e} rad** in angle and {qd_gap:.1e} rad/s in velocity, while the arm travels up to 1 rad.");
    }
    Ok((md, figures))
}

#[cfg(test)]
mod tests {
    use super::load_and_torque_tracking;

    #[test]
    fn the_load_ranks_the_rise_times_only_where_the_groups_do_not_overlap() {
        let inertia = [0.1, 0.2, 0.3, 1.0, 2.0, 3.0];
        let apart = load_and_torque_tracking(&inertia, &[9.0, 8.0, 7.0, 3.0, 2.0, 1.0]);
        assert!(apart.contains("are slower: every one of them rises later"), "{apart}");
        let overlapping = load_and_torque_tracking(&inertia, &[9.0, 2.5, f64::NAN, 3.0, 2.0, 6.0]);
        assert!(overlapping.contains("slower by the medians only: the groups overlap"), "{overlapping}");
        assert!(overlapping.contains("lighter 2.5 ms to beyond the 90 ms window"), "{overlapping}");
    }
}
