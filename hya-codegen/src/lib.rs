//! # hya-codegen
//!
//! Takes a model that `hya-urdf` loaded and validated, and emits unrolled, const-sized Rust
//! implementing [`hya_core::Dynamics`] for it ([`generate()`]), in
//! the spirit of RobCoGen: constants folded into literals, the sines and cosines of all joints in
//! one lane-parallel call, axis-aligned joints and sparse inertias exploited, zeros never
//! multiplied, no allocation. Each function is written once, generic over
//! [`hya_core::Arithmetic`], with every product that feeds a sum fused into one `A::mul_add`;
//! `hya_core::lanes` runs it on plain `f64`, on fused multiply-add where the CPU has it, and on
//! several robot states per vector register for the batch entry points.
//!
//! The generator works in four steps, one module each: [`trace`](mod@trace) runs `hya-core`'s algorithms
//! on a recording number type and finds the statements an output depends on; [`rewrite`] fuses
//! products into sums; [`names`] names them after joints and links; [`render`](mod@render) writes them as blocks
//! of `let` statements. [`generate`](mod@generate) assembles each robot's functions and the file.
//!
//! ```no_run
//! let loaded = hya_urdf::load_file("robots/urdf/hya.urdf")?;
//! let generated = hya_codegen::generate(&loaded, "Hya")?;
//! std::fs::write("hya_dynamics.rs", generated.source)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod error;
pub mod generate;
pub mod names;
pub mod provenance;
pub mod render;
pub mod rewrite;
pub mod trace;
mod tracer;

pub use render::{literal, render, OpCounts, Rendered};
pub use trace::{input, trace, Emitter, Value};

pub use generate::{
    generate, generate_parametric, size_warning, GenerateError, Generated, MAX_JOINTS, WARN_ABOVE_JOINTS,
};
