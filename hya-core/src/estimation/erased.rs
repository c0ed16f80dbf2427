//! The joint count erased once, for the front ends that learn it at run time (the C ABI, Python):
//! an observer or the controller of `N` joints behind an object-safe trait whose methods take
//! slices. Every slice must hold `N` values, or the call is refused with
//! [`Error::SliceLength`] and the state kept; a call does the const-generic work of the type
//! behind it, with no allocation and no further dispatch on `N`. [`with_joints`](crate::dispatch::with_joints)
//! turns the run-time count into the `N` that builds one.

use alloc::boxed::Box;

use crate::estimation::observer_design::{BoxedObserver, ObserverDesign};
use crate::{
    ComputedTorque, DisturbanceEstimator, Dynamics, Error, JointVector, Measurement, Reference, TimedEstimator,
};

/// A disturbance observer on slices: the paper's estimator (stepped at its period, or over
/// timestamped samples) or one it is compared with.
pub trait SliceObserver: Send {
    /// The joint count, the length of every slice.
    fn dof(&self) -> usize;
    /// Whether samples come with their times ([`Self::update_at`]) instead of at the fixed
    /// period ([`Self::update`]).
    fn is_timed(&self) -> bool {
        false
    }
    /// One tick of the fixed period with measured `q`, `q̇` (for the observers that read it) and
    /// `τ`; writes the new `d̂`.
    fn update(&mut self, q: &[f64], qd: Option<&[f64]>, tau: &[f64], d_hat: &mut [f64]) -> Result<(), Error>;
    /// The sample at time `t`, s, with measured `q` and `τ`; writes the new `d̂` and says whether
    /// the step was a gap too long to bridge, after which the estimator restarted at rest.
    fn update_at(&mut self, _t: f64, _q: &[f64], _tau: &[f64], _d_hat: &mut [f64]) -> Result<bool, Error> {
        Err(Error::Unsupported("a sample with its time: this observer steps at its fixed period"))
    }
    /// Writes the latest `d̂`.
    fn disturbance(&self, d_hat: &mut [f64]) -> Result<(), Error>;
    /// Restarts at rest at `(q0, τ0)` (a timed estimator: at the latest sample's time).
    fn reset(&mut self, _q0: &[f64], _tau0: &[f64]) -> Result<(), Error> {
        Err(Error::Unsupported("a restart at rest: only the paper's estimator has one"))
    }
}

/// The computed-torque law on slices.
pub trait SliceController: Send + Sync {
    /// The joint count, the length of every slice.
    fn dof(&self) -> usize;
    /// Writes the commanded torque for the measured `[q, q̇]`, the reference `[q_des, q̇_des,
    /// q̈_des]` and, if given, `d̂`.
    fn command(
        &self,
        state: [&[f64]; 2],
        reference: [&[f64]; 3],
        d_hat: Option<&[f64]>,
        tau: &mut [f64],
    ) -> Result<(), Error>;
}

/// The Cartesian impedance law on a model's frame ([`crate::FrameImpedance`]) on slices.
pub trait SliceCartesian: Send {
    /// The joint count, the length of every joint slice.
    fn dof(&self) -> usize;
    /// The controlled frame's name.
    fn frame(&self) -> &str;
    /// Writes the commanded torque for the measured `[q, q̇]`, the frame's desired `[p_des
    /// (3 values, m), R_des (9, row-major: the frame's desired axes are its columns), ẋ_des (6:
    /// m/s, then rad/s)]` in the base's axes and, if given, `d̂`.
    fn command(
        &mut self,
        state: [&[f64]; 2],
        reference: [&[f64]; 3],
        d_hat: Option<&[f64]>,
        tau: &mut [f64],
    ) -> Result<(), Error>;
}

#[cfg(feature = "alloc")]
impl<const N: usize, D: Dynamics<N> + Send> SliceCartesian for crate::FrameImpedance<N, D> {
    fn dof(&self) -> usize {
        N
    }
    fn frame(&self) -> &str {
        self.frame_name()
    }
    fn command(
        &mut self,
        [q, qd]: [&[f64]; 2],
        [position, orientation, twist]: [&[f64]; 3],
        d_hat: Option<&[f64]>,
        tau: &mut [f64],
    ) -> Result<(), Error> {
        let reference = crate::CartesianReference {
            position: sized::<3>("position_des", position, "3 values: x, y, z in the base, m")?,
            orientation: crate::cartesian::Matrix3::from_row_slice(
                sized::<9>("orientation_des", orientation, "9 values: the 3 × 3 rotation, row-major")?.as_slice(),
            ),
            twist: sized::<6>("twist_des", twist, "6 values: m/s, then rad/s, in the base")?,
        };
        let d_hat = d_hat.map(|d| joints("d_hat", d)).transpose()?;
        joints::<N>("tau", tau)?;
        let command =
            crate::FrameImpedance::command(self, &joints("q", q)?, &joints("qd", qd)?, &reference, d_hat.as_ref())?;
        write("tau", &command.torque, tau)
    }
}

/// `values` as a vector of `K`, if it holds that many (`what` says what they are).
fn sized<const K: usize>(
    name: &'static str,
    values: &[f64],
    requirement: &'static str,
) -> Result<nalgebra::SVector<f64, K>, Error> {
    if values.len() != K {
        return Err(Error::InvalidParameter { name, value: values.len() as f64, requirement });
    }
    Ok(nalgebra::SVector::from_column_slice(values))
}

/// `values` as a joint vector, if it holds `N` of them.
fn joints<const N: usize>(signal: &'static str, values: &[f64]) -> Result<JointVector<N>, Error> {
    if values.len() != N {
        return Err(Error::SliceLength { signal, expected: N, got: values.len() });
    }
    Ok(JointVector::from_column_slice(values))
}

/// Writes `value` into `out`, if it holds `N` numbers.
fn write<const N: usize>(signal: &'static str, value: &JointVector<N>, out: &mut [f64]) -> Result<(), Error> {
    if out.len() != N {
        return Err(Error::SliceLength { signal, expected: N, got: out.len() });
    }
    out.copy_from_slice(value.as_slice());
    Ok(())
}

/// A sample without its time, given to an estimator over timestamped samples.
const UNTIMED: Error = Error::Unsupported("a sample without its time: this estimator steps over timestamped samples");

impl<const N: usize, D: Dynamics<N> + Send> SliceObserver for DisturbanceEstimator<N, D> {
    fn dof(&self) -> usize {
        N
    }
    fn update(&mut self, q: &[f64], _qd: Option<&[f64]>, tau: &[f64], d_hat: &mut [f64]) -> Result<(), Error> {
        let (q, tau) = (joints("q", q)?, joints("tau", tau)?);
        joints::<N>("d_hat", d_hat)?;
        write("d_hat", &DisturbanceEstimator::update(self, &q, &tau)?, d_hat)
    }
    fn disturbance(&self, d_hat: &mut [f64]) -> Result<(), Error> {
        write("d_hat", DisturbanceEstimator::disturbance(self), d_hat)
    }
    fn reset(&mut self, q0: &[f64], tau0: &[f64]) -> Result<(), Error> {
        DisturbanceEstimator::reset(self, joints("q0", q0)?, joints("tau0", tau0)?)
    }
}

impl<const N: usize, D: Dynamics<N> + Clone + Send> SliceObserver for TimedEstimator<N, D> {
    fn dof(&self) -> usize {
        N
    }
    fn is_timed(&self) -> bool {
        true
    }
    fn update(&mut self, _q: &[f64], _qd: Option<&[f64]>, _tau: &[f64], _d_hat: &mut [f64]) -> Result<(), Error> {
        Err(UNTIMED)
    }
    fn update_at(&mut self, t: f64, q: &[f64], tau: &[f64], d_hat: &mut [f64]) -> Result<bool, Error> {
        let (q, tau) = (joints("q", q)?, joints("tau", tau)?);
        joints::<N>("d_hat", d_hat)?;
        let step = TimedEstimator::update(self, t, &q, &tau)?;
        write("d_hat", &step.disturbance, d_hat)?;
        Ok(step.restarted)
    }
    fn disturbance(&self, d_hat: &mut [f64]) -> Result<(), Error> {
        write("d_hat", self.estimator().disturbance(), d_hat)
    }
    fn reset(&mut self, q0: &[f64], tau0: &[f64]) -> Result<(), Error> {
        let estimator = self.estimator();
        let (dynamics, params) = (estimator.dynamics().clone(), *estimator.params());
        *self = TimedEstimator::new(dynamics, params, self.time_s(), joints("q0", q0)?, joints("tau0", tau0)?)?;
        Ok(())
    }
}

/// Any observer of `N` joints, boxed, on slices (without a restart: the baselines have none).
pub struct Boxed<'a, const N: usize>(pub BoxedObserver<'a, N>);

impl<const N: usize> SliceObserver for Boxed<'_, N> {
    fn dof(&self) -> usize {
        N
    }
    fn update(&mut self, q: &[f64], qd: Option<&[f64]>, tau: &[f64], d_hat: &mut [f64]) -> Result<(), Error> {
        let measurement = Measurement {
            position: joints("q", q)?,
            velocity: qd.map(|v| joints("qd", v)).transpose()?,
            torque: joints("tau", tau)?,
        };
        joints::<N>("d_hat", d_hat)?;
        write("d_hat", &self.0.update(&measurement)?, d_hat)
    }
    fn disturbance(&self, d_hat: &mut [f64]) -> Result<(), Error> {
        write("d_hat", self.0.disturbance(), d_hat)
    }
}

impl<const N: usize, D: Dynamics<N> + Send + Sync> SliceController for ComputedTorque<N, D> {
    fn dof(&self) -> usize {
        N
    }
    fn command(
        &self,
        [q, qd]: [&[f64]; 2],
        [q_des, qd_des, qdd_des]: [&[f64]; 3],
        d_hat: Option<&[f64]>,
        tau: &mut [f64],
    ) -> Result<(), Error> {
        let reference = Reference {
            position: joints("q_des", q_des)?,
            velocity: joints("qd_des", qd_des)?,
            acceleration: joints("qdd_des", qdd_des)?,
        };
        let d_hat = d_hat.map(|d| joints("d_hat", d)).transpose()?;
        joints::<N>("tau", tau)?;
        let command = ComputedTorque::command(self, &joints("q", q)?, &joints("qd", qd)?, &reference, d_hat.as_ref())?;
        write("tau", &command.torque, tau)
    }
}

/// The observer `design` on the model `nominal`, started on the `first` measurement, on slices
/// ([`ObserverDesign::build`]); with a first time `t0`, s, the paper's estimator over
/// timestamped samples ([`TimedEstimator`]), which only it steps over.
pub fn observer<'a, const N: usize, D: Dynamics<N> + Clone + Send + 'a>(
    design: &ObserverDesign,
    nominal: D,
    first: &Measurement<N>,
    t0: Option<f64>,
) -> Result<Box<dyn SliceObserver + 'a>, Error> {
    match (design, t0) {
        (ObserverDesign::Paper(params), Some(t0)) => {
            Ok(Box::new(TimedEstimator::new(nominal, *params, t0, first.position, first.torque)?))
        }
        (_, Some(_)) => Err(Error::Unsupported("timestamped samples: only the paper's estimator steps over them")),
        (_, None) => Ok(Box::new(Boxed(design.build(nominal, first)?.0))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_arms::PlanarTwoLink;
    use crate::{FilterParams, Gains};

    fn first() -> Measurement<2> {
        Measurement {
            position: JointVector::from([0.3, -0.2]),
            velocity: Some(JointVector::zeros()),
            torque: JointVector::from([1.0, 0.5]),
        }
    }

    #[test]
    fn on_slices_the_estimator_gives_what_it_gives_on_vectors() {
        let arm = PlanarTwoLink::default();
        let params = FilterParams::paper_at(40.0, 1e-3).unwrap();
        let mut typed = DisturbanceEstimator::new(arm, params, first().position, first().torque).unwrap();
        let mut sliced = observer(&ObserverDesign::Paper(params), arm, &first(), None).unwrap();
        let mut d_hat = [0.0; 2];
        for k in 0..50 {
            let q = [0.3 + 1e-3 * k as f64, -0.2];
            let expected = typed.update(&JointVector::from(q), &JointVector::from([1.0, 0.5])).unwrap();
            sliced.update(&q, None, &[1.0, 0.5], &mut d_hat).unwrap();
            assert_eq!(d_hat, [expected[0], expected[1]]);
        }
    }

    #[test]
    fn a_slice_of_the_wrong_length_is_refused_and_the_state_kept() {
        let arm = PlanarTwoLink::default();
        let design = ObserverDesign::Momentum { bandwidth_rad_s: 40.0, dt_s: 1e-3 };
        let mut sliced = observer(&design, arm, &first(), None).unwrap();
        let mut d_hat = [0.0; 2];
        let error = sliced.update(&[0.3, -0.2, 0.0], Some(&[0.0, 0.0]), &[1.0, 0.5], &mut d_hat).unwrap_err();
        assert_eq!(error, Error::SliceLength { signal: "q", expected: 2, got: 3 });
        let mut short = [0.0; 1];
        assert!(matches!(sliced.disturbance(&mut short), Err(Error::SliceLength { signal: "d_hat", .. })));
        assert!(matches!(sliced.reset(&[0.0; 2], &[0.0; 2]), Err(Error::Unsupported(_))));
        let controller = ComputedTorque::new(arm, Gains::diagonal([100.0; 2], [20.0; 2]).unwrap());
        let mut tau = [0.0; 2];
        let zero = [0.0; 2];
        let error = SliceController::command(&controller, [&zero, &zero], [&zero, &zero, &[0.0]], None, &mut tau);
        assert_eq!(error, Err(Error::SliceLength { signal: "qdd_des", expected: 2, got: 1 }));
    }

    #[test]
    fn a_timed_estimator_takes_only_samples_with_their_times() {
        let arm = PlanarTwoLink::default();
        let design = ObserverDesign::paper_at(40.0, 1e-3).unwrap();
        let mut timed = observer(&design, arm, &first(), Some(0.0)).unwrap();
        assert!(timed.is_timed());
        let mut d_hat = [0.0; 2];
        assert_eq!(timed.update(&[0.3, -0.2], None, &[1.0, 0.5], &mut d_hat), Err(UNTIMED));
        assert_eq!(timed.update_at(0.001, &[0.3, -0.2], &[1.0, 0.5], &mut d_hat), Ok(false));
        let momentum = ObserverDesign::Momentum { bandwidth_rad_s: 40.0, dt_s: 1e-3 };
        assert!(matches!(observer(&momentum, arm, &first(), Some(0.0)), Err(Error::Unsupported(_))));
    }
}
