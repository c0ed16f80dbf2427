//! The observers' designs side by side ("equal bandwidth" in its three meanings) and each joint's
//! linearised loop with its stability margins, per method: the analysis the report's limit
//! cycles are held against. The loop is the one of [`crate::linear`]: the rigid joint with its
//! viscous friction, the PD, the velocity source, the estimator's design or the PID's integral,
//! the actuator's torque response, the delays and the zero-order hold; no stiction.

use std::fmt::Write as _;

use crate::config::scenario::{ActuatorKind, Method, Scenario, VelocitySource};
use crate::error::SimError;
use crate::linear::{equal_bandwidth_table, ActuatorModel, Compensation, JointLoop, ObserverDesign, VelocityModel};
use crate::robot::Robot;
use crate::run::model::LoopDesign;
use crate::torque_response::TorqueResponses;

use super::text::table_row;

/// The methods whose loops are analysed, in the table's order.
const METHODS: [Method; 6] = [Method::None, Method::Pid, Method::Lu, Method::Chen, Method::Momentum, Method::Eso];

/// The paper's estimator's bandwidths whose loops are analysed too, rad/s.
const LU_BANDWIDTHS_RAD_S: [f64; 5] = [20.0, 35.0, 50.0, 100.0, 200.0];

/// The equal-bandwidth table at `omega` (the scenario's observer bandwidth).
fn equal_bandwidth(omega: f64) -> Result<String, SimError> {
    let mut md = format!(
        "\n### What \"equal bandwidth\" means\n\nThe simulator gives every observer the same pole magnitude, {omega} rad/s. That is one of three meanings, and they differ: by up to a factor of 2.6 for the first-order observers (chen, momentum), by 1.3 for the ESO. The paper's third-order filter passes less and lags more than a first-order observer with the same poles. Each observer matched to the paper's filter at {omega} rad/s (ζ = 0.8, ω1 = ω2) by each meaning:\n\n| observer | matched by | parameter [rad/s] | −3 dB bandwidth [rad/s] | low-frequency delay [ms] |\n|---|---|---|---|---|\n"
    );
    for row in equal_bandwidth_table(omega)? {
        md.push_str(&table_row([
            row.method.name().to_owned(),
            row.matching.map_or("(the reference)".to_owned(), |m| m.name().to_owned()),
            format!("{:.1}", row.parameter_rad_s),
            format!("{:.1}", row.bandwidth_3db_rad_s),
            format!("{:.1}", row.low_frequency_delay_s * 1e3),
        ]));
    }
    md.push_str("\nThe closed-loop comparison runs at equal pole magnitude; the bandwidth sweep compares the methods over their whole range.\n");
    Ok(md)
}

/// Joint `j`'s linearised loop under `method` at `bandwidth` in `scenario`; a hydraulic
/// actuator is the model fitted to its measured response where `torque` has one, a first-order
/// lag at its design bandwidth otherwise.
fn joint_loop<const N: usize>(
    scenario: &Scenario,
    torque: Option<&TorqueResponses>,
    (inertia, kp, kd, ki): (f64, f64, f64, f64),
    j: usize,
    method: Method,
    bandwidth: f64,
) -> JointLoop {
    let dt = scenario.controller.dt_s;
    let sensors = &scenario.sensors;
    let plant = &scenario.plant;
    JointLoop {
        inertia,
        viscous: plant.viscous_nm_s.get(j).copied().unwrap_or(0.0),
        kp,
        kd,
        velocity: match sensors.velocity {
            VelocitySource::Sensor => VelocityModel::Sensor,
            VelocitySource::Difference => VelocityModel::Difference { cutoff_rad_s: sensors.velocity_cutoff_rad_s },
            VelocitySource::Filter => {
                ObserverDesign::of(Method::Lu, bandwidth).map_or(VelocityModel::Sensor, VelocityModel::Filter)
            }
        },
        compensation: Compensation::of(method, bandwidth, ki),
        actuator: match plant.actuator {
            ActuatorKind::Ideal => ActuatorModel::Ideal,
            ActuatorKind::Lag => plant
                .actuator_time_constant_s
                .get(j)
                .map_or(ActuatorModel::Ideal, |t| ActuatorModel::Lag { bandwidth_rad_s: 1.0 / t }),
            ActuatorKind::Hydraulic => {
                torque.and_then(|t| t.model(j + 1)).unwrap_or_else(|| {
                    plant.hydraulic.torque_bandwidth_hz.get(j).map_or(ActuatorModel::Ideal, |f| ActuatorModel::Lag {
                        bandwidth_rad_s: std::f64::consts::TAU * f,
                    })
                })
            }
        },
        measurement_delay_s: sensors.measurement_delay_ticks as f64 * dt,
        command_delay_s: sensors.command_delay_ticks as f64 * dt,
        period_s: dt,
    }
}

/// `PM / delay margin` of one loop, or `unstable`.
fn cell(joint: &JointLoop) -> Result<String, SimError> {
    let m = joint.margins()?;
    Ok(if m.stable {
        format!("{:.0}° / {:.1} ms", m.phase_margin_deg, m.delay_margin_s * 1e3)
    } else {
        format!("**unstable** ({} poles)", m.unstable_poles)
    })
}

/// Joint `j`'s `(M_ii, K_P, K_D, K_I)` in `design` under `method` (the PID's own `K_D`).
fn joint_numbers<const N: usize>(design: &LoopDesign<N>, j: usize, method: Method) -> (f64, f64, f64, f64) {
    let kd = if method == Method::Pid { design.pid_kd[j] } else { design.pd.kd()[(j, j)] };
    (design.inertia[j], design.pd.kp()[(j, j)], kd, design.integral[j])
}

/// The gain crossover of each joint's loop under the paper's estimator at the scenario's
/// bandwidth (that of its worst phase margin), rad/s.
pub fn lu_crossovers<const N: usize>(
    robot: &Robot<N>,
    scenario: &Scenario,
    torque: Option<&TorqueResponses>,
) -> Result<[f64; N], SimError> {
    let design = super::loop_design(scenario, robot)?;
    let bandwidth = scenario.controller.observer_bandwidth_rad_s;
    let mut crossovers = [0.0; N];
    for (j, crossover) in crossovers.iter_mut().enumerate() {
        *crossover = joint_loop::<N>(scenario, torque, joint_numbers(&design, j, Method::Lu), j, Method::Lu, bandwidth)
            .margins()?
            .crossover_rad_s;
    }
    Ok(crossovers)
}

/// The section for `scenario` (HyA's goto task in the report) on `robot`.
pub fn section<const N: usize>(
    robot: &Robot<N>,
    scenario: &Scenario,
    torque: Option<&TorqueResponses>,
) -> Result<String, SimError> {
    let bandwidth = scenario.controller.observer_bandwidth_rad_s;
    let mut md = equal_bandwidth(bandwidth)?;
    let design = super::loop_design(scenario, robot)?;
    let _ = writeln!(
        md,
        "\n### Each joint's loop, linearised\n\nPer joint of `{}` at its start pose: the rigid joint `M_ii s² + F_v s` under the PD, the velocity from the scenario's source, the method's compensation (the estimator's design `d̂ = H(s)(M_ii s² q_m − τ_m)`, or the PID's `K_I/s`), the actuator's torque response, the delays and the zero-order hold of the {} ms tick; no stiction. Phase margin / delay margin (the extra delay that makes the loop marginal), from the open loop broken at the command and the Nyquist criterion:\n",
        scenario.name,
        scenario.controller.dt_s * 1e3
    );
    md.push_str(&table_row(["joint".to_owned()].into_iter().chain(METHODS.iter().map(|m| m.name().to_owned()))));
    md.push_str(&table_row(std::iter::repeat_n("---".to_owned(), METHODS.len() + 1)));
    for j in 0..N {
        let mut cells = vec![format!("{}", j + 1)];
        for method in METHODS {
            cells.push(cell(&joint_loop::<N>(
                scenario,
                torque,
                joint_numbers(&design, j, method),
                j,
                method,
                bandwidth,
            ))?);
        }
        md.push_str(&table_row(cells));
    }
    let _ = writeln!(md, "\nThe paper's estimator at other bandwidths (ω1 = ω2), same measure:\n");
    md.push_str(&table_row(
        ["joint".to_owned()].into_iter().chain(LU_BANDWIDTHS_RAD_S.iter().map(|w| format!("{w} rad/s"))),
    ));
    md.push_str(&table_row(std::iter::repeat_n("---".to_owned(), LU_BANDWIDTHS_RAD_S.len() + 1)));
    for j in 0..N {
        let numbers = joint_numbers(&design, j, Method::Lu);
        let mut cells = vec![format!("{}", j + 1)];
        for w in LU_BANDWIDTHS_RAD_S {
            cells.push(cell(&joint_loop::<N>(scenario, torque, numbers, j, Method::Lu, w))?);
        }
        md.push_str(&table_row(cells));
    }
    let actuator = match (scenario.plant.actuator, torque) {
        (ActuatorKind::Hydraulic, Some(_)) => "the actuator as the torque loop fitted to its measured locked response (the Plant section's \"The torque loops, measured as they are used\"; the back-drive of the moving actuator measured there is not in them)",
        (ActuatorKind::Hydraulic, None) => "the actuator as a first-order lag at its design bandwidth, which nothing here measures",
        (ActuatorKind::Lag, _) => "the actuator as its first-order lag",
        (ActuatorKind::Ideal, _) => "the actuator as ideal",
    };
    let _ = write!(md, "\nThese loops have no stiction, take the controller's model as exact (the arm's own parameters differ by the seeded spread), and {actuator}.");
    md.push_str(" Their friction is the viscous term alone: the slope of Coulomb friction at rest (LuGre's bristles, or the `tanh` law's F_c/ε) is not in them. Where a loop is stable with margin and the simulation still moves, stick-slip hunting is one candidate; the next section reruns the scenario without the friction's Stribeck peak.\n");
    Ok(md)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// planar2's description, and the same with its links `factor` times as heavy.
    fn planar2_scaled(factor: f64) -> (String, String) {
        let path = format!("{}/../robots/urdf/planar2.urdf", env!("CARGO_MANIFEST_DIR"));
        let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
        let heavy = [("3.0", "0.004", "0.06"), ("2.0", "0.002", "0.03")].iter().fold(text, |t, (m, ixx, iyy)| {
            let scaled = |v: &str| format!("{}", v.parse::<f64>().unwrap_or(f64::NAN) * factor);
            t.replace(&format!("<mass value=\"{m}\"/>"), &format!("<mass value=\"{}\"/>", scaled(m))).replace(
                &format!("ixx=\"{ixx}\" iyy=\"{iyy}\" izz=\"{iyy}\""),
                &format!("ixx=\"{}\" iyy=\"{}\" izz=\"{}\"", scaled(ixx), scaled(iyy), scaled(iyy)),
            )
        });
        let heavy_path = std::env::temp_dir()
            .join(format!("hya-loops-heavy-planar2-{}.urdf", std::process::id()))
            .display()
            .to_string();
        std::fs::write(&heavy_path, heavy).unwrap_or_else(|e| panic!("{heavy_path}: {e}"));
        (path, heavy_path)
    }

    #[test]
    fn the_loop_analysis_runs_on_the_model_the_loop_runs_on() {
        let (light, heavy) = planar2_scaled(2.0);
        let load = |path: &str| Robot::<2>::load(path).unwrap_or_else(|e| panic!("{e}"));
        let (light_robot, heavy_robot) = (load(&light), load(&heavy));
        let mut scenario = Scenario::builtin("planar2_goto").unwrap_or_else(|e| panic!("{e}"));
        scenario.robot = light.clone();
        let on_light = section(&light_robot, &scenario, None).unwrap_or_else(|e| panic!("{e}"));
        // The scenario names the heavy model for its controller: its loops are the heavy arm's.
        let mut named = scenario.clone();
        named.controller.model_urdf = Some(heavy.clone());
        let on_named = section(&light_robot, &named, None).unwrap_or_else(|e| panic!("{e}"));
        scenario.robot = heavy.clone();
        let on_heavy = section(&heavy_robot, &scenario, None).unwrap_or_else(|e| panic!("{e}"));
        let _ = std::fs::remove_file(&heavy);
        assert_eq!(on_named, on_heavy);
        assert_ne!(on_named, on_light, "twice the inertia left every margin as it was");
    }
}
