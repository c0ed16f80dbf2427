//! A stand-in for your robot's drivers: a simulated arm of any URDF behind `read_joint_positions()`,
//! `read_joint_velocities()`, `read_joint_torques()` and `write_joint_torques()`.
//!
//! Replace this module with calls to your robot's interface; the control loop in `main.rs` stays
//! as it is. The simulated arm differs from the URDF the controller uses, as a real one would:
//!
//! ```text
//! plant:  s M(q) q̈ + s (C(q, q̇) + G(q)) = τ − f(q̇),   f_i(q̇) = b_i q̇_i + F_c,i tanh(q̇_i / v_s)
//! model:    M(q) q̈ +    C(q, q̇) + G(q)  = τ + d       (so the lumped disturbance is
//!                                                        d = ID(q, q̇, q̈) − τ, hya's definition)
//! ```
//!
//! `s = MASS_SCALE`: every mass and inertia is that much larger than the URDF says (an
//! unmodelled payload and model error); `f` is viscous and Coulomb friction (the Coulomb term
//! smoothed over `v_s = STRIBECK_VELOCITY` so that the integrator need not resolve a
//! discontinuity). Inverse dynamics
//! is linear in the inertial parameters, so the plant's accelerations are the model's forward
//! dynamics at a scaled torque: `q̈ = FD(q, q̇, (τ − f(q̇)) / s)`. The state is integrated with
//! classic Runge–Kutta (RK4) at `SUBSTEPS` steps per tick, the torque held over the tick.

use hya_core::{Dynamics, Error, JointVector};

/// How much heavier the simulated arm is than its URDF (1.25: 25 % heavier).
pub const MASS_SCALE: f64 = 1.25;
/// Velocity over which the Coulomb term changes sign, rad/s.
pub const STRIBECK_VELOCITY: f64 = 0.05;
/// Integration steps per control tick.
pub const SUBSTEPS: usize = 10;

/// Joint friction: viscous `b_i` (N·m·s/rad) and Coulomb `F_c,i` (N·m) per joint.
#[derive(Debug, Clone, Copy)]
pub struct Friction<const N: usize> {
    /// `b_i`, N·m·s/rad.
    pub viscous: [f64; N],
    /// `F_c,i`, N·m.
    pub coulomb: [f64; N],
}

/// An arm of `N` joints integrated in time; `D` is the dynamics of its URDF.
pub struct SimulatedArm<const N: usize, D> {
    dynamics: D,
    friction: Friction<N>,
    dt: f64,
    q: JointVector<N>,
    qd: JointVector<N>,
    tau: JointVector<N>,
}

impl<const N: usize, D: Dynamics<N>> SimulatedArm<N, D> {
    /// At rest at `q0`, holding the model's gravity torque there, ticking every `dt` seconds.
    pub fn new(dynamics: D, friction: Friction<N>, dt: f64, q0: JointVector<N>) -> Self {
        let tau = dynamics.gravity(&q0);
        Self { dynamics, friction, dt, q: q0, qd: JointVector::zeros(), tau }
    }

    /// Joint angles, rad. On a real arm: the encoders.
    pub fn read_joint_positions(&self) -> JointVector<N> {
        self.q
    }

    /// Joint velocities, rad/s. On a real arm: the drives' velocity estimate.
    pub fn read_joint_velocities(&self) -> JointVector<N> {
        self.qd
    }

    /// Joint torques, N·m. On a real arm: torque sensors, or the last command without them.
    pub fn read_joint_torques(&self) -> JointVector<N> {
        self.tau
    }

    /// Sends a torque command, held until the next one, and lets one tick pass.
    pub fn write_joint_torques(&mut self, tau: &JointVector<N>) -> Result<(), Error> {
        self.tau = *tau;
        let h = self.dt / SUBSTEPS as f64;
        for _ in 0..SUBSTEPS {
            let (q, qd) = (self.q, self.qd);
            let k1 = self.acceleration(&q, &qd)?;
            let k2 = self.acceleration(&(q + qd * (h / 2.0)), &(qd + k1 * (h / 2.0)))?;
            let k3 = self.acceleration(&(q + (qd + k1 * (h / 2.0)) * (h / 2.0)), &(qd + k2 * (h / 2.0)))?;
            let k4 = self.acceleration(&(q + (qd + k2 * (h / 2.0)) * h), &(qd + k3 * h))?;
            self.q += (qd + (k1 + k2 + k3) * (h / 6.0)) * h;
            self.qd += (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (h / 6.0);
        }
        Ok(())
    }

    /// The lumped disturbance `d = ID(q, q̇, q̈) − τ` acting now, in the URDF's model, N·m: what
    /// the estimator's `d̂` should follow. Only a simulation knows it.
    pub fn true_disturbance(&self) -> Result<JointVector<N>, Error> {
        let qdd = self.acceleration(&self.q, &self.qd)?;
        Ok(self.dynamics.inverse_dynamics(&self.q, &self.qd, &qdd) - self.tau)
    }

    /// The plant's `q̈ = FD(q, q̇, (τ − f(q̇)) / s)`.
    fn acceleration(&self, q: &JointVector<N>, qd: &JointVector<N>) -> Result<JointVector<N>, Error> {
        let Friction { viscous, coulomb } = &self.friction;
        let friction =
            JointVector::from_fn(|i, _| viscous[i] * qd[i] + coulomb[i] * (qd[i] / STRIBECK_VELOCITY).tanh());
        self.dynamics.forward_dynamics(q, qd, &((self.tau - friction) / MASS_SCALE))
    }
}
