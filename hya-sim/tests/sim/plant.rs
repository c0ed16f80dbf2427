//! The plant's physics on one joint turning about the vertical (so gravity exerts no torque):
//! LuGre stiction and breakaway, the steady-sliding friction curve against its closed form, the
//! hydraulic torque loop against its own linearisation, chamber pressures within tank and
//! supply, and no energy created by a closed valve.

use hya_core::JointVector;
use hya_sim::config::plant::{HydraulicSetup, PlantSetup};
use hya_sim::plant::friction::Friction;
use hya_sim::plant::hydraulic::{HydraulicActuators, HydraulicState};
use hya_sim::plant::{Actuators, Plant};
use hya_sim::scenario::{ActuatorKind, FrictionKind, HydraulicConfig, LoadConfig, PlantConfig};
use nalgebra::{SMatrix, SVector};
use rand::SeedableRng;

/// Inertia about the joint axis, kg·m².
const INERTIA: f64 = 0.05;

/// A 1 kg link whose joint turns about the base's vertical axis, range ±1.5 rad.
fn turntable() -> hya_core::model::TreeModel {
    turntable_of(INERTIA)
}

/// [`turntable`] with `inertia` about the joint axis, kg·m².
pub(super) fn turntable_of(inertia: f64) -> hya_core::model::TreeModel {
    let urdf = format!(
        r#"<robot name="turntable">
  <link name="base"/>
  <link name="arm">
    <inertial><mass value="1"/><origin xyz="0 0 0"/><inertia ixx="0.01" iyy="0.01" izz="{inertia}" ixy="0" ixz="0" iyz="0"/></inertial>
  </link>
  <joint name="turn" type="revolute">
    <parent link="base"/><child link="arm"/><axis xyz="0 0 1"/>
    <limit lower="-1.5" upper="1.5" effort="100" velocity="10"/>
  </joint>
</robot>"#
    );
    hya_urdf::load_str(&urdf, "turntable.urdf").unwrap().model
}

/// One joint's plant configuration: LuGre (levels constant in position unless `variation`),
/// ideal actuator.
fn one_joint(friction: FrictionKind, actuator: ActuatorKind, variation: f64) -> PlantConfig {
    let one = |v: f64| vec![v];
    PlantConfig {
        parameter_spread: 0.0,
        friction,
        coulomb_nm: one(2.0),
        static_nm: one(3.0),
        viscous_nm_s: one(0.5),
        stribeck_velocity_rad_s: 0.05,
        coulomb_position_variation: variation,
        bristle_stiffness_nm_rad: one(1.5e4),
        bristle_damping_nm_s_rad: one(2.0 * (1.5e4 * INERTIA).sqrt() * 0.5),
        actuator,
        actuator_time_constant_s: one(0.01),
        hydraulic: one_joint_hydraulics(),
        substeps: Some(10),
        ..PlantConfig::default()
    }
}

/// HyA's third joint's actuator, from the default figures.
pub(super) fn one_joint_hydraulics() -> HydraulicConfig {
    let d = HydraulicConfig::default();
    let first = |v: &Vec<f64>| vec![v[2]];
    HydraulicConfig {
        displacement_m3_rad: first(&d.displacement_m3_rad),
        area_ratio: first(&d.area_ratio),
        dead_volume_m3: first(&d.dead_volume_m3),
        valve_rated_flow_m3_s: first(&d.valve_rated_flow_m3_s),
        valve_natural_frequency_hz: first(&d.valve_natural_frequency_hz),
        valve_null_bias: vec![0.0],
        leakage_m3_s_pa: first(&d.leakage_m3_s_pa),
        torque_bandwidth_hz: first(&d.torque_bandwidth_hz),
        ..d
    }
}

fn plant(config: &PlantConfig, q0: f64, tau0: f64) -> Plant<1> {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
    Plant::new(
        turntable(),
        &hya_sim::plant::generic_dynamics,
        &PlantSetup::of(config, &LoadConfig::default()).unwrap(),
        (JointVector::from([q0]), JointVector::from([tau0])),
        &mut rng,
    )
    .unwrap()
}

/// Runs `plant` for `seconds` under the constant command `tau`, at the configured sub-step of a
/// 1 ms tick; calls `each` after every sub-step.
fn run(plant: &mut Plant<1>, seconds: f64, tau: f64, mut each: impl FnMut(&Plant<1>)) {
    let h = 1e-3 / 10.0;
    for _ in 0..(seconds / h).round() as usize {
        plant.step(h, &JointVector::from([tau])).unwrap();
        each(plant);
    }
}

fn lugre(plant: &Plant<1>) -> &hya_sim::plant::friction::LuGre<1> {
    match plant.friction() {
        Friction::LuGre(f) => f,
        _ => panic!("the plant should run LuGre friction"),
    }
}

#[test]
fn a_joint_loaded_below_its_static_level_sticks() {
    // Position-dependent levels, so the level is read at the start pose. The load is ramped in
    // over 0.5 s, as in a breakaway test (a step excites the bristles' spring, whose presliding
    // velocity can cross the Stribeck velocity on a light link), then held for 2 s.
    let mut p = plant(&one_joint(FrictionKind::Lugre, ActuatorKind::Ideal, 0.3), 0.2, 0.0);
    let level = lugre(&p).static_level(0, 0.2);
    let tau = 0.9 * level;
    for k in 1..=500 {
        run(&mut p, 1e-3, tau * k as f64 / 500.0, |_| {});
    }
    let (q_held, z_held) = (p.state.q[0], p.state.bristle[0]);
    let mut drift: f64 = 0.0;
    run(&mut p, 2.0, tau, |p| {
        // While held, the joint may move only as its bristles deflect.
        let creep = ((p.state.q[0] - q_held) - (p.state.bristle[0] - z_held)).abs();
        drift = drift.max(creep);
    });
    let deflection = (p.state.q[0] - 0.2).abs();
    eprintln!("held at {tau:.3} of {level:.3} N·m: deflection {deflection:.2e} rad, drift beyond it {drift:.2e} rad");
    assert!(drift < 1e-4, "the joint crept {drift} rad beyond its bristle deflection");
    assert!(deflection < 1e-3, "the joint slid {deflection} rad while loaded below its static level");
}

#[test]
fn a_joint_loaded_above_its_static_level_breaks_away() {
    let mut p = plant(&one_joint(FrictionKind::Lugre, ActuatorKind::Ideal, 0.0), 0.0, 0.0);
    let level = lugre(&p).static_level(0, 0.0);
    run(&mut p, 0.5, 1.1 * level, |_| {});
    assert!(p.state.q[0] > 0.01 && p.state.qd[0] > 0.01, "no breakaway: q = {}, q̇ = {}", p.state.q[0], p.state.qd[0]);
}

#[test]
fn steady_sliding_follows_the_closed_form_friction_curve() {
    // Constant torque against LuGre with constant levels: the joint settles at the velocity
    // where τ + τ_f(q̇) = 0; the closed form gives τ_f at that velocity.
    for tau in [2.5, 3.5, 5.0, 8.0] {
        let mut p = plant(&one_joint(FrictionKind::Lugre, ActuatorKind::Ideal, 0.0), -1.4, 0.0);
        run(&mut p, 1.5, tau, |_| {});
        let v = p.state.qd[0];
        let closed_form = lugre(&p).steady_sliding_torque(0, p.state.q[0], v);
        eprintln!("τ = {tau} N·m: steady q̇ = {v:.5} rad/s, closed-form τ_f = {closed_form:.6} N·m");
        assert!((tau + closed_form).abs() < 1e-6 * tau, "τ = {tau}: τ_f({v}) = {closed_form}");
    }
}

/// The hydraulic state of one joint as a vector `(x_v, ẋ_v, p_a, p_b, ∫e)`.
fn pack(s: &HydraulicState<1>) -> SVector<f64, 5> {
    SVector::from([s.spool[0], s.spool_rate[0], s.pressure_a[0], s.pressure_b[0], s.torque_integral[0]])
}

fn unpack(x: &SVector<f64, 5>) -> HydraulicState<1> {
    let v = |k: usize| JointVector::from([x[k]]);
    HydraulicState {
        spool: v(0),
        spool_rate: v(1),
        pressure_a: v(2),
        pressure_b: v(3),
        torque_integral: v(4),
        ..HydraulicState::zeros()
    }
}

#[test]
fn locked_joint_torque_step_matches_the_linearisation() {
    let config = one_joint_hydraulics();
    let actuator = HydraulicActuators::<1>::new(&HydraulicSetup::of(&config).unwrap(), [(-1.5, 1.5)]);
    let (q, qd) = (JointVector::from([0.0]), JointVector::zeros());
    let tau0 = 10.0;
    let rate = |x: &SVector<f64, 5>, tau_ref: f64| {
        pack(&actuator.derivative(&JointVector::from([tau_ref]), &q, &qd, &unpack(x)))
    };
    // Settle at τ0 first (leakage needs a small opening), then linearise there.
    let rk4 = |x: &SVector<f64, 5>, tau_ref: f64, h: f64| {
        let k1 = rate(x, tau_ref);
        let k2 = rate(&(x + k1 * (h / 2.0)), tau_ref);
        let k3 = rate(&(x + k2 * (h / 2.0)), tau_ref);
        let k4 = rate(&(x + k3 * h), tau_ref);
        x + (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (h / 6.0)
    };
    let h = 1e-5;
    let mut x = pack(&actuator.holding(&JointVector::from([tau0])));
    for _ in 0..20_000 {
        x = rk4(&x, tau0, h);
    }
    let equilibrium = x;
    let torque = |x: &SVector<f64, 5>| actuator.torque(&JointVector::from([x[2]]), &JointVector::from([x[3]]))[0];
    // Jacobians by central differences, scaled to each state's magnitude.
    let scale = [1e-6, 1e-3, 1.0, 1.0, 1e-6];
    let mut a = SMatrix::<f64, 5, 5>::zeros();
    for k in 0..5 {
        let mut e = SVector::<f64, 5>::zeros();
        e[k] = scale[k];
        a.set_column(k, &((rate(&(equilibrium + e), tau0) - rate(&(equilibrium - e), tau0)) / (2.0 * scale[k])));
    }
    let b = (rate(&equilibrium, tau0 + 1e-3) - rate(&equilibrium, tau0 - 1e-3)) / 2e-3;
    let c = SVector::<f64, 5>::from([
        0.0,
        0.0,
        config.displacement_m3_rad[0],
        -config.displacement_m3_rad[0] * config.area_ratio[0],
        0.0,
    ]);
    // Linear analysis: steady-state gain −cᵀ A⁻¹ b and the poles.
    let a_inverse = a.try_inverse().unwrap();
    let gain = -(c.transpose() * a_inverse * b)[0];
    let poles = a.complex_eigenvalues();
    // The closed loop's magnitude at the design bandwidth, |cᵀ (jωI − A)⁻¹ b|.
    let design = std::f64::consts::TAU * config.torque_bandwidth_hz[0];
    let complex = |x: f64| nalgebra::Complex::new(x, 0.0);
    let resolvent = (SMatrix::<nalgebra::Complex<f64>, 5, 5>::identity() * nalgebra::Complex::new(0.0, design)
        - a.map(complex))
    .try_inverse()
    .unwrap();
    let magnitude = (c.map(complex).transpose() * resolvent * b.map(complex))[0].norm();
    eprintln!("locked joint: poles {poles:?}; steady gain {gain:.5}; |T(j {design:.0})| = {magnitude:.3}");
    // A small step: the nonlinear response against the linear model's, through the same steps.
    let step = 0.5;
    let (mut nonlinear, mut linear) = (equilibrium, SVector::<f64, 5>::zeros());
    let mut worst: f64 = 0.0;
    for _ in 0..30_000 {
        nonlinear = rk4(&nonlinear, tau0 + step, h);
        let k1 = a * linear + b * step;
        let k2 = a * (linear + k1 * (h / 2.0)) + b * step;
        let k3 = a * (linear + k2 * (h / 2.0)) + b * step;
        let k4 = a * (linear + k3 * h) + b * step;
        linear += (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (h / 6.0);
        worst = worst.max(((torque(&nonlinear) - torque(&equilibrium)) - (c.dot(&linear))).abs());
    }
    let settled = torque(&nonlinear) - torque(&equilibrium);
    eprintln!(
        "step {step} N·m: settled at {settled:.5} N·m, linear model {:.5}; worst gap {worst:.2e} N·m",
        gain * step
    );
    assert!(worst < 0.02 * step, "the response departs from its linearisation by {worst} N·m");
    assert!((settled - gain * step).abs() < 0.005 * step, "steady state {settled} against {}", gain * step);
    assert!((gain - 1.0).abs() < 1e-3, "a locked joint should track its torque reference, gain {gain}");
    assert!((0.5..0.95).contains(&magnitude), "|T| = {magnitude} at the design bandwidth (≈ −3 dB expected)");
}

#[test]
fn chamber_pressures_stay_within_tank_and_supply() {
    let config = one_joint(FrictionKind::Lugre, ActuatorKind::Hydraulic, 0.3);
    let mut p = plant(&config, 0.0, 0.0);
    let (tank, supply) = match p.actuators() {
        hya_sim::plant::Actuators::Hydraulic(h) => h.pressure_range(),
        _ => unreachable!(),
    };
    let (mut low, mut high) = (f64::MAX, f64::MIN);
    // Commands that swing the joint back and forth and push it against friction.
    for (seconds, tau) in [(0.3, 4.0), (0.3, -6.0), (0.2, 0.0), (0.3, 12.0), (0.3, -12.0), (0.3, 1.0)] {
        run(&mut p, seconds, tau, |p| {
            let h = &p.state.hydraulic;
            low = low.min(h.pressure_a[0].min(h.pressure_b[0]));
            high = high.max(h.pressure_a[0].max(h.pressure_b[0]));
        });
    }
    eprintln!("pressures between {low:.0} and {high:.0} Pa (tank {tank}, supply {supply}); q = {}", p.state.q[0]);
    assert!(low >= tank && high <= supply, "pressures left [{tank}, {supply}]: {low} .. {high}");
}

/// `½ J q̇² +` the oil's stored energy, for a plant whose valve stays closed and whose
/// chambers do not leak (so each chamber's oil is a closed, conservative spring).
fn closed_valve_energy() -> (f64, Vec<f64>) {
    let mut config = one_joint(FrictionKind::Off, ActuatorKind::Hydraulic, 0.0);
    config.hydraulic.leakage_m3_s_pa = vec![0.0];
    config.hydraulic.velocity_compensation = 0.0;
    config.hydraulic.torque_bandwidth_hz = vec![1e-12]; // the torque loop does nothing
    let mut p = plant(&config, 0.0, 0.0);
    p.state.qd = JointVector::from([2.0]);
    let start = p.state.hydraulic;
    let h = match p.actuators() {
        hya_sim::plant::Actuators::Hydraulic(h) => h.as_ref().clone(),
        _ => unreachable!(),
    };
    let energy = |p: &Plant<1>| 0.5 * INERTIA * p.state.qd[0].powi(2) + h.oil_energy(0, 0.0, p.state.q[0], &start);
    let e0 = energy(&p);
    let mut series = Vec::new();
    run(&mut p, 0.5, 0.0, |p| series.push(energy(p)));
    (e0, series)
}

#[test]
fn a_closed_valve_creates_no_energy() {
    let (e0, series) = closed_valve_energy();
    let worst = series.iter().map(|e| (e - e0).abs()).fold(0.0, f64::max);
    eprintln!("closed valve, no leakage: energy {e0:.6} J, worst drift {worst:.2e} J");
    assert!(worst < 1e-6 * e0, "energy drifted by {worst} J of {e0} J");
}

/// `state` with entry `k` of `(x_v, ẋ_v, p_a, p_b)` moved by `d`.
fn moved(state: &HydraulicState<1>, k: usize, d: f64) -> HydraulicState<1> {
    let mut moved = *state;
    match k {
        0 => moved.spool[0] += d,
        1 => moved.spool_rate[0] += d,
        2 => moved.pressure_a[0] += d,
        _ => moved.pressure_b[0] += d,
    }
    moved
}

/// The Jacobian of `(ẋ_v, ẍ_v, ṗ_a, ṗ_b)` in `(x_v, ẋ_v, p_a, p_b)` at `s`, by central
/// differences of the plant's own rates, each entry stepped by `steps[k]`.
fn hydraulic_jacobian(actuator: &HydraulicActuators<1>, q: f64, s: &HydraulicState<1>) -> SMatrix<f64, 4, 4> {
    let steps = [1e-7, 1e-4, 10.0, 10.0];
    let rates = |s: &HydraulicState<1>| {
        let r = actuator.held_derivative(&JointVector::from([q]), &JointVector::zeros(), s);
        SVector::<f64, 4>::from([r.spool[0], r.spool_rate[0], r.pressure_a[0], r.pressure_b[0]])
    };
    SMatrix::from_fn(|row, k| (rates(&moved(s, k, steps[k])) - rates(&moved(s, k, -steps[k])))[row] / (2.0 * steps[k]))
}

#[test]
fn the_oils_stiff_rate_bounds_the_chambers_and_the_spools_fastest_modes() {
    let (supply, tank) = (20e6, 0.0);
    let states = [
        // Wide open onto chambers at supply and tank pressure, near each end of the stroke:
        // zero drop across the open lands, the orifice law's steepest slope.
        (1.4, 1.0, supply, tank),
        (-1.4, -1.0, tank, supply),
        (0.0, 0.6, supply - 2e4, 0.5 * supply),
        // Half open with large drops: the chambers are slow and the spool is the fastest.
        (0.3, 0.1, 0.5 * supply, 0.4 * supply),
    ];
    // The default spool (ζ = 0.5), an overdamped one, and leakage a thousand times the default.
    for (damping, leakage) in [(0.5, 1e-13), (3.0, 1e-13), (0.5, 1e-10)] {
        let config = HydraulicConfig {
            valve_damping_ratio: damping,
            leakage_m3_s_pa: vec![leakage],
            supply_pressure_pa: supply,
            tank_pressure_pa: tank,
            ..one_joint_hydraulics()
        };
        let actuator = HydraulicActuators::<1>::new(&HydraulicSetup::of(&config).unwrap(), [(-1.5, 1.5)]);
        for (k, &(q, spool, pa, pb)) in states.iter().enumerate() {
            let s = HydraulicState {
                spool: JointVector::from([spool]),
                pressure_a: JointVector::from([pa]),
                pressure_b: JointVector::from([pb]),
                ..HydraulicState::zeros()
            };
            let j = hydraulic_jacobian(&actuator, q, &s);
            // The pressures' block: Gershgorin's row sums. The spool's block: its eigenvalues.
            let chambers = (j[(2, 2)].abs() + j[(2, 3)].abs()).max(j[(3, 3)].abs() + j[(3, 2)].abs());
            let (trace, det) = (j[(0, 0)] + j[(1, 1)], j[(0, 0)] * j[(1, 1)] - j[(0, 1)] * j[(1, 0)]);
            let discriminant = trace * trace / 4.0 - det;
            let spool_pole = if discriminant < 0.0 { det.sqrt() } else { (trace / 2.0).abs() + discriminant.sqrt() };
            let got = actuator.stiff_rate(&JointVector::from([q]), &s);
            let expected = chambers.max(spool_pole);
            let case = format!("ζ = {damping}, C_l = {leakage}, state {k}");
            assert!((got - expected).abs() <= 1e-5 * expected, "{case}: {got} against {chambers} and {spool_pole}");
            // With the defaults the first three states test the chambers, the last the spool.
            if (damping, leakage) == (0.5, 1e-13) {
                assert_eq!(chambers > spool_pole, k < 3, "{case}: chambers {chambers}/s, spool {spool_pole}/s");
            }
        }
    }
}

#[test]
fn a_valve_wide_open_onto_a_chamber_at_supply_pressure_steps_as_a_fine_step_does() {
    // Near the stroke's upper end the rod side's volume is nearly its dead volume; the valve
    // wide open to it (x_v = −1) with the chamber at supply pressure: zero drop, the orifice's
    // steepest slope, a mode so fast that one RK4 step of the tick's default sub-step (0.5 ms)
    // would leave RK4's stability region. The plant cuts the step into cycles instead.
    let config = PlantConfig { substeps: None, ..one_joint(FrictionKind::Off, ActuatorKind::Hydraulic, 0.0) };
    let supply = config.hydraulic.supply_pressure_pa;
    let start = |p: &mut Plant<1>| {
        let h = &mut p.state.hydraulic;
        (h.spool[0], h.command[0], h.pressure_a[0], h.pressure_b[0]) = (-1.0, -1.0, 0.3 * supply, supply);
    };
    let (mut coarse, mut fine) = (plant(&config, 1.45, 0.0), plant(&config, 1.45, 0.0));
    start(&mut coarse);
    start(&mut fine);
    let Actuators::Hydraulic(actuators) = coarse.actuators() else { panic!("hydraulic actuators") };
    let h = 1e-3 / config.substeps() as f64;
    let rate = actuators.stiff_rate(&coarse.state.q, &coarse.state.hydraulic);
    assert!(h * rate > 2.8, "h λ = {}: not beyond RK4's stability region", h * rate);
    for _ in 0..config.substeps() {
        coarse.step(h, &JointVector::zeros()).unwrap();
    }
    for _ in 0..1000 {
        fine.step(1e-6, &JointVector::zeros()).unwrap();
    }
    let (c, f) = (&coarse.state, &fine.state);
    let gap = (c.hydraulic.pressure_b[0] - f.hydraulic.pressure_b[0])
        .abs()
        .max((c.hydraulic.pressure_a[0] - f.hydraulic.pressure_a[0]).abs());
    // Within a thousandth of the supply after a transient of the whole supply pressure (an RK4
    // cycle at h λ = 1 carries a relative error of 2 % of what decays in it); an RK4 step at h λ
    // beyond 2.8 would multiply the deviation instead (at h λ = 6, 31-fold a step).
    assert!(gap < 1e-3 * supply, "after 1 ms the pressures differ by {gap} Pa");
    // The angle within `PlantConfig::substeps`' criterion of 1e-7 rad per tick.
    assert!((c.q[0] - f.q[0]).abs() < 1e-7, "after 1 ms the angles differ by {} rad", (c.q[0] - f.q[0]).abs());
}
