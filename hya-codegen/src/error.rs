//! Why code could not be generated, and the joint count past which it is not tried.

/// The generator refuses trees with more joints than this, so that generating (in `hya generate`
/// or a `robot!` macro at compile time) stays under about a gigabyte of memory (24 joints:
/// 0.75 GB, 0.8 GB for the parametric twin; see [`WARN_ABOVE_JOINTS`](crate::WARN_ABOVE_JOINTS)); use the run-time model
/// for them.
pub const MAX_JOINTS: usize = 24;

/// Why code could not be generated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GenerateError {
    /// The type name is not a Rust identifier.
    #[error("`{0}` is not a valid Rust type name")]
    TypeName(String),
    /// Too many joints for unrolled code ([`MAX_JOINTS`]).
    #[error("{0} joints: beyond the generator's limit of {MAX_JOINTS} (hya_codegen::MAX_JOINTS): unrolled code for more takes over a gigabyte of memory to generate (32 joints: 40 MB of source, 1.3 GB); use the run-time model (hya_core::model::TreeModel)")]
    TooLarge(usize),
    /// The emitted code did not parse (a generator bug).
    #[error("generated code does not parse: {0}")]
    Syntax(String),
    /// A constant of the model folded to infinity or NaN: a joint with no inertia along its
    /// axis (its articulated inertia `D_i` is zero), which no literal can hold.
    #[error("a constant of `{function}` folds to {value}: a joint meets no inertia along its axis")]
    NonFinite {
        /// The generated function.
        function: &'static str,
        /// The constant.
        value: f64,
    },
    /// An algorithm refused the model (a generator bug: the inputs are sized from the model).
    #[error("tracing the model failed: {0}")]
    Model(#[from] hya_core::model::ModelError),
}
