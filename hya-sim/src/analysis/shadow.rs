//! Estimate quality on identical data: the figures of each estimator that ran in shadow mode
//! ([`crate::run::trace::SHADOWS`]) on one closed loop's measurements.
//!
//! Besides the error against the true disturbance, each estimator is held against its own
//! design: `d̂ − H_m·d`, with `H_m` its designed `d̂/d` (the paper's filter; `β/(s + β)` for Chen's
//! and the momentum observer; `ω³/(s + ω)³` for the ESO) applied to the recorded `d`, each
//! discretised for an input linear between samples (first-order hold), as the paper's filter is.
//! What remains is what the estimator adds beyond its designed lag: noise, model error, the
//! nonlinearity of `M(q)`.

use hya_core::{FilterParams, JointVector, ThirdOrderFilter};
use serde::Serialize;

use crate::config::scenario::{Method, Scenario};
use crate::run::trace::Trace;

/// One shadow estimator's figures, per joint, after the warm-up.
#[derive(Debug, Clone, PartialEq, Serialize, Default)]
pub struct ShadowMetrics {
    /// RMSE of `d̂ − d`, N·m.
    pub rmse_d: Vec<f64>,
    /// RMSE of `d̂ − H_m·d`, its departure from its own design, N·m.
    pub rmse_design: Vec<f64>,
    /// Noise in `d̂`: the RMS of its first difference over √2, N·m (white noise of deviation σ
    /// gives σ).
    pub noise: Vec<f64>,
    /// Amplitude of `d̂ − d` at the sinusoidal load's frequency (whole periods after the
    /// warm-up), N·m: the error in the disturbance's band; `None` without a sinusoidal load.
    pub band_error: Option<Vec<f64>>,
}

/// `H_m·d` for the design of `method` at `bandwidth` (rad/s), sampled every `dt` (s); the
/// filter starts at rest on the first sample.
pub fn designed<const N: usize>(
    method: Method,
    bandwidth: f64,
    dt: f64,
    d: &[JointVector<N>],
) -> Option<Vec<JointVector<N>>> {
    let first = *d.first()?;
    let mut out = Vec::with_capacity(d.len());
    match method {
        Method::Lu => {
            let mut filter = ThirdOrderFilter::new(FilterParams::paper_at(bandwidth, dt).ok()?, first).ok()?;
            out.push(first);
            for u in &d[1..] {
                out.push(filter.step(u).ok()?.x1);
            }
        }
        Method::Chen | Method::Momentum | Method::Eso => {
            let sections = if method == Method::Eso { 3 } else { 1 };
            let mut signal = d.to_vec();
            for _ in 0..sections {
                signal = first_order_hold_lag(bandwidth, dt, &signal);
            }
            out = signal;
        }
        Method::None | Method::Pid => return None,
    }
    Some(out)
}

/// `β/(s + β)` on `u`, exact for an input linear between samples: `y_k = a y_{k−1} + b0 u_k +
/// b1 u_{k−1}`, `a = e^{−βT}`, `b0 = 1 − (1 − a)/(βT)`, `b1 = (1 − a)/(βT) − a` (unity DC gain),
/// at rest on the first sample.
fn first_order_hold_lag<const N: usize>(beta: f64, dt: f64, u: &[JointVector<N>]) -> Vec<JointVector<N>> {
    let a = (-beta * dt).exp();
    let c = (1.0 - a) / (beta * dt);
    let (b0, b1) = (1.0 - c, c - a);
    let mut y = Vec::with_capacity(u.len());
    for (k, uk) in u.iter().enumerate() {
        y.push(match k {
            0 => *uk,
            _ => y[k - 1] * a + uk * b0 + u[k - 1] * b1,
        });
    }
    y
}

/// Per-joint `sqrt(mean(x²))` over the samples. An empty window has no RMS: NaN, which fails
/// every rule, rather than a flattering 0.
pub(crate) fn rms<const N: usize>(samples: impl Iterator<Item = JointVector<N>>) -> Vec<f64> {
    let (sum, count) = samples.fold((JointVector::<N>::zeros(), 0usize), |(s, n), x| (s + x.component_mul(&x), n + 1));
    (sum / count as f64).map(f64::sqrt).as_slice().to_vec()
}

/// The figures of every shadow estimator of `trace` (a run of `scenario`), from tick `start`
/// (the end of the warm-up) on.
pub fn shadow_metrics<const N: usize>(trace: &Trace<N>, scenario: &Scenario, start: usize) -> [ShadowMetrics; 4] {
    let c = &scenario.controller;
    let n = trace.time.len();
    core::array::from_fn(|i| {
        let d_hat = &trace.shadow[i];
        if d_hat.len() != n || start >= n {
            return ShadowMetrics::default();
        }
        let method = crate::run::trace::SHADOWS[i];
        let design = designed(method, c.observer_bandwidth_rad_s, c.dt_s, &trace.d_true).unwrap_or_default();
        let band_error = scenario.loads.sinusoid.as_ref().map(|load| {
            let period = 1.0 / load.frequency_hz;
            let from = trace.time[start];
            let whole = ((trace.time[n - 1] - from) / period).floor() * period;
            let end = trace.time.partition_point(|t| *t < from + whole);
            (0..N)
                .map(|j| {
                    let samples: Vec<(f64, f64)> =
                        (start..end).map(|k| (trace.time[k], d_hat[k][j] - trace.d_true[k][j])).collect();
                    crate::linear::phasor(&samples, std::f64::consts::TAU * load.frequency_hz).norm()
                })
                .collect()
        });
        ShadowMetrics {
            rmse_d: rms((start..n).map(|k| d_hat[k] - trace.d_true[k])),
            rmse_design: match design.len() == n {
                true => rms((start..n).map(|k| d_hat[k] - design[k])),
                false => vec![f64::NAN; N],
            },
            noise: rms(d_hat[start..].windows(2).map(|w| (w[1] - w[0]) / std::f64::consts::SQRT_2)),
            band_error,
        }
    })
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;

    #[test]
    fn designs_have_unity_gain_and_their_lag() {
        // A ramp through each design: after settling the output trails by the design's
        // low-frequency delay (1/β; 3/ω; 1/ω1 + 2ζ/ω2), exactly for a ramp.
        let dt = 1e-3;
        let ramp: Vec<JointVector<1>> = (0..4000).map(|k| JointVector::from([k as f64 * dt])).collect();
        for (method, delay) in [(Method::Chen, 1.0 / 50.0), (Method::Eso, 3.0 / 50.0), (Method::Lu, 0.052)] {
            let out = designed(method, 50.0, dt, &ramp).unwrap();
            let lag = ramp[3999][0] - out[3999][0];
            assert!((lag - delay).abs() < 1e-6, "{method:?}: lag {lag}, design {delay}");
        }
        let constant = vec![JointVector::<1>::from([2.5]); 100];
        assert!(designed(Method::Momentum, 30.0, dt, &constant).unwrap().iter().all(|y| (y[0] - 2.5).abs() < 1e-12));
    }
}
