//! What one closed-loop run records, one entry per control tick.

use hya_core::JointVector;

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
}
