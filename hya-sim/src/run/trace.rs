//! What one closed-loop run records, one entry per control tick.

use hya_core::JointVector;

use crate::config::scenario::Method;

/// The estimators that run in shadow mode in every closed loop, in the order of
/// [`Trace::shadow`]: each on the loop's own measurement stream, none of them acting on it.
pub const SHADOWS: [Method; 4] = [Method::Lu, Method::Chen, Method::Momentum, Method::Eso];

/// Time series of one run, one entry per control tick.
#[derive(Debug, Clone, Default)]
pub struct Trace<const N: usize> {
    /// Time, s.
    pub time: Vec<f64>,
    /// True joint positions, rad.
    pub q: Vec<JointVector<N>>,
    /// Reference positions, rad.
    pub q_des: Vec<JointVector<N>>,
    /// True disturbance, N·m.
    pub d_true: Vec<JointVector<N>>,
    /// Estimated disturbance, N·m (zeros for `none`).
    pub d_hat: Vec<JointVector<N>>,
    /// Commanded torque, N·m.
    pub tau_cmd: Vec<JointVector<N>>,
    /// Each estimator of [`SHADOWS`], run in parallel on the same measurements as the loop's
    /// (shadow mode), N·m: estimate quality compared on identical data.
    pub shadow: [Vec<JointVector<N>>; 4],
}
