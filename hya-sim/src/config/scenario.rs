//! Scenarios: what to simulate, as TOML. The paper's experiments are embedded
//! ([`Scenario::builtin`]); `hya run FILE.toml` runs a user's own.

use serde::{Deserialize, Serialize};

use hya_core::{Clipped, Short};

use crate::error::{SettingError, SimError};

/// One experiment: robot, task, plant, disturbances and the methods to compare.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    /// Its name, used for file names in the report: 1 to 64 of `A–Z a–z 0–9 _ -`, starting with
    /// a letter or digit (see [`check_file_stem`]).
    pub name: String,
    /// One line on what it shows.
    #[serde(default)]
    pub description: String,
    /// A shipped robot by name (`hya`, `panda`, …), or the path of a URDF with 1 to 7 joints.
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
    /// What is measured, and the delays.
    #[serde(default)]
    pub sensors: SensorConfig,
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
    /// Accept physical settings beyond their plausible range ([`PLAUSIBLE`]): a valve flow of
    /// 1e300 m³/s or a torque loop at 1 GHz is almost always a unit mistake, refused unless this
    /// says otherwise. Finiteness and the numerical limits are checked regardless.
    #[serde(default)]
    pub allow_unphysical: bool,
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

/// Most control ticks a run may take: an hour at 1 kHz (every tick's trace is kept in memory).
pub const MAX_TICKS: usize = 3_600_000;

/// Metrics skip this start-up interval (observers and filters settling), s: a scenario must run
/// longer.
pub const WARM_UP_S: f64 = 0.5;

/// The largest scenario file read, bytes.
pub const MAX_SCENARIO_BYTES: u64 = 1 << 20;

/// Longest scenario name, in characters.
pub const MAX_NAME_LEN: usize = 64;

/// Checks that `name` is safe as the start of a file name in any folder: 1 to
/// [`MAX_NAME_LEN`] characters from `A–Z a–z 0–9 _ -`, the first a letter or digit. So no
/// separator, `..`, drive, absolute path or hidden file can come from a scenario.
pub fn check_file_stem(name: &str) -> Result<(), String> {
    let allowed = |c: char| c.is_ascii_alphanumeric() || c == '_' || c == '-';
    match name.chars().next() {
        None => Err("must not be empty".into()),
        Some(first) if !first.is_ascii_alphanumeric() => Err("must start with a letter or digit".into()),
        _ if name.chars().count() > MAX_NAME_LEN => Err(format!("is longer than {MAX_NAME_LEN} characters")),
        _ => match name.chars().find(|c| !allowed(*c)) {
            Some(c) => Err(format!("{c:?} is not allowed (only letters, digits, `_` and `-`)")),
            None => Ok(()),
        },
    }
}

/// A way of computing the command.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Method {
    /// Computed torque without compensation.
    None,
    /// Computed torque with PID: the same PD gains plus an integral term with anti-windup.
    Pid,
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
    /// Every method, in the order of the reports.
    pub const ALL: [Method; 6] = [Method::None, Method::Pid, Method::Lu, Method::Chen, Method::Momentum, Method::Eso];

    /// The method called `name` ([`name`](Self::name)).
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|m| m.name() == name)
    }

    /// Whether the method estimates the disturbance (all but `none` and `pid`).
    pub fn estimates(self) -> bool {
        !matches!(self, Method::None | Method::Pid)
    }

    /// The name used in files and tables.
    pub fn name(self) -> &'static str {
        match self {
            Method::None => "none",
            Method::Pid => "pid",
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
    Hold {},
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
    /// Task space: hold the controlled frame's start pose, then move it by `offset_m` (in the
    /// base) and turn it by the rotation vector `rotation_rad` (in the base) with a minimum-jerk
    /// transition starting at `start_s`; the controller is `controller.cartesian`'s impedance.
    Cartesian {
        /// When the move starts, s.
        start_s: f64,
        /// Duration of the minimum-jerk transition, s.
        transition_s: f64,
        /// The frame's displacement in the base, m (three values).
        offset_m: Vec<f64>,
        /// The frame's turn as a rotation vector in the base, rad (three values, norm below π).
        rotation_rad: Vec<f64>,
    },
}

/// The Cartesian impedance controller of a [`Task::Cartesian`] scenario
/// (`hya_core::CartesianImpedance`): a spring and a damper at one frame of the arm, a posture
/// spring in the task's null space around the start pose.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CartesianConfig {
    /// The controlled link (the description's last link when absent).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub frame: Option<String>,
    /// `K_x`: N/m for the three linear directions, then N·m/rad for the three rotations.
    pub stiffness: Vec<f64>,
    /// `D_x`: N·s/m, then N·m·s/rad.
    pub damping: Vec<f64>,
    /// `K_n` per joint, N·m/rad.
    pub posture_stiffness_nm_rad: Vec<f64>,
    /// `D_n` per joint, N·m·s/rad.
    pub posture_damping_nm_s_rad: Vec<f64>,
}

/// Where the joint velocity that the controller and the observers read comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum VelocitySource {
    /// The backward difference of the encoder angles through a first-order low-pass at
    /// [`SensorConfig::velocity_cutoff_rad_s`].
    #[default]
    Difference,
    /// The paper's filter on the encoder angles, `q̂̇` (lags by `1/ω1 + 2ζ/ω2`).
    Filter,
    /// A velocity sensor, with [`NoiseConfig::velocity`] noise (HyA has none; the paper's
    /// section V comparison defines one).
    Sensor,
}

/// Where the measured joint torque comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum TorqueSource {
    /// From the chamber pressures of hydraulic actuators, `D_a p_a,m − D_b p_b,m`, each
    /// pressure with the sensor's seeded offset and noise; other actuators fall back to
    /// [`TorqueSource::Direct`].
    #[default]
    Pressure,
    /// The actuator's true torque plus [`NoiseConfig::torque`] noise (a load cell).
    Direct,
}

/// Which pressure transducers the controller's torque measurement reads
/// ([`TorqueSource::Pressure`] on hydraulic actuators).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum Transducers {
    /// The inner torque loops' own, as on HyA (one transducer set per joint): the controller's
    /// reading carries the same constant offsets as the loop's
    /// (`plant.hydraulic.torque_loop_pressure_offset_pa`), with a noise draw of its own (a
    /// simplification: the two read at their own instants). The torque error the offsets leave
    /// in the loop, `D_a o_a − D_b o_b`, is then part of what the estimator sees
    /// (`d̂ → d − (D_a o_a − D_b o_b)`) and the compensation removes it.
    #[default]
    Shared,
    /// A second set with offsets of its own (bound `sensors.pressure_offset_pa`): the controller
    /// and the inner loop disagree on the torque by the offsets' difference, which no estimate
    /// sees, so a steady error of about that difference over `K_P` remains.
    Independent,
}

/// What the controller can measure, and when.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SensorConfig {
    /// Encoder resolution, counts per revolution (the angle is rounded to a count, after the
    /// position noise is added).
    pub encoder_counts_per_rev: u64,
    /// The velocity the controller and observers read.
    pub velocity: VelocitySource,
    /// Cut-off of the difference's low-pass, rad/s.
    pub velocity_cutoff_rad_s: f64,
    /// The measured torque.
    pub torque: TorqueSource,
    /// Standard deviation of each pressure sensor's noise, Pa.
    pub pressure_noise_pa: f64,
    /// Bound of each pressure sensor's constant offset (uniform, seeded), Pa; read with
    /// [`Transducers::Independent`] only.
    pub pressure_offset_pa: f64,
    /// Whether the controller reads the inner loops' transducers or a set of its own.
    pub transducers: Transducers,
    /// Control ticks between a measurement and the controller reading it.
    pub measurement_delay_ticks: usize,
    /// Control ticks between the controller's command and the valves receiving it.
    pub command_delay_ticks: usize,
}

impl Default for SensorConfig {
    fn default() -> Self {
        Self {
            encoder_counts_per_rev: 1 << 19,
            velocity: VelocitySource::Difference,
            velocity_cutoff_rad_s: 150.0,
            torque: TorqueSource::Pressure,
            pressure_noise_pa: 1e4,
            pressure_offset_pa: 2.5e4,
            transducers: Transducers::Shared,
            measurement_delay_ticks: 0,
            command_delay_ticks: 1,
        }
    }
}

/// Controller settings: gains from a desired closed-loop natural frequency and damping per joint,
/// stiffened against static friction ([`crate::run::gains`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ControllerConfig {
    /// Desired natural frequency per joint, rad/s: `K_P = M_ii(q0) ω²`.
    pub natural_frequency_rad_s: Vec<f64>,
    /// Desired damping ratio: `K_D = 2 ζ √(K_P M_ii(q0))`.
    pub damping_ratio: f64,
    /// The error at which the PD's torque reaches the joint's nominal static friction, rad.
    pub friction_error_rad: f64,
    /// The highest natural frequency the stiffening may reach, rad/s.
    pub max_natural_frequency_rad_s: f64,
    /// PID: how the integral gain is chosen.
    pub integral_rule: IntegralRule,
    /// Chen's observer: which gain design.
    pub chen_gain: ChenGain,
    /// PID with `integral_rule = "zero_ratio"`: the integral's zero as a fraction of the natural
    /// frequency, `K_I = K_P ω_n · this`.
    pub integral_zero_ratio: f64,
    /// PID: the integral torque's clamp per joint, N·m (anti-windup).
    pub integral_limit_nm: Vec<f64>,
    /// Torque limit per joint, N·m.
    pub torque_limit_nm: Vec<f64>,
    /// Bandwidth of every observer, rad/s (the paper's filter uses ζ = 0.8, ω1 = ω2 = this).
    pub observer_bandwidth_rad_s: f64,
    /// Control period, s.
    pub dt_s: f64,
    /// The controller's and observers' rigid body from this URDF (an identified one, from
    /// `hya identify`) instead of the robot's nominal one; the same joints. A relative path is
    /// taken from the scenario file's folder ([`Scenario::from_file`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub model_urdf: Option<String>,
    /// Joint friction the controller's model adds (`friction.toml` from `hya identify`): a
    /// feed-forward in the command, and a part of `d` the observers no longer have to find.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub friction_toml: Option<String>,
    /// The task-space controller of a [`Task::Cartesian`] scenario (required there, refused
    /// elsewhere); the joint-space gain settings above then act only through the observers'
    /// shared settings and the torque limits.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cartesian: Option<CartesianConfig>,
}

impl Default for ControllerConfig {
    fn default() -> Self {
        Self {
            natural_frequency_rad_s: vec![12.0; 6],
            damping_ratio: 0.8,
            friction_error_rad: 0.05,
            max_natural_frequency_rad_s: 40.0,
            integral_rule: IntegralRule::MatchEstimator,
            chen_gain: ChenGain::Inertia,
            integral_zero_ratio: 0.25,
            integral_limit_nm: vec![30.0; 6],
            torque_limit_nm: vec![150.0; 6],
            observer_bandwidth_rad_s: 50.0,
            dt_s: 1e-3,
            model_urdf: None,
            friction_toml: None,
            cartesian: None,
        }
    }
}

/// The gain `Y` of Chen's observer (`L = Y M⁻¹(q)`, its rates the eigenvalues of `L`), at the
/// observer bandwidth `β`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum ChenGain {
    /// `Y = β M(q0)`: `L = β I` at the start pose, every joint at rate `β` there (a
    /// well-conditioned design, ours).
    #[default]
    Inertia,
    /// The scalar gain of Chen et al. (2000) in Mohammadi's form, `Y = y I` with
    /// `y = β λmax(M(q0))` (`ξ = 0`): the slowest rate at the start pose is `β`, the light joints'
    /// are faster by the inertia ratio, and velocity noise reaches `d̂` through `y`.
    Scalar,
}

/// How the PID baseline's integral gain `K_I` is chosen, per joint.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum IntegralRule {
    /// The paper's estimator's low-frequency disturbance rejection. With `d̂ = H(s) d` and
    /// `1 − H(s) ≈ τ_d s` at low frequency (`τ_d = 1/ω1 + 2ζ/ω2` at the observer bandwidth), a
    /// disturbance leaves `q ≈ τ_d s d / K_P` under compensation and `q ≈ s d / K_I` under PID:
    /// equal when `K_I = K_P / τ_d`. The PID's loop `M s³ + K_D s² + K_P s + K_I` is stable only
    /// for `K_I < K_D K_P / M` (Routh), which the estimator's loop does not need; so `K_I` is
    /// capped at half that bound: `K_I = min(K_P / τ_d, ½ K_D K_P / M_ii(q0))`.
    #[default]
    MatchEstimator,
    /// `K_I = K_P ω_n · integral_zero_ratio`: the integral's zero at a fraction of the natural
    /// frequency (a conventional, softer choice).
    ZeroRatio,
    /// The PID tuned on its own terms: `K_P` as every method's (equal proportional stiffness),
    /// `K_D` and `K_I` placing the rigid joint's three closed-loop poles together,
    /// `M s³ + K_D s² + K_P s + K_I = M (s + ω)³`: `ω = √(K_P / 3M)`, `K_D = 3 M ω`,
    /// `K_I = M ω³` (stable without a cap: `K_I = K_D K_P / 9M`, a ninth of the Routh bound).
    PolePlacement,
}

/// The friction model of the plant.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum FrictionKind {
    /// No friction.
    Off,
    /// The first testbed's `tanh`-smoothed model: no stiction.
    Smooth,
    /// LuGre, with true stiction and seeded position-dependent levels.
    Lugre,
}

/// The actuator model of the plant.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ActuatorKind {
    /// The commanded torque acts at once.
    Ideal,
    /// The first testbed's first-order torque lag.
    Lag,
    /// Servo valves, chambers with compressible oil, inner torque loops.
    Hydraulic,
}

/// The simulated arm: how it differs from the controller's nominal model.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct PlantConfig {
    /// Relative spread of masses, centres of mass and inertias (uniform, seeded).
    pub parameter_spread: f64,
    /// The friction model.
    pub friction: FrictionKind,
    /// Coulomb friction per joint, N·m.
    pub coulomb_nm: Vec<f64>,
    /// Static (breakaway) friction per joint, N·m.
    pub static_nm: Vec<f64>,
    /// Viscous friction per joint (LuGre's `σ2`), N·m·s/rad.
    pub viscous_nm_s: Vec<f64>,
    /// Stribeck velocity, rad/s.
    pub stribeck_velocity_rad_s: f64,
    /// Velocity scale of the smooth model's sign `tanh(q̇ / ε)`, rad/s.
    pub smoothing_rad_s: f64,
    /// Relative variation of the friction levels with position: `1 + a sin(2 q)` for the smooth
    /// model, a seeded profile within `1 ± a` for LuGre.
    pub coulomb_position_variation: f64,
    /// LuGre bristle stiffness `σ0` per joint, N·m/rad.
    pub bristle_stiffness_nm_rad: Vec<f64>,
    /// LuGre bristle damping `σ1` per joint, N·m·s/rad.
    pub bristle_damping_nm_s_rad: Vec<f64>,
    /// The actuator model.
    pub actuator: ActuatorKind,
    /// Time constant of each joint's torque lag (`actuator = "lag"`), s.
    pub actuator_time_constant_s: Vec<f64>,
    /// The hydraulic actuators (`actuator = "hydraulic"`).
    pub hydraulic: HydraulicConfig,
    /// Physics steps per control period; unset, 2 ([`PlantConfig::substeps`]).
    pub substeps: Option<usize>,
}

impl PlantConfig {
    /// RK4 steps per control period: as set, or the fewest that keep the integration error
    /// under 1e-7 rad per 1 ms tick (a hundredth of an encoder count) against a ten times finer
    /// step along a goto move, measured by `tests/sim/integration_step.rs`:
    ///
    /// | actuator | 1 | 2 | 4 sub-steps |
    /// |---|---|---|---|
    /// | hydraulic | 5.2e-8 | 5.2e-8 | 1.4e-8 rad |
    /// | lag | 3.6e-7 | 3.5e-8 | 2.5e-8 rad |
    /// | ideal | 3.7e-7 | 2.6e-8 | 3.0e-9 rad |
    ///
    /// Each sub-step is cut further into equal RK4 cycles wherever the state's stiffest mode
    /// needs it ([`crate::plant::Plant::step`]): sliding bristles, and on hydraulic actuators
    /// the spool (`ω_v` = 1.6e3/s on HyA: a 1 ms step takes two cycles, which is why one and two
    /// sub-steps measure alike) and a chamber's pressure with its valve wide open near zero
    /// drop (the orifice law's stiff mode, from HyA's defaults 2.2e3 to 4.5e3/s at mid-stroke
    /// and 1.2e4/s at a stroke's end). Before that cut existed, the hydraulic plant took 4 sub-steps to keep the
    /// stiff mode inside RK4's stability region at mid-stroke (not at a stroke's end).
    pub fn substeps(&self) -> usize {
        self.substeps.unwrap_or(2)
    }
}

impl Default for PlantConfig {
    fn default() -> Self {
        Self {
            parameter_spread: 0.1,
            friction: FrictionKind::Lugre,
            coulomb_nm: vec![5.0, 5.0, 3.0, 3.0, 2.0, 2.0],
            static_nm: vec![6.5, 6.5, 3.9, 3.9, 2.6, 2.6],
            viscous_nm_s: vec![2.7, 2.7, 1.8, 1.8, 0.9, 0.9],
            stribeck_velocity_rad_s: 0.05,
            smoothing_rad_s: 0.05,
            coulomb_position_variation: 0.3,
            bristle_stiffness_nm_rad: vec![32_500.0, 32_500.0, 19_500.0, 19_500.0, 13_000.0, 13_000.0],
            bristle_damping_nm_s_rad: vec![270.0, 265.0, 62.0, 80.0, 17.0, 11.0],
            actuator: ActuatorKind::Hydraulic,
            actuator_time_constant_s: vec![0.004, 0.004, 0.008, 0.008, 0.015, 0.015],
            hydraulic: HydraulicConfig::default(),
            substeps: None,
        }
    }
}

/// The hydraulic actuators: supply, valves, chambers and the inner torque loop.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct HydraulicConfig {
    /// Supply pressure `p_s`, Pa (gauge).
    pub supply_pressure_pa: f64,
    /// Tank (return) pressure `p_t`, Pa (gauge).
    pub tank_pressure_pa: f64,
    /// Effective bulk modulus of the oil in chambers and hoses `β`, Pa.
    pub bulk_modulus_pa: f64,
    /// Cap-side displacement per radian `D_a` (piston area times lever arm), m³/rad, per joint.
    pub displacement_m3_rad: Vec<f64>,
    /// Rod-side over cap-side area `D_b / D_a` (1 for a rotary vane), per joint.
    pub area_ratio: Vec<f64>,
    /// Volume of each chamber at the end of its stroke, with its hose and manifold `V_0`, m³.
    pub dead_volume_m3: Vec<f64>,
    /// Each valve's rated flow `Q_n` at [`Self::valve_rated_drop_pa`], m³/s.
    pub valve_rated_flow_m3_s: Vec<f64>,
    /// The pressure drop across both lands at which the rated flow is given, Pa.
    pub valve_rated_drop_pa: f64,
    /// Spool natural frequency per joint, Hz.
    pub valve_natural_frequency_hz: Vec<f64>,
    /// Spool damping ratio.
    pub valve_damping_ratio: f64,
    /// Spool null bias per joint, fraction of full opening.
    pub valve_null_bias: Vec<f64>,
    /// Leakage across the piston `C_l`, m³/(s·Pa), per joint.
    pub leakage_m3_s_pa: Vec<f64>,
    /// Torque-loop bandwidth per joint on a locked joint at mid-range, Hz: sets `K_τ`.
    pub torque_bandwidth_hz: Vec<f64>,
    /// Zero of the inner loop's integral term as a fraction of its bandwidth (0 turns it off).
    pub torque_integral_ratio: f64,
    /// Fraction of the piston flow `D̄ q̇` the inner loop feeds forward to the valve (0 to 2).
    pub velocity_compensation: f64,
    /// The inner torque loop's sample rate, Hz (1 to 1e6): it runs every `1 / rate` s and holds
    /// its valve command between samples (HyQ's runs at 1 kHz).
    pub torque_loop_rate_hz: f64,
    /// Standard deviation of the noise of each pressure transducer the inner loop reads, Pa
    /// (fresh at every sample; as `sensors.pressure_noise_pa` by default).
    pub torque_loop_pressure_noise_pa: f64,
    /// Bound of each of those transducers' constant offsets (uniform, seeded), Pa (as
    /// `sensors.pressure_offset_pa` by default).
    pub torque_loop_pressure_offset_pa: f64,
    /// The inner loop's encoder, counts per revolution (1 to 2^53; as
    /// `sensors.encoder_counts_per_rev` by default): its load-motion compensation uses the
    /// backward difference of the rounded angle over the loop's period.
    pub torque_loop_encoder_counts_per_rev: u64,
    /// Cut-off of the first-order low-pass on that difference, Hz (0 to 1e6; 0: none).
    pub torque_loop_velocity_filter_hz: f64,
    /// The valve's dead band, fraction of full opening (0 to below 1): inner-loop outputs within
    /// it give no spool command, those beyond it are shifted by it.
    pub valve_dead_band: f64,
}

impl Default for HydraulicConfig {
    fn default() -> Self {
        Self {
            supply_pressure_pa: 20e6,
            tank_pressure_pa: 0.0,
            bulk_modulus_pa: 5e8,
            displacement_m3_rad: vec![6.3e-6, 6.0e-6, 6.0e-6, 1.125e-5, 3.0e-6, 5.0e-6],
            area_ratio: vec![1.0, 1.0, 1.0, 0.61, 1.0, 0.61],
            dead_volume_m3: vec![3e-6; 6],
            valve_rated_flow_m3_s: vec![4.17e-5; 6],
            valve_rated_drop_pa: 7e6,
            valve_natural_frequency_hz: vec![255.0; 6],
            valve_damping_ratio: 0.5,
            valve_null_bias: vec![0.0; 6],
            leakage_m3_s_pa: vec![1e-13; 6],
            torque_bandwidth_hz: vec![40.0; 6],
            torque_integral_ratio: 0.2,
            velocity_compensation: 1.0,
            torque_loop_rate_hz: 1000.0,
            torque_loop_pressure_noise_pa: 1e4,
            torque_loop_pressure_offset_pa: 2.5e4,
            torque_loop_encoder_counts_per_rev: 1 << 19,
            torque_loop_velocity_filter_hz: 0.0,
            valve_dead_band: 0.0,
        }
    }
}

/// A sensor's noise.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase", deny_unknown_fields)]
pub enum Noise {
    /// None.
    Off {},
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
    /// One count of HyA's 19-bit encoders on the angle; the velocity and torque noise measured
    /// on the hydraulic Atlas arm (uniform bounds), for a velocity sensor or a load cell.
    fn default() -> Self {
        Self {
            position: Noise::Uniform { bound: 1.2e-5 },
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
    /// Removal time, s; the weight stays on when absent.
    #[serde(default)]
    pub remove_s: Option<f64>,
    /// Fall height, m: the impact carries momentum `m √(2 g h)` downward.
    pub fall_height_m: f64,
    /// Duration of the impact pulse, s.
    pub impact_s: f64,
}

const BUILTIN: [(&str, &str); 7] = [
    ("goto_internal", include_str!("../../scenarios/goto_internal.toml")),
    ("sine_internal", include_str!("../../scenarios/sine_internal.toml")),
    ("goto_weight", include_str!("../../scenarios/goto_weight.toml")),
    ("sine_weight", include_str!("../../scenarios/sine_weight.toml")),
    ("estimator_noise_low", include_str!("../../scenarios/estimator_noise_low.toml")),
    ("estimator_noise_high", include_str!("../../scenarios/estimator_noise_high.toml")),
    ("estimator_noise_hydraulic", include_str!("../../scenarios/estimator_noise_hydraulic.toml")),
];

/// A goto task per shipped arm other than HyA (whose is `goto_internal`), `<robot>_goto`:
/// electric arms, with torque-controlled joints and joint-torque sensors.
const ARM_GOTO: [(&str, &str); 4] = [
    ("planar2_goto", include_str!("../../scenarios/planar2_goto.toml")),
    ("ur5_goto", include_str!("../../scenarios/ur5_goto.toml")),
    ("panda_goto", include_str!("../../scenarios/panda_goto.toml")),
    ("iiwa14_goto", include_str!("../../scenarios/iiwa14_goto.toml")),
];

/// Tasks set in task space, under the Cartesian impedance controller (`hya run` alone: the
/// paper's report is in joint space).
const TASK_SPACE: [(&str, &str); 1] = [("panda_cartesian", include_str!("../../scenarios/panda_cartesian.toml"))];

/// `Ok` if every scenario of `scenarios` runs the same robot, as one report covers one robot; the
/// error names two that differ.
pub fn shared_robot(scenarios: &[Scenario]) -> Result<(), SimError> {
    let Some(first) = scenarios.first() else { return Ok(()) };
    match scenarios.iter().find(|s| s.robot != first.robot) {
        None => Ok(()),
        Some(other) => Err(SettingError::new(
            "robot",
            None,
            format!(
                "one report covers one robot: `{}` runs `{}`, `{}` runs `{}`",
                first.name, first.robot, other.name, other.robot
            ),
        )
        .into()),
    }
}

/// `Ok` if `v` is finite and `lo ≤ v ≤ hi`; the error names the key.
fn within(name: &str, v: f64, lo: f64, hi: f64) -> Result<(), SettingError> {
    if v.is_finite() && (lo..=hi).contains(&v) {
        Ok(())
    } else {
        Err(SettingError::new(name, Some(v), format!("must be finite, between {} and {}", Short(lo), Short(hi))))
    }
}

/// The plausible range of each physical setting of a real arm, `(key, low, high, unit)`: a value
/// outside is refused unless the scenario sets `allow_unphysical = true`. Per-joint lists are
/// checked entry by entry. The ranges are wide (orders of magnitude around HyA's and the electric
/// arms' figures); they catch unit mistakes, not design choices.
pub const PLAUSIBLE: [(&str, f64, f64, &str); 33] = [
    ("plant.coulomb_nm", 0.0, 1e4, "N·m"),
    ("plant.static_nm", 0.0, 1e4, "N·m"),
    ("plant.viscous_nm_s", 0.0, 1e4, "N·m·s/rad"),
    ("plant.stribeck_velocity_rad_s", 1e-5, 10.0, "rad/s"),
    ("plant.smoothing_rad_s", 1e-6, 10.0, "rad/s"),
    ("plant.coulomb_position_variation", 0.0, 0.9, ""),
    ("plant.bristle_stiffness_nm_rad", 1.0, 1e9, "N·m/rad"),
    ("plant.bristle_damping_nm_s_rad", 0.0, 1e6, "N·m·s/rad"),
    ("plant.actuator_time_constant_s", 1e-5, 10.0, "s"),
    ("plant.hydraulic.supply_pressure_pa", 1e5, 1e8, "Pa"),
    ("plant.hydraulic.tank_pressure_pa", 0.0, 1e7, "Pa"),
    ("plant.hydraulic.bulk_modulus_pa", 1e7, 1e10, "Pa"),
    ("plant.hydraulic.displacement_m3_rad", 1e-8, 1e-2, "m³/rad"),
    ("plant.hydraulic.area_ratio", 0.05, 20.0, ""),
    ("plant.hydraulic.dead_volume_m3", 1e-8, 0.1, "m³"),
    ("plant.hydraulic.valve_rated_flow_m3_s", 1e-7, 0.1, "m³/s"),
    ("plant.hydraulic.valve_rated_drop_pa", 1e4, 1e8, "Pa"),
    ("plant.hydraulic.valve_natural_frequency_hz", 1.0, 5e3, "Hz"),
    ("plant.hydraulic.valve_damping_ratio", 0.05, 10.0, ""),
    ("plant.hydraulic.leakage_m3_s_pa", 0.0, 1e-9, "m³/(s·Pa)"),
    ("plant.hydraulic.torque_bandwidth_hz", 0.1, 1e3, "Hz"),
    ("plant.hydraulic.torque_integral_ratio", 0.0, 10.0, ""),
    ("plant.hydraulic.velocity_compensation", 0.0, 2.0, ""),
    ("plant.hydraulic.torque_loop_rate_hz", 50.0, 1e5, "Hz"),
    ("plant.hydraulic.torque_loop_pressure_noise_pa", 0.0, 1e7, "Pa"),
    ("plant.hydraulic.torque_loop_pressure_offset_pa", 0.0, 1e7, "Pa"),
    ("plant.hydraulic.torque_loop_encoder_counts_per_rev", 256.0, 9007199254740992.0, "counts/rev"),
    ("plant.hydraulic.torque_loop_velocity_filter_hz", 0.0, 1e5, "Hz"),
    ("plant.hydraulic.valve_dead_band", 0.0, 0.5, ""),
    ("sensors.velocity_cutoff_rad_s", 1.0, 1e5, "rad/s"),
    ("sensors.pressure_noise_pa", 0.0, 1e7, "Pa"),
    ("sensors.pressure_offset_pa", 0.0, 1e7, "Pa"),
    ("loads.sinusoid.amplitude_nm", -1e4, 1e4, "N·m"),
];

/// `Ok` if every value of `key` lies in its [`PLAUSIBLE`] range.
fn plausible(key: &str, values: &[f64]) -> Result<(), SettingError> {
    // A key without a range would pass unchecked: a misspelt key is refused instead, so the
    // built-in scenarios' checks (tested) catch it.
    let Some(&(_, lo, hi, unit)) = PLAUSIBLE.iter().find(|(k, ..)| *k == key) else {
        return Err(SettingError::new(key, None, "has no plausible range in hya_sim::scenario::PLAUSIBLE (a bug)"));
    };
    match values.iter().position(|v| !(lo..=hi).contains(v)) {
        None => Ok(()),
        Some(i) => {
            let index = if values.len() > 1 { format!("[{i}]") } else { String::new() };
            Err(SettingError::new(
                format!("{key}{index}"),
                Some(values[i]),
                format!(
                    "beyond the plausible range {} to {} {unit} (a unit mistake?); set allow_unphysical = true to run \
                     it anyway",
                    Short(lo),
                    Short(hi)
                ),
            ))
        }
    }
}

impl Task {
    /// Checks every number of the task against the run's `duration`.
    fn validate(&self, duration: f64) -> Result<(), SettingError> {
        match self {
            Task::Hold {} => Ok(()),
            Task::Goto { start_s, transition_s, delta_rad } => {
                within("task.start_s", *start_s, 0.0, duration)?;
                within("task.transition_s", *transition_s, 1e-3, 1e4)?;
                for (i, d) in delta_rad.iter().enumerate() {
                    within(&format!("task.delta_rad[{i}]"), *d, -std::f64::consts::TAU, std::f64::consts::TAU)?;
                }
                Ok(())
            }
            Task::Sine { amplitude_rad, frequency_hz, ramp_s } => {
                for (i, a) in amplitude_rad.iter().enumerate() {
                    within(&format!("task.amplitude_rad[{i}]"), *a, -std::f64::consts::TAU, std::f64::consts::TAU)?;
                }
                within("task.frequency_hz", *frequency_hz, 1e-6, 100.0)?;
                within("task.ramp_s", *ramp_s, 0.0, 1e4)
            }
            Task::Cartesian { start_s, transition_s, offset_m, rotation_rad } => {
                within("task.start_s", *start_s, 0.0, duration)?;
                within("task.transition_s", *transition_s, 1e-3, 1e4)?;
                // The study's final window starts 1 s after the move.
                if start_s + transition_s + 1.0 >= duration {
                    return Err(SettingError::new(
                        "task.start_s + task.transition_s",
                        Some(start_s + transition_s),
                        format!(
                            "must end more than 1 s before duration_s = {} (the frame is judged holding the moved pose)",
                            Short(duration)
                        ),
                    ));
                }
                three("task.offset_m", offset_m, 10.0)?;
                three("task.rotation_rad", rotation_rad, std::f64::consts::PI)?;
                let turn = rotation_rad.iter().map(|r| r * r).sum::<f64>().sqrt();
                if turn >= std::f64::consts::PI {
                    return Err(SettingError::new(
                        "task.rotation_rad",
                        Some(turn),
                        "its norm (the angle turned) must be below π: a half turn's direction is ambiguous",
                    ));
                }
                Ok(())
            }
        }
    }

    /// Whether the task is set in task space (the controller is then Cartesian).
    pub fn is_cartesian(&self) -> bool {
        matches!(self, Task::Cartesian { .. })
    }
}

/// `Ok` if `values` holds three numbers within `±bound`; the error names the key.
fn three(key: &str, values: &[f64], bound: f64) -> Result<(), SettingError> {
    if values.len() != 3 {
        return Err(SettingError::new(key, Some(values.len() as f64), "needs three values (x, y, z in the base)"));
    }
    for (i, v) in values.iter().enumerate() {
        within(&format!("{key}[{i}]"), *v, -bound, bound)?;
    }
    Ok(())
}

impl CartesianConfig {
    /// Checks the six task-space gains (finite, `≥ 0`, below 10⁶); the posture lists are
    /// checked per joint with the arm ([`crate::config::settings::Setup`]).
    fn validate(&self) -> Result<(), SettingError> {
        for (key, values) in
            [("controller.cartesian.stiffness", &self.stiffness), ("controller.cartesian.damping", &self.damping)]
        {
            if values.len() != 6 {
                return Err(SettingError::new(
                    key,
                    Some(values.len() as f64),
                    "needs six values: three linear (N/m or N·s/m), then three angular (N·m/rad or N·m·s/rad)",
                ));
            }
            for (i, v) in values.iter().enumerate() {
                within(&format!("{key}[{i}]"), *v, 0.0, 1e6)?;
            }
        }
        Ok(())
    }
}

impl Scenario {
    /// Parses and checks a scenario; `source` names it in errors.
    pub fn from_toml(text: &str, source: &str) -> Result<Self, SimError> {
        let scenario: Scenario =
            toml::from_str(text).map_err(|e| SimError::Scenario { origin: source.into(), message: e.to_string() })?;
        scenario.validate().map_err(|setting| SimError::InvalidScenario { origin: source.into(), setting })?;
        Ok(scenario)
    }

    /// The paths of the files a run of this scenario reads: the robot (if a URDF rather than a
    /// shipped arm's name), the controller's model and friction. For `--force`, which must not
    /// remove any of them ([`crate::output::OutputDir::open`]).
    pub fn files_read(&self) -> impl Iterator<Item = &std::path::Path> {
        let controller = [&self.controller.model_urdf, &self.controller.friction_toml];
        std::iter::once(&self.robot).chain(controller.into_iter().flatten()).map(std::path::Path::new)
    }

    /// Reads, parses and checks the scenario file at `path` (at most [`MAX_SCENARIO_BYTES`]).
    /// Relative paths in it (`robot` where it is not a shipped arm's name,
    /// `controller.model_urdf`, `controller.friction_toml`) are taken relative to the file's
    /// folder, as MuJoCo's and ROS's files take theirs, not to the working directory.
    pub fn from_file(path: &std::path::Path) -> Result<Self, SimError> {
        let origin = path.display().to_string();
        let text = crate::io::input::read_text(path, MAX_SCENARIO_BYTES)
            .map_err(|message| SimError::Scenario { origin: origin.clone(), message })?;
        let mut scenario = Self::from_toml(&text, &origin)?;
        if let Some(folder) = path.parent().filter(|f| !f.as_os_str().is_empty()) {
            let resolve = |p: &mut String| {
                if std::path::Path::new(p.as_str()).is_relative() {
                    *p = folder.join(p.as_str()).display().to_string();
                }
            };
            // A bare word that is no shipped arm's name and names no file beside the scenario
            // stays a name, for the message that suggests the nearest arm.
            let path_like = |p: &str| p.contains(std::path::MAIN_SEPARATOR) || p.contains('/') || p.ends_with(".urdf");
            let beside = |p: &str| folder.join(p).exists();
            if hya_robots::find(&scenario.robot).is_none() && (path_like(&scenario.robot) || beside(&scenario.robot)) {
                resolve(&mut scenario.robot);
            }
            scenario
                .controller
                .model_urdf
                .iter_mut()
                .chain(scenario.controller.friction_toml.iter_mut())
                .for_each(resolve);
        }
        Ok(scenario)
    }

    /// The scenario file at `name`, if one stands there, else the built-in scenario of that
    /// name; neither is an error that lists the built-in names and suggests the nearest.
    pub fn file_or_builtin(name: &str) -> Result<Self, SimError> {
        let path = std::path::Path::new(name);
        if std::fs::symlink_metadata(path).is_ok() {
            return Self::from_file(path);
        }
        if let Ok(scenario) = Self::builtin(name) {
            return Ok(scenario);
        }
        let names: Vec<&str> =
            Self::builtin_names().chain(Self::arm_goto_names()).chain(Self::task_space_names()).collect();
        let suggestion = hya_core::closest(name, names.iter().copied())
            .map(|near| format!("; did you mean `{near}`?"))
            .unwrap_or_default();
        Err(SimError::Scenario {
            origin: hya_core::Clipped(name, 60).to_string(),
            message: format!(
                "neither a scenario file nor a built-in scenario ({}){suggestion} (`hya scenarios` describes them)",
                names.join(", ")
            ),
        })
    }

    /// The names of the embedded scenarios, in the order `hya reproduce` runs them.
    pub fn builtin_names() -> impl Iterator<Item = &'static str> {
        BUILTIN.iter().map(|(name, _)| *name)
    }

    /// The names of the embedded goto tasks of the other shipped arms (`ur5_goto`, …).
    pub fn arm_goto_names() -> impl Iterator<Item = &'static str> {
        ARM_GOTO.iter().map(|(name, _)| *name)
    }

    /// The names of the embedded task-space scenarios (`panda_cartesian`).
    pub fn task_space_names() -> impl Iterator<Item = &'static str> {
        TASK_SPACE.iter().map(|(name, _)| *name)
    }

    /// An embedded scenario by name: one of the paper's experiments or an arm's goto task.
    pub fn builtin(name: &str) -> Result<Self, SimError> {
        let (_, text) =
            BUILTIN.iter().chain(&ARM_GOTO).chain(&TASK_SPACE).find(|(n, _)| *n == name).ok_or_else(|| {
                SimError::Scenario { origin: name.into(), message: "no such built-in scenario".into() }
            })?;
        Self::from_toml(text, name)
    }

    /// One point of a sweep over this scenario: a copy named `<name>_<tag>` that runs only
    /// `method`, with `change` applied to it.
    pub fn variant(&self, tag: &str, method: Method, change: impl FnOnce(&mut Scenario)) -> Scenario {
        let mut variant = self.clone();
        variant.name = format!("{}_{tag}", self.name);
        variant.methods = vec![method];
        change(&mut variant);
        variant
    }

    /// The shortened version for `--quick`: event times and duration scaled.
    pub fn quick(&self) -> Self {
        let k = self.quick_time_scale;
        let mut quick = self.clone();
        quick.duration_s *= k;
        if let Task::Goto { start_s, .. } | Task::Cartesian { start_s, .. } = &mut quick.task {
            *start_s *= k;
        }
        if let Some(drop) = &mut quick.loads.weight_drop {
            drop.drop_s *= k;
            drop.remove_s = drop.remove_s.map(|r| r * k);
        }
        quick
    }

    /// Checks every setting, as [`Self::from_toml`] does (for a scenario changed after parsing,
    /// e.g. by [`Self::quick`]).
    pub fn check(&self) -> Result<(), SimError> {
        self.validate().map_err(|setting| SimError::InvalidScenario { origin: self.name.clone(), setting })
    }

    /// Every physical setting within its [`PLAUSIBLE`] range.
    fn check_plausible(&self) -> Result<(), SettingError> {
        let (p, h, s) = (&self.plant, &self.plant.hydraulic, &self.sensors);
        let lists: [(&str, &[f64]); 30] = [
            ("plant.coulomb_nm", &p.coulomb_nm),
            ("plant.static_nm", &p.static_nm),
            ("plant.viscous_nm_s", &p.viscous_nm_s),
            ("plant.stribeck_velocity_rad_s", &[p.stribeck_velocity_rad_s]),
            ("plant.smoothing_rad_s", &[p.smoothing_rad_s]),
            ("plant.coulomb_position_variation", &[p.coulomb_position_variation]),
            ("plant.bristle_stiffness_nm_rad", &p.bristle_stiffness_nm_rad),
            ("plant.bristle_damping_nm_s_rad", &p.bristle_damping_nm_s_rad),
            ("plant.actuator_time_constant_s", &p.actuator_time_constant_s),
            ("plant.hydraulic.supply_pressure_pa", &[h.supply_pressure_pa]),
            ("plant.hydraulic.tank_pressure_pa", &[h.tank_pressure_pa]),
            ("plant.hydraulic.bulk_modulus_pa", &[h.bulk_modulus_pa]),
            ("plant.hydraulic.displacement_m3_rad", &h.displacement_m3_rad),
            ("plant.hydraulic.area_ratio", &h.area_ratio),
            ("plant.hydraulic.dead_volume_m3", &h.dead_volume_m3),
            ("plant.hydraulic.valve_rated_flow_m3_s", &h.valve_rated_flow_m3_s),
            ("plant.hydraulic.valve_rated_drop_pa", &[h.valve_rated_drop_pa]),
            ("plant.hydraulic.valve_natural_frequency_hz", &h.valve_natural_frequency_hz),
            ("plant.hydraulic.valve_damping_ratio", &[h.valve_damping_ratio]),
            ("plant.hydraulic.leakage_m3_s_pa", &h.leakage_m3_s_pa),
            ("plant.hydraulic.torque_bandwidth_hz", &h.torque_bandwidth_hz),
            ("plant.hydraulic.torque_integral_ratio", &[h.torque_integral_ratio]),
            ("plant.hydraulic.velocity_compensation", &[h.velocity_compensation]),
            ("plant.hydraulic.torque_loop_rate_hz", &[h.torque_loop_rate_hz]),
            ("plant.hydraulic.torque_loop_pressure_noise_pa", &[h.torque_loop_pressure_noise_pa]),
            ("plant.hydraulic.torque_loop_pressure_offset_pa", &[h.torque_loop_pressure_offset_pa]),
            ("plant.hydraulic.torque_loop_encoder_counts_per_rev", &[h.torque_loop_encoder_counts_per_rev as f64]),
            ("plant.hydraulic.torque_loop_velocity_filter_hz", &[h.torque_loop_velocity_filter_hz]),
            ("plant.hydraulic.valve_dead_band", &[h.valve_dead_band]),
            ("sensors.velocity_cutoff_rad_s", &[s.velocity_cutoff_rad_s]),
        ];
        for (key, values) in lists {
            plausible(key, values)?;
        }
        plausible("sensors.pressure_noise_pa", &[s.pressure_noise_pa])?;
        plausible("sensors.pressure_offset_pa", &[s.pressure_offset_pa])?;
        if let Some(sinusoid) = &self.loads.sinusoid {
            plausible("loads.sinusoid.amplitude_nm", &sinusoid.amplitude_nm)?;
        }
        Ok(())
    }

    fn validate(&self) -> Result<(), SettingError> {
        let positive = |name: &str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(SettingError::new(name, Some(v), "must be finite and > 0"))
            }
        };
        check_file_stem(&self.name)
            .map_err(|why| SettingError::new("name", None, format!("\"{}\" {why}", Clipped(&self.name, 40))))?;
        let dt = self.controller.dt_s;
        within("controller.dt_s", dt, 1e-5, 0.1)?;
        positive("controller.dt_s", dt)?;
        if !(self.duration_s.is_finite() && self.duration_s > WARM_UP_S + dt) {
            return Err(SettingError::new(
                "duration_s",
                Some(self.duration_s),
                format!("must be longer than the {WARM_UP_S} s warm-up the metrics skip, plus one tick"),
            ));
        }
        if self.duration_s / dt > MAX_TICKS as f64 {
            return Err(SettingError::new(
                "duration_s / controller.dt_s",
                Some(self.duration_s / dt),
                format!("at most {MAX_TICKS} ticks (an hour at 1 kHz; each tick's trace is kept)"),
            ));
        }
        positive("controller.observer_bandwidth_rad_s", self.controller.observer_bandwidth_rad_s)?;
        within(
            "controller.observer_bandwidth_rad_s × controller.dt_s",
            self.controller.observer_bandwidth_rad_s * dt,
            0.0,
            hya_core::MAX_RATE_TIMES_DT,
        )?;
        positive("controller.friction_error_rad", self.controller.friction_error_rad)?;
        positive("controller.max_natural_frequency_rad_s", self.controller.max_natural_frequency_rad_s)?;
        positive("controller.integral_zero_ratio", self.controller.integral_zero_ratio)?;
        within("controller.damping_ratio", self.controller.damping_ratio, 0.05, 10.0)?;
        within("quick_time_scale", self.quick_time_scale, 1e-3, 1.0)?;
        for (name, values, lo, hi) in [
            ("controller.natural_frequency_rad_s", &self.controller.natural_frequency_rad_s, 1e-3, 1e3),
            ("controller.torque_limit_nm", &self.controller.torque_limit_nm, 1e-6, 1e6),
            ("controller.integral_limit_nm", &self.controller.integral_limit_nm, 0.0, 1e6),
        ] {
            for (i, v) in values.iter().enumerate() {
                within(&format!("{name}[{i}]"), *v, lo, hi)?;
            }
        }
        within("plant.parameter_spread", self.plant.parameter_spread, 0.0, 0.9)?;
        positive("plant.smoothing_rad_s", self.plant.smoothing_rad_s)?;
        positive("plant.stribeck_velocity_rad_s", self.plant.stribeck_velocity_rad_s)?;
        positive("sensors.velocity_cutoff_rad_s", self.sensors.velocity_cutoff_rad_s)?;
        if let Some(q0) = &self.initial_position_rad {
            for (i, q) in q0.iter().enumerate() {
                within(&format!("initial_position_rad[{i}]"), *q, -100.0, 100.0)?;
            }
        }
        self.task.validate(self.duration_s)?;
        match (&self.task, &self.controller.cartesian) {
            (Task::Cartesian { .. }, None) => {
                return Err(SettingError::new(
                    "controller.cartesian",
                    None,
                    "a task of kind cartesian needs the impedance's gains (stiffness, damping, posture_stiffness_nm_rad, posture_damping_nm_s_rad)",
                ))
            }
            (Task::Cartesian { .. }, Some(gains)) => gains.validate()?,
            (_, Some(_)) => {
                return Err(SettingError::new(
                    "controller.cartesian",
                    None,
                    "acts only with a task of kind cartesian; this scenario's controller works in joint space",
                ))
            }
            (_, None) => {}
        }
        if self.task.is_cartesian() && self.methods.contains(&Method::Pid) {
            return Err(SettingError::new(
                "methods",
                None,
                "pid's integral acts on joint errors, which a task of kind cartesian does not have: name none, lu, chen, momentum or eso",
            ));
        }
        for (name, noise) in [
            ("noise.position", self.noise.position),
            ("noise.velocity", self.noise.velocity),
            ("noise.torque", self.noise.torque),
        ] {
            match noise {
                Noise::Off {} => {}
                Noise::Uniform { bound } => within(&format!("{name}.bound"), bound, 0.0, 1e3)?,
                Noise::Gaussian { sigma } => within(&format!("{name}.sigma"), sigma, 0.0, 1e3)?,
            }
        }
        if let Some(s) = &self.loads.sinusoid {
            for (i, a) in s.amplitude_nm.iter().enumerate() {
                within(&format!("loads.sinusoid.amplitude_nm[{i}]"), *a, -1e4, 1e4)?;
            }
            within("loads.sinusoid.frequency_hz", s.frequency_hz, 1e-6, 1e3)?;
        }
        for (key, v) in [
            ("sensors.pressure_noise_pa", self.sensors.pressure_noise_pa),
            ("sensors.pressure_offset_pa", self.sensors.pressure_offset_pa),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(SettingError::new(key, Some(v), "must be finite and ≥ 0"));
            }
        }
        within(
            "sensors.encoder_counts_per_rev",
            self.sensors.encoder_counts_per_rev as f64,
            16.0,
            (1u64 << 40) as f64,
        )?;
        within("sensors.measurement_delay_ticks", self.sensors.measurement_delay_ticks as f64, 0.0, 100.0)?;
        within("sensors.command_delay_ticks", self.sensors.command_delay_ticks as f64, 0.0, 100.0)?;
        within("plant.substeps", self.plant.substeps() as f64, 1.0, 1000.0)?;
        if self.methods.is_empty() {
            return Err(SettingError::new("methods", None, "name at least one of none, pid, lu, chen, momentum, eso"));
        }
        if let Some(twice) =
            self.methods.iter().enumerate().find_map(|(i, m)| self.methods[..i].contains(m).then_some(m))
        {
            return Err(SettingError::new(
                "methods",
                None,
                format!("`{}` is named twice (its runs would be pooled as if they were more seeds)", twice.name()),
            ));
        }
        if !self.allow_unphysical {
            self.check_plausible()?;
        }
        if let Some(drop) = &self.loads.weight_drop {
            within("loads.weight_drop.mass_kg", drop.mass_kg, 1e-6, 1e3)?;
            within("loads.weight_drop.impact_s", drop.impact_s, 1e-6, 1.0)?;
            within("loads.weight_drop.drop_s", drop.drop_s, 0.0, 1e7)?;
            within("loads.weight_drop.fall_height_m", drop.fall_height_m, 0.0, 10.0)?;
            if let Some(remove) = drop.remove_s.filter(|r| !r.is_finite() || *r <= drop.drop_s) {
                return Err(SettingError::new(
                    "loads.weight_drop.remove_s",
                    Some(remove),
                    format!("must come after drop_s = {}", Short(drop.drop_s)),
                ));
            }
        }
        Ok(())
    }
}
