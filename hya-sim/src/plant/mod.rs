//! The simulated arm: true rigid-body dynamics with perturbed parameters, joint friction, a
//! first-order hydraulic torque loop per joint and external loads, integrated with classic RK4.
//!
//! ```text
//! M_true(q) q̈ + C_true + G_true = τ_act + τ_friction(q, q̇) + τ_ext(t, q)
//! τ̇_act = (τ_cmd − τ_act) / T_i
//! τ_friction,i = −[(F_c + (F_s − F_c) e^{−(q̇/v_s)²}) (1 + a sin 2q) tanh(q̇/ε) + F_v q̇]
//! ```

use hya_core::model::TreeModel;
use hya_core::spatial::RigidBodyInertia;
use hya_core::{Dynamics, JointVector};
use nalgebra::Vector3;
use rand::Rng;

use crate::scenario::{LoadConfig, PlantConfig, WeightDrop};
use crate::SimError;

/// Per-joint friction: Coulomb and static levels with a Stribeck transition, viscous damping and
/// a smooth sign; the Coulomb and static levels vary with position.
#[derive(Debug, Clone)]
pub struct Friction<const N: usize> {
    coulomb: JointVector<N>,
    breakaway: JointVector<N>,
    viscous: JointVector<N>,
    stribeck_velocity: f64,
    smoothing: f64,
    position_variation: f64,
}

impl<const N: usize> Friction<N> {
    /// From the plant configuration.
    pub fn new(config: &PlantConfig) -> Result<Self, SimError> {
        Ok(Self {
            coulomb: per_joint("plant.coulomb_nm", &config.coulomb_nm)?,
            breakaway: per_joint("plant.static_nm", &config.static_nm)?,
            viscous: per_joint("plant.viscous_nm_s", &config.viscous_nm_s)?,
            stribeck_velocity: config.stribeck_velocity_rad_s,
            smoothing: config.smoothing_rad_s,
            position_variation: config.coulomb_position_variation,
        })
    }

    /// The friction torque on each joint, N·m (opposes motion).
    pub fn torque(&self, q: &JointVector<N>, qd: &JointVector<N>) -> JointVector<N> {
        JointVector::from_fn(|i, _| {
            let v = qd[i];
            let stribeck = (-(v / self.stribeck_velocity).powi(2)).exp();
            let level = (self.coulomb[i] + (self.breakaway[i] - self.coulomb[i]) * stribeck)
                * (1.0 + self.position_variation * (2.0 * q[i]).sin());
            -(level * (v / self.smoothing).tanh() + self.viscous[i] * v)
        })
    }
}

/// A per-joint list from the configuration, checked for length and finiteness.
pub fn per_joint<const N: usize>(name: &str, values: &[f64]) -> Result<JointVector<N>, SimError> {
    if values.len() != N {
        return Err(SimError::Config(format!("{name}: expected {N} values (one per joint), got {}", values.len())));
    }
    if let Some(v) = values.iter().find(|v| !v.is_finite()) {
        return Err(SimError::Config(format!("{name}: {v} is not a finite number")));
    }
    Ok(JointVector::from_column_slice(values))
}

/// The nominal model with every body's mass, centre of mass and rotational inertia scaled by
/// independent uniform factors in `[1 − spread, 1 + spread]`.
pub fn perturbed(model: &TreeModel, spread: f64, rng: &mut impl Rng) -> TreeModel {
    let factor = |rng: &mut dyn rand::RngCore| 1.0 + spread * (2.0 * rng.gen::<f64>() - 1.0);
    model.map_inertias(|_, inertia| {
        let Some((mass, com, about_com)) = inertia.centre_of_mass_form() else { return *inertia };
        let mass = mass * factor(rng);
        let com = Vector3::new(com.x * factor(rng), com.y * factor(rng), com.z * factor(rng));
        RigidBodyInertia::from_centre_of_mass(mass, com, about_com * factor(rng))
    })
}

/// Builds the plant's true rigid-body dynamics from a model (perturbed, or carrying a payload).
pub type DynamicsFactory<const N: usize> = dyn Fn(&TreeModel) -> Result<Box<dyn Dynamics<N>>, SimError>;

/// The generic tree model as the plant's dynamics: works for any robot.
pub fn generic_dynamics<const N: usize>(model: &TreeModel) -> Result<Box<dyn Dynamics<N>>, SimError> {
    Ok(Box::new(model.clone().into_dynamics::<N>().map_err(|e| SimError::Config(e.to_string()))?))
}

/// The arm's state: joint positions and velocities, and the actuators' torques.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlantState<const N: usize> {
    /// Joint positions, rad.
    pub q: JointVector<N>,
    /// Joint velocities, rad/s.
    pub qd: JointVector<N>,
    /// Actuator torques, N·m.
    pub tau_act: JointVector<N>,
}

/// The simulated arm.
pub struct Plant<const N: usize> {
    model: TreeModel,
    unloaded: Box<dyn Dynamics<N>>,
    loaded: Option<(Box<dyn Dynamics<N>>, WeightDrop)>,
    friction: Option<Friction<N>>,
    actuator_time_constant: JointVector<N>,
    sinusoid: Option<(JointVector<N>, f64)>,
    /// The current state.
    pub state: PlantState<N>,
    /// The current time, s.
    pub time: f64,
}

impl<const N: usize> Plant<N> {
    /// An arm at rest at `q0` whose actuators already hold `tau0`; `dynamics` builds its rigid
    /// body from `true_model` (and from the model with the payload).
    pub fn new(
        true_model: TreeModel,
        dynamics: &DynamicsFactory<N>,
        config: &PlantConfig,
        loads: &LoadConfig,
        q0: JointVector<N>,
        tau0: JointVector<N>,
    ) -> Result<Self, SimError> {
        let loaded = match &loads.weight_drop {
            Some(drop) => {
                let with_payload = true_model
                    .with_point_mass(&drop.frame, drop.mass_kg)
                    .map_err(|e| SimError::Config(format!("loads.weight_drop: {e}")))?;
                Some((dynamics(&with_payload)?, drop.clone()))
            }
            None => None,
        };
        let sinusoid = match &loads.sinusoid {
            Some(s) => Some((per_joint("loads.sinusoid.amplitude_nm", &s.amplitude_nm)?, s.frequency_hz)),
            None => None,
        };
        let actuator_time_constant: JointVector<N> =
            per_joint("plant.actuator_time_constant_s", &config.actuator_time_constant_s)?;
        if actuator_time_constant.iter().any(|t| *t <= 0.0) {
            return Err(SimError::Config("plant.actuator_time_constant_s: every entry must be > 0".into()));
        }
        Ok(Self {
            unloaded: dynamics(&true_model)?,
            model: true_model,
            loaded,
            friction: if config.friction { Some(Friction::new(config)?) } else { None },
            actuator_time_constant,
            sinusoid,
            state: PlantState { q: q0, qd: JointVector::zeros(), tau_act: tau0 },
            time: 0.0,
        })
    }

    /// The true dynamics at time `t`: with the payload while it rests on the arm.
    pub fn dynamics(&self, t: f64) -> &dyn Dynamics<N> {
        match &self.loaded {
            Some((loaded, drop)) if t >= drop.drop_s && t < drop.remove_s => loaded.as_ref(),
            _ => self.unloaded.as_ref(),
        }
    }

    /// External joint torques at `t`: the sinusoid, and the weight's impact pulse.
    pub fn external_torque(&self, t: f64, q: &JointVector<N>) -> JointVector<N> {
        let mut tau = JointVector::zeros();
        if let Some((amplitude, frequency)) = &self.sinusoid {
            tau += JointVector::from_fn(|i, _| {
                amplitude[i]
                    * (2.0 * std::f64::consts::PI * frequency * t + i as f64 * std::f64::consts::PI / 3.0).sin()
            });
        }
        if let Some((_, drop)) = &self.loaded {
            if t >= drop.drop_s && t < drop.drop_s + drop.impact_s {
                // Momentum m √(2 g h), delivered downward as a constant force over the pulse.
                let force = drop.mass_kg * (2.0 * 9.81 * drop.fall_height_m).sqrt() / drop.impact_s;
                if let Ok(jacobian) = self.model.frame_jacobian(&drop.frame, q.as_slice()) {
                    tau -= JointVector::from_fn(|i, _| jacobian[(2, i)] * force);
                }
            }
        }
        tau
    }

    /// Everything acting on the joints besides the actuators: friction and external loads.
    pub fn passive_torque(&self, t: f64, q: &JointVector<N>, qd: &JointVector<N>) -> JointVector<N> {
        let friction = self.friction.as_ref().map_or(JointVector::zeros(), |f| f.torque(q, qd));
        friction + self.external_torque(t, q)
    }

    /// The true joint accelerations in state `s` at time `t`.
    pub fn acceleration(&self, t: f64, s: &PlantState<N>) -> Result<JointVector<N>, SimError> {
        let total = s.tau_act + self.passive_torque(t, &s.q, &s.qd);
        self.dynamics(t).forward_dynamics(&s.q, &s.qd, &total).map_err(|e| SimError::Numerical(e.to_string()))
    }

    fn derivative(&self, t: f64, s: &PlantState<N>, tau_cmd: &JointVector<N>) -> Result<PlantState<N>, SimError> {
        Ok(PlantState {
            q: s.qd,
            qd: self.acceleration(t, s)?,
            tau_act: (tau_cmd - s.tau_act).component_div(&self.actuator_time_constant),
        })
    }

    /// One classic RK4 step of length `h` with the command `τ_cmd` held.
    pub fn step(&mut self, h: f64, tau_cmd: &JointVector<N>) -> Result<(), SimError> {
        let (t, s) = (self.time, self.state);
        let along = |k: &PlantState<N>, a: f64| PlantState {
            q: s.q + k.q * a,
            qd: s.qd + k.qd * a,
            tau_act: s.tau_act + k.tau_act * a,
        };
        let k1 = self.derivative(t, &s, tau_cmd)?;
        let k2 = self.derivative(t + h / 2.0, &along(&k1, h / 2.0), tau_cmd)?;
        let k3 = self.derivative(t + h / 2.0, &along(&k2, h / 2.0), tau_cmd)?;
        let k4 = self.derivative(t + h, &along(&k3, h), tau_cmd)?;
        let sum = |f: fn(&PlantState<N>) -> JointVector<N>| (f(&k1) + f(&k2) * 2.0 + f(&k3) * 2.0 + f(&k4)) * (h / 6.0);
        self.state =
            PlantState { q: s.q + sum(|k| k.q), qd: s.qd + sum(|k| k.qd), tau_act: s.tau_act + sum(|k| k.tau_act) };
        self.time += h;
        if !(self.state.q.iter().chain(self.state.qd.iter()).all(|v| v.is_finite())) {
            return Err(SimError::Numerical(format!("the plant's state became non-finite at t = {:.4} s", self.time)));
        }
        Ok(())
    }
}
