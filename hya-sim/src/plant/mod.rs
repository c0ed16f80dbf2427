//! The simulated arm: true rigid-body dynamics with perturbed parameters, joint friction (LuGre
//! by default), hydraulic actuators (by default) and external loads, integrated with classic RK4
//! at a fixed sub-step.
//!
//! ```text
//! M_true(q) q̈ + C_true + G_true = τ_act + τ_f + τ_ext(t, q)
//! ```
//!
//! `τ_act` comes from the actuator model: hydraulic ([`hydraulic`]: valve, chamber pressures,
//! a sampled inner torque loop), a first-order lag `τ̇_act = (τ_cmd − τ_act) / T` (the first
//! testbed's), or ideal (`τ_act = τ_cmd`). `τ_f` is LuGre or the smooth model ([`friction`]).
//!
//! The hydraulic inner loop is discrete: at each of its sample instants, `T_s` apart, the plant runs
//! it once ([`HydraulicActuators::sample`]) and RK4 then integrates with its valve command held;
//! a step that spans a sample instant is split there, so the loop samples exactly on time
//! whatever the physics step.

pub mod friction;
pub mod hydraulic;
pub mod lockstep;

pub use friction::Friction;
pub use hydraulic::{HydraulicActuators, HydraulicState};

use hya_core::bodies_batch::{body_columns, BODY_PARAMETERS};
use hya_core::model::TreeModel;
use hya_core::spatial::RigidBodyInertia;
use hya_core::{Dynamics, JointVector};
use nalgebra::Vector3;
use rand::Rng;

use crate::config::plant::{ActuatorSetup, PlantSetup};
use crate::config::scenario::WeightDrop;
use crate::error::SimError;

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

pub use crate::robot::DynamicsFactory;

/// The generic tree model as the plant's dynamics: works for any robot.
pub fn generic_dynamics<const N: usize>(model: &TreeModel) -> Result<Box<dyn Dynamics<N>>, SimError> {
    Ok(Box::new(model.clone().into_dynamics::<N>()?))
}

/// A joint speed no arm reaches, rad/s (HyA's joints reach 12 rad/s, fast electric arms a few
/// tens): an integration stage beyond it is the simulation running away ([`SimError::Diverged`]),
/// not a property of the model.
pub const MAX_PLAUSIBLE_SPEED_RAD_S: f64 = 100.0;

/// The joint beyond [`MAX_PLAUSIBLE_SPEED_RAD_S`] in `state` (the fastest, a non-finite angle or
/// velocity counting as infinitely fast) and its velocity; `None` if every joint is within it.
fn fastest<const N: usize>(state: &PlantState<N>) -> Option<(usize, f64)> {
    let speed = |j: usize| {
        if state.q[j].is_finite() && state.qd[j].is_finite() {
            state.qd[j].abs()
        } else {
            f64::INFINITY
        }
    };
    let joint = (0..N).max_by(|&a, &b| speed(a).total_cmp(&speed(b)))?;
    let velocity = if state.q[joint].is_finite() { state.qd[joint] } else { f64::NAN };
    (speed(joint) > MAX_PLAUSIBLE_SPEED_RAD_S).then_some((joint, velocity))
}

/// The arm's state: joints, friction bristles and actuators.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlantState<const N: usize> {
    /// Joint positions, rad.
    pub q: JointVector<N>,
    /// Joint velocities, rad/s.
    pub qd: JointVector<N>,
    /// LuGre bristle deflections `z`, rad (zero for the other friction models).
    pub bristle: JointVector<N>,
    /// The lag actuator's torque, N·m (zero for the other actuators).
    pub lag_torque: JointVector<N>,
    /// The hydraulic actuators' state (zero for the other actuators).
    pub hydraulic: HydraulicState<N>,
}

impl<const N: usize> PlantState<N> {
    /// `self + a k`, field by field (one RK4 stage).
    fn along(&self, k: &Self, a: f64) -> Self {
        Self {
            q: self.q + k.q * a,
            qd: self.qd + k.qd * a,
            bristle: self.bristle + k.bristle * a,
            lag_torque: self.lag_torque + k.lag_torque * a,
            hydraulic: self.hydraulic.along(&k.hydraulic, a),
        }
    }

    /// At rest at zero, every field zero.
    pub fn zeros() -> Self {
        let zero = JointVector::zeros();
        Self { q: zero, qd: zero, bristle: zero, lag_torque: zero, hydraulic: HydraulicState::zeros() }
    }

    fn is_finite(&self) -> bool {
        [self.q, self.qd, self.bristle, self.lag_torque].iter().all(|v| v.iter().all(|x| x.is_finite()))
            && self.hydraulic.is_finite()
    }
}

/// Classic RK4's new state from `s` and its four stages over `h`.
fn rk4_sum<const N: usize>(s: &PlantState<N>, [k1, k2, k3, k4]: [&PlantState<N>; 4], h: f64) -> PlantState<N> {
    s.along(k1, h / 6.0).along(k2, h / 3.0).along(k3, h / 3.0).along(k4, h / 6.0)
}

/// The largest `h λ` an RK4 step takes on the plant's stiff modes, the bristles' relaxation and
/// the oil's (RK4 is stable to 2.78 on the negative real axis; 1 keeps it accurate).
pub const MAX_STIFF_STEP: f64 = 1.0;

/// The most RK4 sub-steps one [`Plant::step`] divides into.
pub const MAX_SUBCYCLES: usize = 64;

/// The equal RK4 cycles a step of `h` takes on a stiff mode of rate `rate` (1/s): as many as keep
/// `h_cycle · rate ≤` [`MAX_STIFF_STEP`], at least one and at most [`MAX_SUBCYCLES`].
pub fn cycles_for(h: f64, rate: f64) -> usize {
    ((h * rate / MAX_STIFF_STEP).ceil() as usize).clamp(1, MAX_SUBCYCLES)
}

/// How the commanded torque reaches the joints.
#[derive(Debug, Clone)]
pub enum Actuators<const N: usize> {
    /// `τ_act = τ_cmd`.
    Ideal,
    /// `τ̇_act = (τ_cmd − τ_act) / T`, per joint `T`, s.
    Lag(JointVector<N>),
    /// Servo valves, chambers and inner torque loops.
    Hydraulic(Box<HydraulicActuators<N>>),
}

/// One rigid body's bodies as [`hya_core::BodiesBatch`] reads them, by parameter.
type Bodies<const N: usize> = [JointVector<N>; BODY_PARAMETERS];

/// The bodies of `model`'s `N` joints, by parameter ([`hya_core::bodies_batch`]); an error if
/// it has not `N`.
fn bodies_of<const N: usize>(model: &TreeModel) -> Result<Bodies<N>, SimError> {
    let bodies = model.bodies();
    if bodies.len() != N {
        return Err(SimError::JointCount { robot: model.name().to_owned(), expected: N, found: bodies.len() });
    }
    Ok(body_columns(&core::array::from_fn(|i| bodies[i].inertia.parameters())))
}

/// A rigid body of the arm: its dynamics, and its bodies for the seeds' lockstep ([`lockstep`]).
struct RigidBody<const N: usize> {
    dynamics: Box<dyn Dynamics<N>>,
    bodies: Bodies<N>,
}

impl<const N: usize> RigidBody<N> {
    fn of(model: &TreeModel, dynamics: &DynamicsFactory<N>) -> Result<Self, SimError> {
        Ok(Self { dynamics: dynamics(model)?, bodies: bodies_of(model)? })
    }
}

/// The simulated arm.
pub struct Plant<const N: usize> {
    model: TreeModel,
    unloaded: RigidBody<N>,
    /// The arm with its payload, and when it carries it.
    loaded: Option<(RigidBody<N>, WeightDrop)>,
    friction: Friction<N>,
    actuators: Actuators<N>,
    sinusoid: Option<(JointVector<N>, f64)>,
    gravity: f64,
    /// The current state.
    pub state: PlantState<N>,
    /// The current time, s.
    pub time: f64,
    /// The first whole step at which a joint passed [`MAX_PLAUSIBLE_SPEED_RAD_S`]: the joint,
    /// the time, s, and its velocity, rad/s (for [`SimError::Diverged`]).
    runaway: Option<(usize, f64, f64)>,
}

/// The joint ranges the actuators span: the description's limits, or `q0 ± π` where it gives
/// none.
fn joint_ranges<const N: usize>(model: &TreeModel, q0: &JointVector<N>) -> [(f64, f64); N] {
    core::array::from_fn(|i| {
        let limits = model.bodies().get(i).map(|b| b.limits);
        let lower = limits.and_then(|l| l.lower).unwrap_or(q0[i] - std::f64::consts::PI);
        let upper = limits.and_then(|l| l.upper).unwrap_or(q0[i] + std::f64::consts::PI);
        (lower, upper)
    })
}

impl<const N: usize> Plant<N> {
    /// An arm at rest at `q0` whose actuators already hold `tau0`, built as `setup` says;
    /// `dynamics` builds its rigid body from `true_model` (and from the model with the payload);
    /// `rng` draws the friction's position profiles, then the seed of the hydraulic actuators'
    /// pressure transducers ([`HydraulicActuators::seeded`]).
    pub fn new(
        true_model: TreeModel,
        dynamics: &DynamicsFactory<N>,
        setup: &PlantSetup<N>,
        (q0, tau0): (JointVector<N>, JointVector<N>),
        rng: &mut impl Rng,
    ) -> Result<Self, SimError> {
        let loaded = match &setup.loads.weight_drop {
            Some(drop) => {
                let model = true_model.with_point_mass(&drop.frame, drop.mass_kg)?;
                Some((RigidBody::of(&model, dynamics)?, drop.clone()))
            }
            None => None,
        };
        let sinusoid = setup.loads.sinusoid.map(|s| (s.amplitude, s.frequency_hz));
        let friction = Friction::new(&setup.friction, rng);
        let actuators = match &setup.actuators {
            ActuatorSetup::Ideal => Actuators::Ideal,
            ActuatorSetup::Lag(time_constant) => Actuators::Lag(*time_constant),
            ActuatorSetup::Hydraulic(h) => Actuators::Hydraulic(Box::new(
                HydraulicActuators::new(h, joint_ranges(&true_model, &q0)).seeded(rng.gen()),
            )),
        };
        let hydraulic = match &actuators {
            Actuators::Hydraulic(h) => HydraulicState { loop_angle: h.encoder(&q0), ..h.holding(&tau0) },
            _ => HydraulicState::zeros(),
        };
        let lag_torque = if matches!(actuators, Actuators::Lag(_)) { tau0 } else { JointVector::zeros() };
        let zero = JointVector::zeros();
        Ok(Self {
            unloaded: RigidBody::of(&true_model, dynamics)?,
            gravity: true_model.gravity_vector().norm(),
            model: true_model,
            loaded,
            friction,
            actuators,
            sinusoid,
            state: PlantState { q: q0, qd: zero, bristle: zero, lag_torque, hydraulic },
            time: 0.0,
            runaway: None,
        })
    }

    /// The actuator model.
    pub fn actuators(&self) -> &Actuators<N> {
        &self.actuators
    }

    /// The friction model.
    pub fn friction(&self) -> &Friction<N> {
        &self.friction
    }

    /// The true dynamics at time `t`: with the payload while it rests on the arm.
    pub fn dynamics(&self, t: f64) -> &dyn Dynamics<N> {
        self.rigid_body(t).dynamics.as_ref()
    }

    /// The rigid body at `t`: with the payload while it rests on the arm.
    fn rigid_body(&self, t: f64) -> &RigidBody<N> {
        match &self.loaded {
            Some((loaded, drop)) if Self::carries(drop, t) => loaded,
            _ => &self.unloaded,
        }
    }

    /// Whether the payload `drop` rests on the arm at `t`.
    fn carries(drop: &WeightDrop, t: f64) -> bool {
        t >= drop.drop_s && drop.remove_s.is_none_or(|r| t < r)
    }

    /// The bodies of [`Self::dynamics`] at `t`, by parameter.
    fn bodies(&self, t: f64) -> &Bodies<N> {
        &self.rigid_body(t).bodies
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
                let force = drop.mass_kg * (2.0 * self.gravity * drop.fall_height_m).sqrt() / drop.impact_s;
                if let Ok(jacobian) = self.model.frame_jacobian(&drop.frame, q.as_slice()) {
                    tau -= JointVector::from_fn(|i, _| jacobian[(2, i)] * force);
                }
            }
        }
        tau
    }

    /// The torque the actuators apply in state `s`, N·m.
    pub fn actuator_torque(&self, s: &PlantState<N>, tau_cmd: &JointVector<N>) -> JointVector<N> {
        match &self.actuators {
            Actuators::Ideal => *tau_cmd,
            Actuators::Lag(_) => s.lag_torque,
            Actuators::Hydraulic(h) => h.torque(&s.hydraulic.pressure_a, &s.hydraulic.pressure_b),
        }
    }

    /// The friction torque and the bristle rate `ż` in state `s`.
    fn friction_torque(&self, s: &PlantState<N>) -> (JointVector<N>, JointVector<N>) {
        match &self.friction {
            Friction::Off => (JointVector::zeros(), JointVector::zeros()),
            Friction::Smooth(f) => (f.torque(&s.q, &s.qd), JointVector::zeros()),
            Friction::LuGre(f) => {
                let rate = f.bristle_rate(&s.q, &s.qd, &s.bristle);
                (f.torque(&s.qd, &s.bristle, &rate), rate)
            }
        }
    }

    /// Everything acting on the joints besides the actuators: friction and external loads.
    pub fn passive_torque(&self, t: f64, s: &PlantState<N>) -> JointVector<N> {
        self.friction_torque(s).0 + self.external_torque(t, &s.q)
    }

    /// Every torque on the joints in state `s` at `t` (actuators, friction, loads) and the
    /// bristle rate `ż`: the derivative's part before the rigid body.
    fn joint_torque(&self, t: f64, s: &PlantState<N>, tau_cmd: &JointVector<N>) -> (JointVector<N>, JointVector<N>) {
        let (friction, bristle) = self.friction_torque(s);
        (self.actuator_torque(s, tau_cmd) + friction + self.external_torque(t, &s.q), bristle)
    }

    fn derivative(&self, t: f64, s: &PlantState<N>, tau_cmd: &JointVector<N>) -> Result<PlantState<N>, SimError> {
        let (total, bristle) = self.joint_torque(t, s, tau_cmd);
        let qdd = self
            .dynamics(t)
            .forward_dynamics(&s.q, &s.qd, &total)
            .map_err(|source| SimError::Step { time_s: t, source })?;
        Ok(self.rate(s, tau_cmd, (qdd, bristle)))
    }

    /// The derivative of state `s` given its joint accelerations `q̈` and bristle rate `ż`.
    fn rate(
        &self,
        s: &PlantState<N>,
        tau_cmd: &JointVector<N>,
        (qdd, bristle): (JointVector<N>, JointVector<N>),
    ) -> PlantState<N> {
        let (lag_torque, hydraulic) = match &self.actuators {
            Actuators::Ideal => (JointVector::zeros(), HydraulicState::zeros()),
            Actuators::Lag(time_constant) => {
                ((tau_cmd - s.lag_torque).component_div(time_constant), HydraulicState::zeros())
            }
            Actuators::Hydraulic(h) => (JointVector::zeros(), h.held_derivative(&s.q, &s.qd, &s.hydraulic)),
        };
        PlantState { q: s.qd, qd: qdd, bristle, lag_torque, hydraulic }
    }

    /// Advances one control period `dt` in `substeps` equal [`Plant::step`]s with the command
    /// `τ_cmd` held, and returns the joint accelerations at its start: the first RK4 stage,
    /// evaluated once for both.
    pub fn advance(&mut self, dt: f64, substeps: usize, tau_cmd: &JointVector<N>) -> Result<JointVector<N>, SimError> {
        self.sample_if_due(tau_cmd);
        let start = self.stage(self.time, &self.state, tau_cmd)?;
        let h = dt / substeps.max(1) as f64;
        self.step_from(h, tau_cmd, Some(start))?;
        for _ in 1..substeps {
            self.step(h, tau_cmd)?;
        }
        Ok(start.qd)
    }

    /// Advances by `h` with the command `τ_cmd` held: classic RK4, in as many equal sub-steps
    /// as keep `h_sub · λ ≤` [`MAX_STIFF_STEP`] for the fastest stiff rate `λ` at the start, the
    /// bristles' relaxation or the hydraulic actuators' ([`HydraulicActuators::stiff_rate`]; at
    /// most [`MAX_SUBCYCLES`]); one cycle while the joints move slowly, no valve is wide open
    /// onto a chamber near its supply or tank pressure and the spools are slow for `h`. Hydraulic
    /// actuators' inner loops run at each of their sample instants on the way, the sub-steps
    /// split there.
    pub fn step(&mut self, h: f64, tau_cmd: &JointVector<N>) -> Result<(), SimError> {
        self.step_from(h, tau_cmd, None)
    }

    /// [`Plant::step`], given the state's derivative at the start if it is known.
    fn step_from(&mut self, h: f64, tau_cmd: &JointVector<N>, start: Option<PlantState<N>>) -> Result<(), SimError> {
        let cycles = self.cycles(h);
        // The known derivative is the first stage of the first cycle, whatever its length.
        let mut first = start;
        for _ in 0..cycles {
            self.rk4_sampled(h / cycles as f64, tau_cmd, first.take())?;
        }
        Ok(())
    }

    /// How many equal RK4 sub-steps a step of `h` takes from the current state ([`Self::step`]).
    fn cycles(&self, h: f64) -> usize {
        let bristles = match &self.friction {
            Friction::LuGre(f) => f.relaxation_rate(&self.state.q, &self.state.qd),
            _ => 0.0,
        };
        let oil = match &self.actuators {
            Actuators::Hydraulic(a) => a.stiff_rate(&self.state.q, &self.state.hydraulic),
            _ => 0.0,
        };
        cycles_for(h, bristles.max(oil))
    }

    /// The span to the hydraulic inner loops' next sample instant, s, if it falls within a
    /// step of `left` ([`Self::rk4_sampled`] splits the step there); `None` if it does not or
    /// the arm has no such loops.
    fn sample_split(&self, left: f64) -> Option<f64> {
        let Actuators::Hydraulic(actuators) = &self.actuators else { return None };
        let to_sample = actuators.next_sample_time() - self.time;
        (to_sample < left - hydraulic::SAMPLE_TOLERANCE * actuators.sample_period()).then_some(to_sample)
    }

    /// Runs the hydraulic inner loops if one of their sample instants is now; whether they ran.
    fn sample_if_due(&mut self, tau_cmd: &JointVector<N>) -> bool {
        match &mut self.actuators {
            Actuators::Hydraulic(h) if h.sample_due(self.time) => {
                let s = &mut self.state;
                h.sample(self.time, tau_cmd, &s.q, &mut s.hydraulic);
                true
            }
            _ => false,
        }
    }

    /// [`Plant::rk4`] over `h`, split at the hydraulic inner loops' sample instants, which run
    /// the loops; one step of `h` for the other actuators.
    fn rk4_sampled(&mut self, h: f64, tau_cmd: &JointVector<N>, mut k1: Option<PlantState<N>>) -> Result<(), SimError> {
        let mut left = h;
        loop {
            if self.sample_if_due(tau_cmd) {
                k1 = None;
            }
            let Some(to_sample) = self.sample_split(left) else { return self.rk4(left, tau_cmd, k1) };
            self.rk4(to_sample, tau_cmd, k1.take())?;
            left -= to_sample;
        }
    }

    /// One classic RK4 step of length `h` with the command `τ_cmd` held; `k1` is the state's
    /// derivative now, if known.
    fn rk4(&mut self, h: f64, tau_cmd: &JointVector<N>, k1: Option<PlantState<N>>) -> Result<(), SimError> {
        let (t, s) = (self.time, self.state);
        let k1 = match k1 {
            Some(k1) => k1,
            None => self.stage(t, &s, tau_cmd)?,
        };
        let k2 = self.stage(t + h / 2.0, &s.along(&k1, h / 2.0), tau_cmd)?;
        let k3 = self.stage(t + h / 2.0, &s.along(&k2, h / 2.0), tau_cmd)?;
        let k4 = self.stage(t + h, &s.along(&k3, h), tau_cmd)?;
        self.commit(h, rk4_sum(&s, [&k1, &k2, &k3, &k4], h))
    }

    /// Takes `next` as the state `h` after the current one: an error if it is not finite; notes
    /// a joint past [`MAX_PLAUSIBLE_SPEED_RAD_S`].
    fn commit(&mut self, h: f64, next: PlantState<N>) -> Result<(), SimError> {
        let t = self.time;
        if !next.is_finite() {
            let cause = SimError::Numerical(format!("the plant's state became non-finite at t = {:.4} s", t + h));
            return Err(self.diverged(t + h, &next, cause).unwrap_or_else(|cause| cause));
        }
        self.state = next;
        self.time += h;
        if self.runaway.is_none() {
            self.runaway = fastest(&next).map(|(joint, velocity)| (joint, self.time, velocity));
        }
        Ok(())
    }

    /// The derivative at an integration stage `stage`; a failure there is [`Self::diverged`].
    fn stage(&self, t: f64, stage: &PlantState<N>, tau_cmd: &JointVector<N>) -> Result<PlantState<N>, SimError> {
        self.derivative(t, stage, tau_cmd).map_err(|cause| self.diverged(t, stage, cause).unwrap_or_else(|e| e))
    }

    /// [`SimError::Diverged`] if a joint passed [`MAX_PLAUSIBLE_SPEED_RAD_S`] at a whole step
    /// ([`Self::runaway`]) or does in `stage` (or `stage` is non-finite); otherwise `Err(cause)`,
    /// a failure of its own.
    fn diverged(&self, t: f64, stage: &PlantState<N>, cause: SimError) -> Result<SimError, SimError> {
        let (joint, runaway_s, velocity) = match self.runaway {
            Some(runaway) => runaway,
            None => match fastest(stage) {
                Some((joint, velocity)) => (joint, t, velocity),
                None => return Err(cause),
            },
        };
        let cause = match cause {
            SimError::Step { source, .. } => source.to_string(),
            other => other.to_string(),
        };
        Ok(SimError::Diverged {
            time_s: t,
            joint: joint + 1,
            runaway_s,
            velocity,
            limit_rad_s: MAX_PLAUSIBLE_SPEED_RAD_S,
            cause,
        })
    }
}
