//! The linear analysis checked two ways: the observers' design figures against closed forms
//! derived independently (Cardano's formula for lu's −3 dB point), and one joint's margins
//! against a small-signal simulation of the same loop in discrete time (the plant integrated by
//! RK4 at T/20, the controller sampled at T with its command held, delays as whole ticks, the
//! observers and velocity sources stepped as the simulator steps them).

use std::collections::VecDeque;

use hya_core::{FilterParams, JointVector, ThirdOrderFilter};
use hya_sim::linear::{
    equal_bandwidth_table, ActuatorModel, Compensation, JointLoop, Matching, ObserverDesign, VelocityModel,
};
use hya_sim::Method;

/// The control period, s.
const T: f64 = 1e-3;

/// RK4 steps per control period.
const SUBSTEPS: usize = 20;

/// The positive root of `x³ + a x² + b x + c = 0` for `a, b > 0 > c` (one sign change: exactly
/// one), by Cardano's formula, or its trigonometric form where all three roots are real.
fn cardano(a: f64, b: f64, c: f64) -> f64 {
    let p = b - a * a / 3.0;
    let q = 2.0 * a * a * a / 27.0 - a * b / 3.0 + c;
    let discriminant = (q / 2.0).powi(2) + (p / 3.0).powi(3);
    let roots: Vec<f64> = if discriminant > 0.0 {
        vec![(-q / 2.0 + discriminant.sqrt()).cbrt() + (-q / 2.0 - discriminant.sqrt()).cbrt()]
    } else {
        let angle = (3.0 * q / (2.0 * p) * (-3.0 / p).sqrt()).acos() / 3.0;
        (0..3).map(|k| 2.0 * (-p / 3.0).sqrt() * (angle - std::f64::consts::TAU * k as f64 / 3.0).cos()).collect()
    };
    let positive: Vec<f64> = roots.iter().map(|t| t - a / 3.0).filter(|x| *x > 0.0).collect();
    assert_eq!(positive.len(), 1, "{roots:?}");
    positive[0]
}

#[test]
fn lu_minus_3_db_solves_its_cubic() {
    // ω1 = ω2 = ω, x = (ω_b/ω)²: |H|² = 1/((1 + x)((1 − x)² + 4ζ²x)) = 1/2, i.e.
    // x³ + (4ζ² − 1) x² + (4ζ² − 1) x − 1 = 0.
    for (zeta, omega) in [(0.8, 50.0), (0.8, 120.0), (1.2, 50.0), (0.75, 20.0)] {
        let k = 4.0 * zeta * zeta - 1.0;
        let expected = omega * cardano(k, k, -1.0).sqrt();
        let design = ObserverDesign::Lu { zeta, omega1_rad_s: omega, omega2_rad_s: omega };
        assert!((design.bandwidth_3db() - expected).abs() < 1e-9 * omega, "ζ = {zeta}, ω = {omega}");
    }
    let paper = ObserverDesign::of(Method::Lu, 50.0).unwrap();
    assert!((paper.bandwidth_3db() - 32.0).abs() < 0.5, "{}", paper.bandwidth_3db());
}

#[test]
fn low_order_bandwidths_and_every_delay_match_their_closed_forms() {
    let eso = ObserverDesign::Eso { omega_rad_s: 50.0 };
    assert!((eso.bandwidth_3db() - 50.0 * (2f64.cbrt() - 1.0).sqrt()).abs() < 1e-9);
    assert!((eso.bandwidth_3db() - 25.5).abs() < 0.05);
    let first = ObserverDesign::FirstOrder { beta_rad_s: 37.0 };
    assert!((first.bandwidth_3db() - 37.0).abs() < 1e-9);
    // Group delay −dφ/dω at low frequency, by a central difference of the phase.
    let lu = ObserverDesign::of(Method::Lu, 50.0).unwrap();
    let slope = |d: &ObserverDesign| -(d.response(1e-3).arg() - d.response(-1e-3).arg()) / 2e-3;
    assert!((slope(&lu) - (1.0 / 50.0 + 1.6 / 50.0)).abs() < 1e-6, "{}", slope(&lu));
    assert!((lu.low_frequency_delay() - 0.052).abs() < 1e-12);
    for d in [eso, first, lu] {
        assert!((d.response(0.0).re - 1.0).abs() < 1e-15 && d.response(0.0).im == 0.0);
        assert!((slope(&d) - d.low_frequency_delay()).abs() < 1e-6, "{d:?}");
    }
    assert_eq!(lu.pole_magnitudes(), vec![50.0; 3]);
}

#[test]
fn equal_bandwidth_rows_reproduce_their_defining_equality() {
    let rows = equal_bandwidth_table(50.0).unwrap();
    assert_eq!(rows.len(), 10);
    let lu = rows[0];
    assert_eq!((lu.method, lu.matching), (Method::Lu, None));
    for row in &rows[1..] {
        let (mine, theirs) = match row.matching.unwrap() {
            Matching::PoleMagnitude => (row.design.parameter_rad_s(), lu.parameter_rad_s),
            Matching::Bandwidth3Db => (row.design.bandwidth_3db(), lu.bandwidth_3db_rad_s),
            Matching::LowFrequencyDelay => (row.design.low_frequency_delay(), lu.low_frequency_delay_s),
        };
        assert!((mine - theirs).abs() < 1e-9 * theirs, "{row:?}");
        assert_eq!(row.bandwidth_3db_rad_s, row.design.bandwidth_3db());
        assert_eq!(row.low_frequency_delay_s, row.design.low_frequency_delay());
    }
    // First order matched by delay: β = 1/0.052.
    let chen_delay = rows.iter().find(|r| r.method == Method::Chen && r.matching == Some(Matching::LowFrequencyDelay));
    assert!((chen_delay.unwrap().parameter_rad_s - 1.0 / 0.052).abs() < 1e-9);
}

/// One HyA-like joint under the simulator's rule: `ω_n`, `ζ = 0.8`, a velocity sensor, actuator
/// bandwidth 2π·40 rad/s, one tick of command delay.
fn hya_like(inertia: f64, viscous: f64, natural_frequency: f64, method: Method) -> JointLoop {
    let mut joint = JointLoop::computed_torque(inertia, viscous, natural_frequency, 0.8, T);
    joint.actuator = ActuatorModel::Lag { bandwidth_rad_s: std::f64::consts::TAU * 40.0 };
    joint.command_delay_s = T;
    joint.compensation = Compensation::of(method, 50.0, joint.kp * natural_frequency * 0.25);
    joint
}

/// The exact step of `β/(s + β)` for an input linear between samples.
struct FirstOrder {
    a: f64,
    ramp: f64,
    y: f64,
    u: f64,
}

impl FirstOrder {
    fn new(beta: f64) -> Self {
        let a = (-beta * T).exp();
        Self { a, ramp: 1.0 - (1.0 - a) / (beta * T), y: 0.0, u: 0.0 }
    }

    /// `y₁ = a y₀ + (1 − a) u₀ + (1 − (1 − a)/(βT)) (u₁ − u₀)`.
    fn step(&mut self, u: f64) -> f64 {
        self.y = self.a * self.y + (1.0 - self.a) * self.u + self.ramp * (u - self.u);
        self.u = u;
        self.y
    }
}

/// The compensation as the controller steps it.
enum Stepped {
    None,
    Integral {
        ki: f64,
        sum: f64,
    },
    /// The paper's filters on `q_m` and `τ_m`: `d̂ = J q̂̈ − τ̂`.
    Lu(Box<(ThirdOrderFilter<1>, ThirdOrderFilter<1>)>),
    /// The momentum form `d̂ = β/(s+β)(s J v − τ_m) = β (J v − F J v) − F τ_m`, `F = β/(s+β)`.
    FirstOrder {
        beta: f64,
        momentum: FirstOrder,
        torque: FirstOrder,
    },
}

impl Stepped {
    fn of(compensation: &Compensation) -> Self {
        match compensation {
            Compensation::None => Self::None,
            Compensation::Integral { ki } => Self::Integral { ki: *ki, sum: 0.0 },
            Compensation::Estimator(ObserverDesign::Lu { zeta, omega1_rad_s, omega2_rad_s }) => {
                let params = FilterParams::new(*zeta, *omega1_rad_s, *omega2_rad_s, T).unwrap();
                let filter = || ThirdOrderFilter::new(params, JointVector::zeros()).unwrap();
                Self::Lu(Box::new((filter(), filter())))
            }
            Compensation::VelocityEstimator(ObserverDesign::FirstOrder { beta_rad_s }) => Self::FirstOrder {
                beta: *beta_rad_s,
                momentum: FirstOrder::new(*beta_rad_s),
                torque: FirstOrder::new(*beta_rad_s),
            },
            other => panic!("not simulated here: {other:?}"),
        }
    }

    /// `c` for the readings `q_m`, `v`, `τ_m` of one tick.
    fn step(&mut self, inertia: f64, q: f64, v: f64, tau: f64) -> f64 {
        match self {
            Self::None => 0.0,
            Self::Integral { ki, sum } => {
                *sum += *ki * q * T;
                *sum
            }
            Self::Lu(filters) => {
                let angle = filters.0.step(&JointVector::from([q])).unwrap().x3[0];
                let torque = filters.1.step(&JointVector::from([tau])).unwrap().x1[0];
                inertia * angle - torque
            }
            Self::FirstOrder { beta, momentum, torque } => {
                let p = inertia * v;
                *beta * (p - momentum.step(p)) - torque.step(tau)
            }
        }
    }
}

/// The velocity the controller reads, as the simulator's sensors step it.
enum SteppedVelocity {
    Sensor,
    /// `v_k = a v_{k−1} + (1 − a)(q_k − q_{k−1})/T`, `a = e^{−ω_c T}`.
    Difference {
        a: f64,
        previous: f64,
        estimate: f64,
    },
    /// `q̂̇` of a third-order filter on the angles.
    Filter(Box<ThirdOrderFilter<1>>),
}

impl SteppedVelocity {
    fn of(velocity: &VelocityModel) -> Self {
        match velocity {
            VelocityModel::Sensor => Self::Sensor,
            VelocityModel::Difference { cutoff_rad_s } => {
                Self::Difference { a: (-cutoff_rad_s * T).exp(), previous: 0.0, estimate: 0.0 }
            }
            VelocityModel::Filter(ObserverDesign::Lu { zeta, omega1_rad_s, omega2_rad_s }) => {
                let params = FilterParams::new(*zeta, *omega1_rad_s, *omega2_rad_s, T).unwrap();
                Self::Filter(Box::new(ThirdOrderFilter::new(params, JointVector::zeros()).unwrap()))
            }
            other => panic!("not simulated here: {other:?}"),
        }
    }

    /// `v` for the readings `q_m`, `q̇_m` of one tick.
    fn step(&mut self, q: f64, sensed: f64) -> f64 {
        match self {
            Self::Sensor => sensed,
            Self::Difference { a, previous, estimate } => {
                *estimate = *a * *estimate + (1.0 - *a) * (q - *previous) / T;
                *previous = q;
                *estimate
            }
            Self::Filter(filter) => filter.step(&JointVector::from([q])).unwrap().x2[0],
        }
    }
}

/// The joint's state: angle, velocity, actuator torque.
type State = [f64; 3];

/// `ẋ` of the plant and actuator under the held command `u`.
fn derivative(joint: &JointLoop, x: &State, u: f64) -> State {
    let torque_rate = match joint.actuator {
        ActuatorModel::Ideal => 0.0,
        ActuatorModel::Lag { bandwidth_rad_s: w } => w * (u - x[2]),
        ActuatorModel::SecondOrder { .. } => panic!("this simulation has first-order actuators only"),
    };
    [x[1], (x[2] - joint.viscous * x[1]) / joint.inertia, torque_rate]
}

/// One RK4 step of `h`.
fn rk4(joint: &JointLoop, x: &State, u: f64, h: f64) -> State {
    let add = |a: &State, k: &State, f: f64| [a[0] + f * k[0], a[1] + f * k[1], a[2] + f * k[2]];
    let k1 = derivative(joint, x, u);
    let k2 = derivative(joint, &add(x, &k1, h / 2.0), u);
    let k3 = derivative(joint, &add(x, &k2, h / 2.0), u);
    let k4 = derivative(joint, &add(x, &k3, h), u);
    std::array::from_fn(|i| x[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]))
}

/// The joint's angle at every tick after a velocity kick of 1 rad/s at rest, for `ticks` ticks.
fn impulse_response(joint: &JointLoop, ticks: usize) -> Vec<f64> {
    let (measurement_ticks, command_ticks) =
        ((joint.measurement_delay_s / T).round() as usize, (joint.command_delay_s / T).round() as usize);
    let mut compensation = Stepped::of(&joint.compensation);
    let mut velocity = SteppedVelocity::of(&joint.velocity);
    let mut readings: VecDeque<State> = VecDeque::new();
    let mut commands: VecDeque<f64> = std::iter::repeat_n(0.0, command_ticks).collect();
    let mut x: State = [0.0, 1.0, 0.0];
    let mut angles = Vec::with_capacity(ticks);
    for _ in 0..ticks {
        readings.push_back(x);
        if readings.len() > measurement_ticks + 1 {
            readings.pop_front();
        }
        let [q, sensed, tau] = readings[0];
        let v = velocity.step(q, sensed);
        let c = compensation.step(joint.inertia, q, v, tau);
        commands.push_back(-joint.kp * q - joint.kd * v - c);
        let u = commands.pop_front().unwrap();
        if joint.actuator == ActuatorModel::Ideal {
            x[2] = u;
        }
        for _ in 0..SUBSTEPS {
            x = rk4(joint, &x, u, T / SUBSTEPS as f64);
        }
        angles.push(x[0]);
    }
    angles
}

/// The largest `|q|` over ticks `range`.
fn peak(angles: &[f64], range: std::ops::Range<usize>) -> f64 {
    angles[range].iter().fold(0.0, |m, q| m.max(q.abs()))
}

/// The loops checked: a stiff PD, the paper's estimator, chen's and the PID on it, and a light
/// joint with strong friction under lu with the backward difference and with the paper's filter
/// as the velocity source.
fn cases() -> Vec<(&'static str, JointLoop)> {
    let light = |velocity| JointLoop { velocity, ..hya_like(0.05, 3.0, 40.0, Method::Lu) };
    vec![
        ("none", hya_like(1.0, 2.0, 40.0, Method::None)),
        ("lu", hya_like(1.0, 2.0, 40.0, Method::Lu)),
        ("chen", hya_like(0.5, 3.0, 30.0, Method::Chen)),
        ("pid", hya_like(2.0, 2.0, 40.0, Method::Pid)),
        ("lu, difference", light(VelocityModel::Difference { cutoff_rad_s: 150.0 })),
        ("lu, filter", light(VelocityModel::Filter(ObserverDesign::of(Method::Lu, 50.0).unwrap()))),
    ]
}

#[test]
fn the_delay_margin_separates_decaying_from_growing_impulse_responses() {
    const TICKS: usize = 3000;
    for (name, joint) in cases() {
        let margins = joint.margins().unwrap();
        assert!(margins.stable, "{name}: {margins:?}");
        let margin_ticks = margins.delay_margin_s / T;
        assert!(margin_ticks > 6.0, "{name}: a delay margin of {margin_ticks} ticks is too short to resolve");
        // 0.7 D and 1.3 D clearly, and the whole ticks at least half a tick either side of D.
        let extra = [
            (0.7 * margin_ticks).round(),
            (margin_ticks - 0.5).floor(),
            (margin_ticks + 0.5).ceil(),
            (1.3 * margin_ticks).round(),
        ];
        for (ticks, grows) in extra.into_iter().zip([false, false, true, true]) {
            let mut delayed = joint;
            delayed.command_delay_s += ticks * T;
            let angles = impulse_response(&delayed, TICKS);
            let (early, late) = (peak(&angles, 0..500), peak(&angles, TICKS - 500..TICKS));
            // Growing or decaying by a factor 5 over 2.5 s, and at all next to D.
            let factor = if (ticks - margin_ticks).abs() < 2.0 { 1.0 } else { 5.0 };
            let which = format!("{name} with {ticks} extra ticks (D = {margin_ticks:.2})");
            if grows {
                assert!(late > factor * early, "{which}: peaks {early:.3e} then {late:.3e}");
            } else {
                assert!(late * factor < early, "{which}: peaks {early:.3e} then {late:.3e}");
            }
            // The linear model agrees on the side of the margin.
            assert_eq!(delayed.margins().unwrap().stable, !grows, "{which}");
        }
    }
}

#[test]
fn near_its_margin_a_loop_rings_at_its_crossover() {
    const TICKS: usize = 3000;
    for (name, joint) in cases() {
        let margins = joint.margins().unwrap();
        let mut delayed = joint;
        delayed.command_delay_s += (margins.delay_margin_s / T).round() * T;
        let angles = impulse_response(&delayed, TICKS);
        // Upward zero crossings over the last two seconds.
        let tail = &angles[TICKS - 2000..];
        let ups: Vec<usize> = (1..tail.len()).filter(|&k| tail[k - 1] < 0.0 && tail[k] >= 0.0).collect();
        assert!(ups.len() > 5, "{name}: {} upward crossings", ups.len());
        let period = (ups[ups.len() - 1] - ups[0]) as f64 * T / (ups.len() - 1) as f64;
        let ringing = std::f64::consts::TAU / period;
        assert!(
            (ringing / margins.crossover_rad_s - 1.0).abs() < 0.2,
            "{name}: rings at {ringing:.1} rad/s, crossover {:.1}",
            margins.crossover_rad_s
        );
    }
}

#[test]
fn the_nyquist_count_agrees_with_the_simulation_on_a_lagging_velocity_source() {
    // The paper's filter at 50 rad/s lags the PD's velocity by 52 ms: at ω_n = 20 rad/s on a
    // 1 kg·m² joint the loop has two poles in the right half-plane, with a sensor none.
    const TICKS: usize = 3000;
    let sensor = hya_like(1.0, 2.0, 20.0, Method::None);
    let filtered =
        JointLoop { velocity: VelocityModel::Filter(ObserverDesign::of(Method::Lu, 50.0).unwrap()), ..sensor };
    for (joint, poles) in [(sensor, 0), (filtered, 2)] {
        let margins = joint.margins().unwrap();
        assert_eq!(margins.unstable_poles, poles, "{margins:?}");
        let angles = impulse_response(&joint, TICKS);
        let (early, late) = (peak(&angles, 0..500), peak(&angles, TICKS - 500..TICKS));
        assert_eq!(late > early, poles > 0, "peaks {early:.3e} then {late:.3e} with {poles} unstable poles");
    }
}
