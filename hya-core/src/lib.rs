//! # hya-core
//!
//! The disturbance estimator of Lu, Sandy & Buchli, "Nonlinear disturbance attenuation control of
//! hydraulic robotics", and the computed-torque controller that uses it, for arms with `N` joints.
//!
//! The rigid-body model is `M(q) q̈ + C(q, q̇) + G(q) = τ + d`, with `d` the lumped disturbance
//! (friction, model error, external loads). The estimator filters the measured joint angles and
//! the measured torques with two identical third-order filters ([`filter::ThirdOrderFilter`]) and
//! forms `d̂ = ID(q̂, q̂̇, q̂̈) − τ̂` ([`estimator::DisturbanceEstimator`]); the controller
//! ([`control::ComputedTorque`]) subtracts `d̂` from its command. Sign convention everywhere: a
//! positive `d` pushes the joints like a positive `τ`, and compensation subtracts `d̂`.
//!
//! The crate is `no_std`; its hot paths (filter step, estimator update, controller step) never
//! allocate. Numbers are SI: rad, rad/s, rad/s², N·m, s.

#![no_std]
#![cfg_attr(docsrs, feature(doc_cfg))]

#[cfg(feature = "alloc")]
extern crate alloc;
#[cfg(feature = "std")]
extern crate std;

pub mod attenuation;
pub mod control;
pub mod dispatch;
pub mod display;
pub mod dual;
pub mod dynamics;
#[cfg(feature = "alloc")]
pub mod erased;
pub mod error;
pub mod estimator;
pub mod filter;
pub mod filter_pair;
mod finite;
mod fma;
pub mod lanes;
mod linalg;
#[cfg(feature = "alloc")]
pub mod model;
#[cfg(feature = "alloc")]
pub mod observer_design;
pub mod observers;
#[cfg(feature = "sampling")]
pub mod sampling;
pub mod scalar;
pub mod spatial;
pub mod step_cache;
pub mod test_arms;
pub mod timed;
mod trig;

pub use fma::{mul_add, with_fma, FmaSupport, FMA_SUPPORT};
pub use lanes::Arithmetic;
pub use linalg::symmetric_eigenvalues;
pub use scalar::Real;
pub use trig::{sin_cos, sin_cos_lanes, sin_cos_lanes_fused};

pub use attenuation::DisturbanceAttenuation;
pub use control::{ComputedTorque, Gains, PdPlacement, Reference};
pub use display::{closest, Clipped, Short};
pub use dynamics::{Dynamics, JointMatrix, JointVector, OnSlicesN, SliceDynamics, STANDARD_GRAVITY};
pub use error::Error;
pub use estimator::DisturbanceEstimator;
pub use filter::{
    Discretisation, FilterParams, FilterState, ThirdOrderFilter, MAX_FILTER_INPUT, MIN_RATE_TIMES_DT, MIN_ZETA,
};
pub use filter_pair::{FilterPair, Next, PairState, StepClock};
pub use finite::{finite_result, MAX_RATE_TIMES_DT};
#[cfg(feature = "alloc")]
pub use observer_design::{BoxedObserver, NonlinearGain, ObserverDesign};
pub use observers::{
    DisturbanceObserver, ExtendedStateObserver, Measurement, MomentumObserver, NonlinearDisturbanceObserver,
};
pub use step_cache::DiscretisationCache;
pub use timed::{Step, TimedEstimator};
