//! Per-joint statistics kept up to date tick by tick, each in a few joint vectors of memory:
//! what a run's metrics are made of, so that they need no stored time series and cost the
//! same memory for a run of 20 s as for one of 2000 s.
//!
//! Each sums in the order the ticks arrive, so a mean or an RMS equals, bit for bit, the
//! one computed from the stored series; the spread about the mean and the correlation use
//! Welford's one-pass updates, equal to the two-pass figures up to rounding.

use hya_core::JointVector;

/// A time window `[from, to)`, s.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Window {
    /// Its first instant, s.
    pub from: f64,
    /// Its end (excluded), s.
    pub to: f64,
}

impl Window {
    /// `[from, to)`.
    pub fn new(from: f64, to: f64) -> Self {
        Self { from, to }
    }

    /// Whether `t` lies in the window.
    pub fn contains(&self, t: f64) -> bool {
        t >= self.from && t < self.to
    }
}

/// Per-joint mean of the samples pushed: `Σ x / n` (NaN before any sample).
#[derive(Debug, Clone, Copy)]
pub struct Mean<const N: usize> {
    sum: JointVector<N>,
    count: usize,
}

impl<const N: usize> Default for Mean<N> {
    fn default() -> Self {
        Self { sum: JointVector::zeros(), count: 0 }
    }
}

impl<const N: usize> Mean<N> {
    /// Adds a sample.
    pub fn push(&mut self, x: &JointVector<N>) {
        self.sum += x;
        self.count += 1;
    }

    /// The mean so far, per joint.
    pub fn value(&self) -> JointVector<N> {
        self.sum / self.count as f64
    }

    /// The samples pushed.
    pub fn count(&self) -> usize {
        self.count
    }
}

/// Per-joint root mean square, `√(Σ x² / n)`: NaN before any sample, which fails every rule,
/// rather than a flattering 0.
#[derive(Debug, Clone, Copy, Default)]
pub struct Rms<const N: usize>(Mean<N>);

impl<const N: usize> Rms<N> {
    /// Adds a sample.
    pub fn push(&mut self, x: &JointVector<N>) {
        self.0.push(&x.component_mul(x));
    }

    /// The RMS so far, per joint.
    pub fn value(&self) -> Vec<f64> {
        self.0.value().map(f64::sqrt).as_slice().to_vec()
    }

    /// The samples pushed.
    pub fn count(&self) -> usize {
        self.0.count()
    }
}

/// Noise of a series: the RMS of its first difference over √2 (white noise of deviation σ
/// gives σ, a smooth series nearly 0), from the second sample pushed on.
#[derive(Debug, Clone, Copy, Default)]
pub struct StepNoise<const N: usize> {
    previous: Option<JointVector<N>>,
    steps: Rms<N>,
}

impl<const N: usize> StepNoise<N> {
    /// Adds a sample.
    pub fn push(&mut self, x: &JointVector<N>) {
        if let Some(previous) = self.previous {
            self.steps.push(&((x - previous) / std::f64::consts::SQRT_2));
        }
        self.previous = Some(*x);
    }

    /// The noise so far, per joint.
    pub fn value(&self) -> Vec<f64> {
        self.steps.value()
    }
}

/// Per-joint largest and smallest sample.
#[derive(Debug, Clone, Copy)]
pub struct Extremes<const N: usize> {
    low: JointVector<N>,
    high: JointVector<N>,
}

impl<const N: usize> Default for Extremes<N> {
    fn default() -> Self {
        Self { low: JointVector::repeat(f64::INFINITY), high: JointVector::repeat(f64::NEG_INFINITY) }
    }
}

impl<const N: usize> Extremes<N> {
    /// Adds a sample.
    pub fn push(&mut self, x: &JointVector<N>) {
        self.low = self.low.zip_map(x, f64::min);
        self.high = self.high.zip_map(x, f64::max);
    }

    /// Largest `|x|`, per joint (0 before any sample).
    pub fn max_abs(&self) -> Vec<f64> {
        self.low.zip_map(&self.high, |l, h| 0.0_f64.max(-l).max(h)).as_slice().to_vec()
    }

    /// Peak-to-peak, per joint (0 before any sample).
    pub fn peak_to_peak(&self) -> Vec<f64> {
        self.low.zip_map(&self.high, |l, h| if h >= l { h - l } else { 0.0 }).as_slice().to_vec()
    }
}

/// Per-joint spread about the mean, `√(Σ (x − x̄)² / n)`, by Welford's update.
#[derive(Debug, Clone, Copy)]
pub struct Spread<const N: usize> {
    count: usize,
    mean: JointVector<N>,
    squares: JointVector<N>,
}

impl<const N: usize> Default for Spread<N> {
    fn default() -> Self {
        Self { count: 0, mean: JointVector::zeros(), squares: JointVector::zeros() }
    }
}

impl<const N: usize> Spread<N> {
    /// Adds a sample: `δ = x − x̄`, `x̄ += δ/n`, `M₂ += δ (x − x̄)`.
    pub fn push(&mut self, x: &JointVector<N>) {
        self.count += 1;
        let delta = x - self.mean;
        self.mean += delta / self.count as f64;
        self.squares += delta.component_mul(&(x - self.mean));
    }

    /// The spread so far, per joint (NaN before any sample).
    pub fn value(&self) -> Vec<f64> {
        (self.squares / self.count as f64).map(f64::sqrt).as_slice().to_vec()
    }
}

/// Per-joint Pearson correlation of two series, by Welford's co-moment update; 0 where either
/// series is constant.
#[derive(Debug, Clone, Copy)]
pub struct Correlation<const N: usize> {
    count: usize,
    mean_a: JointVector<N>,
    mean_b: JointVector<N>,
    co: JointVector<N>,
    aa: JointVector<N>,
    bb: JointVector<N>,
}

impl<const N: usize> Default for Correlation<N> {
    fn default() -> Self {
        let zeros = JointVector::zeros();
        Self { count: 0, mean_a: zeros, mean_b: zeros, co: zeros, aa: zeros, bb: zeros }
    }
}

impl<const N: usize> Correlation<N> {
    /// Adds a pair of samples.
    pub fn push(&mut self, a: &JointVector<N>, b: &JointVector<N>) {
        self.count += 1;
        let n = self.count as f64;
        let (da, db) = (a - self.mean_a, b - self.mean_b);
        self.mean_a += da / n;
        self.mean_b += db / n;
        self.co += da.component_mul(&(b - self.mean_b));
        self.aa += da.component_mul(&(a - self.mean_a));
        self.bb += db.component_mul(&(b - self.mean_b));
    }

    /// The correlation so far, per joint.
    pub fn value(&self) -> Vec<f64> {
        (0..N)
            .map(|j| {
                let (saa, sbb) = (self.aa[j], self.bb[j]);
                if saa > 0.0 && sbb > 0.0 {
                    self.co[j] / (saa * sbb).sqrt()
                } else {
                    0.0
                }
            })
            .collect()
    }
}

/// Per joint, the time from a window's start until `|e|`, having left its band, stays back
/// within it for `hold` seconds; 0 where it never leaves, the whole window where it never
/// returns.
#[derive(Debug, Clone)]
pub struct Recovery<const N: usize> {
    window: Window,
    hold: f64,
    band: Option<Vec<f64>>,
    left: [bool; N],
    inside_since: [Option<f64>; N],
    recovered: [Option<f64>; N],
}

impl<const N: usize> Recovery<N> {
    /// Watches `window`, with the hold time `hold` (s); the band is given at the window's
    /// first tick ([`Recovery::push`]).
    pub fn new(window: Window, hold: f64) -> Self {
        Self { window, hold, band: None, left: [false; N], inside_since: [None; N], recovered: [None; N] }
    }

    /// Adds the error `e` at `t`; `band` is asked for once, at the window's first tick.
    pub fn push(&mut self, t: f64, e: &JointVector<N>, band: impl FnOnce() -> Vec<f64>) {
        if !self.window.contains(t) {
            return;
        }
        let band = self.band.get_or_insert_with(band);
        for j in 0..N {
            let inside = e[j].abs() <= band[j];
            if self.recovered[j].is_some() || (!self.left[j] && inside) {
                continue;
            }
            self.left[j] = true;
            if inside {
                let since = *self.inside_since[j].get_or_insert(t);
                if t - since >= self.hold {
                    self.recovered[j] = Some(since - self.window.from);
                }
            } else {
                self.inside_since[j] = None;
            }
        }
    }

    /// The recovery times, s, per joint.
    pub fn value(&self) -> Vec<f64> {
        (0..N)
            .map(|j| match (self.left[j], self.recovered[j]) {
                (false, _) => 0.0,
                (true, Some(after)) => after,
                (true, None) => self.window.to - self.window.from,
            })
            .collect()
    }
}

/// The largest spectral line of a series after its straight-line trend is removed: what is
/// left of a limit cycle once drift (creep) is taken out.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpectralLine {
    /// The line's amplitude (of the sine), in the series' unit.
    pub amplitude: f64,
    /// Its frequency, Hz.
    pub frequency_hz: f64,
    /// The trend's change over the series' span, in the series' unit (its drift).
    pub drift: f64,
}

/// The [`SpectralLine`] of `x` sampled every `step` s from `t0`, over the bins `m / T`
/// (`T = n · step`) from two periods per window up to `max_hz`: the least-squares line
/// `a + b t` is removed, then `2 |Σ r_k e^{−jωt_k}| / n` at each bin. `None` with fewer than
/// two bins.
pub fn spectral_line(x: &[f64], t0: f64, step: f64, max_hz: f64) -> Option<SpectralLine> {
    let n = x.len();
    let span = n as f64 * step;
    let bins = (max_hz * span).floor() as usize;
    if n < 4 || bins < 3 {
        return None;
    }
    let t = |k: usize| t0 + k as f64 * step;
    let t_mean = t0 + 0.5 * (n - 1) as f64 * step;
    let x_mean = x.iter().sum::<f64>() / n as f64;
    let (mut sxy, mut sxx) = (0.0, 0.0);
    for (k, v) in x.iter().enumerate() {
        sxy += (t(k) - t_mean) * (v - x_mean);
        sxx += (t(k) - t_mean) * (t(k) - t_mean);
    }
    let slope = sxy / sxx;
    let residual: Vec<f64> = x.iter().enumerate().map(|(k, v)| v - x_mean - slope * (t(k) - t_mean)).collect();
    let mut best = (0.0_f64, 0.0);
    for first in (2..=bins).step_by(BINS_AT_ONCE) {
        let sums = bin_sums(&residual, (t0, step, span), first, bins);
        for (m, sum) in (first..=bins).zip(sums) {
            let amplitude = 2.0 * sum.norm() / n as f64;
            if amplitude > best.0 {
                best = (amplitude, m as f64 / span);
            }
        }
    }
    Some(SpectralLine { amplitude: best.0, frequency_hz: best.1, drift: slope * span })
}

/// Bins [`bin_sums`] runs side by side: each bin's rotation is a chain of dependent products,
/// so a few chains at once keep the multipliers busy.
const BINS_AT_ONCE: usize = 4;

/// `Σ r_k e^{−jω_m t_k}` for bins `m = first, first + 1, …` (at most [`BINS_AT_ONCE`], none past
/// `last`), `ω_m = 2π m / span`, `t_k = t0 + k step`: `e^{−jω t_k}` by rotation from `e^{−jω t0}`,
/// one complex product per sample; each bin's arithmetic in the same order as alone (bins past
/// `last` are computed and dropped).
fn bin_sums(
    residual: &[f64],
    (t0, step, span): (f64, f64, f64),
    first: usize,
    last: usize,
) -> impl Iterator<Item = nalgebra::Complex<f64>> {
    let omega: [f64; BINS_AT_ONCE] = core::array::from_fn(|i| std::f64::consts::TAU * (first + i) as f64 / span);
    let (c, d) = (omega.map(|w| (w * step).cos()), omega.map(|w| -(w * step).sin()));
    let (mut re, mut im) = (omega.map(|w| (w * t0).cos()), omega.map(|w| -(w * t0).sin()));
    let (mut sum_re, mut sum_im) = ([0.0; BINS_AT_ONCE], [0.0; BINS_AT_ONCE]);
    for r in residual {
        for i in 0..BINS_AT_ONCE {
            sum_re[i] += re[i] * r;
            sum_im[i] += im[i] * r;
            // (re + j im)(c + j d)
            (re[i], im[i]) = (re[i] * c[i] - im[i] * d[i], im[i] * c[i] + re[i] * d[i]);
        }
    }
    (0..BINS_AT_ONCE).take(last + 1 - first).map(move |i| nalgebra::Complex::new(sum_re[i], sum_im[i]))
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;

    fn v(x: f64) -> JointVector<1> {
        JointVector::from([x])
    }

    #[test]
    fn running_statistics_equal_their_definitions() {
        let xs = [1.0, -2.0, 4.0, 0.5, 3.0];
        let (mut mean, mut rms, mut noise, mut extremes, mut spread) =
            (Mean::default(), Rms::default(), StepNoise::default(), Extremes::default(), Spread::default());
        for x in xs {
            mean.push(&v(x));
            rms.push(&v(x));
            noise.push(&v(x));
            extremes.push(&v(x));
            spread.push(&v(x));
        }
        let n = xs.len() as f64;
        let m = xs.iter().sum::<f64>() / n;
        assert_eq!(mean.value()[0], m);
        assert_eq!(rms.value()[0], (xs.iter().map(|x| x * x).sum::<f64>() / n).sqrt());
        let steps: Vec<f64> = xs.windows(2).map(|w| (w[1] - w[0]) / std::f64::consts::SQRT_2).collect();
        assert_eq!(noise.value()[0], (steps.iter().map(|s| s * s).sum::<f64>() / 4.0).sqrt());
        assert_eq!((extremes.max_abs()[0], extremes.peak_to_peak()[0]), (4.0, 6.0));
        let two_pass = (xs.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / n).sqrt();
        assert!((spread.value()[0] - two_pass).abs() < 1e-14);
        assert!(Rms::<1>::default().value()[0].is_nan(), "no samples, no RMS");
        assert_eq!(Extremes::<1>::default().peak_to_peak()[0], 0.0);
    }

    #[test]
    fn correlation_is_pearsons() {
        let mut c = Correlation::default();
        for (a, b) in [(1.0, 2.0), (2.0, 4.5), (3.0, 5.5), (4.0, 8.0)] {
            c.push(&v(a), &v(b));
        }
        // Two-pass: ā = 2.5, b̄ = 5; Σ da db = 9.5, Σ da² = 5, Σ db² = 18.5.
        assert!((c.value()[0] - 9.5 / (5.0f64 * 18.5).sqrt()).abs() < 1e-14);
        let mut flat = Correlation::default();
        flat.push(&v(1.0), &v(1.0));
        flat.push(&v(2.0), &v(1.0));
        assert_eq!(flat.value()[0], 0.0);
    }

    #[test]
    fn a_spectral_line_is_found_apart_from_the_drift() {
        // A 0.4 Hz sine of 2 mrad on a ramp of 5 mrad over 10 s, sampled at 1 kHz.
        let step = 1e-3;
        let x: Vec<f64> = (0..10_000)
            .map(|k| {
                let t = 3.0 + k as f64 * step;
                2e-3 * (std::f64::consts::TAU * 0.4 * t + 0.3).sin() + 5e-4 * t
            })
            .collect();
        let line = spectral_line(&x, 3.0, step, 10.0).unwrap();
        assert!((line.frequency_hz - 0.4).abs() < 1e-9, "{line:?}");
        assert!((line.amplitude - 2e-3).abs() < 1e-4, "{line:?}");
        assert!((line.drift - 5e-3).abs() < 5e-4, "{line:?}");
        // A ramp alone has no line to speak of.
        let ramp: Vec<f64> = (0..10_000).map(|k| 1e-3 * k as f64 * step).collect();
        assert!(spectral_line(&ramp, 0.0, step, 10.0).unwrap().amplitude < 1e-12);
        assert!(spectral_line(&ramp[..100], 0.0, step, 10.0).is_none(), "0.1 s holds too few bins");
    }

    #[test]
    fn recovery_counts_from_the_window_to_the_start_of_the_hold() {
        let window = Window::new(1.0, 5.0);
        let errors = |out: f64, back: f64, t: f64| if t >= out && t < back { 1.0 } else { 0.0 };
        let run = |out: f64, back: f64| {
            let mut r = Recovery::<1>::new(window, 0.5);
            for k in 0..600 {
                let t = k as f64 * 0.01;
                r.push(t, &v(errors(out, back, t)), || vec![0.1]);
            }
            r.value()[0]
        };
        assert!((run(1.2, 2.0) - 1.0).abs() < 1e-9, "left at 1.2, back at 2.0 for good: {}", run(1.2, 2.0));
        assert_eq!(run(10.0, 11.0), 0.0, "never left the band");
        assert_eq!(run(1.2, 9.0), 4.0, "never came back within the window");
    }
}
