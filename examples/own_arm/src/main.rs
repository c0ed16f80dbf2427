//! Your own arm with hya: dynamics generated from `urdf/own_arm.urdf` by `robot!`, the paper's
//! disturbance estimator and computed-torque control in a 1 kHz loop.
//!
//! ```text
//! d̂ = ID(q̂, q̂̇, q̂̈) − τ̂                              (estimator: filtered angles and torques)
//! τ = M(q) q̈_des + C(q, q̇) + G(q) − K_D ė − K_P e − d̂   (controller, e = q − q_des)
//! ```
//!
//! The loop runs twice on a simulated arm that is heavier than its URDF and has joint friction
//! (`simulated_arm.rs`): once without `d̂`, once with it, and prints the RMS tracking error per
//! joint of each run, and how closely `d̂` followed the disturbance. The lines marked `◀ robot`
//! are where a real arm's measurements are read and its commands written.

mod simulated_arm;

use hya_core::{ComputedTorque, DisturbanceEstimator, Error, FilterParams, Gains, JointVector, Reference};
use simulated_arm::{Friction, SimulatedArm};

hya_macros::robot!(OwnArm, "urdf/own_arm.urdf");

/// The arm's joint count, from its URDF: every per-joint list below has this many entries.
const N: usize = OwnArm::DOF;
/// Control period, s (1 kHz).
const DT: f64 = 0.001;
/// Length of each run, s.
const SECONDS: f64 = 5.0;
/// Where the arm starts and about which it moves, rad.
const HOME: [f64; N] = [0.0, -0.6, 1.2];
/// Amplitude of each joint's motion, rad.
const AMPLITUDE: [f64; N] = [0.8, 0.6, 0.8];
/// Frequency of each joint's motion, Hz.
const FREQUENCY: [f64; N] = [0.3, 0.5, 0.4];
/// `K_P` (N·m/rad) per joint.
const KP: [f64; N] = [300.0, 300.0, 80.0];
/// `K_D` (N·m·s/rad) per joint.
const KD: [f64; N] = [30.0, 30.0, 8.0];
/// The simulated arm's joint friction, which the URDF does not know.
const FRICTION: Friction<N> = Friction { viscous: [0.4, 0.6, 0.3], coulomb: [1.0, 1.5, 0.8] };

fn main() -> Result<(), Error> {
    println!("own_arm: joints {}; {SECONDS} s at {} Hz", OwnArm::JOINT_NAMES.join(", "), 1.0 / DT);
    let without = track(false)?;
    let with = track(true)?;
    println!("without compensation: tracking RMS (mrad) {}", row(&(without.of(&without.tracking) * 1e3)));
    println!("with compensation:    tracking RMS (mrad) {}", row(&(with.of(&with.tracking) * 1e3)));
    println!("disturbance d, with compensation: RMS (N·m) {}", row(&with.of(&with.disturbance)));
    println!("estimate error d̂ − d, with compensation: RMS (N·m) {}", row(&with.of(&with.estimate_error)));
    Ok(())
}

/// One run of the control loop, with or without the estimate `d̂` in the command.
fn track(compensate: bool) -> Result<Rms, Error> {
    let mut arm = SimulatedArm::new(OwnArm, FRICTION, DT, HOME.into()); // ◀ robot: connect
    let limits = OwnArm::EFFORT_LIMITS.map(|limit| limit.unwrap_or(0.0)).into();
    let gains = Gains::diagonal(KP, KD)?;
    let controller = ComputedTorque::new(OwnArm, gains).with_torque_limit(limits)?;
    let (q_m, tau_m) = (arm.read_joint_positions(), arm.read_joint_torques());
    let mut estimator = DisturbanceEstimator::new(OwnArm, FilterParams::paper(DT)?, q_m, tau_m)?;
    let mut rms = Rms::default();
    for k in 0..(SECONDS / DT).round() as usize {
        let q = arm.read_joint_positions(); // ◀ robot: encoders, rad
        let qd = arm.read_joint_velocities(); // ◀ robot: joint velocities, rad/s
        let d_hat = estimator.update(&q, &arm.read_joint_torques())?; // ◀ robot: torques, N·m
        let reference = reference_at(k as f64 * DT);
        let tau = controller.command(&q, &qd, &reference, compensate.then_some(&d_hat))?.torque;
        rms.add(&(q - reference.position), &d_hat, &arm.true_disturbance()?); // simulation only
        arm.write_joint_torques(&tau)?; // ◀ robot: torque commands, N·m
    }
    Ok(rms)
}

/// `q_des = HOME + A (1 − cos ωt) / 2` per joint, starting at rest at `HOME`, with its
/// derivatives `q̇_des = A ω sin(ωt) / 2` and `q̈_des = A ω² cos(ωt) / 2`.
fn reference_at(t: f64) -> Reference<N> {
    let omega = |i: usize| 2.0 * std::f64::consts::PI * FREQUENCY[i];
    Reference {
        position: JointVector::from_fn(|i, _| HOME[i] + AMPLITUDE[i] * (1.0 - (omega(i) * t).cos()) / 2.0),
        velocity: JointVector::from_fn(|i, _| AMPLITUDE[i] * omega(i) * (omega(i) * t).sin() / 2.0),
        acceleration: JointVector::from_fn(|i, _| AMPLITUDE[i] * omega(i).powi(2) * (omega(i) * t).cos() / 2.0),
    }
}

/// Sums of squares per joint over a run: tracking error `e`, disturbance `d`, `d̂ − d`.
#[derive(Default)]
struct Rms {
    ticks: usize,
    tracking: JointVector<N>,
    disturbance: JointVector<N>,
    estimate_error: JointVector<N>,
}

impl Rms {
    /// Adds one tick's squares.
    fn add(&mut self, error: &JointVector<N>, d_hat: &JointVector<N>, d: &JointVector<N>) {
        self.tracking += error.component_mul(error);
        self.disturbance += d.component_mul(d);
        self.estimate_error += (d_hat - d).component_mul(&(d_hat - d));
        self.ticks += 1;
    }

    /// `√(Σ x² / ticks)` per joint of one of the sums.
    fn of(&self, sum: &JointVector<N>) -> JointVector<N> {
        (sum / self.ticks.max(1) as f64).map(f64::sqrt)
    }
}

/// A vector as space-separated numbers with four decimals.
fn row(values: &JointVector<N>) -> String {
    values.iter().map(|v| format!("{v:.4}")).collect::<Vec<_>>().join(" ")
}
