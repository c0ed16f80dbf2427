//! A scenario's per-joint settings, checked once for an arm of `N` joints: every list becomes a
//! [`JointVector<N>`] of the right length, finite and in range, or the scenario is refused with
//! the key named. The plant, the controller's gain rule, the PID and the task receive these
//! typed settings; none of them reads a raw list again (the observers take no per-joint list).
//!
//! A list is converted only where it acts: the bristle lists for LuGre friction, the time
//! constants for lag actuators, the valve and chamber lists for hydraulic ones, the integral
//! clamp for the PID; so a 7-joint arm with electric actuators need not restate HyA's six
//! hydraulic figures. The static friction levels are always read: the gain rule stiffens
//! against them.

use hya_core::JointVector;

use crate::config::scenario::{ActuatorKind, FrictionKind, HydraulicConfig, LoadConfig, PlantConfig, Scenario, Task};
use crate::error::{SettingError, SimError};
use crate::robot::{with_robot, ForRobot, Robot};

/// The start pose of a scenario: its own, else the shipped robot's home pose (`robots.list`),
/// else zeros.
pub fn initial_position(scenario: &Scenario, dof: usize) -> Vec<f64> {
    match (&scenario.initial_position_rad, hya_robots::find(&scenario.robot)) {
        (Some(q), _) => q.clone(),
        (None, Some(robot)) => robot.home.to_vec(),
        (None, None) => vec![0.0; dof],
    }
}

/// A per-joint list from the configuration, checked for length and finiteness.
pub fn per_joint<const N: usize>(name: &str, values: &[f64]) -> Result<JointVector<N>, SimError> {
    if values.len() != N {
        return Err(SimError::ListLength { key: name.to_owned(), expected: N, got: values.len() });
    }
    if let Some(i) = values.iter().position(|v| !v.is_finite()) {
        return Err(SettingError::new(format!("{name}[{i}]"), Some(values[i]), "must be a finite number").into());
    }
    Ok(JointVector::from_column_slice(values))
}

/// `values` with every entry checked by `ok`, which `requirement` describes.
fn each<const N: usize>(
    name: &str,
    values: JointVector<N>,
    ok: impl Fn(f64) -> bool,
    requirement: &str,
) -> Result<JointVector<N>, SimError> {
    match values.iter().position(|v| !ok(*v)) {
        Some(i) => Err(SettingError::new(format!("{name}[{i}]"), Some(values[i]), requirement).into()),
        None => Ok(values),
    }
}

/// The friction levels per joint, N·m and N·m·s/rad (when friction is on).
#[derive(Debug, Clone, PartialEq)]
pub struct FrictionLists<const N: usize> {
    /// Coulomb level `F_c`.
    pub coulomb: JointVector<N>,
    /// Static (breakaway) level `F_s ≥ F_c`.
    pub breakaway: JointVector<N>,
    /// Viscous coefficient `σ2 ≥ 0`.
    pub viscous: JointVector<N>,
    /// LuGre bristle stiffness `σ0 > 0` and damping `σ1 ≥ 0`, for LuGre friction.
    pub bristles: Option<(JointVector<N>, JointVector<N>)>,
}

/// The hydraulic actuators' per-joint figures and the inner torque loop's settings, checked
/// (see [`HydraulicConfig`] for units).
#[derive(Debug, Clone, PartialEq)]
pub struct HydraulicLists<const N: usize> {
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

/// The inner torque loop's sample rates simulated, Hz: from 1 Hz to 1 MHz (each sample above
/// the physics step's rate costs an RK4 step).
pub const TORQUE_LOOP_RATE_HZ: (f64, f64) = (1.0, 1e6);

/// The most counts per revolution of the inner loop's encoder: 2^53 (a resolution of 7e-16 rad,
/// the angle's own rounding near 1 rad; more would not be finer).
pub const MAX_ENCODER_COUNTS: u64 = 1 << 53;

impl<const N: usize> HydraulicLists<N> {
    /// Checks and converts the per-joint figures and the inner loop's settings of `h`.
    pub fn of(h: &HydraulicConfig) -> Result<Self, SimError> {
        let scalar = |name: &str, v: f64, ok: fn(f64) -> bool, requirement: &str| {
            if v.is_finite() && ok(v) {
                Ok(v)
            } else {
                Err(SettingError::new(format!("plant.hydraulic.{name}"), Some(v), requirement))
            }
        };
        let positive = |name: &str, values: &[f64]| {
            let key = format!("plant.hydraulic.{name}");
            each(&key, per_joint::<N>(&key, values)?, |v| v > 0.0, "must be > 0")
        };
        Ok(Self {
            displacement: positive("displacement_m3_rad", &h.displacement_m3_rad)?,
            area_ratio: positive("area_ratio", &h.area_ratio)?,
            dead_volume: positive("dead_volume_m3", &h.dead_volume_m3)?,
            rated_flow: positive("valve_rated_flow_m3_s", &h.valve_rated_flow_m3_s)?,
            valve_frequency_hz: positive("valve_natural_frequency_hz", &h.valve_natural_frequency_hz)?,
            torque_bandwidth_hz: positive("torque_bandwidth_hz", &h.torque_bandwidth_hz)?,
            null_bias: each(
                "plant.hydraulic.valve_null_bias",
                per_joint("plant.hydraulic.valve_null_bias", &h.valve_null_bias)?,
                |b| b.abs() <= 0.2,
                "is beyond ±0.2 of full opening",
            )?,
            leakage: each(
                "plant.hydraulic.leakage_m3_s_pa",
                per_joint("plant.hydraulic.leakage_m3_s_pa", &h.leakage_m3_s_pa)?,
                |l| l >= 0.0,
                "must be ≥ 0",
            )?,
            torque_loop_rate_hz: scalar(
                "torque_loop_rate_hz",
                h.torque_loop_rate_hz,
                |r| (TORQUE_LOOP_RATE_HZ.0..=TORQUE_LOOP_RATE_HZ.1).contains(&r),
                "must be finite, between 1 and 1e6 Hz",
            )?,
            torque_loop_pressure_noise_pa: scalar(
                "torque_loop_pressure_noise_pa",
                h.torque_loop_pressure_noise_pa,
                |v| v >= 0.0,
                "must be finite and ≥ 0",
            )?,
            torque_loop_pressure_offset_pa: scalar(
                "torque_loop_pressure_offset_pa",
                h.torque_loop_pressure_offset_pa,
                |v| v >= 0.0,
                "must be finite and ≥ 0",
            )?,
            torque_loop_encoder_counts_per_rev: match h.torque_loop_encoder_counts_per_rev {
                n @ 1..=MAX_ENCODER_COUNTS => n,
                n => {
                    return Err(SettingError::new(
                        "plant.hydraulic.torque_loop_encoder_counts_per_rev",
                        Some(n as f64),
                        "must be between 1 and 2^53",
                    )
                    .into())
                }
            },
            torque_loop_velocity_filter_hz: scalar(
                "torque_loop_velocity_filter_hz",
                h.torque_loop_velocity_filter_hz,
                |f| (0.0..=TORQUE_LOOP_RATE_HZ.1).contains(&f),
                "must be finite, 0 (no filter) or up to 1e6 Hz",
            )?,
            valve_dead_band: scalar(
                "valve_dead_band",
                h.valve_dead_band,
                |d| (0.0..1.0).contains(&d),
                "must be finite, ≥ 0 and below 1 (full opening)",
            )?,
        })
    }
}

/// The plant's per-joint settings: what [`crate::plant::Plant`] is built from.
#[derive(Debug, Clone, PartialEq)]
pub struct PlantLists<const N: usize> {
    /// The friction levels, unless friction is off.
    pub friction: Option<FrictionLists<N>>,
    /// The lag actuators' time constants, s (`actuator = "lag"`).
    pub actuator_time_constant: Option<JointVector<N>>,
    /// The hydraulic actuators' figures (`actuator = "hydraulic"`).
    pub hydraulic: Option<HydraulicLists<N>>,
    /// The sinusoidal load's amplitudes, N·m.
    pub sinusoid_amplitude: Option<JointVector<N>>,
}

impl<const N: usize> PlantLists<N> {
    /// Checks and converts the lists of `plant` and `loads` that act.
    pub fn of(p: &PlantConfig, loads: &LoadConfig) -> Result<Self, SimError> {
        let friction = match p.friction {
            FrictionKind::Off => None,
            _ => Some(FrictionLists::of(p)?),
        };
        Ok(Self {
            friction,
            actuator_time_constant: match p.actuator {
                ActuatorKind::Lag => Some(each(
                    "plant.actuator_time_constant_s",
                    per_joint("plant.actuator_time_constant_s", &p.actuator_time_constant_s)?,
                    |t| t > 0.0,
                    "must be > 0",
                )?),
                _ => None,
            },
            hydraulic: match p.actuator {
                ActuatorKind::Hydraulic => Some(HydraulicLists::of(&p.hydraulic)?),
                _ => None,
            },
            sinusoid_amplitude: match &loads.sinusoid {
                Some(s) => Some(per_joint("loads.sinusoid.amplitude_nm", &s.amplitude_nm)?),
                None => None,
            },
        })
    }
}

impl<const N: usize> FrictionLists<N> {
    /// Checks and converts the friction lists of `p`; the bristle lists too for LuGre friction.
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
        let viscous =
            each("plant.viscous_nm_s", per_joint("plant.viscous_nm_s", &p.viscous_nm_s)?, |v| v >= 0.0, "must be ≥ 0")?;
        let bristles = if p.friction == FrictionKind::Lugre {
            Some((
                each(
                    "plant.bristle_stiffness_nm_rad",
                    per_joint("plant.bristle_stiffness_nm_rad", &p.bristle_stiffness_nm_rad)?,
                    |s| s > 0.0,
                    "must be > 0",
                )?,
                each(
                    "plant.bristle_damping_nm_s_rad",
                    per_joint("plant.bristle_damping_nm_s_rad", &p.bristle_damping_nm_s_rad)?,
                    |d| d >= 0.0,
                    "must be ≥ 0",
                )?,
            ))
        } else {
            None
        };
        Ok(Self { coulomb, breakaway, viscous, bristles })
    }
}

/// Every per-joint setting of a scenario, for an arm of `N` joints.
#[derive(Debug, Clone, PartialEq)]
pub struct JointSettings<const N: usize> {
    /// The start pose, rad.
    pub initial_position: JointVector<N>,
    /// The goto task's step or the sine task's amplitudes, rad (zeros for `hold`).
    pub task: JointVector<N>,
    /// The controller's natural frequencies, rad/s.
    pub natural_frequency: JointVector<N>,
    /// The nominal static friction the gain rule stiffens against, N·m (`plant.static_nm`).
    pub static_friction: JointVector<N>,
    /// The PID's integral clamp, N·m (when the scenario runs `pid`).
    pub integral_limit: Option<JointVector<N>>,
    /// The controller's torque limits, N·m.
    pub torque_limit: JointVector<N>,
    /// The plant's.
    pub plant: PlantLists<N>,
}

impl<const N: usize> JointSettings<N> {
    /// Checks and converts every per-joint list of `scenario` that acts.
    pub fn of(scenario: &Scenario) -> Result<Self, SimError> {
        let c = &scenario.controller;
        let task = match &scenario.task {
            Task::Hold {} => JointVector::zeros(),
            Task::Goto { delta_rad, .. } => per_joint("task.delta_rad", delta_rad)?,
            Task::Sine { amplitude_rad, .. } => per_joint("task.amplitude_rad", amplitude_rad)?,
        };
        Ok(Self {
            initial_position: per_joint("initial_position_rad", &initial_position(scenario, N))?,
            task,
            natural_frequency: per_joint("controller.natural_frequency_rad_s", &c.natural_frequency_rad_s)?,
            static_friction: per_joint("plant.static_nm", &scenario.plant.static_nm)?,
            integral_limit: match scenario.methods.contains(&crate::config::scenario::Method::Pid) {
                true => Some(per_joint("controller.integral_limit_nm", &c.integral_limit_nm)?),
                false => None,
            },
            torque_limit: per_joint("controller.torque_limit_nm", &c.torque_limit_nm)?,
            plant: PlantLists::of(&scenario.plant, &scenario.loads)?,
        })
    }
}

/// The scenario checked against its robot: the per-joint lists, which need the joint count.
impl Scenario {
    /// Checks what [`Scenario::check`] cannot without the robot: that it loads, and that every
    /// per-joint list that acts fits its joints, naming all lists that do not in one error
    /// ([`SimError::ListLengths`]) rather than one per run. For a command to call before it
    /// prints its cost and starts simulating.
    pub fn check_for_robot(&self) -> Result<(), SimError> {
        struct Lists<'a>(&'a Scenario);
        impl ForRobot for Lists<'_> {
            type Output = ();
            fn call<const N: usize>(self, _: Robot<N>) -> Result<(), SimError> {
                // Each list that does not fit is noted, then filled to N copies of its first
                // value in a copy of the scenario, so that the next one is found.
                let mut scenario = self.0.clone();
                let mut misfits = Vec::new();
                let first_error = loop {
                    match JointSettings::<N>::of(&scenario) {
                        Ok(_) => break None,
                        Err(SimError::ListLength { key, got, .. }) if misfits.len() < 64 => {
                            scenario = scenario.with_list_filled(&key, N)?;
                            misfits.push(format!("`{key}` ({got} values)"));
                        }
                        Err(other) => break Some(other),
                    }
                };
                match (misfits.len(), first_error) {
                    (0, None) => Ok(()),
                    (0, Some(error)) => Err(error),
                    // A value check behind the misfits (such as `static_nm ≥ coulomb_nm` against
                    // a filled default) stops the search: it is named too.
                    (count, then) => {
                        let then = then.map(|e| format!("; then, with those filled: {e}")).unwrap_or_default();
                        Err(SimError::ListLengths { count, expected: N, lists: misfits.join(", ") + &then })
                    }
                }
            }
        }
        with_robot(&self.robot, Lists(self))
    }

    /// This scenario with the list at the dotted `key` (`plant.coulomb_nm`) replaced by `n`
    /// copies of its first value (0 if it has none).
    fn with_list_filled(&self, key: &str, n: usize) -> Result<Self, SimError> {
        let bad = |why: String| SimError::Scenario { origin: self.name.clone(), message: why };
        let mut value = toml::Value::try_from(self).map_err(|e| bad(e.to_string()))?;
        let mut slot = &mut value;
        for part in key.split('.') {
            slot = slot.get_mut(part).ok_or_else(|| bad(format!("no setting `{key}` (a bug)")))?;
        }
        let first = slot.as_array().and_then(|a| a.first()).cloned().unwrap_or(toml::Value::Float(0.0));
        *slot = toml::Value::Array(vec![first; n]);
        value.try_into().map_err(|e: toml::de::Error| bad(e.to_string()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lists_are_checked_once_with_their_key_named() {
        let mut scenario = Scenario::builtin("goto_internal").unwrap();
        assert!(JointSettings::<6>::of(&scenario).is_ok());
        let error = JointSettings::<7>::of(&scenario).unwrap_err().to_string();
        assert!(error.contains("expected 7 values"), "{error}");
        scenario.plant.bristle_damping_nm_s_rad[2] = -1.0;
        let error = JointSettings::<6>::of(&scenario).unwrap_err().to_string();
        assert!(error.contains("`plant.bristle_damping_nm_s_rad[2]` = -1"), "{error}");
        // Lists that do not act are not read: lag actuators ignore the hydraulic figures.
        scenario.plant.bristle_damping_nm_s_rad[2] = 1.0;
        scenario.plant.actuator = ActuatorKind::Lag;
        scenario.plant.hydraulic.area_ratio = vec![];
        assert!(JointSettings::<6>::of(&scenario).unwrap().plant.hydraulic.is_none());
        // The integral clamp is read only for a scenario that runs the PID.
        scenario.controller.integral_limit_nm = vec![];
        assert!(JointSettings::<6>::of(&scenario).unwrap_err().to_string().contains("controller.integral_limit_nm"));
        scenario.methods.retain(|m| *m != crate::config::scenario::Method::Pid);
        assert!(JointSettings::<6>::of(&scenario).unwrap().integral_limit.is_none());
    }
}
