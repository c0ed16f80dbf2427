//! The hydraulic actuators measured as the loops use them: small-signal torque frequency
//! responses `A(jω) = τ_act / τ_cmd` per joint at three amplitudes, on a locked joint and on the
//! arm held at its start pose by the PD (the position loop closed). Fitted to the locked
//! responses at the smallest amplitude, the actuator model of the linearised loops: the torque
//! loop with its resonance and a dead time,
//!
//! ```text
//! A(s) = ω_n² e^{−s T_a} / (s² + 2ζ ω_n s + ω_n²)
//! ```
//!
//! On the moving joint the actuator is not `A` alone: the load's motion changes the chambers'
//! pressures, `τ_act = A τ_cmd − B(jω) q̇`, and the held runs give the back-drive `B = (A τ_cmd −
//! τ_act) / q̇` (`A` the locked response), in N·m·s/rad, which acts on the joint as damping where
//! its real part is positive.
//!
//! A run holds the command's sine `a sin(ωt)` on top of the holding torque, sampled by the
//! 1 ms control tick and held between ticks as the controller's command is. Both signals are read
//! at the ticks over whole periods after settling; the command's samples are those of the sine,
//! so the held command's fundamental is theirs times the zero-order hold
//! `Z(jω) = (1 − e^{−jωT})/(jωT)`, which the linear loop models apart. So
//! `A = phasor(τ_act) / (phasor(τ_cmd) Z)`. Pressure noise, transducer offsets, friction and the
//! parameter spread are off: the responses are the actuators' and the arm's alone.

use nalgebra::Complex;
use serde::Serialize;

use crate::analysis::seeds::parallel_map;
use crate::config::cost::Cost;
use crate::config::scenario::{ActuatorKind, FrictionKind, Scenario};
use crate::config::settings::Setup;
use crate::error::SimError;
use crate::linear::{jw, ActuatorModel, PhasorSum};
use crate::plant::{Actuators, HydraulicActuators};
use crate::run::rollout::scenario_plant;

/// The frequencies measured, Hz (up to a sixth of the 1 kHz tick's Nyquist frequency).
pub const FREQUENCIES_HZ: [f64; 8] = [1.0, 2.0, 5.0, 10.0, 20.0, 40.0, 60.0, 80.0];

/// The command amplitudes, N·m: small signals, and one where the flow limit may show.
pub const AMPLITUDES_NM: [f64; 3] = [0.05, 0.2, 1.0];

/// RK4 steps per control tick of a locked actuator (its fastest mode, the valve spool's at
/// 1600 rad/s, takes `h λ` = 0.16 of RK4's 2.78).
const LOCKED_SUBSTEPS: usize = 10;

/// Settling before a measurement, s, and at least this many periods.
const SETTLE_S: f64 = 0.5;
const SETTLE_PERIODS: f64 = 3.0;

/// The measurement window: whole periods, at least this many and at least this long, s.
const WINDOW_PERIODS: f64 = 2.0;
const WINDOW_S: f64 = 0.25;

/// Where the joint is while its actuator is measured.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Mounting {
    /// Held still: the actuator against its locked load.
    #[serde(rename = "locked")]
    Locked,
    /// The arm held at its start pose by the PD (`τ = g(q) − K_P (q − q0) − K_D q̇` plus the
    /// sine), free to move: the load's motion feeds back through the chambers.
    #[serde(rename = "position loop closed")]
    Held,
}

impl Mounting {
    /// Its name in the report.
    pub fn name(self) -> &'static str {
        match self {
            Mounting::Locked => "locked",
            Mounting::Held => "position loop closed",
        }
    }
}

/// One joint's measured `A(jω)` at one amplitude and mounting.
#[derive(Debug, Clone, Serialize)]
pub struct Response {
    /// How the joint was held.
    pub mounting: Mounting,
    /// The command's amplitude, N·m.
    pub amplitude_nm: f64,
    /// The joint, from 1.
    pub joint: usize,
    /// Per frequency of [`FREQUENCIES_HZ`]: `(|A|, ∠A in degrees)`.
    pub gain_phase: Vec<(f64, f64)>,
    /// Held only, per frequency: the back-drive `B` as `(|B| in N·m·s/rad, ∠B in degrees)`.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub back_drive: Vec<(f64, f64)>,
}

impl Response {
    /// The complex responses at [`FREQUENCIES_HZ`].
    pub fn complex(&self) -> Vec<Complex<f64>> {
        self.gain_phase.iter().map(|&(g, p)| Complex::from_polar(g, p.to_radians())).collect()
    }
}

/// The second-order torque loop with dead time fitted to one joint's responses.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ActuatorFit {
    /// The joint, from 1.
    pub joint: usize,
    /// `ω_n`, rad/s.
    pub natural_rad_s: f64,
    /// `ζ`.
    pub damping: f64,
    /// `T_a`, s.
    pub delay_s: f64,
    /// The RMS over the frequencies of `|A_measured − A_fit|`.
    pub residual: f64,
}

impl ActuatorFit {
    /// The fitted model.
    pub fn model(&self) -> ActuatorModel {
        ActuatorModel::SecondOrder { natural_rad_s: self.natural_rad_s, damping: self.damping, delay_s: self.delay_s }
    }
}

/// Everything measured, and the fits.
#[derive(Debug, Clone, Serialize)]
pub struct TorqueResponses {
    /// The frequencies, Hz.
    pub frequencies_hz: Vec<f64>,
    /// Every joint, amplitude and mounting.
    pub responses: Vec<Response>,
    /// Per joint, fitted to the locked responses at the smallest amplitude.
    pub fits: Vec<ActuatorFit>,
}

/// Joint `joint`'s (from 1) response at `amplitude` and `mounting` among `responses`.
fn find(responses: &[Response], mounting: Mounting, amplitude: f64, joint: usize) -> Option<&Response> {
    responses.iter().find(|r| r.mounting == mounting && r.amplitude_nm == amplitude && r.joint == joint)
}

impl TorqueResponses {
    /// Joint `joint`'s (from 1) response at `amplitude` and `mounting`.
    pub fn response(&self, mounting: Mounting, amplitude: f64, joint: usize) -> Option<&Response> {
        find(&self.responses, mounting, amplitude, joint)
    }

    /// Joint `joint`'s (from 1) fitted model.
    pub fn model(&self, joint: usize) -> Option<ActuatorModel> {
        self.fits.iter().find(|f| f.joint == joint).map(ActuatorFit::model)
    }
}

/// The zero-order hold of period `t` at `ω`: `(1 − e^{−jωT})/(jωT)`.
fn hold(omega: f64, t: f64) -> Complex<f64> {
    (Complex::from(1.0) - Complex::from_polar(1.0, -omega * t)) / jw(omega * t)
}

/// The phasor sums of the command and the torque, one per joint, over the window.
struct Window<const N: usize> {
    from: f64,
    to: f64,
    command: [PhasorSum; N],
    torque: [PhasorSum; N],
    velocity: [PhasorSum; N],
}

impl<const N: usize> Window<N> {
    fn new(frequency_hz: f64) -> Self {
        let period = 1.0 / frequency_hz;
        let from = SETTLE_S.max(SETTLE_PERIODS * period);
        let periods = (WINDOW_S * frequency_hz).ceil().max(WINDOW_PERIODS);
        let omega = std::f64::consts::TAU * frequency_hz;
        Self {
            from,
            to: from + periods * period,
            command: [PhasorSum::new(omega); N],
            torque: [PhasorSum::new(omega); N],
            velocity: [PhasorSum::new(omega); N],
        }
    }

    /// Adds the tick at `t` (in the window's half-open span) of command and torque deviations
    /// and the joints' velocities.
    fn push(&mut self, t: f64, command: &[f64; N], torque: &[f64; N], velocity: &[f64; N]) {
        if t >= self.from - 1e-9 && t < self.to - 1e-9 {
            for j in 0..N {
                self.command[j].push(t, command[j]);
                self.torque[j].push(t, torque[j]);
                self.velocity[j].push(t, velocity[j]);
            }
        }
    }

    /// Per joint, the torque's and the velocity's phasors over the held command's: `A` and
    /// `q̇ / τ_cmd`.
    fn responses(&self, omega: f64, dt: f64) -> [(Complex<f64>, Complex<f64>); N] {
        core::array::from_fn(|j| {
            let command = self.command[j].value() * hold(omega, dt);
            (self.torque[j].value() / command, self.velocity[j].value() / command)
        })
    }
}

/// `scenario` with everything off that is not the actuators and the arm: friction, pressure
/// noise and offsets, parameter spread, loads.
pub fn clean(scenario: &Scenario) -> Scenario {
    let mut s = scenario.clone();
    s.plant.friction = FrictionKind::Off;
    s.plant.parameter_spread = 0.0;
    s.plant.hydraulic.torque_loop_pressure_noise_pa = 0.0;
    s.plant.hydraulic.torque_loop_pressure_offset_pa = 0.0;
    s.loads = Default::default();
    s
}

/// Every locked joint at once (a locked joint's actuator does not feel the others), commanded
/// `τ0 + a sin(2π f t)`: `A` per joint.
fn locked<const N: usize>(
    actuators: &HydraulicActuators<N>,
    (q0, tau0): (hya_core::JointVector<N>, hya_core::JointVector<N>),
    (frequency_hz, amplitude): (f64, f64),
    dt: f64,
) -> [Complex<f64>; N] {
    let mut actuators = actuators.clone();
    let mut s = actuators.holding(&tau0);
    let rest = hya_core::JointVector::<N>::zeros();
    let omega = std::f64::consts::TAU * frequency_hz;
    let mut window = Window::<N>::new(frequency_hz);
    let h = dt / LOCKED_SUBSTEPS as f64;
    let ticks = (window.to / dt).ceil() as usize;
    for k in 0..ticks {
        let t = k as f64 * dt;
        let sine = amplitude * (omega * t).sin();
        let torque = actuators.torque(&s.pressure_a, &s.pressure_b) - tau0;
        window.push(t, &[sine; N], &core::array::from_fn(|j| torque[j]), &[0.0; N]);
        actuators.sample(t, &(tau0 + hya_core::JointVector::<N>::repeat(sine)), &q0, &mut s);
        for _ in 0..LOCKED_SUBSTEPS {
            let rate = |x: &crate::plant::HydraulicState<N>| actuators.held_derivative(&q0, &rest, x);
            let k1 = rate(&s);
            let k2 = rate(&s.along(&k1, h / 2.0));
            let k3 = rate(&s.along(&k2, h / 2.0));
            let k4 = rate(&s.along(&k3, h));
            s = s.along(&k1, h / 6.0).along(&k2, h / 3.0).along(&k3, h / 3.0).along(&k4, h / 6.0);
        }
    }
    window.responses(omega, dt).map(|(a, _)| a)
}

/// Joint `j` on the arm held by the PD at `q0`, its command `g(q) − K_P (q − q0) − K_D q̇`
/// plus `a sin(2π f t)`: `A` and `q̇ / τ_cmd` of joint `j`.
fn held<const N: usize>(
    robot: &crate::robot::Robot<N>,
    joints: &Setup<N>,
    (kp, kd): (&[f64; N], &[f64; N]),
    q0: hya_core::JointVector<N>,
    (j, frequency_hz, amplitude): (usize, f64, f64),
) -> Result<(Complex<f64>, Complex<f64>), SimError> {
    let nominal = robot.nominal.as_ref();
    let dt = joints.timing.dt_s;
    let hold_torque = nominal.gravity(&q0);
    let (mut plant, _) = scenario_plant(&robot.model, joints, q0, hold_torque)?;
    let Actuators::Hydraulic(actuators) = plant.actuators().clone() else {
        return Err(SimError::Numerical("the torque response needs hydraulic actuators".into()));
    };
    let omega = std::f64::consts::TAU * frequency_hz;
    let mut window = Window::<1>::new(frequency_hz);
    let ticks = (window.to / dt).ceil() as usize;
    let substeps = joints.timing.substeps;
    for k in 0..ticks {
        let t = k as f64 * dt;
        let s = plant.state;
        let mut command = nominal.gravity(&s.q);
        for i in 0..N {
            command[i] -= kp[i] * (s.q[i] - q0[i]) + kd[i] * s.qd[i];
        }
        command[j] += amplitude * (omega * t).sin();
        let torque = actuators.torque(&s.hydraulic.pressure_a, &s.hydraulic.pressure_b)[j];
        // The actuator answers the whole command, the PD's reaction to the motion included;
        // the holding torque is taken out of both (a constant adds nothing at ω over whole
        // periods, but its rounding would swamp a small sine's).
        window.push(t, &[command[j] - hold_torque[j]], &[torque - hold_torque[j]], &[s.qd[j]]);
        plant.advance(dt, substeps, &command)?;
    }
    Ok(window.responses(omega, dt)[0])
}

/// What [`measure`] costs on `scenario` for an arm of `joints` joints: per amplitude and
/// frequency, the actuators locked and each joint held (nothing where they are not hydraulic).
pub fn cost(scenario: &Scenario, joints: usize) -> Cost {
    if scenario.plant.actuator != ActuatorKind::Hydraulic {
        return Cost::NONE;
    }
    let dt = scenario.controller.dt_s;
    let per_frequency: Cost = FREQUENCIES_HZ
        .iter()
        .map(|&f| {
            let mut s = clean(scenario);
            s.duration_s = (Window::<1>::new(f).to / dt).ceil() * dt;
            Cost::open_loop(1, s.duration_s, dt / LOCKED_SUBSTEPS as f64) + Cost::of_runs(&s, joints, 0)
        })
        .sum();
    (0..AMPLITUDES_NM.len()).map(|_| per_frequency).sum()
}

/// Measures every joint of `scenario` (hydraulic actuators; `None` otherwise) on `robot` and
/// fits each joint's model to its locked response at the smallest amplitude.
pub fn measure<const N: usize>(
    robot: &crate::robot::Robot<N>,
    scenario: &Scenario,
) -> Result<Option<TorqueResponses>, SimError> {
    if scenario.plant.actuator != ActuatorKind::Hydraulic {
        return Ok(None);
    }
    let scenario = clean(scenario);
    let joints = Setup::<N>::of(&scenario)?;
    let q0 = joints.initial_position;
    let gains = crate::run::gains(robot.nominal.as_ref(), &joints)?;
    let kp: [f64; N] = core::array::from_fn(|i| gains.kp()[(i, i)]);
    let kd: [f64; N] = core::array::from_fn(|i| gains.kd()[(i, i)]);
    let dt = joints.timing.dt_s;
    let (plant, _) = scenario_plant(&robot.model, &joints, q0, robot.nominal.gravity(&q0))?;
    let Actuators::Hydraulic(actuators) = plant.actuators().clone() else { return Ok(None) };
    let polar = |a: Complex<f64>| (a.norm(), a.arg().to_degrees());
    let mut responses = Vec::new();
    for amplitude in AMPLITUDES_NM {
        let per_frequency: Vec<[Complex<f64>; N]> = FREQUENCIES_HZ
            .iter()
            .map(|&f| locked(&actuators, (q0, robot.nominal.gravity(&q0)), (f, amplitude), dt))
            .collect();
        for j in 0..N {
            let gain_phase = per_frequency.iter().map(|a| polar(a[j])).collect();
            responses.push(Response {
                mounting: Mounting::Locked,
                amplitude_nm: amplitude,
                joint: j + 1,
                gain_phase,
                back_drive: Vec::new(),
            });
        }
    }
    let jobs: Vec<(f64, usize, f64)> =
        AMPLITUDES_NM.iter().flat_map(|&a| (0..N).flat_map(move |j| FREQUENCIES_HZ.map(|f| (a, j, f)))).collect();
    let measured = parallel_map(&jobs, |&(a, j, f)| held(robot, &joints, (&kp, &kd), q0, (j, f, a)));
    let mut measured = measured.into_iter();
    for amplitude in AMPLITUDES_NM {
        for j in 0..N {
            let held = measured.by_ref().take(FREQUENCIES_HZ.len()).collect::<Result<Vec<_>, _>>()?;
            let locked =
                find(&responses, Mounting::Locked, amplitude, j + 1).map(Response::complex).unwrap_or_default();
            // B = (A_locked τ_cmd − τ_act) / q̇ = (A_locked − A_held) / (q̇ / τ_cmd).
            let back_drive = held.iter().zip(&locked).map(|((a, v), l)| polar((l - a) / v)).collect();
            responses.push(Response {
                mounting: Mounting::Held,
                amplitude_nm: amplitude,
                joint: j + 1,
                gain_phase: held.iter().map(|(a, _)| polar(*a)).collect(),
                back_drive,
            });
        }
    }
    let fits = responses
        .iter()
        .filter(|r| r.mounting == Mounting::Locked && r.amplitude_nm == AMPLITUDES_NM[0])
        .map(|r| {
            let points: Vec<(f64, Complex<f64>)> =
                FREQUENCIES_HZ.iter().map(|f| std::f64::consts::TAU * f).zip(r.complex()).collect();
            ActuatorFit { joint: r.joint, ..fit(&points) }
        })
        .collect();
    Ok(Some(TorqueResponses { frequencies_hz: FREQUENCIES_HZ.to_vec(), responses, fits }))
}

/// The dead times tried, s: 0 to 5 ms by 0.05 ms.
const DELAYS_S: (f64, usize) = (5e-5, 100);

/// The damping ratios tried: 0.05 to 2, evenly in `ln ζ`.
const DAMPINGS: (f64, f64, usize) = (0.05, 2.0, 60);

/// The natural frequencies searched, rad/s: `2π` × 2 Hz to 2 kHz.
const NATURAL_RAD_S: (f64, f64) = (std::f64::consts::TAU * 2.0, std::f64::consts::TAU * 2e3);

/// The second-order loop with dead time nearest `points` (`(ω, A)`) in the least-squares sense,
/// `min Σ |A − ω_n² e^{−jωT}/(−ω² + 2jζω_n ω + ω_n²)|²`: for every dead time and damping of a
/// grid, a golden-section search of `ln ω_n`; the best triple. The joint is left 0.
pub fn fit(points: &[(f64, Complex<f64>)]) -> ActuatorFit {
    let model =
        |natural_rad_s: f64, damping: f64, delay_s: f64| ActuatorModel::SecondOrder { natural_rad_s, damping, delay_s };
    let cost = |m: ActuatorModel| points.iter().map(|&(w, a)| (a - m.response(w)).norm_sqr()).sum::<f64>();
    let golden = (5f64.sqrt() - 1.0) / 2.0;
    let mut best =
        ActuatorFit { joint: 0, natural_rad_s: f64::NAN, damping: f64::NAN, delay_s: 0.0, residual: f64::INFINITY };
    let ln_damping = (DAMPINGS.0.ln(), DAMPINGS.1.ln());
    for k in 0..=DELAYS_S.1 {
        let delay = k as f64 * DELAYS_S.0;
        for i in 0..DAMPINGS.2 {
            let damping = (ln_damping.0 + (ln_damping.1 - ln_damping.0) * i as f64 / (DAMPINGS.2 - 1) as f64).exp();
            let (mut lo, mut hi) = (NATURAL_RAD_S.0.ln(), NATURAL_RAD_S.1.ln());
            for _ in 0..60 {
                let (a, b) = (hi - golden * (hi - lo), lo + golden * (hi - lo));
                if cost(model(a.exp(), damping, delay)) < cost(model(b.exp(), damping, delay)) {
                    hi = b;
                } else {
                    lo = a;
                }
            }
            let natural = (0.5 * (lo + hi)).exp();
            let c = cost(model(natural, damping, delay));
            if c < best.residual {
                best = ActuatorFit { joint: 0, natural_rad_s: natural, damping, delay_s: delay, residual: c };
            }
        }
    }
    best.residual = (best.residual / points.len().max(1) as f64).sqrt();
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_fit_finds_the_loop_it_was_given() {
        // A damping ratio and a dead time on the fit's grids: ζ = 0.05 (40/59)-th of the way
        // in ln ζ to 2, T = 1.2 ms.
        let damping = (0.05f64.ln() + (2.0f64.ln() - 0.05f64.ln()) * 40.0 / 59.0).exp();
        let given =
            ActuatorModel::SecondOrder { natural_rad_s: std::f64::consts::TAU * 65.0, damping, delay_s: 1.2e-3 };
        let points: Vec<(f64, Complex<f64>)> =
            FREQUENCIES_HZ.iter().map(|f| std::f64::consts::TAU * f).map(|w| (w, given.response(w))).collect();
        let found = fit(&points);
        let ActuatorModel::SecondOrder { natural_rad_s, damping: z, delay_s } = found.model() else {
            panic!("a second-order fit")
        };
        assert!((natural_rad_s / (std::f64::consts::TAU * 65.0) - 1.0).abs() < 1e-4, "{found:?}");
        assert!((z / damping - 1.0).abs() < 1e-9 && (delay_s - 1.2e-3).abs() < 1e-9, "{found:?}");
        assert!(found.residual < 1e-6, "{found:?}");
    }

    #[test]
    fn the_hold_is_a_half_period_delay_at_low_frequency() {
        // Z(jω) ≈ e^{−jωT/2}: unit gain, phase −ωT/2.
        let (omega, t) = (2.0, 1e-3);
        let z = hold(omega, t);
        assert!((z.norm() - 1.0).abs() < 1e-6 && (z.arg() + omega * t / 2.0).abs() < 1e-9, "{z}");
    }

    #[test]
    fn a_locked_actuator_with_integral_action_passes_slow_commands_whole() {
        let robot = crate::robot::Robot::<6>::load("hya").unwrap_or_else(|e| panic!("{e}"));
        let scenario = clean(&Scenario::builtin("goto_internal").unwrap_or_else(|e| panic!("{e}")));
        let joints = Setup::<6>::of(&scenario).unwrap_or_else(|e| panic!("{e}"));
        let (q0, tau0) = (joints.initial_position, robot.nominal.gravity(&joints.initial_position));
        let (plant, _) = scenario_plant(&robot.model, &joints, q0, tau0).unwrap_or_else(|e| panic!("{e}"));
        let Actuators::Hydraulic(actuators) = plant.actuators().clone() else {
            panic!("HyA's actuators are hydraulic")
        };
        for a in locked(&actuators, (q0, tau0), (1.0, 0.2), 1e-3) {
            // The PI loop's integral makes the DC gain one.
            assert!((a.norm() - 1.0).abs() < 0.05 && a.arg().abs() < 0.2, "A(1 Hz) = {a}");
        }
    }
}
