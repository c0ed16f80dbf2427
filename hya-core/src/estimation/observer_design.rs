//! One description of every disturbance observer, built the same way by every front end (the
//! simulator, the command line, Python, C): which observer, designed how, started on the first
//! measurement, and boxed so that a run-time choice needs no generic code.
//!
//! All are designed by one number, a pole magnitude `β` (rad/s) at the control period `dt`:
//!
//! - the paper's estimator: its filters `H(s)` at `ζ = 0.8`, `ω1 = ω2 = β` (or any
//!   [`FilterParams`]); the slowest pole magnitude is `min(ω1, ω2)`;
//! - Chen's nonlinear observer, by one of two gain designs ([`NonlinearGain`]);
//! - the generalized-momentum observer, gain `β` on every joint;
//! - the extended-state observer, every pole at `−β`.

use alloc::boxed::Box;

use crate::{
    symmetric_eigenvalues, DisturbanceEstimator, DisturbanceObserver, Dynamics, Error, ExtendedStateObserver,
    FilterParams, JointVector, Measurement, MomentumObserver, NonlinearDisturbanceObserver,
};

/// A disturbance observer chosen at run time, which may move between threads.
pub type BoxedObserver<'a, const N: usize> = Box<dyn DisturbanceObserver<N> + Send + 'a>;

/// The gain design of Chen's nonlinear observer `ż = −L z − L(p(q̇) + …)`, `L = Y M⁻¹(q)`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum NonlinearGain {
    /// `Y = β M(q0)`: `L = β I` at the start pose, every rate `β` there (well conditioned).
    #[default]
    Inertia,
    /// `Y = y I` with `y = β λmax(M(q0))` (Chen 2000, Mohammadi et al.): the slowest rate at the
    /// start pose is `β`, the others faster by the inertia's spread.
    Scalar,
}

/// Which observer, and its design.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ObserverDesign {
    /// The paper's estimator with these filters.
    Paper(FilterParams),
    /// Chen's nonlinear observer at pole magnitude `bandwidth_rad_s`.
    Nonlinear {
        /// `β`, rad/s.
        bandwidth_rad_s: f64,
        /// The control period, s.
        dt_s: f64,
        /// How `β` sets the gain.
        gain: NonlinearGain,
    },
    /// The generalized-momentum observer, gain `bandwidth_rad_s` (1/s) on every joint.
    Momentum {
        /// `β`, rad/s.
        bandwidth_rad_s: f64,
        /// The control period, s.
        dt_s: f64,
    },
    /// The model-assisted extended-state observer, every pole at `−bandwidth_rad_s`.
    ExtendedState {
        /// `β`, rad/s.
        bandwidth_rad_s: f64,
        /// The control period, s.
        dt_s: f64,
    },
}

impl ObserverDesign {
    /// The paper's estimator at `ζ = 0.8`, `ω1 = ω2 = bandwidth_rad_s`.
    pub fn paper_at(bandwidth_rad_s: f64, dt_s: f64) -> Result<Self, Error> {
        FilterParams::paper_at(bandwidth_rad_s, dt_s).map(Self::Paper)
    }

    /// The observer on the model `nominal`, started on the `first` measurement (at rest there
    /// for the paper's estimator, `d̂ = G(q) − τ`; observers that read `q̇` take it from `first`,
    /// or zero), and its rates at the start pose (1/s, per joint) from its design.
    pub fn build<'a, const N: usize, D: Dynamics<N> + Send + 'a>(
        &self,
        nominal: D,
        first: &Measurement<N>,
    ) -> Result<(BoxedObserver<'a, N>, JointVector<N>), Error> {
        let q0 = first.position;
        let qd0 = first.velocity.unwrap_or_else(JointVector::zeros);
        Ok(match *self {
            Self::Paper(params) => {
                // H(s)'s poles: −ω1 and −ζω2 ± jω2√(1 − ζ²), of magnitudes ω1 and ω2.
                let rate = params.omega1_rad_s().min(params.omega2_rad_s());
                let estimator = DisturbanceEstimator::new(nominal, params, q0, first.torque)?;
                (Box::new(estimator), JointVector::repeat(rate))
            }
            Self::Nonlinear { bandwidth_rad_s, dt_s, gain } => {
                let chen = match gain {
                    NonlinearGain::Inertia => {
                        NonlinearDisturbanceObserver::with_bandwidth(nominal, bandwidth_rad_s, dt_s, &q0, qd0)?
                    }
                    NonlinearGain::Scalar => {
                        let largest = symmetric_eigenvalues(&nominal.mass_matrix(&q0)).max();
                        NonlinearDisturbanceObserver::new(nominal, bandwidth_rad_s * largest, dt_s, qd0)?
                    }
                };
                let rates = chen.rates(&q0)?;
                (Box::new(chen), rates)
            }
            Self::Momentum { bandwidth_rad_s, dt_s } => {
                let gains = JointVector::repeat(bandwidth_rad_s);
                (Box::new(MomentumObserver::new(nominal, gains, dt_s, q0, qd0, first.torque)?), gains)
            }
            Self::ExtendedState { bandwidth_rad_s, dt_s } => {
                let eso = ExtendedStateObserver::new(nominal, bandwidth_rad_s, dt_s, q0)?;
                (Box::new(eso), JointVector::repeat(bandwidth_rad_s))
            }
        })
    }

    /// Whether the observer reads measured velocities.
    pub fn reads_velocity(&self) -> bool {
        matches!(self, Self::Nonlinear { .. } | Self::Momentum { .. })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_arms::PlanarTwoLink;

    #[test]
    fn each_design_builds_its_observer_with_its_rates() {
        let arm = PlanarTwoLink::default();
        let first = Measurement {
            position: JointVector::from([0.3, -0.2]),
            velocity: Some(JointVector::zeros()),
            torque: JointVector::from([1.0, 0.5]),
        };
        let (lu, rates) = ObserverDesign::paper_at(40.0, 1e-3).unwrap().build(arm, &first).unwrap();
        assert_eq!(rates, JointVector::<2>::repeat(40.0));
        // At rest on the first row: d̂ = G(q) − τ.
        let g = arm.gravity(&first.position);
        assert!((lu.disturbance() - (g - first.torque)).amax() < 1e-12);
        let design = |gain| ObserverDesign::Nonlinear { bandwidth_rad_s: 40.0, dt_s: 1e-3, gain };
        let (_, inertia) = design(NonlinearGain::Inertia).build(arm, &first).unwrap();
        assert!((inertia - JointVector::<2>::repeat(40.0)).amax() < 1e-9, "L = β I at the start pose: {inertia}");
        let (_, scalar) = design(NonlinearGain::Scalar).build(arm, &first).unwrap();
        assert!((scalar.min() - 40.0).abs() < 1e-9 && scalar.max() > 40.0, "slowest rate β: {scalar}");
        for design in [
            ObserverDesign::Momentum { bandwidth_rad_s: 40.0, dt_s: 1e-3 },
            ObserverDesign::ExtendedState { bandwidth_rad_s: 40.0, dt_s: 1e-3 },
        ] {
            assert_eq!(design.build(arm, &first).unwrap().1, JointVector::<2>::repeat(40.0));
        }
        assert!(ObserverDesign::paper_at(-1.0, 1e-3).is_err());
    }
}
