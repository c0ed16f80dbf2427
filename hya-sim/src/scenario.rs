//! Scenarios: what to simulate, as TOML. The paper's experiments are embedded
//! ([`Scenario::builtin`]); `hya run FILE.toml` runs a user's own.

use serde::{Deserialize, Serialize};

use crate::SimError;

/// One experiment: robot, task, plant, disturbances and the methods to compare.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    /// Its name, used for file names in the report.
    pub name: String,
    /// One line on what it shows.
    #[serde(default)]
    pub description: String,
    /// A shipped robot (`hya`).
    #[serde(default = "default_robot")]
    pub robot: String,
    /// Simulated time, s.
    pub duration_s: f64,
    /// Seed of every random draw (parameter perturbation, sensor noise).
    #[serde(default = "default_seed")]
    pub seed: u64,
    /// Methods to run: `none`, `lu`, `chen`, `momentum`, `eso`.
    pub methods: Vec<Method>,
    /// Initial joint positions, rad (the authors' home pose by default).
    #[serde(default)]
    pub initial_position_rad: Option<Vec<f64>>,
    /// The reference to track.
    pub task: Task,
    /// Controller settings.
    #[serde(default)]
    pub controller: ControllerConfig,
    /// The simulated arm.
    #[serde(default)]
    pub plant: PlantConfig,
    /// Sensor noise.
    #[serde(default)]
    pub noise: NoiseConfig,
    /// External loads.
    #[serde(default)]
    pub loads: LoadConfig,
    /// Event times (task start, weight drop and removal) and the duration are multiplied by this
    /// factor with `--quick`; frequencies and transition times are kept.
    #[serde(default = "default_quick_time_scale")]
    pub quick_time_scale: f64,
}

fn default_robot() -> String {
    "hya".into()
}
fn default_seed() -> u64 {
    1
}
fn default_quick_time_scale() -> f64 {
    0.3
}

/// A way of computing the command.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Method {
    /// Computed torque without compensation.
    None,
    /// The paper's estimator (Lu, Sandy & Buchli).
    Lu,
    /// Chen's nonlinear disturbance observer (Mohammadi's gain).
    Chen,
    /// The generalized-momentum observer.
    Momentum,
    /// The model-assisted extended state observer.
    Eso,
}

impl Method {
    /// The name used in files and tables.
    pub fn name(self) -> &'static str {
        match self {
            Method::None => "none",
            Method::Lu => "lu",
            Method::Chen => "chen",
            Method::Momentum => "momentum",
            Method::Eso => "eso",
        }
    }
}

/// The reference trajectory.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase", deny_unknown_fields)]
pub enum Task {
    /// Hold the initial pose.
    Hold,
    /// Hold, then move to `start + delta` with a minimum-jerk transition starting at `start_s`.
    Goto {
        /// When the move starts, s.
        start_s: f64,
        /// Duration of the minimum-jerk transition, s.
        transition_s: f64,
        /// Joint offsets of the setpoint, rad.
        delta_rad: Vec<f64>,
    },
    /// `q_des = q0 + A sin(2π f t)` on every joint, ramped in over `ramp_s`.
    Sine {
        /// Amplitudes, rad.
        amplitude_rad: Vec<f64>,
        /// Frequency, Hz.
        frequency_hz: f64,
        /// Ramp-in of the amplitude, s.
        ramp_s: f64,
    },
}

/// Where the controller's velocity comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum VelocitySource {
    /// The (noisy) velocity sensor.
    #[default]
    Measured,
    /// The paper's filter, `q̂̇` (lags by `1/ω1 + 2ζ/ω2`).
    Filtered,
}

/// Controller settings: gains from a desired closed-loop natural frequency and damping per joint.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ControllerConfig {
    /// Desired natural frequency per joint, rad/s: `K_P = M_ii(q0) ω²`.
    pub natural_frequency_rad_s: Vec<f64>,
    /// Desired damping ratio: `K_D = 2 ζ ω M_ii(q0)`.
    pub damping_ratio: f64,
    /// Torque limit per joint, N·m.
    pub torque_limit_nm: Vec<f64>,
    /// The controller's velocity source.
    pub velocity: VelocitySource,
    /// Bandwidth of every observer, rad/s (the paper's filter uses ζ = 0.8, ω1 = ω2 = this).
    pub observer_bandwidth_rad_s: f64,
    /// Control period, s.
    pub dt_s: f64,
}

impl Default for ControllerConfig {
    fn default() -> Self {
        Self {
            natural_frequency_rad_s: vec![12.0; 6],
            damping_ratio: 0.8,
            torque_limit_nm: vec![150.0; 6],
            velocity: VelocitySource::Measured,
            observer_bandwidth_rad_s: 50.0,
            dt_s: 1e-3,
        }
    }
}

/// The simulated arm: how it differs from the controller's nominal model.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct PlantConfig {
    /// Relative spread of masses, centres of mass and inertias (uniform, seeded).
    pub parameter_spread: f64,
    /// Friction on or off.
    pub friction: bool,
    /// Coulomb friction per joint, N·m.
    pub coulomb_nm: Vec<f64>,
    /// Static (breakaway) friction per joint, N·m.
    pub static_nm: Vec<f64>,
    /// Viscous friction per joint, N·m·s/rad.
    pub viscous_nm_s: Vec<f64>,
    /// Stribeck velocity, rad/s.
    pub stribeck_velocity_rad_s: f64,
    /// Velocity scale of the smooth sign `tanh(q̇ / ε)`, rad/s.
    pub smoothing_rad_s: f64,
    /// Relative variation of the Coulomb level with position: `Fc (1 + a sin(2 q))`.
    pub coulomb_position_variation: f64,
    /// Time constant of each joint's hydraulic torque loop, s.
    pub actuator_time_constant_s: Vec<f64>,
    /// Physics steps per control period.
    pub substeps: usize,
}

impl Default for PlantConfig {
    fn default() -> Self {
        Self {
            parameter_spread: 0.1,
            friction: true,
            coulomb_nm: vec![5.0, 5.0, 3.0, 3.0, 2.0, 2.0],
            static_nm: vec![6.5, 6.5, 3.9, 3.9, 2.6, 2.6],
            viscous_nm_s: vec![2.7, 2.7, 1.8, 1.8, 0.9, 0.9],
            stribeck_velocity_rad_s: 0.05,
            smoothing_rad_s: 0.05,
            coulomb_position_variation: 0.3,
            actuator_time_constant_s: vec![0.004, 0.004, 0.008, 0.008, 0.015, 0.015],
            substeps: 5,
        }
    }
}

/// A sensor's noise.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase", deny_unknown_fields)]
pub enum Noise {
    /// None.
    Off,
    /// Uniform in `[−bound, bound]`.
    Uniform {
        /// The bound.
        bound: f64,
    },
    /// Gaussian with standard deviation `sigma`.
    Gaussian {
        /// The standard deviation.
        sigma: f64,
    },
}

/// Noise on each sensor.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct NoiseConfig {
    /// Joint angle, rad.
    pub position: Noise,
    /// Joint velocity, rad/s.
    pub velocity: Noise,
    /// Joint torque, N·m.
    pub torque: Noise,
}

impl Default for NoiseConfig {
    /// The hydraulic-joint sensor noise measured on the Atlas arm (uniform bounds).
    fn default() -> Self {
        Self {
            position: Noise::Uniform { bound: 3.4e-4 },
            velocity: Noise::Uniform { bound: 0.055 },
            torque: Noise::Uniform { bound: 0.073 },
        }
    }
}

/// External loads.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields, default)]
pub struct LoadConfig {
    /// Sinusoidal joint torques.
    pub sinusoid: Option<SinusoidLoad>,
    /// A weight dropped on the end effector.
    pub weight_drop: Option<WeightDrop>,
}

/// `d_ext,i = A_i sin(2π f t + φ_i)`, `φ_i = i π / 3`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SinusoidLoad {
    /// Amplitude per joint, N·m.
    pub amplitude_nm: Vec<f64>,
    /// Frequency, Hz.
    pub frequency_hz: f64,
}

/// A payload dropped onto a frame: it lands with an impact pulse and is removed later.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WeightDrop {
    /// Payload mass, kg.
    pub mass_kg: f64,
    /// The frame it lands on.
    pub frame: String,
    /// Landing time, s.
    pub drop_s: f64,
    /// Removal time, s.
    pub remove_s: f64,
    /// Fall height, m: the impact carries momentum `m √(2 g h)` downward.
    pub fall_height_m: f64,
    /// Duration of the impact pulse, s.
    pub impact_s: f64,
}

const BUILTIN: [(&str, &str); 6] = [
    ("goto_internal", include_str!("../scenarios/goto_internal.toml")),
    ("sine_internal", include_str!("../scenarios/sine_internal.toml")),
    ("goto_weight", include_str!("../scenarios/goto_weight.toml")),
    ("sine_weight", include_str!("../scenarios/sine_weight.toml")),
    ("estimator_noise_low", include_str!("../scenarios/estimator_noise_low.toml")),
    ("estimator_noise_high", include_str!("../scenarios/estimator_noise_high.toml")),
];

impl Scenario {
    /// Parses and checks a scenario; `source` names it in errors.
    pub fn from_toml(text: &str, source: &str) -> Result<Self, SimError> {
        let scenario: Scenario =
            toml::from_str(text).map_err(|e| SimError::Scenario { origin: source.into(), message: e.to_string() })?;
        scenario.validate().map_err(|message| SimError::Scenario { origin: source.into(), message })?;
        Ok(scenario)
    }

    /// The names of the embedded scenarios, in the order `hya reproduce` runs them.
    pub fn builtin_names() -> impl Iterator<Item = &'static str> {
        BUILTIN.iter().map(|(name, _)| *name)
    }

    /// An embedded scenario by name.
    pub fn builtin(name: &str) -> Result<Self, SimError> {
        let (_, text) = BUILTIN
            .iter()
            .find(|(n, _)| *n == name)
            .ok_or_else(|| SimError::Scenario { origin: name.into(), message: "no such built-in scenario".into() })?;
        Self::from_toml(text, name)
    }

    /// The shortened version for `--quick`: event times and duration scaled.
    pub fn quick(&self) -> Self {
        let k = self.quick_time_scale;
        let mut quick = self.clone();
        quick.duration_s *= k;
        if let Task::Goto { start_s, .. } = &mut quick.task {
            *start_s *= k;
        }
        if let Some(drop) = &mut quick.loads.weight_drop {
            drop.drop_s *= k;
            drop.remove_s *= k;
        }
        quick
    }

    fn validate(&self) -> Result<(), String> {
        let positive = |name: &str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(format!("{name} must be finite and > 0, got {v}"))
            }
        };
        positive("duration_s", self.duration_s)?;
        positive("controller.dt_s", self.controller.dt_s)?;
        positive("controller.observer_bandwidth_rad_s", self.controller.observer_bandwidth_rad_s)?;
        positive("quick_time_scale", self.quick_time_scale)?;
        positive("plant.smoothing_rad_s", self.plant.smoothing_rad_s)?;
        positive("plant.stribeck_velocity_rad_s", self.plant.stribeck_velocity_rad_s)?;
        if self.plant.substeps == 0 {
            return Err("plant.substeps must be at least 1".into());
        }
        if self.methods.is_empty() {
            return Err("methods: name at least one of none, lu, chen, momentum, eso".into());
        }
        if let Some(drop) = &self.loads.weight_drop {
            positive("loads.weight_drop.mass_kg", drop.mass_kg)?;
            positive("loads.weight_drop.impact_s", drop.impact_s)?;
            if drop.remove_s <= drop.drop_s {
                return Err(format!(
                    "loads.weight_drop: remove_s ({}) must come after drop_s ({})",
                    drop.remove_s, drop.drop_s
                ));
            }
        }
        Ok(())
    }
}
