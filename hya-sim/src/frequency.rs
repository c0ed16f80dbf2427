//! Frequency validation of the observers: sinusoidal disturbances from 0.1 to 10 Hz on a clean
//! plant (the rigid body alone, exact sensors), the measured `d̂/d` of each observer against its
//! design's transfer function.
//!
//! | observer | design `d̂/d` |
//! |---|---|
//! | lu | `ω1 ω2² / ((s + ω1)(s² + 2ζ ω2 s + ω2²))` |
//! | chen, momentum | `β / (s + β)` |
//! | eso | `ω³ / (s + ω)³` |

use nalgebra::Complex;

use crate::config::cost::Cost;
use crate::config::scenario::{
    ActuatorKind, FrictionKind, Method, Noise, NoiseConfig, Scenario, SinusoidLoad, TorqueSource, VelocitySource,
};
use crate::error::SimError;
use crate::io::svg::{line_grid_scaled, Panel, Scale, Series, PALETTE};

/// The frequencies swept, Hz.
pub const FREQUENCIES_HZ: [f64; 8] = [0.1, 0.2, 0.5, 1.0, 2.0, 3.0, 5.0, 10.0];

/// The joint whose response is measured (SFE, 0-based).
pub const JOINT: usize = 1;

/// One observer's measured and design response at one frequency.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Point {
    /// The observer.
    pub method: Method,
    /// Frequency, Hz.
    pub frequency_hz: f64,
    /// Measured `d̂/d` at that frequency.
    pub measured: Complex<f64>,
    /// The design's `d̂/d`.
    pub design: Complex<f64>,
}

/// The design transfer function of `method` at `ω` for the bandwidth `β`
/// ([`ObserverDesign::of`](crate::linear::ObserverDesign::of)); zero for none and pid.
pub fn design(method: Method, beta: f64, omega: f64) -> Complex<f64> {
    crate::linear::ObserverDesign::of(method, beta).map_or(Complex::new(0.0, 0.0), |d| d.response(omega))
}

pub use crate::linear::phasor;

/// A clean version of `base` (no friction, ideal actuators, no parameter error, exact sensors
/// with a velocity sensor for the observers that read one) holding its pose under a sinusoidal
/// torque on every joint at `frequency_hz`, for a whole number of periods after settling.
fn clean_scenario(base: &Scenario, frequency_hz: f64, joints: usize) -> Scenario {
    let mut s = base.clone();
    s.name = "frequency".into();
    s.plant.friction = FrictionKind::Off;
    s.plant.actuator = ActuatorKind::Ideal;
    s.plant.parameter_spread = 0.0;
    s.noise = NoiseConfig { position: Noise::Off {}, velocity: Noise::Off {}, torque: Noise::Off {} };
    s.sensors.velocity = VelocitySource::Sensor;
    s.sensors.torque = TorqueSource::Direct;
    s.sensors.encoder_counts_per_rev = 1 << 40;
    s.loads.weight_drop = None;
    s.loads.sinusoid = Some(SinusoidLoad { amplitude_nm: vec![2.0; joints], frequency_hz });
    let periods = (3.0 * frequency_hz).ceil().max(2.0);
    s.duration_s = 2.0 + periods / frequency_hz;
    s
}

/// The observers [`measure`] runs at each frequency.
const METHODS: [Method; 4] = [Method::Lu, Method::Chen, Method::Momentum, Method::Eso];

/// What [`measure`] costs on `base` for an arm of `joints` joints: one run per observer and
/// frequency, each keeping its trace until it is measured.
pub fn cost(base: &Scenario, frequencies_hz: &[f64], joints: usize) -> Cost {
    frequencies_hz
        .iter()
        .flat_map(|&f| METHODS.map(|_| Cost::of_runs(&clean_scenario(base, f, joints), 1, 1)))
        .fold(Cost::NONE, Cost::then)
}

/// Every observer's measured response on `base`'s robot and controller at `frequencies_hz`
/// ([`FREQUENCIES_HZ`] for the report).
pub fn measure<const N: usize>(
    robot: &crate::robot::Robot<N>,
    base: &Scenario,
    frequencies_hz: &[f64],
) -> Result<Vec<Point>, SimError> {
    let beta = base.controller.observer_bandwidth_rad_s;
    let mut points = Vec::new();
    for &frequency_hz in frequencies_hz {
        let scenario = clean_scenario(base, frequency_hz, N);
        let omega = std::f64::consts::TAU * frequency_hz;
        for method in METHODS {
            let trace = crate::analysis::simulate::simulate(&scenario, method, robot)?.trace;
            // The whole periods after the first 2 s.
            let start = trace.time.partition_point(|t| *t < 2.0);
            let d: Vec<(f64, f64)> =
                (start..trace.time.len()).map(|k| (trace.time[k], trace.d_true[k][JOINT])).collect();
            let d_hat: Vec<(f64, f64)> =
                (start..trace.time.len()).map(|k| (trace.time[k], trace.d_hat[k][JOINT])).collect();
            let measured = phasor(&d_hat, omega) / phasor(&d, omega);
            points.push(Point { method, frequency_hz, measured, design: design(method, beta, omega) });
        }
    }
    Ok(points)
}

/// Magnitude and phase of every observer, measured (dots) against design (lines).
pub fn figure(points: &[Point]) -> String {
    let methods = [Method::Lu, Method::Chen, Method::Momentum, Method::Eso];
    let mut panels = Vec::new();
    for (title, y_label, value) in [
        ("|d̂/d| against frequency", "gain", (|c: Complex<f64>| c.norm()) as fn(Complex<f64>) -> f64),
        ("phase of d̂/d", "phase [deg]", |c: Complex<f64>| c.arg().to_degrees()),
    ] {
        let mut series = Vec::new();
        for (k, method) in methods.iter().enumerate() {
            let color = PALETTE[(k + 1) % PALETTE.len()];
            let mine: Vec<&Point> = points.iter().filter(|p| p.method == *method).collect();
            let x = |p: &Point| p.frequency_hz;
            series.push(Series {
                label: format!("{} design", method.name()),
                points: mine.iter().map(|p| (x(p), value(p.design))).collect(),
                color,
                dashed: true,
                markers: false,
            });
            series.push(Series {
                label: format!("{} measured", method.name()),
                points: mine.iter().map(|p| (x(p), value(p.measured))).collect(),
                color,
                dashed: false,
                markers: true,
            });
        }
        panels.push(Panel { title: title.into(), y_label: y_label.into(), series });
    }
    let title = format!("observer responses on joint {} (clean plant): design (dashed), measured (dots)", JOINT + 1);
    line_grid_scaled(&title, "frequency [Hz]", &panels, 2, Scale::Log)
}
