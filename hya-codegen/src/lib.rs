//! # hya-codegen
//!
//! Reads a URDF, validates it into a [`hya_core::model::TreeModel`] ([`load`]), and emits
//! unrolled, const-sized Rust implementing [`hya_core::Dynamics`] for it ([`generate()`]), in
//! the spirit of RobCoGen: constants folded into literals, one `sin_cos` per revolute joint,
//! axis-aligned joints and sparse inertias exploited, zeros never multiplied, no allocation.
//!
//! ```no_run
//! let loaded = hya_codegen::load_file("robots/urdf/hya.urdf")?;
//! let generated = hya_codegen::generate(&loaded, "Hya")?;
//! std::fs::write("hya_dynamics.rs", generated.source)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod error;
pub mod expr;
pub mod generate;
pub mod load;
pub mod names;

pub use error::{LoadError, Problem, Warning};
pub use generate::{
    generate, generate_parametric, size_warning, GenerateError, Generated, MAX_JOINTS, WARN_ABOVE_JOINTS,
};
pub use load::{load_file, load_str, LoadedModel, Source};
