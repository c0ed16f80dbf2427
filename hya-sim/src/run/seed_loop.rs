//! One seed's closed loop around its plant, a control period at a time: [`super::run_loop`]
//! steps one seed alone, [`super::RunSetup::run_together`] several in lockstep.

use std::collections::VecDeque;

use hya_core::{BoxedObserver, ComputedTorque, Dynamics, Gains, JointVector, Measurement};

use super::sensors::Sensors;
use super::task::Trajectory;
use super::trace::{Recording, Tick, Trace, SHADOWS};
use super::{cartesian, model, observer_designed, true_model, ClosedLoop, IntegralAction};
use crate::config::scenario::Method;
use crate::config::settings::Setup;
use crate::error::SimError;
use crate::plant::{Plant, PlantState};
use crate::robot::Robot;

/// One seed's closed loop around its plant: sensors and delays, the controller and its
/// observer, the shadows, the trace and the metrics, stepped a control period at a time by
/// [`super::run_loop`] (one seed) or [`super::RunSetup::run_together`] (seeds together).
pub(super) struct SeedLoop<'a, const N: usize> {
    joints: &'a Setup<N>,
    method: Method,
    nominal: &'a (dyn Dynamics<N> + Send + Sync + 'a),
    trajectory: &'a Trajectory<N>,
    sensors: Sensors<N>,
    offset_torque: JointVector<N>,
    controller: ComputedTorque<N, &'a (dyn Dynamics<N> + Send + Sync + 'a)>,
    cartesian: Option<cartesian::CartesianLaw<'a, N>>,
    readings: VecDeque<Measurement<N>>,
    commands: VecDeque<JointVector<N>>,
    applied: JointVector<N>,
    estimator: Option<BoxedObserver<'a, N>>,
    /// Each shadow's observer; `None` for the loop's own method, whose estimate is `d̂` itself
    /// (the same design on the same measurements), so it is not computed twice.
    shadows: Vec<Option<BoxedObserver<'a, N>>>,
    shadow: [JointVector<N>; SHADOWS.len()],
    integral: Option<IntegralAction<N>>,
    /// This tick's reference position, `d̂` and command, recorded after the plant's step.
    tick: (JointVector<N>, JointVector<N>, JointVector<N>),
    trace: Trace<N>,
    metrics: crate::analysis::metrics::MetricsRecorder<N>,
    bandwidth_rad_s: Option<Vec<f64>>,
}

impl<'a, const N: usize> SeedLoop<'a, N> {
    /// The loop of `seed` and its plant, at rest at the trajectory's start holding gravity.
    pub(super) fn new(
        (joints, model, seed): (&'a Setup<N>, &'a model::LoopModel<'_, N>, u64),
        method: Method,
        robot: &'a Robot<N>,
        (trajectory, recording): (&'a Trajectory<N>, Recording),
    ) -> Result<(Self, Plant<N>), SimError> {
        let nominal = model.dynamics();
        let dt = joints.timing.dt_s;
        let q0 = trajectory.at(0.0).position;
        let (true_model, mut rng) = true_model(&robot.model, joints.parameter_spread, seed);
        let hold = nominal.gravity(&q0);
        let plant = Plant::new(true_model, robot.plant.as_ref(), &joints.plant, (q0, hold), &mut rng)?;
        let bandwidth = joints.control.observer_bandwidth_rad_s;
        let mut sensors = Sensors::new(joints.sensors.clone(), joints.noise.clone(), seed, dt, bandwidth);
        let offset_torque = sensors.offset_torque(&plant);
        let loop_design = model.design_at(joints, &q0)?;
        let mut gains = loop_design.pd;
        if method == Method::Pid {
            let setup = |source| SimError::Setup { setting: "controller.integral_rule".into(), source };
            gains = Gains::diagonal(gains.kp().diagonal().into(), loop_design.pid_kd.into()).map_err(setup)?;
        }
        let controller = ComputedTorque::new(nominal, gains)
            .with_torque_limit(joints.torque_limit)
            .map_err(|source| SimError::Setup { setting: "controller".into(), source })?;
        // A task set in task space is the Cartesian impedance controller's instead.
        let cartesian = match &joints.cartesian {
            Some(setup) => {
                cartesian::CartesianLaw::new((setup, &joints.task), nominal, &robot.model, (&q0, joints.torque_limit))?
            }
            None => None,
        };

        // The delays: readings wait `measurement_delay_ticks` before the controller sees them, and
        // commands `command_delay_ticks` before the valves do (the actuators hold `G(q0)` until then).
        let (measurement_delay, command_delay) =
            (joints.sensors.measurement_delay_ticks, joints.sensors.command_delay_ticks);
        let mut readings: VecDeque<Measurement<N>> = VecDeque::with_capacity(measurement_delay + 1);
        let commands: VecDeque<JointVector<N>> = std::iter::repeat_n(hold, command_delay).collect();
        readings.push_back(sensors.read(&plant, &hold)?);
        let design = (bandwidth, dt, joints.control.chen_gain);
        let (estimator, bandwidth_rad_s) = match observer_designed(method, nominal, design, &readings[0])? {
            Some((o, rates)) => (Some(o), Some(rates)),
            None => (None, None),
        };
        // Shadow mode: every estimator on the same measurements, none acting on the loop.
        let mut shadows = Vec::with_capacity(SHADOWS.len());
        for shadow in SHADOWS {
            if shadow == method {
                shadows.push(None);
                continue;
            }
            let designed = observer_designed(shadow, nominal, design, &readings[0])?;
            let (observer, _) = designed.ok_or(SimError::Nothing("a shadow method without an observer"))?;
            shadows.push(Some(observer));
        }
        let integral =
            (method == Method::Pid).then(|| IntegralAction::new(loop_design.integral, joints)).transpose()?;
        let last_time = joints.timing.last_time_s();
        let zero = JointVector::zeros();
        let seed_loop = Self {
            joints,
            method,
            nominal,
            trajectory,
            sensors,
            offset_torque,
            controller,
            cartesian,
            readings,
            commands,
            applied: hold,
            estimator,
            shadows,
            shadow: [zero; SHADOWS.len()],
            integral,
            tick: (zero, zero, zero),
            trace: Trace::new(joints.timing.steps, recording),
            metrics: crate::analysis::metrics::MetricsRecorder::new(joints, method.estimates(), last_time),
            bandwidth_rad_s,
        };
        Ok((seed_loop, plant))
    }

    /// Tick `k`: reads the sensors on `plant` (handing the reading the controller sees to
    /// `log`), updates the observers, commands; returns the torque the actuators receive over
    /// the coming period.
    pub(super) fn command(
        &mut self,
        k: usize,
        plant: &Plant<N>,
        log: &mut impl FnMut(f64, &Measurement<N>),
    ) -> Result<JointVector<N>, SimError> {
        let t = k as f64 * self.joints.timing.dt_s;
        if k > 0 {
            self.readings.push_back(self.sensors.read(plant, &self.applied)?);
            if self.readings.len() > self.joints.sensors.measurement_delay_ticks + 1 {
                self.readings.pop_front();
            }
        }
        let measurement = self.readings[0];
        log(t, &measurement);
        let at = |source| SimError::Step { time_s: t, source };
        let d_hat = match self.estimator.as_mut() {
            Some(o) if k > 0 => o.update(&measurement).map_err(at)?,
            Some(o) => *o.disturbance(),
            None => JointVector::zeros(),
        };
        for (observer, estimate) in self.shadows.iter_mut().zip(self.shadow.iter_mut()) {
            *estimate = match observer {
                Some(o) if k > 0 => o.update(&measurement).map_err(at)?,
                Some(o) => *o.disturbance(),
                None => d_hat,
            };
        }
        let velocity = measurement.velocity.unwrap_or_else(JointVector::zeros);
        let reference = self.trajectory.at(t);
        // The PID's integral enters where d̂ does: τ = … − K_P e − K_I ∫e.
        let integral_torque = self.integral.as_mut().map(|i| i.step(&(measurement.position - reference.position)));
        let compensation = match (&integral_torque, self.method.estimates()) {
            (Some(torque), _) => Some(torque),
            (None, true) => Some(&d_hat),
            (None, false) => None,
        };
        let command = match self.cartesian.as_mut() {
            Some(law) => law.command(t, (&measurement.position, &velocity), compensation)?,
            None => {
                self.controller.command(&measurement.position, &velocity, &reference, compensation).map_err(at)?.torque
            }
        };
        self.commands.push_back(command);
        self.applied = self.commands.pop_front().unwrap_or(command);
        self.tick = (reference.position, d_hat, command);
        Ok(self.applied)
    }

    /// Records tick `k` once `plant` has stepped over the period from `state`, where its joints
    /// accelerated at `acceleration`.
    pub(super) fn record(
        &mut self,
        k: usize,
        plant: &Plant<N>,
        (state, acceleration): (&PlantState<N>, &JointVector<N>),
    ) {
        let (q_des, d_hat, tau_cmd) = self.tick;
        let tick = Tick {
            t: k as f64 * self.joints.timing.dt_s,
            q: state.q,
            q_des,
            d_true: self.nominal.inverse_dynamics(&state.q, &state.qd, acceleration)
                - plant.actuator_torque(state, &self.applied)
                - self.offset_torque,
            d_hat,
            tau_cmd,
            shadow: self.shadow,
        };
        self.trace.record(k, &tick);
        self.metrics.push(&tick);
    }

    pub(super) fn finish(self) -> ClosedLoop<N> {
        ClosedLoop { trace: self.trace, metrics: self.metrics.finish(), bandwidth_rad_s: self.bandwidth_rad_s }
    }
}
