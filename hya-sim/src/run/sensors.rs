//! Sensing as on HyA: quantised joint encoders, a velocity derived from them (unless a scenario
//! defines a velocity sensor), and the joint torque from the chamber pressures. Seeded: the same
//! seed gives the same draws, bit for bit.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

use hya_core::{FilterParams, JointVector, Measurement, ThirdOrderFilter};

use crate::config::scenario::{Noise, NoiseConfig, SensorConfig, TorqueSource, Transducers, VelocitySource};
use crate::error::SimError;
use crate::plant::hydraulic::HydraulicActuators;
use crate::plant::{Actuators, Plant};

/// The joint velocity the controller and observers read.
#[derive(Debug, Clone)]
enum VelocityEstimate<const N: usize> {
    /// `v_k = a v_{k−1} + (1 − a)(q_k − q_{k−1}) / T`, `a = e^{−ω_c T}`.
    Difference { previous: JointVector<N>, estimate: JointVector<N>, pole: f64, dt: f64 },
    /// `q̂̇` of the paper's filter.
    Filter(Box<ThirdOrderFilter<N>>),
    /// A velocity sensor.
    Sensor,
}

/// Draws every sensor's reading from one seeded stream.
#[derive(Debug, Clone)]
pub struct Sensors<const N: usize> {
    rng: ChaCha8Rng,
    noise: NoiseConfig,
    config: SensorConfig,
    /// Constant offsets of the cap- and rod-side pressure sensors, Pa.
    offsets: (JointVector<N>, JointVector<N>),
    velocity: Option<VelocityEstimate<N>>,
    /// `ω1 = ω2` for the filter velocity source, and the control period.
    filter: (f64, f64),
}

fn draw<const N: usize>(rng: &mut ChaCha8Rng, noise: Noise) -> JointVector<N> {
    match noise {
        Noise::Off {} => JointVector::zeros(),
        Noise::Uniform { bound } => JointVector::from_fn(|_, _| bound * (2.0 * rng.gen::<f64>() - 1.0)),
        Noise::Gaussian { sigma: 0.0 } => JointVector::zeros(),
        Noise::Gaussian { sigma } => match Normal::new(0.0, sigma) {
            Ok(normal) => JointVector::from_fn(|_, _| normal.sample(rng)),
            Err(_) => JointVector::zeros(),
        },
    }
}

impl<const N: usize> Sensors<N> {
    /// Sensors for `config` with `noise`, from stream 1 of `seed`, read every `dt` s; a filter velocity
    /// source uses the paper's filter at `ζ = 0.8`, `ω1 = ω2 = bandwidth`.
    pub fn new(config: SensorConfig, noise: NoiseConfig, seed: u64, dt: f64, bandwidth: f64) -> Self {
        // Stream 1 of the seed (the plant draws from stream 0), so no two seeds share numbers.
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        rng.set_stream(1);
        // Drawn whichever set is read, so that the noise that follows is the same in both.
        let bound = config.pressure_offset_pa;
        let offsets = (draw(&mut rng, Noise::Uniform { bound }), draw(&mut rng, Noise::Uniform { bound }));
        Self { rng, noise, config, offsets, velocity: None, filter: (bandwidth, dt) }
    }

    /// The encoder's reading of `q`: noise added, then rounded to a count.
    fn encoder(&mut self, q: &JointVector<N>) -> JointVector<N> {
        let resolution = std::f64::consts::TAU / self.config.encoder_counts_per_rev as f64;
        let noisy = q + draw(&mut self.rng, self.noise.position);
        noisy.map(|x| (x / resolution).round() * resolution)
    }

    /// The measured joint torque of `plant` while `applied` is commanded, N·m: from the chamber
    /// pressures (each sensor with its offset and noise), or the true actuator torque plus noise.
    fn torque(&mut self, plant: &Plant<N>, applied: &JointVector<N>) -> JointVector<N> {
        let state = &plant.state;
        match (plant.actuators(), self.config.torque) {
            (Actuators::Hydraulic(h), TorqueSource::Pressure) => {
                let gaussian = Noise::Gaussian { sigma: self.config.pressure_noise_pa };
                let offsets = self.pressure_offsets(h);
                let pa = state.hydraulic.pressure_a + offsets.0 + draw(&mut self.rng, gaussian);
                let pb = state.hydraulic.pressure_b + offsets.1 + draw(&mut self.rng, gaussian);
                h.torque(&pa, &pb)
            }
            _ => plant.actuator_torque(state, applied) + draw(&mut self.rng, self.noise.torque),
        }
    }

    /// The constant offsets of the pressure transducers the controller reads, Pa.
    fn pressure_offsets(&self, h: &HydraulicActuators<N>) -> (JointVector<N>, JointVector<N>) {
        match self.config.transducers {
            Transducers::Shared => h.pressure_offsets(),
            Transducers::Independent => self.offsets,
        }
    }

    /// The constant error of the torque the controller reads from `plant`, N·m: its pressure
    /// transducers' offsets seen as torque, `D_a o_a − D_b o_b` (zero for other sources).
    pub fn offset_torque(&self, plant: &Plant<N>) -> JointVector<N> {
        match (plant.actuators(), self.config.torque) {
            (Actuators::Hydraulic(h), TorqueSource::Pressure) => {
                let (a, b) = self.pressure_offsets(h);
                h.torque(&a, &b)
            }
            _ => JointVector::zeros(),
        }
    }

    /// Reads every sensor of `plant` once (one control tick): encoder angles, the derived (or
    /// sensed) velocity and the measured torque.
    pub fn read(&mut self, plant: &Plant<N>, applied: &JointVector<N>) -> Result<Measurement<N>, SimError> {
        let position = self.encoder(&plant.state.q);
        let torque = self.torque(plant, applied);
        let velocity = match self.velocity.as_mut() {
            None => {
                self.velocity = Some(self.start_velocity(&position)?);
                match self.config.velocity {
                    VelocitySource::Sensor => plant.state.qd + draw(&mut self.rng, self.noise.velocity),
                    _ => JointVector::zeros(),
                }
            }
            Some(VelocityEstimate::Difference { previous, estimate, pole, dt }) => {
                *estimate = *estimate * *pole + (position - *previous) * ((1.0 - *pole) / *dt);
                *previous = position;
                *estimate
            }
            Some(VelocityEstimate::Filter(filter)) => {
                filter.step(&position).map_err(|e| SimError::Numerical(format!("velocity filter: {e}")))?.x2
            }
            Some(VelocityEstimate::Sensor) => plant.state.qd + draw(&mut self.rng, self.noise.velocity),
        };
        Ok(Measurement { position, velocity: Some(velocity), torque })
    }

    fn start_velocity(&self, position: &JointVector<N>) -> Result<VelocityEstimate<N>, SimError> {
        let (bandwidth, dt) = self.filter;
        Ok(match self.config.velocity {
            VelocitySource::Difference => VelocityEstimate::Difference {
                previous: *position,
                estimate: JointVector::zeros(),
                pole: (-self.config.velocity_cutoff_rad_s * dt).exp(),
                dt,
            },
            VelocitySource::Filter => {
                let config = |source| SimError::Setup { setting: "sensors.velocity = \"filter\"".into(), source };
                let params = FilterParams::paper_at(bandwidth, dt).map_err(config)?;
                VelocityEstimate::Filter(Box::new(ThirdOrderFilter::new(params, *position).map_err(config)?))
            }
            VelocitySource::Sensor => VelocityEstimate::Sensor,
        })
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;
    use crate::config::scenario::Scenario;
    use crate::robot::Robot;

    /// With shared transducers the controller's torque is the inner loops' measured torque (their
    /// offsets); with independent ones it carries offsets of its own.
    #[test]
    fn shared_transducers_carry_the_loops_offsets() {
        let mut scenario = Scenario::builtin("goto_internal").unwrap();
        scenario.sensors.pressure_noise_pa = 0.0;
        let robot = Robot::<6>::load(&scenario.robot).unwrap();
        let settings = crate::config::settings::Setup::<6>::of(&scenario).unwrap();
        let tau0 = JointVector::from([1.0, -2.0, 3.0, 0.5, -0.5, 0.2]);
        let (plant, _) =
            crate::run::rollout::scenario_plant(&robot.model, &settings, settings.initial_position, tau0).unwrap();
        let Actuators::Hydraulic(h) = plant.actuators() else { panic!("HyA's scenario has hydraulic actuators") };
        let (oa, ob) = h.pressure_offsets();
        assert!(oa.amax() > 0.0, "the loops' transducers have offsets");
        let state = &plant.state.hydraulic;
        let loops = h.torque(&(state.pressure_a + oa), &(state.pressure_b + ob));
        let read = |transducers| {
            let config = SensorConfig { transducers, ..scenario.sensors.clone() };
            Sensors::new(config, scenario.noise.clone(), scenario.seed, 1e-3, 50.0).read(&plant, &tau0).unwrap().torque
        };
        assert_eq!(read(Transducers::Shared), loops);
        let independent = read(Transducers::Independent);
        assert!((independent - loops).amax() > 1e-3, "independent offsets: {independent} against {loops}");
    }
}
