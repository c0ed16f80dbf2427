//! What the runs show: each run's metrics ([`metrics`], [`outcome`]), many seeds with their
//! intervals ([`seeds`]), the paper's claims judged by fixed rules ([`claims`]) and bandwidth
//! sweeps ([`sweep`]).

pub mod claims;
pub mod metrics;
pub mod outcome;
pub mod seeds;
pub mod shadow;
pub mod sweep;
