//! A stand-in for your robot's drivers: a simulated arm behind `read_joint_positions()`,
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
//! smoothed over `v_s` so that the integrator need not resolve a discontinuity). Inverse dynamics
//! is linear in the inertial parameters, so the plant's accelerations are the model's forward
//! dynamics at a scaled torque: `q̈ = FD(q, q̇, (τ − f(q̇)) / s)`. The state is integrated with
//! classic Runge–Kutta (RK4) at `SUBSTEPS` steps per tick, the torque held over the tick.

use hya_core::{Dynamics, Error, JointVector};

/// How much heavier the simulated arm is than its URDF (1.25: 25 % heavier).
pub const MASS_SCALE: f64 = 1.25;
/// Viscous friction `b_i`, N·m·s/rad.
pub const VISCOUS: [f64; 3] = [0.4, 0.6, 0.3];
/// Coulomb friction `F_c,i`, N·m.
pub const COULOMB: [f64; 3] = [1.0, 1.5, 0.8];
/// Velocity over which the Coulomb term changes sign, rad/s.
pub const STRIBECK_VELOCITY: f64 = 0.05;
/// Integration steps per control tick.
pub const SUBSTEPS: usize = 10;

/// A three-joint arm integrated in time; `D` is the dynamics of its URDF.
pub struct SimulatedArm<D> {
    dynamics: D,
    dt: f64,
    q: JointVector<3>,
    qd: JointVector<3>,
    tau: JointVector<3>,
}

impl<D: Dynamics<3>> SimulatedArm<D> {
    /// At rest at `q0`, holding `tau0`, ticking every `dt` seconds.
    pub fn new(dynamics: D, dt: f64, q0: JointVector<3>, tau0: JointVector<3>) -> Self {
        Self { dynamics, dt, q: q0, qd: JointVector::zeros(), tau: tau0 }
    }

    /// Joint angles, rad. On a real arm: the encoders.
    pub fn read_joint_positions(&self) -> JointVector<3> {
        self.q
    }

    /// Joint velocities, rad/s. On a real arm: the drives' velocity estimate.
    pub fn read_joint_velocities(&self) -> JointVector<3> {
        self.qd
    }

    /// Joint torques, N·m. On a real arm: torque sensors, or the last command without them.
    pub fn read_joint_torques(&self) -> JointVector<3> {
        self.tau
    }

    /// Sends a torque command, held until the next one, and lets one tick pass.
    pub fn write_joint_torques(&mut self, tau: &JointVector<3>) -> Result<(), Error> {
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
    pub fn true_disturbance(&self) -> Result<JointVector<3>, Error> {
        let qdd = self.acceleration(&self.q, &self.qd)?;
        Ok(self.dynamics.inverse_dynamics(&self.q, &self.qd, &qdd) - self.tau)
    }

    /// The plant's `q̈ = FD(q, q̇, (τ − f(q̇)) / s)`.
    fn acceleration(&self, q: &JointVector<3>, qd: &JointVector<3>) -> Result<JointVector<3>, Error> {
        let friction =
            JointVector::from_fn(|i, _| VISCOUS[i] * qd[i] + COULOMB[i] * (qd[i] / STRIBECK_VELOCITY).tanh());
        self.dynamics.forward_dynamics(q, qd, &((self.tau - friction) / MASS_SCALE))
    }
}
