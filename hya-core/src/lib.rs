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

/// The estimation half: the filter and its pair on `q` and `τ`, the paper's estimator (fixed-step
/// and timed), the observers it is compared with, the computed-torque and Cartesian impedance
/// controllers, and both
/// behind slices for front ends that learn the joint count at run time.
mod estimation {
    pub mod attenuation;
    pub mod cartesian;
    pub mod control;
    #[cfg(feature = "alloc")]
    pub mod erased;
    pub mod estimator;
    pub mod filter;
    pub mod filter_pair;
    #[cfg(feature = "alloc")]
    pub mod observer_design;
    pub mod observers;
    pub mod step_cache;
    pub mod timed;
}

/// The rigid-body half: the `Dynamics<N>` trait, the number types the algorithms are written on
/// (`Real`, dual numbers, lanes of states), spatial algebra, and the run-time tree model with
/// every algorithm written once.
mod rigid_body {
    pub mod bodies_batch;
    pub mod dual;
    pub mod dynamics;
    pub(crate) mod fma;
    pub mod frame_kinematics;
    pub mod lanes;
    pub(crate) mod linalg;
    #[cfg(feature = "alloc")]
    pub mod model;
    #[cfg(feature = "sampling")]
    pub mod sampling;
    pub mod scalar;
    pub(crate) mod site;
    pub mod spatial;
    pub(crate) mod through_inverse;
    pub(crate) mod trig;
}

pub mod dispatch;
pub mod display;
pub mod error;
mod finite;
pub mod test_arms;

pub use estimation::{attenuation, cartesian, control, estimator, filter, filter_pair, observers, step_cache, timed};
#[cfg(feature = "alloc")]
pub use estimation::{erased, observer_design};
#[cfg(feature = "alloc")]
pub use rigid_body::model;
#[cfg(feature = "sampling")]
pub use rigid_body::sampling;
pub use rigid_body::{bodies_batch, dual, dynamics, frame_kinematics, lanes, scalar, spatial};
use rigid_body::{fma, linalg, trig};

pub use fma::{mul_add, with_fma, FmaSupport, FMA_SUPPORT};
pub use lanes::Arithmetic;
pub use linalg::symmetric_eigenvalues;
pub use scalar::Real;
pub use trig::{sin_cos, sin_cos_lanes, sin_cos_lanes_fused};

pub use attenuation::DisturbanceAttenuation;
pub use bodies_batch::{BodiesBatch, BodyColumns};
pub use cartesian::{CartesianImpedance, CartesianReference, FrameState, Impedance};
#[cfg(feature = "alloc")]
pub use cartesian::{FrameImpedance, TreeFrame};
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
pub use frame_kinematics::{FrameJacobian, FrameKinematics, FrameVector};
#[cfg(feature = "alloc")]
pub use observer_design::{BoxedObserver, NonlinearGain, ObserverDesign};
pub use observers::{
    DisturbanceObserver, ExtendedStateObserver, Measurement, MomentumObserver, NonlinearDisturbanceObserver,
};
pub use step_cache::DiscretisationCache;
pub use timed::{Step, TimedEstimator};
