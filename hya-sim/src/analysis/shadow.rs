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
use serde::{Deserialize, Serialize};

use crate::analysis::running::{Rms, StepNoise, Window};
use crate::config::plant::SinusoidLoad;
use crate::config::scenario::Method;
use crate::linear::PhasorSum;

/// One shadow estimator's figures, per joint, after the warm-up.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
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

/// `H_m` of one estimator's design at `bandwidth` (rad/s), sampled every `dt` (s), stepped
/// sample by sample; it starts at rest on the first sample it is given.
#[derive(Debug, Clone)]
pub struct Design<const N: usize> {
    method: Method,
    bandwidth: f64,
    dt: f64,
    state: Option<DesignState<N>>,
}

#[derive(Debug, Clone)]
enum DesignState<const N: usize> {
    /// The paper's filter.
    Lu(Box<ThirdOrderFilter<N>>),
    /// First-order sections in series: one for Chen's and the momentum observer, three for the
    /// ESO.
    Lags(Vec<FirstOrderHoldLag<N>>),
}

impl<const N: usize> Design<N> {
    /// The design of `method`; `None` for the methods without an estimator.
    pub fn new(method: Method, bandwidth: f64, dt: f64) -> Option<Self> {
        method.estimates().then_some(Self { method, bandwidth, dt, state: None })
    }

    /// `H_m·d` at this sample; `None` where the design cannot be discretised.
    pub fn step(&mut self, d: &JointVector<N>) -> Option<JointVector<N>> {
        let Some(state) = self.state.as_mut() else {
            self.state = Some(match self.method {
                Method::Lu => DesignState::Lu(Box::new(
                    ThirdOrderFilter::new(FilterParams::paper_at(self.bandwidth, self.dt).ok()?, *d).ok()?,
                )),
                method => {
                    let sections = if method == Method::Eso { 3 } else { 1 };
                    DesignState::Lags(vec![FirstOrderHoldLag::at_rest(self.bandwidth, self.dt, d); sections])
                }
            });
            return Some(*d);
        };
        match state {
            DesignState::Lu(filter) => filter.step(d).ok().map(|s| s.x1),
            DesignState::Lags(sections) => Some(sections.iter_mut().fold(*d, |u, lag| lag.step(&u))),
        }
    }
}

/// `β/(s + β)`, exact for an input linear between samples: `y_k = a y_{k−1} + b0 u_k +
/// b1 u_{k−1}`, `a = e^{−βT}`, `b0 = 1 − (1 − a)/(βT)`, `b1 = (1 − a)/(βT) − a` (unity DC gain).
#[derive(Debug, Clone, Copy)]
struct FirstOrderHoldLag<const N: usize> {
    a: f64,
    b0: f64,
    b1: f64,
    y: JointVector<N>,
    u: JointVector<N>,
}

impl<const N: usize> FirstOrderHoldLag<N> {
    /// At rest on `u0`.
    fn at_rest(beta: f64, dt: f64, u0: &JointVector<N>) -> Self {
        let a = (-beta * dt).exp();
        let c = (1.0 - a) / (beta * dt);
        Self { a, b0: 1.0 - c, b1: c - a, y: *u0, u: *u0 }
    }

    fn step(&mut self, u: &JointVector<N>) -> JointVector<N> {
        self.y = self.y * self.a + u * self.b0 + self.u * self.b1;
        self.u = *u;
        self.y
    }
}

/// One shadow estimator's figures, accumulated tick by tick.
#[derive(Debug, Clone)]
pub struct ShadowRecorder<const N: usize> {
    design: Option<Design<N>>,
    error: Rms<N>,
    design_error: Rms<N>,
    noise: StepNoise<N>,
    band: Option<BandError<N>>,
}

/// The amplitude of `d̂ − d` at a sinusoidal load's frequency, over whole periods from the
/// first tick after the warm-up to the run's last tick.
#[derive(Debug, Clone)]
struct BandError<const N: usize> {
    period: f64,
    last_time: f64,
    window: Option<Window>,
    phasors: [PhasorSum; N],
}

impl<const N: usize> ShadowRecorder<N> {
    /// The recorder of `method` (of [`crate::run::trace::SHADOWS`]) at the observers' pole
    /// magnitude `bandwidth` (rad/s) and control period `dt` (s), under the sinusoidal load
    /// (whose band it watches), whose last tick is at `last_time` (s).
    pub fn new(
        method: Method,
        (bandwidth, dt): (f64, f64),
        sinusoid: Option<&SinusoidLoad<N>>,
        last_time: f64,
    ) -> Self {
        Self {
            design: Design::new(method, bandwidth, dt),
            error: Rms::default(),
            design_error: Rms::default(),
            noise: StepNoise::default(),
            band: sinusoid.map(|load| BandError {
                period: 1.0 / load.frequency_hz,
                last_time,
                window: None,
                phasors: [PhasorSum::new(std::f64::consts::TAU * load.frequency_hz); N],
            }),
        }
    }

    /// Adds one tick: the true disturbance `d` and this estimator's `d_hat` at `t`, which counts
    /// toward the figures `after_warm_up`.
    pub fn push(&mut self, t: f64, d: &JointVector<N>, d_hat: &JointVector<N>, after_warm_up: bool) {
        let designed = self.design.as_mut().and_then(|design| design.step(d));
        if designed.is_none() {
            self.design = None;
        }
        if !after_warm_up {
            return;
        }
        let error = d_hat - d;
        self.error.push(&error);
        if let Some(designed) = designed {
            self.design_error.push(&(d_hat - designed));
        }
        self.noise.push(d_hat);
        if let Some(band) = self.band.as_mut() {
            let window = *band.window.get_or_insert_with(|| {
                let whole = ((band.last_time - t) / band.period).floor() * band.period;
                Window::new(t, t + whole)
            });
            if window.contains(t) {
                band.phasors.iter_mut().zip(error.iter()).for_each(|(p, e)| p.push(t, *e));
            }
        }
    }

    /// The figures; empty ones where no tick followed the warm-up.
    pub fn finish(&self) -> ShadowMetrics {
        if self.error.count() == 0 {
            return ShadowMetrics::default();
        }
        ShadowMetrics {
            rmse_d: self.error.value(),
            rmse_design: match self.design {
                Some(_) => self.design_error.value(),
                None => vec![f64::NAN; N],
            },
            noise: self.noise.value(),
            band_error: self.band.as_ref().map(|b| b.phasors.iter().map(|p| p.value().norm()).collect()),
        }
    }
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
            let mut design = Design::new(method, 50.0, dt).unwrap();
            let out: Vec<JointVector<1>> = ramp.iter().map(|d| design.step(d).unwrap()).collect();
            let lag = ramp[3999][0] - out[3999][0];
            assert!((lag - delay).abs() < 1e-6, "{method:?}: lag {lag}, design {delay}");
        }
        let mut momentum = Design::new(Method::Momentum, 30.0, dt).unwrap();
        assert!((0..100).all(|_| (momentum.step(&JointVector::<1>::from([2.5])).unwrap()[0] - 2.5).abs() < 1e-12));
    }
}
