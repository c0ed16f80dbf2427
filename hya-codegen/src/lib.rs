//! # hya-codegen
//!
//! Takes a model that `hya-urdf` loaded and validated, and emits unrolled, const-sized Rust
//! implementing [`hya_core::Dynamics`] for it ([`generate()`]), in
//! the spirit of RobCoGen: constants folded into literals, the sines and cosines of all joints in
//! one lane-parallel call, axis-aligned joints and sparse inertias exploited, zeros never
//! multiplied, no allocation. Each function holds two variants of the same statements: in one, a
//! product feeding a sum in the same block becomes one `hya_core::mul_add`, compiled for fused
//! multiply-add and run where the CPU has it (`hya_core::with_fma`: decided at compile time
//! when the target has FMA, at run time on x86 with `std`); the other keeps the plain
//! arithmetic. Rust never fuses by itself, so this is the only way the FMA unit is used.
//!
//! ```no_run
//! let loaded = hya_urdf::load_file("robots/urdf/hya.urdf")?;
//! let generated = hya_codegen::generate(&loaded, "Hya")?;
//! std::fs::write("hya_dynamics.rs", generated.source)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod expr;
pub mod generate;
pub mod names;
pub mod provenance;

pub use generate::{
    generate, generate_parametric, size_warning, GenerateError, Generated, MAX_JOINTS, WARN_ABOVE_JOINTS,
};
