//! What the runs show: each run's metrics, accumulated tick by tick ([`running`], [`metrics`],
//! [`simulate`]), many seeds with their intervals ([`seeds`]), split over machines ([`seed_shards`]), the paper's claims judged by
//! fixed rules ([`claims`]) and bandwidth sweeps ([`sweep`]).

pub mod claims;
pub mod metrics;
pub mod running;
pub mod seed_shards;
pub mod seeds;
pub mod shadow;
pub mod simulate;
pub mod sweep;
