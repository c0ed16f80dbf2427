//! The plant of a scenario, checked once for an arm of `N` joints: the friction law and the
//! actuators as data-carrying enums, so that the plant receives the settings of its own kind and
//! nothing else ([`PlantSetup`]). Every rule the plant relies on (`F_s ≥ F_c > 0`, the tank below
//! the supply, an integral ratio in `[0, 1]`, …) is checked here, with the key named, and the
//! weight drop's frame against the arm ([`PlantSetup::check_against`]); building the plant from a
//! setup so checked cannot fail on a setting.

use hya_core::model::TreeModel;
use hya_core::JointVector;

use crate::config::lists::{per_joint, per_joint_where, scalar};
use crate::config::scenario::{ActuatorKind, FrictionKind, HydraulicConfig, LoadConfig, PlantConfig, WeightDrop};
use crate::error::{SettingError, SimError};

/// The friction levels every law shares, per joint where they are lists.
#[derive(Debug, Clone, PartialEq)]
pub struct FrictionLevels<const N: usize> {
    /// Coulomb level `F_c > 0`, N·m.
    pub coulomb: JointVector<N>,
    /// Static (breakaway) level `F_s ≥ F_c`, N·m.
    pub breakaway: JointVector<N>,
    /// Viscous coefficient `σ2 ≥ 0`, N·m·s/rad.
    pub viscous: JointVector<N>,
    /// Stribeck velocity `v_s > 0`, rad/s.
    pub stribeck_velocity: f64,
    /// Relative variation of the levels with position `a`, in `[0, 1)` (friction stays positive).
    pub position_variation: f64,
}

/// The friction law and its settings.
#[derive(Debug, Clone, PartialEq)]
pub enum FrictionSetup<const N: usize> {
    /// No friction.
    Off,
    /// The smooth model, its sign smoothed by `tanh(q̇ / ε)`, `ε > 0` in rad/s.
    Smooth {
        /// The levels.
        levels: FrictionLevels<N>,
        /// `ε`, rad/s.
        smoothing: f64,
    },
    /// LuGre, with bristle stiffness `σ0 > 0` and damping `σ1 ≥ 0` per joint.
    LuGre {
        /// The levels.
        levels: FrictionLevels<N>,
        /// `σ0`, N·m/rad.
        stiffness: JointVector<N>,
        /// `σ1`, N·m·s/rad.
        damping: JointVector<N>,
    },
}

/// The hydraulic actuators' figures and the inner torque loop's settings, checked (see
/// [`HydraulicConfig`] for units).
#[derive(Debug, Clone, PartialEq)]
pub struct HydraulicSetup<const N: usize> {
    /// Supply pressure `p_s > 0`, Pa.
    pub supply_pressure: f64,
    /// Tank pressure `0 ≤ p_t < p_s`, Pa.
    pub tank_pressure: f64,
    /// Bulk modulus `β > 0`, Pa.
    pub bulk_modulus: f64,
    /// The valve's rated pressure drop `Δp_n > 0`, Pa.
    pub rated_drop: f64,
    /// The spool's damping ratio `ζ_v > 0`.
    pub valve_damping: f64,
    /// The integral zero over the torque bandwidth, in `[0, 1]`.
    pub torque_integral_ratio: f64,
    /// The load-motion compensation `k_vc`, in `[0, 2]` (1 cancels the piston flow).
    pub velocity_compensation: f64,
    /// Cap-side displacement `D_a`, m³/rad.
    pub displacement: JointVector<N>,
    /// `D_b / D_a`.
    pub area_ratio: JointVector<N>,
    /// Dead volume `V_0`, m³.
    pub dead_volume: JointVector<N>,
    /// Rated valve flow `Q_n`, m³/s.
    pub rated_flow: JointVector<N>,
    /// Spool natural frequency, Hz.
    pub valve_frequency_hz: JointVector<N>,
    /// Torque-loop bandwidth, Hz.
    pub torque_bandwidth_hz: JointVector<N>,
    /// Spool null bias, fraction of full opening, within ±0.2.
    pub null_bias: JointVector<N>,
    /// Leakage `C_l ≥ 0`, m³/(s·Pa).
    pub leakage: JointVector<N>,
    /// The inner torque loop's sample rate, Hz, within [`TORQUE_LOOP_RATE_HZ`].
    pub torque_loop_rate_hz: f64,
    /// Its pressure transducers' noise (standard deviation, ≥ 0), Pa.
    pub torque_loop_pressure_noise_pa: f64,
    /// Their offsets' bound (≥ 0), Pa.
    pub torque_loop_pressure_offset_pa: f64,
    /// Its encoder's counts per revolution, 1 to 2^53.
    pub torque_loop_encoder_counts_per_rev: u64,
    /// Cut-off of its derived velocity's low-pass, Hz (0: none), within [`TORQUE_LOOP_RATE_HZ`]'s
    /// upper bound.
    pub torque_loop_velocity_filter_hz: f64,
    /// The valve's dead band, fraction of full opening, in `[0, 1)`.
    pub valve_dead_band: f64,
}

/// How the commanded torque reaches the joints, with the settings of that kind.
#[derive(Debug, Clone, PartialEq)]
pub enum ActuatorSetup<const N: usize> {
    /// `τ_act = τ_cmd`.
    Ideal,
    /// `τ̇_act = (τ_cmd − τ_act) / T`, per joint `T > 0`, s.
    Lag(JointVector<N>),
    /// Servo valves, chambers and inner torque loops.
    Hydraulic(Box<HydraulicSetup<N>>),
}

/// A sinusoidal joint torque `A_i sin(2π f t + i π/3)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SinusoidLoad<const N: usize> {
    /// `A_i`, N·m.
    pub amplitude: JointVector<N>,
    /// `f`, Hz.
    pub frequency_hz: f64,
}

/// The external loads.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadSetup<const N: usize> {
    /// The sinusoidal load.
    pub sinusoid: Option<SinusoidLoad<N>>,
    /// The weight dropped on a link (its frame checked against the arm by
    /// [`PlantSetup::check_against`]).
    pub weight_drop: Option<WeightDrop>,
}

/// Everything the plant is built from.
#[derive(Debug, Clone, PartialEq)]
pub struct PlantSetup<const N: usize> {
    /// The friction law.
    pub friction: FrictionSetup<N>,
    /// The actuators.
    pub actuators: ActuatorSetup<N>,
    /// The external loads.
    pub loads: LoadSetup<N>,
}

/// The inner torque loop's sample rates simulated, Hz: from 1 Hz to 1 MHz (each sample above
/// the physics step's rate costs an RK4 step).
pub const TORQUE_LOOP_RATE_HZ: (f64, f64) = (1.0, 1e6);

/// The most counts per revolution of the inner loop's encoder: 2^53 (a resolution of 7e-16 rad,
/// the angle's own rounding near 1 rad; more would not be finer).
pub const MAX_ENCODER_COUNTS: u64 = 1 << 53;

impl<const N: usize> HydraulicSetup<N> {
    /// Checks and converts the hydraulic settings `h`: the per-joint lists first (so that a
    /// check of every list's length sees them all), then the scalars.
    pub fn of(h: &HydraulicConfig) -> Result<Self, SimError> {
        let key = |name: &str| format!("plant.hydraulic.{name}");
        let positive = |name: &str, v: f64| scalar(&key(name), v, |v| v > 0.0, "must be finite and > 0");
        let list = |name: &str, values: &[f64], ok: fn(f64) -> bool, requirement: &str| {
            per_joint_where::<N>(&key(name), values, ok, requirement)
        };
        let displacement = list("displacement_m3_rad", &h.displacement_m3_rad, |v| v > 0.0, "must be > 0")?;
        let area_ratio = list("area_ratio", &h.area_ratio, |v| v > 0.0, "must be > 0")?;
        let dead_volume = list("dead_volume_m3", &h.dead_volume_m3, |v| v > 0.0, "must be > 0")?;
        let rated_flow = list("valve_rated_flow_m3_s", &h.valve_rated_flow_m3_s, |v| v > 0.0, "must be > 0")?;
        let valve_frequency_hz =
            list("valve_natural_frequency_hz", &h.valve_natural_frequency_hz, |v| v > 0.0, "must be > 0")?;
        let torque_bandwidth_hz = list("torque_bandwidth_hz", &h.torque_bandwidth_hz, |v| v > 0.0, "must be > 0")?;
        let null_bias =
            list("valve_null_bias", &h.valve_null_bias, |b| b.abs() <= 0.2, "is beyond ±0.2 of full opening")?;
        let leakage = list("leakage_m3_s_pa", &h.leakage_m3_s_pa, |l| l >= 0.0, "must be ≥ 0")?;
        let supply = positive("supply_pressure_pa", h.supply_pressure_pa)?;
        Ok(Self {
            supply_pressure: supply,
            tank_pressure: scalar(
                &key("tank_pressure_pa"),
                h.tank_pressure_pa,
                |t| t >= 0.0 && t < supply,
                format!("must be ≥ 0 and below the supply pressure {}", hya_core::Short(supply)),
            )?,
            bulk_modulus: positive("bulk_modulus_pa", h.bulk_modulus_pa)?,
            rated_drop: positive("valve_rated_drop_pa", h.valve_rated_drop_pa)?,
            valve_damping: positive("valve_damping_ratio", h.valve_damping_ratio)?,
            torque_integral_ratio: scalar(
                &key("torque_integral_ratio"),
                h.torque_integral_ratio,
                |r| (0.0..=1.0).contains(&r),
                "must be in [0, 1]",
            )?,
            velocity_compensation: scalar(
                &key("velocity_compensation"),
                h.velocity_compensation,
                |k| (0.0..=2.0).contains(&k),
                "must be in [0, 2] (1 cancels the piston flow)",
            )?,
            displacement,
            area_ratio,
            dead_volume,
            rated_flow,
            valve_frequency_hz,
            torque_bandwidth_hz,
            null_bias,
            leakage,
            torque_loop_rate_hz: scalar(
                &key("torque_loop_rate_hz"),
                h.torque_loop_rate_hz,
                |r| (TORQUE_LOOP_RATE_HZ.0..=TORQUE_LOOP_RATE_HZ.1).contains(&r),
                "must be finite, between 1 and 1e6 Hz",
            )?,
            torque_loop_pressure_noise_pa: scalar(
                &key("torque_loop_pressure_noise_pa"),
                h.torque_loop_pressure_noise_pa,
                |v| v >= 0.0,
                "must be finite and ≥ 0",
            )?,
            torque_loop_pressure_offset_pa: scalar(
                &key("torque_loop_pressure_offset_pa"),
                h.torque_loop_pressure_offset_pa,
                |v| v >= 0.0,
                "must be finite and ≥ 0",
            )?,
            torque_loop_encoder_counts_per_rev: match h.torque_loop_encoder_counts_per_rev {
                n @ 1..=MAX_ENCODER_COUNTS => n,
                n => {
                    return Err(SettingError::new(
                        key("torque_loop_encoder_counts_per_rev"),
                        Some(n as f64),
                        "must be between 1 and 2^53",
                    )
                    .into())
                }
            },
            torque_loop_velocity_filter_hz: scalar(
                &key("torque_loop_velocity_filter_hz"),
                h.torque_loop_velocity_filter_hz,
                |f| (0.0..=TORQUE_LOOP_RATE_HZ.1).contains(&f),
                "must be finite, 0 (no filter) or up to 1e6 Hz",
            )?,
            valve_dead_band: scalar(
                &key("valve_dead_band"),
                h.valve_dead_band,
                |d| (0.0..1.0).contains(&d),
                "must be finite, ≥ 0 and below 1 (full opening)",
            )?,
        })
    }
}

impl<const N: usize> FrictionLevels<N> {
    /// Checks and converts the levels of `p`.
    pub fn of(p: &PlantConfig) -> Result<Self, SimError> {
        let coulomb = per_joint::<N>("plant.coulomb_nm", &p.coulomb_nm)?;
        let breakaway = per_joint::<N>("plant.static_nm", &p.static_nm)?;
        if let Some(i) = (0..N).find(|&i| !(coulomb[i] > 0.0 && breakaway[i] >= coulomb[i])) {
            return Err(SettingError::new(
                format!("plant.static_nm[{i}]"),
                Some(breakaway[i]),
                format!("must be ≥ plant.coulomb_nm[{i}] = {} > 0", hya_core::Short(coulomb[i])),
            )
            .into());
        }
        Ok(Self {
            coulomb,
            breakaway,
            viscous: per_joint_where("plant.viscous_nm_s", &p.viscous_nm_s, |v| v >= 0.0, "must be ≥ 0")?,
            stribeck_velocity: scalar(
                "plant.stribeck_velocity_rad_s",
                p.stribeck_velocity_rad_s,
                |v| v > 0.0,
                "must be finite and > 0",
            )?,
            position_variation: scalar(
                "plant.coulomb_position_variation",
                p.coulomb_position_variation,
                |a| (0.0..1.0).contains(&a),
                "must be in [0, 1) so that friction stays positive",
            )?,
        })
    }
}

impl<const N: usize> FrictionSetup<N> {
    /// The levels, `None` without friction.
    pub fn levels(&self) -> Option<&FrictionLevels<N>> {
        match self {
            Self::Off => None,
            Self::Smooth { levels, .. } | Self::LuGre { levels, .. } => Some(levels),
        }
    }

    /// Checks and converts the friction settings of `p`: the levels for any law, the bristle
    /// lists for LuGre.
    pub fn of(p: &PlantConfig) -> Result<Self, SimError> {
        Ok(match p.friction {
            FrictionKind::Off => Self::Off,
            FrictionKind::Smooth => Self::Smooth {
                levels: FrictionLevels::of(p)?,
                smoothing: scalar("plant.smoothing_rad_s", p.smoothing_rad_s, |v| v > 0.0, "must be finite and > 0")?,
            },
            FrictionKind::Lugre => Self::LuGre {
                levels: FrictionLevels::of(p)?,
                stiffness: per_joint_where(
                    "plant.bristle_stiffness_nm_rad",
                    &p.bristle_stiffness_nm_rad,
                    |s| s > 0.0,
                    "must be > 0",
                )?,
                damping: per_joint_where(
                    "plant.bristle_damping_nm_s_rad",
                    &p.bristle_damping_nm_s_rad,
                    |d| d >= 0.0,
                    "must be ≥ 0",
                )?,
            },
        })
    }
}

impl<const N: usize> ActuatorSetup<N> {
    /// Checks and converts the settings of `p`'s actuator kind.
    pub fn of(p: &PlantConfig) -> Result<Self, SimError> {
        Ok(match p.actuator {
            ActuatorKind::Ideal => Self::Ideal,
            ActuatorKind::Lag => Self::Lag(per_joint_where(
                "plant.actuator_time_constant_s",
                &p.actuator_time_constant_s,
                |t| t > 0.0,
                "must be > 0",
            )?),
            ActuatorKind::Hydraulic => Self::Hydraulic(Box::new(HydraulicSetup::of(&p.hydraulic)?)),
        })
    }
}

impl<const N: usize> PlantSetup<N> {
    /// Checks and converts the settings of `plant` and `loads` that act: a 7-joint arm with
    /// electric actuators need not restate HyA's six hydraulic figures.
    pub fn of(plant: &PlantConfig, loads: &LoadConfig) -> Result<Self, SimError> {
        Ok(Self {
            friction: FrictionSetup::of(plant)?,
            actuators: ActuatorSetup::of(plant)?,
            loads: LoadSetup {
                sinusoid: match &loads.sinusoid {
                    Some(s) => Some(SinusoidLoad {
                        amplitude: per_joint("loads.sinusoid.amplitude_nm", &s.amplitude_nm)?,
                        frequency_hz: scalar(
                            "loads.sinusoid.frequency_hz",
                            s.frequency_hz,
                            |f| f > 0.0,
                            "must be finite and > 0",
                        )?,
                    }),
                    None => None,
                },
                weight_drop: loads.weight_drop.clone(),
            },
        })
    }

    /// The rigid body alone: no friction, ideal actuators, no loads.
    pub fn rigid_body() -> Self {
        Self {
            friction: FrictionSetup::Off,
            actuators: ActuatorSetup::Ideal,
            loads: LoadSetup { sinusoid: None, weight_drop: None },
        }
    }

    /// `Ok` if the settings that name a link name one of `model`'s: the weight drop's frame.
    pub fn check_against(&self, model: &TreeModel) -> Result<(), SimError> {
        match &self.loads.weight_drop {
            Some(drop) => model
                .frame(&drop.frame)
                .map(|_| ())
                .map_err(|e| SettingError::new("loads.weight_drop.frame", None, e.to_string()).into()),
            None => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_friction_laws_settings_are_refused_with_their_key() {
        type Change = fn(&mut PlantConfig);
        let cases: &[(&str, Change)] = &[
            ("plant.coulomb_position_variation", |p| p.coulomb_position_variation = 1.0),
            ("plant.coulomb_position_variation", |p| p.coulomb_position_variation = -0.1),
            ("plant.stribeck_velocity_rad_s", |p| p.stribeck_velocity_rad_s = 0.0),
            ("plant.stribeck_velocity_rad_s", |p| p.stribeck_velocity_rad_s = f64::NAN),
            ("plant.static_nm[1]", |p| p.static_nm[1] = 0.5 * p.coulomb_nm[1]),
            ("plant.bristle_stiffness_nm_rad[0]", |p| p.bristle_stiffness_nm_rad[0] = 0.0),
            ("plant.smoothing_rad_s", |p| {
                p.friction = FrictionKind::Smooth;
                p.smoothing_rad_s = -1.0
            }),
        ];
        for (key, change) in cases {
            let mut plant = PlantConfig::default();
            change(&mut plant);
            let error = FrictionSetup::<6>::of(&plant).unwrap_err().to_string();
            assert!(error.contains(&format!("`{key}`")), "the refusal does not name {key}: {error}");
        }
        // Friction off reads none of them.
        let plant =
            PlantConfig { friction: FrictionKind::Off, coulomb_position_variation: 5.0, ..PlantConfig::default() };
        assert_eq!(FrictionSetup::<6>::of(&plant).unwrap(), FrictionSetup::Off);
    }
}
