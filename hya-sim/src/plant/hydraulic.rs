//! Hydraulic joint actuators: a servo valve, two chambers with compressible oil, leakage, and the
//! inner torque loop a hydraulic arm runs, so that the outer controller still commands torque.
//!
//! Per joint, with the valve opening `x_v ∈ [−1, 1]` (fraction of full opening), chamber
//! pressures `p_a, p_b` and the joint angle `q`:
//!
//! ```text
//! ẍ_v = ω_v² (u_k + b − x_v) − 2 ζ_v ω_v ẋ_v                   spool, second order
//! Q(Δp) = K_v Δp / (Δp² + δ²)^{1/4}                            orifice, ≈ K_v sgn(Δp) √|Δp|
//! x_v ≥ 0: Q_a = x_v Q(p_s − p_a),   Q_b = −x_v Q(p_b − p_t)
//! x_v < 0: Q_a = x_v Q(p_a − p_t),   Q_b = −x_v Q(p_s − p_b)
//! Q_l = C_l (p_a − p_b)                                         leakage across the piston
//! V_a = V_0 + D_a (q − q_lo),   V_b = V_0 + D_b (q_hi − q)        chamber volumes
//! ṗ_a = β / V_a (Q_a − Q_l − D_a q̇)
//! ṗ_b = β / V_b (Q_b + Q_l + D_b q̇)
//! τ_h = D_a p_a − D_b p_b                                         torque on the joint
//! ```
//!
//! `D_a = A_a r` is the cap side's displacement per radian (piston area times lever arm for a
//! cylinder, vane displacement for a rotary actuator), `D_b = α D_a` the rod side's; `K_q =
//! K_v √((p_s − p_t)/2)` is the valve's flow gain at the nominal drop, `D̄ = (D_a + D_b)/2`.
//!
//! **The inner torque loop** is digital, as on HyQ: it runs at the sample instants `t_k = t_{k−1}
//! + T_s` (`T_s = 1 / f_s`, `f_s` = `torque_loop_rate_hz`; `t_0` the plant's time 0, each next
//! instant counted from the plant's time when the loop ran, so it keeps step with the plant's
//! clock, a sum of sub-steps, and with the control ticks when `T_s` divides them) on measured
//! pressures and holds its valve command `u_k` until the next (a zero-order hold). `u_k` and the integral `I_k` are
//! part of [`HydraulicState`] but not integrated: RK4 carries them unchanged. A physics step
//! that spans a sample instant is split there ([`crate::plant::Plant::step`]), so every rate is
//! exact and none is refused for not dividing the physics step; a rate above the physics step's
//! costs one RK4 step per sample. At `t_k`:
//!
//! ```text
//! p_a,m = p_a + o_a + n_a,   p_b,m = p_b + o_b + n_b           pressure transducers
//! e_k = τ_ref − (D_a p_a,m − D_b p_b,m)
//! q_k = r round(q(t_k) / r),   r = 2π / counts                  encoder
//! v_k = a v_{k−1} + (1 − a)(q_k − q_{k−1}) / T_s,   a = e^{−2π f_v T_s}   derived velocity
//! u_k = sat(dz(K_τ (e_k + ω_i I_k) + k_vc D̄ v_k / K_q))
//! I_{k+1} = I_k + T_s e_k,  unless |K_τ ω_i I_k| ≥ 1 + δ_v and K_τ ω_i I_k e_k > 0  (anti-windup)
//! dz(u) = 0 for |u| ≤ δ_v,   u − δ_v sgn(u) beyond                  valve dead band
//! ```
//!
//! Each transducer has a constant offset `o`, uniform in `±torque_loop_pressure_offset_pa`, and
//! white Gaussian noise `n` of standard deviation `torque_loop_pressure_noise_pa`, fresh at every
//! sample; both drawn from the actuators' own generator ([`HydraulicActuators::seeded`]; the plant
//! seeds it from its own). The loop regulates the *measured* torque, so the joint's true torque
//! stands off by `D_a o_a − D_b o_b` and carries the noise through the loop. (The controller's
//! measured torque, `crate::run::sensors`, reads these transducers' offsets by default, as on
//! HyA, or a set of its own: `sensors.transducers`; see
//! [`HydraulicActuators::pressure_offsets`].)
//!
//! The load-motion compensation uses the velocity the loop can compute itself: the backward
//! difference of its encoder's angle (`torque_loop_encoder_counts_per_rev` counts per turn)
//! over its own period, through a first-order low-pass at `f_v` =
//! `torque_loop_velocity_filter_hz` (0: none, `a = 0`). It lags `q̇` by about `T_s/2 + 1/(2π
//! f_v)` and carries the quantum `r / T_s` (0.012 rad/s at 2^19 counts and 1 kHz).
//!
//! The dead band `δ_v` (`valve_dead_band`, a fraction of full opening, default 0) models an
//! overlapped spool seen from the command: inputs within it move no oil, those beyond it are
//! shifted by it (full opening then takes `1 + δ_v`). The integral winds across it, so small
//! torque errors are corrected late.
//!
//! The loop gain `K_τ` is designed for a torque bandwidth `ω_τ` on a locked joint at mid-range,
//! in continuous time (where `τ̇_h = K_lock x_v`, `K_lock = β K_q (D_a/V_a + D_b/V_b)`): `K_τ =
//! ω_τ / K_lock`; the integral term (zero at `ω_i`, a fraction of `ω_τ`) removes the steady error
//! that leakage leaves; it stops integrating once its share alone opens the valve fully
//! (conditional integration, an anti-windup). Sampling adds a delay of about `T_s/2` that the
//! design does not see. As `T_s → 0` the loop becomes the continuous one of
//! [`HydraulicActuators::derivative`] (`u = sat(K_τ (e + ω_i ∫e dt) + k_vc D̄ q̇ / K_q)` on the
//! true pressures and velocity), the design's reference. On a moving load the piston's own
//! motion feeds back on the pressures, so the achieved torque bandwidth depends on the inertia
//! the joint carries and on its pose: it falls out of the model. The lever arm is taken constant
//! over the stroke (a real cylinder's varies with angle).
//!
//! The defaults (1 kHz, HyA's pressure transducers and encoder) change the plant from the
//! continuous loop this model had before; that loop is approached with `torque_loop_rate_hz =
//! 1e5`, `torque_loop_pressure_noise_pa = torque_loop_pressure_offset_pa = 0` and
//! `torque_loop_encoder_counts_per_rev = 2^53` (a locked joint's step then rises within 2 % of
//! the continuous loop's, `tests/sim/torque_loop.rs`; `allow_unphysical` for the rate above
//! [`crate::config::scenario::PLAUSIBLE`]'s 1e5 Hz is not needed).

use hya_core::JointVector;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;

use crate::config::plant::HydraulicSetup;

/// Regularisation pressure `δ` of the orifice law, Pa: below it the flow is linear in `Δp`, so
/// the law has a finite slope at `Δp = 0` (the square root's is infinite).
pub const ORIFICE_REGULARISATION_PA: f64 = 1e5;

/// The hydraulic state of every joint.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HydraulicState<const N: usize> {
    /// Valve opening, fraction of full opening.
    pub spool: JointVector<N>,
    /// Its rate, 1/s.
    pub spool_rate: JointVector<N>,
    /// Cap-side chamber pressure, Pa.
    pub pressure_a: JointVector<N>,
    /// Rod-side chamber pressure, Pa.
    pub pressure_b: JointVector<N>,
    /// The inner loop's integral of the torque error `I_k`, N·m·s: held between samples (the
    /// continuous loop of [`HydraulicActuators::derivative`] integrates it).
    pub torque_integral: JointVector<N>,
    /// The inner loop's valve command `u_k`, fraction of full opening: held between samples.
    pub command: JointVector<N>,
    /// The inner loop's last encoder reading `q_k`, rad: held between samples.
    pub loop_angle: JointVector<N>,
    /// The inner loop's derived velocity `v_k`, rad/s: held between samples.
    pub loop_velocity: JointVector<N>,
}

impl<const N: usize> HydraulicState<N> {
    /// All zero (the rates of a resting actuator, or an unused state).
    pub fn zeros() -> Self {
        let z = JointVector::zeros();
        Self {
            spool: z,
            spool_rate: z,
            pressure_a: z,
            pressure_b: z,
            torque_integral: z,
            command: z,
            loop_angle: z,
            loop_velocity: z,
        }
    }

    /// `self + a k`, field by field.
    pub fn along(&self, k: &Self, a: f64) -> Self {
        Self {
            spool: self.spool + k.spool * a,
            spool_rate: self.spool_rate + k.spool_rate * a,
            pressure_a: self.pressure_a + k.pressure_a * a,
            pressure_b: self.pressure_b + k.pressure_b * a,
            torque_integral: self.torque_integral + k.torque_integral * a,
            command: self.command + k.command * a,
            loop_angle: self.loop_angle + k.loop_angle * a,
            loop_velocity: self.loop_velocity + k.loop_velocity * a,
        }
    }

    /// Whether every entry is finite.
    pub fn is_finite(&self) -> bool {
        [
            self.spool,
            self.spool_rate,
            self.pressure_a,
            self.pressure_b,
            self.torque_integral,
            self.command,
            self.loop_angle,
            self.loop_velocity,
        ]
        .iter()
        .all(|v| v.iter().all(|x| x.is_finite()))
    }
}

/// One joint's actuator.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Joint {
    /// `D_a`, `D_b`, m³/rad.
    displacement_a: f64,
    displacement_b: f64,
    /// `V_0`, m³.
    dead_volume: f64,
    /// The joint range the chambers span, rad.
    lower: f64,
    upper: f64,
    /// `K_v`, m³/(s·√Pa) at full opening.
    orifice: f64,
    /// `ω_v`, rad/s, and `ζ_v`.
    valve_frequency: f64,
    valve_damping: f64,
    /// `b`, fraction of full opening.
    null_bias: f64,
    /// `C_l`, m³/(s·Pa).
    leakage: f64,
    /// `K_τ`, 1/(N·m).
    torque_gain: f64,
    /// `ω_i`, rad/s.
    integral_rate: f64,
    /// `k_vc D̄ / K_q`, s/rad.
    velocity_compensation: f64,
    /// `δ_v`, fraction of full opening.
    dead_band: f64,
}

/// The actuators of all joints, with the supply they share, and the inner loops' sample clock.
#[derive(Debug, Clone)]
pub struct HydraulicActuators<const N: usize> {
    joints: [Joint; N],
    supply: f64,
    tank: f64,
    bulk_modulus: f64,
    /// The fastest spool's faster pole, 1/s ([`spool_pole`]): a constant of the valves.
    fastest_spool: f64,
    /// `T_s`, s.
    period: f64,
    /// The next sample instant, s.
    next_sample: f64,
    /// The pressure transducers' noise, standard deviation, Pa.
    pressure_noise: f64,
    /// Their offset bound, Pa, and the offsets of the cap- and rod-side transducers.
    offset_bound: f64,
    offsets: (JointVector<N>, JointVector<N>),
    /// Draws the offsets, then the noise.
    rng: ChaCha8Rng,
    /// The encoder's resolution `r`, rad.
    resolution: f64,
    /// The derived velocity's low-pass pole `a`.
    velocity_pole: f64,
}

/// Sample instants within this fraction of `T_s` of the plant's time count as now (the time is
/// a sum of sub-steps, so it meets an instant only to rounding).
pub const SAMPLE_TOLERANCE: f64 = 1e-6;

/// `Q(Δp) / K_v = Δp / (Δp² + δ²)^{1/4}`, √Pa.
fn orifice_law(drop: f64) -> f64 {
    let d = ORIFICE_REGULARISATION_PA;
    drop / (drop * drop + d * d).sqrt().sqrt()
}

/// `Q'(Δp) / K_v = (Δp²/2 + δ²) / (Δp² + δ²)^{5/4}`, 1/√Pa: the orifice law's slope, largest
/// (`1/√δ`) at zero drop.
fn orifice_slope(drop: f64) -> f64 {
    let d = ORIFICE_REGULARISATION_PA;
    let s = drop * drop + d * d;
    (0.5 * drop * drop + d * d) / (s * s.sqrt().sqrt())
}

/// The faster pole of a spool `ẍ = ω² (u − x) − 2 ζ ω ẋ`, 1/s: `ω` (a complex pair, or a
/// double pole) when `ζ ≤ 1`, else `ω (ζ + √(ζ² − 1))`.
pub fn spool_pole(frequency: f64, damping: f64) -> f64 {
    frequency * (damping + (damping * damping - 1.0).max(0.0).sqrt()).max(1.0)
}

impl<const N: usize> HydraulicActuators<N> {
    /// From the checked settings `setup`, for joints spanning `ranges` (rad; the chambers'
    /// volumes run from `V_0` at one end to `V_0 + D·(q_hi − q_lo)` at the other). The pressure
    /// transducers' offsets are zero and their noise comes from seed 0 until [`Self::seeded`].
    pub fn new(setup: &HydraulicSetup<N>, ranges: [(f64, f64); N]) -> Self {
        let HydraulicSetup {
            supply_pressure: supply,
            tank_pressure: tank,
            bulk_modulus,
            rated_drop,
            valve_damping,
            torque_integral_ratio,
            velocity_compensation: compensation,
            displacement,
            area_ratio: ratio,
            dead_volume,
            rated_flow,
            valve_frequency_hz: valve_hz,
            torque_bandwidth_hz: bandwidth_hz,
            null_bias: bias,
            leakage,
            ..
        } = *setup;
        let period = 1.0 / setup.torque_loop_rate_hz;
        let joints = core::array::from_fn(|i| {
            // Valve sizing: Q_n at Δp_n across both lands, so K_v = Q_n / √(Δp_n / 2).
            let orifice = rated_flow[i] / (rated_drop / 2.0).sqrt();
            let (lower, upper) = ranges[i];
            let mut joint = Joint {
                displacement_a: displacement[i],
                displacement_b: displacement[i] * ratio[i],
                dead_volume: dead_volume[i],
                lower,
                upper,
                orifice,
                valve_frequency: std::f64::consts::TAU * valve_hz[i],
                valve_damping,
                null_bias: bias[i],
                leakage: leakage[i],
                torque_gain: 0.0,
                integral_rate: torque_integral_ratio * std::f64::consts::TAU * bandwidth_hz[i],
                velocity_compensation: 0.0,
                dead_band: setup.valve_dead_band,
            };
            let flow_gain = orifice * ((supply - tank) / 2.0).sqrt();
            let middle = 0.5 * (lower + upper);
            joint.torque_gain =
                std::f64::consts::TAU * bandwidth_hz[i] / joint.locked_gain(bulk_modulus, flow_gain, middle);
            joint.velocity_compensation =
                compensation * 0.5 * (joint.displacement_a + joint.displacement_b) / flow_gain;
            joint
        });
        let fastest_spool = joints.iter().map(|j| spool_pole(j.valve_frequency, j.valve_damping)).fold(0.0, f64::max);
        Self {
            joints,
            supply,
            tank,
            bulk_modulus,
            fastest_spool,
            period,
            next_sample: 0.0,
            pressure_noise: setup.torque_loop_pressure_noise_pa,
            offset_bound: setup.torque_loop_pressure_offset_pa,
            offsets: (JointVector::zeros(), JointVector::zeros()),
            rng: ChaCha8Rng::seed_from_u64(0),
            resolution: std::f64::consts::TAU / setup.torque_loop_encoder_counts_per_rev as f64,
            velocity_pole: match setup.torque_loop_velocity_filter_hz {
                f if f > 0.0 => (-std::f64::consts::TAU * f * period).exp(),
                _ => 0.0,
            },
        }
    }

    /// The actuators with their pressure transducers' generator seeded by `seed`: the offsets
    /// drawn from it (uniform within the bound, cap sides then rod sides), then every sample's
    /// noise.
    pub fn seeded(mut self, seed: u64) -> Self {
        self.rng = ChaCha8Rng::seed_from_u64(seed);
        let bound = self.offset_bound;
        let mut draw = || JointVector::from_fn(|_, _| bound * (2.0 * self.rng.gen::<f64>() - 1.0));
        self.offsets = (draw(), draw());
        self
    }

    /// The constant offsets of the cap- and rod-side pressure transducers the inner loops read,
    /// Pa (the controller's torque sensing reads the same ones with shared transducers).
    pub fn pressure_offsets(&self) -> (JointVector<N>, JointVector<N>) {
        self.offsets
    }

    /// Supply and tank pressure, Pa.
    pub fn pressure_range(&self) -> (f64, f64) {
        (self.tank, self.supply)
    }

    /// `τ_h = D_a p_a − D_b p_b` per joint, N·m.
    pub fn torque(&self, pressure_a: &JointVector<N>, pressure_b: &JointVector<N>) -> JointVector<N> {
        JointVector::from_fn(|i, _| {
            let j = &self.joints[i];
            j.displacement_a * pressure_a[i] - j.displacement_b * pressure_b[i]
        })
    }

    /// The actuators at rest holding `tau0` in equilibrium: chamber pressures with `p_a + p_b =
    /// p_s + p_t` (equal drops across the two lands) and the torque the inner loop measures
    /// (its transducers' offsets added, noise aside) at `τ0`, so `τ_h = τ0 − (D_a o_a − D_b o_b)`; the spool opened just
    /// enough to feed the leakage, `x_v Q(p_s − p_a) = C_l (p_a − p_b)`; the loop's integral
    /// holding that opening with no torque error, and commanding it.
    pub fn holding(&self, tau0: &JointVector<N>) -> HydraulicState<N> {
        let sum = self.supply + self.tank;
        let mut state = HydraulicState::zeros();
        for (i, j) in self.joints.iter().enumerate() {
            let offset_torque = j.displacement_a * self.offsets.0[i] - j.displacement_b * self.offsets.1[i];
            let pa = ((tau0[i] - offset_torque + j.displacement_b * sum) / (j.displacement_a + j.displacement_b))
                .clamp(self.tank, self.supply);
            let pb = sum - pa;
            // Opening towards a (x_v > 0) when a holds the higher pressure; the metering land
            // then sees p_s − p_a (= p_b − p_t), otherwise p_a − p_t.
            let land = orifice_law(if pa >= pb { self.supply - pa } else { pa - self.tank });
            let opening = if land > 0.0 { j.leakage * (pa - pb) / (j.orifice * land) } else { 0.0 };
            state.pressure_a[i] = pa;
            state.pressure_b[i] = pb;
            state.spool[i] = opening;
            state.command[i] = opening - j.null_bias;
            let integral_gain = j.torque_gain * j.integral_rate;
            if integral_gain > 0.0 {
                // The input that gives this command through the dead band.
                let input = state.command[i] + j.dead_band * state.command[i].signum();
                state.torque_integral[i] = if state.command[i] == 0.0 { 0.0 } else { input / integral_gain };
            }
        }
        state
    }

    /// Chamber volumes `(V_a, V_b)` of joint `i` at `q`, m³ (never below the dead volume).
    pub fn volumes(&self, i: usize, q: f64) -> (f64, f64) {
        self.joints[i].volumes(q)
    }

    /// The time derivative of the hydraulic state under the continuous-time inner loop, the
    /// design's reference and the sampled loop's limit as `T_s → 0`: with the torque reference
    /// `τ_ref` held, the loop reads the true pressures and the true `q̇` of the joints at `q, q̇`
    /// and integrates its error; `command` is left as it is. The plant runs
    /// [`Self::held_derivative`] and [`Self::sample`] instead.
    pub fn derivative(
        &self,
        tau_ref: &JointVector<N>,
        q: &JointVector<N>,
        qd: &JointVector<N>,
        s: &HydraulicState<N>,
    ) -> HydraulicState<N> {
        let torque = self.torque(&s.pressure_a, &s.pressure_b);
        let mut rate = HydraulicState::zeros();
        for (i, j) in self.joints.iter().enumerate() {
            let error = tau_ref[i] - torque[i];
            let (command, integrating) = j.loop_law(error, s.torque_integral[i], qd[i]);
            rate.torque_integral[i] = if integrating { error } else { 0.0 };
            self.physics_rate(i, command, q[i], qd[i], s, &mut rate);
        }
        rate
    }

    /// The time derivative of the hydraulic state between two samples of the inner loop, for
    /// the joints at `q, q̇`: the valve follows the held command `u_k`; the command and the
    /// integral do not change.
    pub fn held_derivative(&self, q: &JointVector<N>, qd: &JointVector<N>, s: &HydraulicState<N>) -> HydraulicState<N> {
        let mut rate = HydraulicState::zeros();
        for i in 0..N {
            self.physics_rate(i, s.command[i], q[i], qd[i], s, &mut rate);
        }
        rate
    }

    /// Joint `i`'s spool and chamber rates in `rate` with the valve commanded to `command`.
    fn physics_rate(
        &self,
        i: usize,
        command: f64,
        q: f64,
        qd: f64,
        s: &HydraulicState<N>,
        rate: &mut HydraulicState<N>,
    ) {
        let j = &self.joints[i];
        rate.spool[i] = s.spool_rate[i];
        rate.spool_rate[i] = j.valve_frequency * j.valve_frequency * (command + j.null_bias - s.spool[i])
            - 2.0 * j.valve_damping * j.valve_frequency * s.spool_rate[i];
        let (flow_a, flow_b) = self.valve_flows(j, s.spool[i], s.pressure_a[i], s.pressure_b[i]);
        let leak = j.leakage * (s.pressure_a[i] - s.pressure_b[i]);
        let (va, vb) = j.volumes(q);
        rate.pressure_a[i] = self.bulk_modulus / va * (flow_a - leak - j.displacement_a * qd);
        rate.pressure_b[i] = self.bulk_modulus / vb * (flow_b + leak + j.displacement_b * qd);
    }

    /// A bound on the fastest rate among the actuators' stiff modes at `q` in state `s`, 1/s.
    ///
    /// - The chambers' pressures: `∂ṗ_a/∂p_a = −β/V_a (|x_v| K_v Q'(Δp_a) + C_l)` with `Δp_a` the
    ///   drop across the land the valve opens to chamber `a`, and `∂ṗ_a/∂p_b = β C_l / V_a` through
    ///   the leakage; by Gershgorin's theorem no eigenvalue of the two pressures' block is
    ///   faster than the larger row sum `β/V (|x_v| K_v Q'(Δp) + 2 C_l)`. With the valve wide
    ///   open near zero drop (a chamber at supply or tank pressure) it reaches
    ///   `β K_v / (V √δ)`: from HyA's defaults, 2.2e3 to 4.5e3/s at mid-stroke (by joint) and
    ///   1.2e4/s at a stroke's end (`V = V_0`).
    /// - Each spool, a second-order lag: its faster pole, `ω_v` when `ζ_v ≤ 1`, else
    ///   `ω_v (ζ_v + √(ζ_v² − 1))`.
    ///
    /// Not counted: the oil columns as springs against the joints' inertia, `ω_h`, which needs
    /// the mass matrix (on HyA at most 88 Hz, 550/s, at the start pose: the report's plant
    /// section). The plant sub-cycles its RK4 steps on this rate as on the bristles'
    /// ([`crate::plant::Plant::step`]).
    pub fn stiff_rate(&self, q: &JointVector<N>, s: &HydraulicState<N>) -> f64 {
        let chambers = self.joints.iter().enumerate().map(|(i, j)| {
            let x = s.spool[i].clamp(-1.0, 1.0);
            let (pa, pb) = (s.pressure_a[i], s.pressure_b[i]);
            let (drop_a, drop_b) =
                if x >= 0.0 { (self.supply - pa, pb - self.tank) } else { (pa - self.tank, self.supply - pb) };
            let (va, vb) = j.volumes(q[i]);
            let open = j.orifice * x.abs();
            let chamber_a = self.bulk_modulus / va * (open * orifice_slope(drop_a) + 2.0 * j.leakage);
            let chamber_b = self.bulk_modulus / vb * (open * orifice_slope(drop_b) + 2.0 * j.leakage);
            chamber_a.max(chamber_b)
        });
        chambers.fold(self.fastest_spool, f64::max)
    }

    /// The inner loops' sample period `T_s`, s.
    pub fn sample_period(&self) -> f64 {
        self.period
    }

    /// The time of the inner loops' next sample, s.
    pub fn next_sample_time(&self) -> f64 {
        self.next_sample
    }

    /// Whether the inner loops sample at `time`: their next instant is `time` (to rounding) or
    /// past, or `time` went back by more than a period (a state restored to an earlier time).
    pub fn sample_due(&self, time: f64) -> bool {
        let next = self.next_sample_time();
        next <= time + SAMPLE_TOLERANCE * self.period || next > time + 2.0 * self.period
    }

    /// The inner loops' encoder reading of `q`, rad: rounded to a count.
    pub fn encoder(&self, q: &JointVector<N>) -> JointVector<N> {
        q.map(|x| (x / self.resolution).round() * self.resolution)
    }

    /// Runs the inner loops once at `time`, a sample instant, with the torque reference
    /// `τ_ref`, the joints at `q` and the hydraulic state `s`: reads the pressure transducers
    /// and the encoders, derives the velocity, sets the held command `u_k`, updates the integral
    /// and sets the next instant to `time + T_s`.
    pub fn sample(&mut self, time: f64, tau_ref: &JointVector<N>, q: &JointVector<N>, s: &mut HydraulicState<N>) {
        let angle = self.encoder(q);
        let a = self.velocity_pole;
        s.loop_velocity = s.loop_velocity * a + (angle - s.loop_angle) * ((1.0 - a) / self.period);
        s.loop_angle = angle;
        for i in 0..N {
            let j = self.joints[i];
            let pa = s.pressure_a[i] + self.offsets.0[i] + self.noise();
            let pb = s.pressure_b[i] + self.offsets.1[i] + self.noise();
            let torque = j.displacement_a * pa - j.displacement_b * pb;
            let error = tau_ref[i] - torque;
            let (command, integrating) = j.loop_law(error, s.torque_integral[i], s.loop_velocity[i]);
            s.command[i] = command;
            if integrating {
                s.torque_integral[i] += self.period * error;
            }
        }
        self.next_sample = time + self.period;
    }

    /// One draw of a transducer's noise, Pa (none drawn without noise).
    fn noise(&mut self) -> f64 {
        match self.pressure_noise > 0.0 {
            true => self.pressure_noise * self.rng.sample::<f64, _>(StandardNormal),
            false => 0.0,
        }
    }

    /// `(Q_a, Q_b)` into the chambers through a valve opened by `x` (clamped to ±1), m³/s.
    fn valve_flows(&self, j: &Joint, x: f64, pa: f64, pb: f64) -> (f64, f64) {
        let x = x.clamp(-1.0, 1.0);
        let k = j.orifice * x;
        if x >= 0.0 {
            (k * orifice_law(self.supply - pa), -k * orifice_law(pb - self.tank))
        } else {
            (k * orifice_law(pa - self.tank), -k * orifice_law(self.supply - pb))
        }
    }

    /// The hydraulic natural frequency of each joint at `q` carrying `inertia` (the diagonal of
    /// the mass matrix), rad/s: `ω_h = √(β (D_a²/V_a + D_b²/V_b) / J)`, the oil columns as
    /// springs against the load. It falls with the load's inertia and with the chambers' volumes.
    pub fn natural_frequency(&self, q: &JointVector<N>, inertia: &JointVector<N>) -> JointVector<N> {
        JointVector::from_fn(|i, _| {
            let j = &self.joints[i];
            (self.bulk_modulus * j.oil_stiffness_per_modulus(q[i]) / inertia[i]).sqrt()
        })
    }

    /// The energy stored in joint `i`'s compressed oil relative to `p_ref` at the current
    /// volumes, J, for the closed-valve energy balance: with no flow through the valve, a
    /// chamber's oil obeys `p = p_0 + β ln(V_0/V)`, and the energy stored in it since `V_0` is
    /// `U(V) = −∫ p dV` (the work the piston has done on the oil).
    pub fn oil_energy(&self, i: usize, q0: f64, q: f64, start: &HydraulicState<N>) -> f64 {
        let (va0, vb0) = self.joints[i].volumes(q0);
        let (va, vb) = self.joints[i].volumes(q);
        let beta = self.bulk_modulus;
        let chamber = |p0: f64, v0: f64, v: f64| -(p0 * (v - v0) + beta * (v * (v0 / v).ln() + v - v0));
        chamber(start.pressure_a[i], va0, va) + chamber(start.pressure_b[i], vb0, vb)
    }
}

impl Joint {
    /// The inner loop's valve command for the torque error `e`, the integral `I` and the
    /// velocity `v`: `sat(dz(K_τ (e + ω_i I) + k_vc D̄ v / K_q))`; and whether the integral may
    /// grow (the anti-windup: not once its share alone opens the valve fully, `|share| ≥ 1 +
    /// δ_v`, and `e` pushes it further).
    fn loop_law(&self, error: f64, integral: f64, velocity: f64) -> (f64, bool) {
        let integral_share = self.torque_gain * self.integral_rate * integral;
        let integrating = !(integral_share.abs() >= 1.0 + self.dead_band && integral_share * error > 0.0);
        let input = self.torque_gain * error + integral_share + self.velocity_compensation * velocity;
        let command = if input.abs() <= self.dead_band { 0.0 } else { input - self.dead_band * input.signum() };
        (command.clamp(-1.0, 1.0), integrating)
    }

    fn volumes(&self, q: f64) -> (f64, f64) {
        let a = self.dead_volume + self.displacement_a * (q - self.lower).max(0.0);
        let b = self.dead_volume + self.displacement_b * (self.upper - q).max(0.0);
        (a, b)
    }

    /// `D_a²/V_a + D_b²/V_b` at `q`, m³ (the oil stiffness divided by `β`).
    fn oil_stiffness_per_modulus(&self, q: f64) -> f64 {
        let (va, vb) = self.volumes(q);
        self.displacement_a * self.displacement_a / va + self.displacement_b * self.displacement_b / vb
    }

    /// `K_lock = β K_q (D_a/V_a + D_b/V_b)`: `τ̇_h` per unit valve opening on a locked joint.
    fn locked_gain(&self, bulk_modulus: f64, flow_gain: f64, q: f64) -> f64 {
        let (va, vb) = self.volumes(q);
        bulk_modulus * flow_gain * (self.displacement_a / va + self.displacement_b / vb)
    }
}
