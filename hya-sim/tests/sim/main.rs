//! The simulator's integration tests, in one binary: every test links the whole simulator and
//! the generated dynamics of every shipped arm, so one binary instead of nine saves eight links
//! and most of the disk a test build needs.
#![allow(clippy::unwrap_used)] // test helpers: a failed unwrap is a failed test

mod arms;
mod cartesian;
mod claims;
mod controller_model;
mod experiments;
mod frequency;
mod integration_step;
mod linear;
mod lockstep;
mod mujoco_reference;
mod plant;
mod scenario_validation;
mod study_cost;
mod sweep;
mod torque_loop;
