//! The error type of `hya-core`.

use thiserror::Error;

/// Everything that can go wrong in `hya-core`: bad parameters, bad measurements, numerical failure.
///
/// Every variant names the offending quantity; none of them leaves an estimator, filter or
/// controller in a changed state (operations that fail are transactional).
#[derive(Debug, Clone, Copy, PartialEq, Error)]
pub enum Error {
    /// A construction parameter is out of its valid range.
    #[error("invalid parameter `{name}` = {}: must be {requirement}", crate::Short(*value))]
    InvalidParameter {
        /// Name of the parameter, as in the documentation (`zeta`, `omega1_rad_s`, ...).
        name: &'static str,
        /// The value that was given.
        value: f64,
        /// What the value must satisfy.
        requirement: &'static str,
    },
    /// A measurement, reference or estimate handed to a hot path is NaN or infinite.
    #[error("non-finite {signal}[{index}] = {value}; the input was rejected and the state kept")]
    NonFinite {
        /// Which signal (`q_m`, `tau_m`, `q_des`, ...).
        signal: &'static str,
        /// The joint index within that signal.
        index: usize,
        /// The offending value.
        value: f64,
    },
    /// A finite sample beyond the filter's input range ([`MAX_FILTER_INPUT`](crate::MAX_FILTER_INPUT)):
    /// accepting it could overflow the filter's states, or an estimate computed from them, for
    /// good.
    #[error("{signal}[{index}] = {} is too large: beyond ±1e12, the filter's input range; the input was rejected and the state kept", crate::Short(*value))]
    Overflow {
        /// Which signal (`q_m`, `tau_m`, `u`).
        signal: &'static str,
        /// The channel index within that signal.
        index: usize,
        /// The offending sample.
        value: f64,
    },
    /// An observer needs a measurement the caller did not provide.
    #[error("this observer needs the measurement `{signal}`, which was not given")]
    MissingMeasurement {
        /// Which signal (`qd_m`).
        signal: &'static str,
    },
    /// A batch call's slices hold different numbers of states.
    #[error("batch argument {argument} holds {got} states, the batch {expected}")]
    BatchLength {
        /// The argument's position (0 for the first joint-vector slice).
        argument: usize,
        /// The number of states of the batch (its output's length).
        expected: usize,
        /// The number the argument holds.
        got: usize,
    },
    /// A row batch's slice (row after row of numbers) ends inside a row.
    #[error("batch argument {argument} holds {values} numbers, not a whole number of rows of {width}")]
    PartialRow {
        /// The argument's position (the output's is after the inputs').
        argument: usize,
        /// How many numbers it holds.
        values: usize,
        /// The numbers per row.
        width: usize,
    },
    /// A slice handed to an observer or controller on slices ([`crate::estimation::erased`]) holds another
    /// number of values than the joints.
    #[error("{signal} holds {got} values; the model has {expected} joints")]
    SliceLength {
        /// Which signal (`q`, `tau`, `d_hat`, ...).
        signal: &'static str,
        /// The joint count.
        expected: usize,
        /// The slice's length.
        got: usize,
    },
    /// A call this observer does not take: a sample without its time for an estimator stepped
    /// over timestamps, one with a time for an observer stepped at its period, a restart of an
    /// observer that has none. Says which.
    #[error("this observer does not take {0}")]
    Unsupported(&'static str),
    /// The mass matrix is not positive definite at this configuration, so forward dynamics fails.
    #[error("the mass matrix is not positive definite at this configuration")]
    SingularMassMatrix,
    /// A result computed from finite inputs is not finite: the inputs are beyond what double
    /// precision carries through the computation (a joint velocity of 1e160 squares to
    /// infinity). No output of the call is valid.
    #[error("{quantity}[{index}] = {value}: the result is not finite (the inputs are too large for double precision); no output is valid")]
    NonFiniteResult {
        /// Which result (`tau`, `qdd`, `mass`).
        quantity: &'static str,
        /// The first non-finite entry.
        index: usize,
        /// Its value.
        value: f64,
    },
}
