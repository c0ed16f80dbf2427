//! What one closed-loop run keeps of its time series for figures and CSV files, bounded in
//! memory: every control tick of a run up to [`MAX_TRACE_SAMPLES`] ticks, every `stride`-th
//! tick of a longer one. The run's metrics do not come from here: they are accumulated from
//! every tick as the run goes ([`crate::analysis::metrics::MetricsRecorder`]), so neither
//! depends on the simulated duration.

use hya_core::JointVector;

use crate::config::scenario::Method;

/// The estimators that run in shadow mode in every closed loop, in the order of
/// [`crate::analysis::metrics::Metrics::shadow`]: each on the loop's own measurement stream,
/// none of them acting on it.
pub const SHADOWS: [Method; 4] = [Method::Lu, Method::Chen, Method::Momentum, Method::Eso];

/// The most ticks a trace keeps: 30 s at 1 kHz (every built-in scenario but the 45 s weight
/// drop), about 7.4 MB for a 6-joint arm. A longer run keeps every `stride`-th tick
/// ([`Trace::stride_for`]).
pub const MAX_TRACE_SAMPLES: usize = 30_000;

/// Bytes one kept tick holds for an `n`-joint arm: time and five joint vectors.
pub const fn bytes_per_sample(n: usize) -> usize {
    8 * (1 + 5 * n)
}

/// Which ticks of a run its trace keeps.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Recording {
    /// Every tick up to [`MAX_TRACE_SAMPLES`], evenly thinned beyond.
    Bounded,
    /// None: the run is wanted for its metrics alone.
    Off,
}

/// Time series of one run, one entry per kept tick.
#[derive(Debug, Clone, Default)]
pub struct Trace<const N: usize> {
    /// Every how many control ticks an entry is kept (1: every tick; 0: none).
    pub stride: usize,
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

/// What the loop produced at one control tick.
#[derive(Debug, Clone, Copy)]
pub struct Tick<const N: usize> {
    /// Time, s.
    pub t: f64,
    /// True joint positions, rad.
    pub q: JointVector<N>,
    /// Reference positions, rad.
    pub q_des: JointVector<N>,
    /// True disturbance, N·m.
    pub d_true: JointVector<N>,
    /// Estimated disturbance, N·m (zeros for `none`).
    pub d_hat: JointVector<N>,
    /// Commanded torque, N·m.
    pub tau_cmd: JointVector<N>,
    /// Each estimator of [`SHADOWS`], run on the loop's measurements, N·m.
    pub shadow: [JointVector<N>; 4],
}

impl<const N: usize> Trace<N> {
    /// Every how many ticks a run of `ticks` ticks keeps one: 1 up to [`MAX_TRACE_SAMPLES`],
    /// else the least stride that keeps at most that many.
    pub fn stride_for(ticks: usize) -> usize {
        ticks.div_ceil(MAX_TRACE_SAMPLES).max(1)
    }

    /// An empty trace for a run of `ticks` ticks, with its room reserved.
    pub fn new(ticks: usize, recording: Recording) -> Self {
        let stride = match recording {
            Recording::Bounded => Self::stride_for(ticks),
            Recording::Off => 0,
        };
        let kept = if stride == 0 { 0 } else { ticks.div_ceil(stride) };
        Self {
            stride,
            time: Vec::with_capacity(kept),
            q: Vec::with_capacity(kept),
            q_des: Vec::with_capacity(kept),
            d_true: Vec::with_capacity(kept),
            d_hat: Vec::with_capacity(kept),
            tau_cmd: Vec::with_capacity(kept),
        }
    }

    /// Keeps tick number `k` if the stride says so.
    pub fn record(&mut self, k: usize, tick: &Tick<N>) {
        if self.stride == 0 || !k.is_multiple_of(self.stride) {
            return;
        }
        self.time.push(tick.t);
        self.q.push(tick.q);
        self.q_des.push(tick.q_des);
        self.d_true.push(tick.d_true);
        self.d_hat.push(tick.d_hat);
        self.tau_cmd.push(tick.tau_cmd);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_trace_keeps_at_most_its_bound_evenly() {
        assert_eq!(Trace::<1>::stride_for(0), 1);
        assert_eq!(Trace::<1>::stride_for(MAX_TRACE_SAMPLES), 1);
        assert_eq!(Trace::<1>::stride_for(MAX_TRACE_SAMPLES + 1), 2);
        let zero = JointVector::from([0.0]);
        let tick = |k: usize| Tick {
            t: k as f64,
            q: zero,
            q_des: zero,
            d_true: zero,
            d_hat: zero,
            tau_cmd: zero,
            shadow: [zero; 4],
        };
        for ticks in [10, MAX_TRACE_SAMPLES + 1, 2_000_000] {
            let mut trace = Trace::<1>::new(ticks, Recording::Bounded);
            for k in 0..ticks {
                trace.record(k, &tick(k));
            }
            assert!(trace.time.len() <= MAX_TRACE_SAMPLES, "{ticks} ticks kept {}", trace.time.len());
            assert!(trace.time.len() * trace.stride >= ticks, "{ticks} ticks: only {} kept", trace.time.len());
            assert_eq!(trace.time[1] - trace.time[0], trace.stride as f64);
        }
        let mut off = Trace::<1>::new(100, Recording::Off);
        off.record(0, &tick(0));
        assert!(off.time.is_empty());
    }
}
