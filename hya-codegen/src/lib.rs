//! # hya-codegen
//!
//! Reads a URDF, validates it into a [`hya_core::model::TreeModel`] ([`load`]), and emits
//! unrolled, const-sized Rust implementing [`hya_core::Dynamics`] for it.

pub mod error;
pub mod load;

pub use error::{LoadError, Problem, Warning};
pub use load::{load_file, load_str, LoadedModel};
