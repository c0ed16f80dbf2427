//! The paper's third-order filter, discretised exactly for an input linear between samples.
//!
//! Per channel, with identical parameters `ζ, ω1, ω2` on every channel:
//!
//! ```text
//! ẋ1 = x2
//! ẋ2 = x3
//! ẋ3 = ω1 ω2² (u − x1) − (ω2² + 2ζ ω1 ω2) x2 − (ω1 + 2ζ ω2) x3
//!
//! H(s) = x1/u = ω1 ω2² / ((s + ω1)(s² + 2ζ ω2 s + ω2²))
//! ```
//!
//! so `x2 = s H u` and `x3 = s² H u`: fed with joint angles, the states are the filtered angle,
//! velocity and acceleration, with no numerical differentiation.
//!
//! # Discretisation
//!
//! With `ẋ = A x + B u` and `u` linear between the samples `u_k`, `u_{k+1}` (first-order hold),
//!
//! ```text
//! x_{k+1} = Φ x_k + (Γa − Γb) u_k + Γb u_{k+1},   Φ = e^{AT}
//! exp([[A T, B T, 0], [0, 0, 1], [0, 0, 0]]) = [[Φ, Γa, Γb], [0, 1, 1], [0, 0, 1]]
//! ```
//!
//! which is exact for ramps and matches `H(jω)` closely well below the sample rate. A zero-order
//! hold would not: the held staircase leaks into `x3` (relative degree one), biasing `x3` for a
//! parabola and delaying the output by half a sample.
//!
//! What no hold can avoid: a parabola `u = c t²/2` is seen as its piecewise-linear interpolant,
//! whose periodic remainder aliases onto `x3` as a relative bias `Σ_{k≠0} H(jkω_s)`,
//! `ω_s = 2π/T`, which grows as `ω1 ω2² (ω1 + 2ζω2) T⁴`: about 2e-8 at the paper's `ωT = 0.05`,
//! up to 1.5e-5 at `ωT = 0.25` and 1e-4 at `ωT = 0.5` for `ζ = 1.5`.
//!
//! # Properties
//!
//! Unity DC gain; low-frequency group delay `1/ω1 + 2ζ/ω2` (52 ms for the paper's `ζ = 0.8`,
//! `ω1 = ω2 = 50 rad/s`), −3 dB near 32 rad/s (5.1 Hz) for those values.

use nalgebra::{Complex, Matrix3, SMatrix, Vector3};

use crate::finite::{check, discretisable, positive};

/// The largest magnitude a filter accepts as input: no angle in rad or torque in N·m comes near
/// it, and with it the states, and estimates computed from them, stay far from overflow.
pub const MAX_FILTER_INPUT: f64 = 1e12;
use crate::rigid_body::linalg::matrix_exponential;
use crate::{Error, JointVector};

/// Validated filter parameters: damping `ζ`, corner frequencies `ω1`, `ω2` (rad/s), sample time (s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FilterParams {
    zeta: f64,
    omega1_rad_s: f64,
    omega2_rad_s: f64,
    dt_s: f64,
}

/// The paper's damping ratio of the filter's second-order factor.
pub const PAPER_ZETA: f64 = 0.8;

/// The paper's `ω1 = ω2`, rad/s.
pub const PAPER_BANDWIDTH_RAD_S: f64 = 50.0;

/// The smallest damping ratio `ζ` a filter takes: below it the second-order factor rings for
/// thousands of periods, which no real design wants.
pub const MIN_ZETA: f64 = 1e-3;

/// The smallest `ω · dt` a filter takes, for `ω1` and `ω2`: below it a corner frequency takes
/// more than a million samples to act, and each sample moves the states by too little to tell
/// from rounding (at `dt = 1e-300`, every output equalled the first).
pub const MIN_RATE_TIMES_DT: f64 = 1e-6;

impl FilterParams {
    /// Checks that every parameter is finite and strictly positive, that
    /// [`MIN_ZETA`]` ≤ ζ ≤ 100`, and that `ω1 · dt` and `ω2 · dt` lie within
    /// [`MIN_RATE_TIMES_DT`] and [`MAX_RATE_TIMES_DT`](crate::MAX_RATE_TIMES_DT).
    pub fn new(zeta: f64, omega1_rad_s: f64, omega2_rad_s: f64, dt_s: f64) -> Result<Self, Error> {
        let dt_s = positive("dt_s", dt_s)?;
        let zeta = positive("zeta", zeta)?;
        if !(MIN_ZETA..=100.0).contains(&zeta) {
            return Err(Error::InvalidParameter {
                name: "zeta",
                value: zeta,
                requirement: "at least 0.001 and at most 100",
            });
        }
        let rate = |name, omega| {
            let omega = discretisable(name, omega, dt_s)?;
            match omega * dt_s >= MIN_RATE_TIMES_DT {
                true => Ok(omega),
                false => Err(Error::InvalidParameter {
                    name,
                    value: omega,
                    requirement: "such that it times dt_s is at least 1e-6, or the filter barely moves between samples",
                }),
            }
        };
        Ok(Self {
            zeta,
            omega1_rad_s: rate("omega1_rad_s", omega1_rad_s)?,
            omega2_rad_s: rate("omega2_rad_s", omega2_rad_s)?,
            dt_s,
        })
    }

    /// The paper's values, `ζ = 0.8`, `ω1 = ω2 = 50 rad/s`, at the given sample time.
    pub fn paper(dt_s: f64) -> Result<Self, Error> {
        Self::paper_at(PAPER_BANDWIDTH_RAD_S, dt_s)
    }

    /// The paper's shape, `ζ = 0.8` and `ω1 = ω2`, at another bandwidth.
    pub fn paper_at(bandwidth_rad_s: f64, dt_s: f64) -> Result<Self, Error> {
        Self::new(PAPER_ZETA, bandwidth_rad_s, bandwidth_rad_s, dt_s)
    }

    /// Damping ratio `ζ` of the second-order factor.
    pub fn zeta(&self) -> f64 {
        self.zeta
    }

    /// Corner frequency `ω1` of the first-order factor, rad/s.
    pub fn omega1_rad_s(&self) -> f64 {
        self.omega1_rad_s
    }

    /// Natural frequency `ω2` of the second-order factor, rad/s.
    pub fn omega2_rad_s(&self) -> f64 {
        self.omega2_rad_s
    }

    /// Sample time `T`, s.
    pub fn dt_s(&self) -> f64 {
        self.dt_s
    }

    /// The same filter over another sample time `dt_s` (a log's own step), checked as in
    /// [`new`](Self::new).
    pub fn with_dt(&self, dt_s: f64) -> Result<Self, Error> {
        Self::new(self.zeta, self.omega1_rad_s, self.omega2_rad_s, dt_s)
    }

    /// Low-frequency group delay `1/ω1 + 2ζ/ω2`, s.
    pub fn group_delay_s(&self) -> f64 {
        1.0 / self.omega1_rad_s + 2.0 * self.zeta / self.omega2_rad_s
    }

    /// Continuous state matrix `A` (companion form of the denominator of `H`).
    pub fn state_matrix(&self) -> Matrix3<f64> {
        let (z, w1, w2) = (self.zeta, self.omega1_rad_s, self.omega2_rad_s);
        Matrix3::new(0.0, 1.0, 0.0, 0.0, 0.0, 1.0, -w1 * w2 * w2, -(w2 * w2 + 2.0 * z * w1 * w2), -(w1 + 2.0 * z * w2))
    }

    /// Continuous input vector `B = (0, 0, ω1 ω2²)`.
    pub fn input_vector(&self) -> Vector3<f64> {
        Vector3::new(0.0, 0.0, self.omega1_rad_s * self.omega2_rad_s * self.omega2_rad_s)
    }

    /// Continuous frequency response of the three states, `[H, jω H, (jω)² H]` at `ω` rad/s.
    pub fn continuous_response(&self, omega_rad_s: f64) -> [Complex<f64>; 3] {
        let s = Complex::new(0.0, omega_rad_s);
        let (z, w1, w2) = (self.zeta, self.omega1_rad_s, self.omega2_rad_s);
        let h = Complex::from(w1 * w2 * w2) / ((s + w1) * (s * s + s * (2.0 * z * w2) + w2 * w2));
        [h, s * h, s * s * h]
    }
}

/// Why [`ThirdOrderFilter::peek_over`] refuses the input `u`: its first non-finite entry
/// ([`Error::NonFinite`]) or, if all are finite, its first beyond [`MAX_FILTER_INPUT`]
/// ([`Error::Overflow`]).
#[cold]
#[inline(never)]
fn refused_input<const N: usize>(signal: &'static str, u: &JointVector<N>) -> Error {
    if let Err(error) = check(signal, u) {
        return error;
    }
    let index = u.iter().position(|x| x.abs() > MAX_FILTER_INPUT).unwrap_or(0);
    Error::Overflow { signal, index, value: u[index] }
}

/// `v`, or zero where it is below the smallest normal double.
///
/// A constant input (an encoder at rest, a held torque) makes `x2` and `x3` decay towards zero
/// forever; flushed before they turn subnormal, where arithmetic runs 10 to 100 times slower.
#[inline(always)]
fn flush_subnormal(v: f64) -> f64 {
    if v.abs() < f64::MIN_POSITIVE {
        0.0
    } else {
        v
    }
}

/// The three states of every channel: `x1` (the filtered input), `x2 = ẋ1`, `x3 = ẍ1`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FilterState<const N: usize> {
    /// Filtered input (`q̂` for joint angles, `τ̂` for torques).
    pub x1: JointVector<N>,
    /// Its first derivative (`q̂̇`).
    pub x2: JointVector<N>,
    /// Its second derivative (`q̂̈`).
    pub x3: JointVector<N>,
}

impl<const N: usize> FilterState<N> {
    /// The rest state `(x0, 0, 0)` from which the paper starts.
    pub fn at_rest(x0: JointVector<N>) -> Self {
        Self { x1: x0, x2: JointVector::zeros(), x3: JointVector::zeros() }
    }
}

/// One step's first-order-hold discretisation: `x_{k+1} = Φ x_k + γ_now u_k + γ_next u_{k+1}`
/// with `Φ = e^{AT}`, `γ_now = Γa − Γb`, `γ_next = Γb` (see the module's equations), for the
/// sample time `T` of the parameters it was built from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Discretisation {
    transition: Matrix3<f64>,
    input_now: Vector3<f64>,
    input_next: Vector3<f64>,
}

impl Discretisation {
    /// `Φ`, `γ_now`, `γ_next` over `params`' sample time, from one 5×5 matrix exponential.
    pub fn new(params: &FilterParams) -> Self {
        let t = params.dt_s;
        let mut augmented = SMatrix::<f64, 5, 5>::zeros();
        augmented.fixed_view_mut::<3, 3>(0, 0).copy_from(&(params.state_matrix() * t));
        augmented.fixed_view_mut::<3, 1>(0, 3).copy_from(&(params.input_vector() * t));
        augmented[(3, 4)] = 1.0;
        let e = matrix_exponential(&augmented);
        let gamma_a: Vector3<f64> = e.fixed_view::<3, 1>(0, 3).into();
        let gamma_b: Vector3<f64> = e.fixed_view::<3, 1>(0, 4).into();
        Self { transition: e.fixed_view::<3, 3>(0, 0).into(), input_now: gamma_a - gamma_b, input_next: gamma_b }
    }

    /// The state transition `Φ = e^{AT}`.
    pub fn transition(&self) -> &Matrix3<f64> {
        &self.transition
    }
}

/// The paper's third-order filter on `N` channels, stepped at a fixed sample time, or over a
/// step of any length with [`peek_over`](Self::peek_over).
///
/// One 3x3 `Φ` and two input vectors, computed once at construction, serve every channel.
#[derive(Debug, Clone, PartialEq)]
pub struct ThirdOrderFilter<const N: usize> {
    params: FilterParams,
    discretisation: Discretisation,
    state: FilterState<N>,
    last_input: JointVector<N>,
}

impl<const N: usize> ThirdOrderFilter<N> {
    /// A filter at rest at `x0`: `x1 = x0`, `x2 = x3 = 0`, last input `x0`.
    pub fn new(params: FilterParams, x0: JointVector<N>) -> Result<Self, Error> {
        check("x0", &x0)?;
        Ok(Self {
            params,
            discretisation: Discretisation::new(&params),
            state: FilterState::at_rest(x0),
            last_input: x0,
        })
    }

    /// The discretisation over the parameters' own sample time.
    pub fn discretisation(&self) -> &Discretisation {
        &self.discretisation
    }

    /// The parameters the filter was built with.
    pub fn params(&self) -> &FilterParams {
        &self.params
    }

    /// The current state.
    pub fn state(&self) -> &FilterState<N> {
        &self.state
    }

    /// Back to rest at `x0`, as at construction.
    pub fn reset(&mut self, x0: JointVector<N>) -> Result<(), Error> {
        check("x0", &x0)?;
        self.state = FilterState::at_rest(x0);
        self.last_input = x0;
        Ok(())
    }

    /// Sets an arbitrary state, with `last_input` the sample the next step interpolates from.
    pub fn set_state(&mut self, state: FilterState<N>, last_input: JointVector<N>) -> Result<(), Error> {
        check("x1", &state.x1)?;
        check("x2", &state.x2)?;
        check("x3", &state.x3)?;
        check("last_input", &last_input)?;
        self.state = state;
        self.last_input = last_input;
        Ok(())
    }

    /// The state one sample ahead for the new input `u`, without committing it.
    ///
    /// `signal` names the input in the error if `u` is not finite ([`Error::NonFinite`]), or
    /// beyond [`MAX_FILTER_INPUT`] ([`Error::Overflow`]). The filter is stable, so inputs within
    /// that range keep every state bounded by a fixed multiple of it: every state it returns is
    /// finite, and so is every later one.
    #[inline]
    pub fn peek(&self, signal: &'static str, u: &JointVector<N>) -> Result<FilterState<N>, Error> {
        self.peek_over(&self.discretisation, signal, u)
    }

    /// As [`peek`](Self::peek), over the step that `step` discretises instead of the filter's own
    /// sample time: a log's irregular step, with `step` built from
    /// [`FilterParams::with_dt`] (or taken from a [`DiscretisationCache`](crate::estimation::step_cache::DiscretisationCache)).
    /// Over a step of the filter's own length it computes exactly what `peek` does.
    #[inline(always)]
    pub fn peek_over(
        &self,
        step: &Discretisation,
        signal: &'static str,
        u: &JointVector<N>,
    ) -> Result<FilterState<N>, Error> {
        // One pass with no exit (NaN fails `≤`); which entry and why only on failure.
        if !u.iter().fold(true, |within, x| within & (x.abs() <= MAX_FILTER_INPUT)) {
            return Err(refused_input(signal, u));
        }
        let (phi, now, next) = (&step.transition, &step.input_now, &step.input_next);
        let s = &self.state;
        let mut out = FilterState::<N>::at_rest(JointVector::zeros());
        // Channel by channel: x⁺ = Φ x + γ_now u_prev + γ_next u. No exit inside the loop, so
        // the compiler runs the channels side by side in vector registers.
        for j in 0..N {
            let (x1, x2, x3, previous, sample) = (s.x1[j], s.x2[j], s.x3[j], self.last_input[j], u[j]);
            let row = |r: usize| {
                flush_subnormal(
                    phi[(r, 0)] * x1 + phi[(r, 1)] * x2 + phi[(r, 2)] * x3 + now[r] * previous + next[r] * sample,
                )
            };
            (out.x1[j], out.x2[j], out.x3[j]) = (row(0), row(1), row(2));
        }
        let finite = |j: usize| out.x1[j].is_finite() & out.x2[j].is_finite() & out.x3[j].is_finite();
        if (0..N).fold(true, |all, j| all & finite(j)) {
            Ok(out)
        } else {
            let index = (0..N).position(|j| !finite(j)).unwrap_or(0);
            Err(Error::Overflow { signal, index, value: u[index] })
        }
    }

    /// Commits a state obtained from [`peek`](Self::peek) with the same input `u`.
    #[inline]
    pub fn commit(&mut self, state: FilterState<N>, u: JointVector<N>) {
        self.state = state;
        self.last_input = u;
    }

    /// Advances one sample with the new input `u` and returns the new state.
    ///
    /// A non-finite `u` is rejected with [`Error::NonFinite`] and leaves the state untouched.
    pub fn step(&mut self, u: &JointVector<N>) -> Result<&FilterState<N>, Error> {
        let next = self.peek("u", u)?;
        self.commit(next, *u);
        Ok(&self.state)
    }

    /// Frequency response of the stepped filter, `[x1/u, x2/u, x3/u]` at `ω` rad/s:
    /// `(zI − Φ)⁻¹ ((Γa − Γb) + z Γb)` with `z = e^{jωT}`.
    ///
    /// `None` if `z` is an eigenvalue of `Φ` (never for a stable filter).
    pub fn discrete_response(&self, omega_rad_s: f64) -> Option<[Complex<f64>; 3]> {
        let phase = omega_rad_s * self.params.dt_s;
        let z = Complex::new(libm::cos(phase), libm::sin(phase));
        let complex = |v: f64| Complex::new(v, 0.0);
        let d = &self.discretisation;
        let system = Matrix3::<Complex<f64>>::identity() * z - d.transition.map(complex);
        let rhs = d.input_now.map(complex) + d.input_next.map(complex) * z;
        let x = system.lu().solve(&rhs)?;
        Some([x[0], x[1], x[2]])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::ComplexField;

    fn paper_filter() -> ThirdOrderFilter<1> {
        ThirdOrderFilter::new(FilterParams::paper(1e-3).unwrap(), JointVector::zeros()).unwrap()
    }

    #[test]
    fn invalid_parameters_name_themselves() {
        let bad = [
            FilterParams::new(0.0, 50.0, 50.0, 1e-3),
            FilterParams::new(0.8, f64::NAN, 50.0, 1e-3),
            FilterParams::new(0.8, 50.0, -1.0, 1e-3),
            FilterParams::new(0.8, 50.0, 50.0, f64::INFINITY),
            // Below the smallest damping ratio and the smallest ω · dt.
            FilterParams::new(1e-4, 50.0, 50.0, 1e-3),
            FilterParams::new(0.8, 0.5, 50.0, 1e-6),
        ];
        let names: [&str; 6] = ["zeta", "omega1_rad_s", "omega2_rad_s", "dt_s", "zeta", "omega1_rad_s"];
        for (result, expected) in bad.iter().zip(names) {
            match result {
                Err(Error::InvalidParameter { name, .. }) => assert_eq!(*name, expected),
                other => panic!("expected an error naming {expected}, got {other:?}"),
            }
        }
    }

    #[test]
    fn paper_filter_corner_and_delay_are_as_documented() {
        let params = FilterParams::paper(1e-3).unwrap();
        assert!((params.group_delay_s() - 0.052).abs() < 1e-12);
        let gain_db = |w: f64| 20.0 * params.continuous_response(w)[0].modulus().log10();
        assert!(gain_db(31.0) > -3.0 && gain_db(33.0) < -3.0);
    }

    #[test]
    fn non_finite_input_is_rejected_and_state_kept() {
        let mut filter = paper_filter();
        filter.step(&JointVector::from([1.0])).unwrap();
        let before = filter.clone();
        let err = filter.step(&JointVector::from([f64::NAN])).unwrap_err();
        assert!(matches!(err, Error::NonFinite { index: 0, .. }));
        assert_eq!(filter, before);
    }

    #[test]
    fn a_refused_input_names_its_first_non_finite_entry_else_its_first_beyond_the_bound() {
        let filter = ThirdOrderFilter::new(FilterParams::paper(1e-3).unwrap(), JointVector::<3>::zeros()).unwrap();
        let refused = |u: [f64; 3]| filter.peek("u", &JointVector::from(u)).unwrap_err();
        // Non-finite wins over an earlier entry beyond the bound.
        assert!(matches!(refused([2e12, 1.0, f64::INFINITY]), Error::NonFinite { index: 2, .. }));
        assert!(matches!(refused([3e12, f64::NAN, f64::NEG_INFINITY]), Error::NonFinite { index: 1, .. }));
        let Error::Overflow { signal, index, value } = refused([1.0, -2e12, 3e12]) else { panic!("not an overflow") };
        assert_eq!((signal, index, value), ("u", 1, -2e12));
        // The bound itself is accepted.
        assert!(filter.peek("u", &JointVector::from([MAX_FILTER_INPUT, -MAX_FILTER_INPUT, 0.0])).is_ok());
    }

    #[test]
    fn a_zero_input_decays_to_zero_without_subnormal_states() {
        // A kick, then exact zeros (a joint at rest with zero torque): the states decay
        // geometrically, through the subnormal range unless flushed.
        let mut filter = ThirdOrderFilter::<1>::new(FilterParams::paper(1e-3).unwrap(), JointVector::zeros()).unwrap();
        filter.step(&JointVector::from([1.0])).unwrap();
        for _ in 0..60_000 {
            let state = filter.step(&JointVector::from([0.0])).unwrap();
            for v in [state.x1[0], state.x2[0], state.x3[0]] {
                assert!(v == 0.0 || v.is_normal(), "subnormal state {v:e}");
            }
        }
        assert_eq!((filter.state().x1[0], filter.state().x2[0], filter.state().x3[0]), (0.0, 0.0, 0.0));
    }

    #[test]
    fn discrete_response_approaches_continuous_well_below_sample_rate() {
        let filter = paper_filter();
        let params = *filter.params();
        for w in [0.1, 1.0, 10.0, 50.0, 100.0] {
            let d = filter.discrete_response(w).unwrap();
            let c = params.continuous_response(w);
            for i in 0..3 {
                assert!((d[i] - c[i]).modulus() <= 1e-3 * c[i].modulus(), "state {i} at {w} rad/s");
            }
        }
    }
}
