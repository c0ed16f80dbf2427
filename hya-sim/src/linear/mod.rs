//! Linear analysis of the observers and of each joint's loop: the design transfer functions
//! `d̂/d`, what "equal bandwidth" means between observers of different order, and the margins of
//! one joint holding a pose, linearised, with its delays.
//!
//! - [`designs`]: the observers' design transfer functions and the meanings of equal bandwidth;
//! - [`joint_loop`]: one joint's loop, its margins, lagged cancellation;
//! - [`phasors`]: `s = jω`, delays and a signal's complex amplitude at one frequency.

pub mod designs;
pub mod joint_loop;
pub mod phasors;

pub use designs::{equal_bandwidth_table, paper_delay, EqualBandwidthRow, Matching, ObserverDesign};
pub use joint_loop::{
    effective_inertia, ActuatorModel, Compensation, JointLoop, Margins, VelocityModel, ViscousResidual,
};
pub use phasors::{jw, phasor, PhasorSum};

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use crate::config::scenario::Method;
    use crate::error::SimError;
    use nalgebra::Complex;

    #[test]
    fn every_design_has_unity_dc_gain_and_its_documented_delay() {
        for method in [Method::Lu, Method::Chen, Method::Momentum, Method::Eso] {
            let design = ObserverDesign::of(method, 50.0).unwrap();
            assert!((design.response(1e-9) - Complex::from(1.0)).norm() < 1e-9, "{}", method.name());
            // −dφ/dω by a central difference at 10⁻³ rad/s.
            let h = 1e-4;
            let slope = (design.response(1e-3 + h).arg() - design.response(1e-3 - h).arg()) / (2.0 * h);
            assert!((-slope - design.low_frequency_delay()).abs() < 1e-6, "{}: {}", method.name(), -slope);
        }
    }

    #[test]
    fn invalid_designs_and_loops_are_refused() {
        assert!(ObserverDesign::Eso { omega_rad_s: f64::NAN }.check().is_err());
        assert!(ObserverDesign::Lu { zeta: -0.8, omega1_rad_s: 50.0, omega2_rad_s: 50.0 }.check().is_err());
        assert!(ObserverDesign::FirstOrder { beta_rad_s: 0.0 }.bandwidth_3db().is_nan());
        assert!(equal_bandwidth_table(f64::INFINITY).is_err());
        let mut joint = JointLoop::computed_torque(1.0, 2.0, 20.0, 0.8, 1e-3);
        joint.command_delay_s = -1e-3;
        assert!(matches!(joint.margins(), Err(SimError::Parameter(_))));
    }

    #[test]
    fn lagged_cancellation_makes_the_joint_heavier() {
        // (1 + L) s (J s + F_v) − e^{−sT_m} A e^{−sT_c} Z (K_P + K_D V) = J_eff s² + O(s³).
        let mut joint = JointLoop::computed_torque(0.8, 2.5, 20.0, 0.8, 1e-3);
        joint.actuator = ActuatorModel::Lag { bandwidth_rad_s: std::f64::consts::TAU * 40.0 };
        joint.command_delay_s = 1e-3;
        joint.compensation = Compensation::of(Method::Lu, 50.0, 0.0);
        let w = 1e-3;
        let s = jw(w);
        let pd = joint.actuator(w) * (Complex::from(joint.kp) + s * joint.kd);
        let second_order = ((joint.open_loop(w) + 1.0) * s * (s * joint.inertia + joint.viscous) - pd) / (s * s);
        let expected = effective_inertia(joint.inertia, joint.viscous, joint.cancellation_lag_s().unwrap());
        assert!(expected > joint.inertia);
        assert!((second_order.re - expected).abs() < 1e-3 * expected, "{second_order} against {expected}");
    }

    #[test]
    fn the_exact_residual_has_the_lagged_asymptote_and_keeps_the_damping_late() {
        let design = ObserverDesign::of(Method::Lu, 50.0).unwrap();
        let slow = ViscousResidual::at(&design, 2.0, 1e-4);
        assert!((slow.added_inertia - effective_inertia(0.0, 2.0, design.low_frequency_delay())).abs() < 1e-6);
        assert!(slow.kept_damping.abs() < 1e-6, "{slow:?}");
        let fast = ViscousResidual::at(&design, 2.0, 1e5);
        assert!(fast.added_inertia.abs() < 1e-6 && (fast.kept_damping - 2.0).abs() < 1e-6, "{fast:?}");
        // Between, the residual's phasor is `F_v (1 − H) jω` itself.
        let w = 80.0;
        let at = ViscousResidual::at(&design, 2.0, w);
        let phasor = (Complex::from(1.0) - design.response(w)) * jw(w) * 2.0;
        let rebuilt = jw(w) * jw(w) * at.added_inertia + jw(w) * at.kept_damping;
        assert!((phasor - rebuilt).norm() < 1e-12 * phasor.norm());
    }
}
