//! Unrolled, const-sized Rust dynamics for one robot.
//!
//! Each entry point of [`hya_core::Dynamics`] is `hya-core`'s own algorithm
//! ([`hya_core::model::algorithms`]) run on the tracing number type [`Value`](crate::Value): every constant
//! of the model folds into the code, every operation on a joint input becomes one named
//! statement, and each function keeps only what its outputs need (gravity has no velocity
//! terms, velocity terms no gravity). Emitted through `quote`, formatted by prettyplease, with
//! a comment where each body's pass begins.

use hya_core::model::TreeModel;
use proc_macro2::{Literal, TokenStream};
use quote::quote;

pub use crate::error::{GenerateError, MAX_JOINTS};
use crate::names::{comment_safe, Names};
use crate::provenance::Provenance;
use crate::render::{literal, OpCounts};
use crate::tracer::{Function, InertiaSource, Tracer};
use hya_urdf::LoadedModel;

/// Generated source for one robot, with the operation count of each function.
#[derive(Debug, Clone)]
pub struct Generated {
    /// The Rust module text, formatted.
    pub source: String,
    /// `(function name, counts)` for each generated function.
    pub stats: Vec<(&'static str, OpCounts)>,
}

impl Generated {
    /// A table of each function's additions, multiplications, divisions and `sin_cos` calls.
    pub fn stats_table(&self) -> String {
        let mut table =
            format!("{:<36} {:>7} {:>7} {:>8} {:>5} {:>5}\n", "function", "adds", "muls", "mul_adds", "divs", "trig");
        for (function, c) in &self.stats {
            table +=
                &format!("{function:<36} {:>7} {:>7} {:>8} {:>5} {:>5}\n", c.adds, c.muls, c.mul_adds, c.divs, c.trig);
        }
        table
    }
}

/// Beyond this many joints the generator warns: unrolled code grows with about the square of
/// the joints, the derivatives' most (measured with `hya generate` on a serial chain of
/// revolute joints with offset centres of mass, release build, `/usr/bin/time -v`: 8 joints
/// give 2.8 MB of source and take 0.1 GB of memory, 16 joints 10.6 MB and 0.35 GB, 24 joints
/// 23 MB and 0.75 GB, 32 joints 40 MB and 1.3 GB, 50 joints 96 MB and 3.0 GB; HyA's 6 joints
/// give 1.5 MB), and the run-time model ([`hya_core::model::TreeModel`]) becomes the better tool.
pub const WARN_ABOVE_JOINTS: usize = 16;

/// Lints generated code may trip: long literals, `let x = …; x`, `a * -b`.
fn allowed_lints() -> TokenStream {
    quote! {
        #[allow(
            clippy::approx_constant,
            clippy::excessive_precision,
            clippy::unreadable_literal,
            clippy::let_and_return,
            clippy::neg_multiply,
            clippy::too_many_lines,
            clippy::neg_cmp_op_on_partial_ord
        )]
    }
}

/// The kernels and `impl Dynamics<N> for Type`, with `extra` functions' kernels beside them and
/// their own `impl` (the tip's kinematics; the parametric twin's `BodiesBatch`), in an anonymous
/// `const` block: the names it imports and its `f_of` helpers stay out of the caller's module.
fn dynamics_impl(tracer: &Tracer, functions: &[Function], extra: Option<(&[Function], &TokenStream)>) -> TokenStream {
    let (lints, type_name, dof) = (allowed_lints(), &tracer.type_name, tracer.dof());
    let empty = TokenStream::new();
    let (frame_functions, frame_impl) = extra.unwrap_or((&[], &empty));
    let kernels = functions.iter().chain(frame_functions).map(|f| &f.kernel);
    let conversions = functions.iter().chain(frame_functions).map(|f| &f.conversion);
    let entries = functions.iter().map(|f| &f.entry);
    quote! {
        #lints
        const _: () = {
            use ::hya_core::dynamics::check_batch;
            use ::hya_core::lanes::{batch, kernels, single, Arithmetic, Kernel};
            use ::hya_core::{Dynamics, Error, JointMatrix, JointVector};
            #(#kernels)*
            #(#conversions)*
            impl Dynamics<#dof> for #type_name {
                #(#entries)*
            }
            #frame_impl
        };
    }
}

fn check_size(model: &TreeModel) -> Result<(), GenerateError> {
    match model.dof() {
        n if n > MAX_JOINTS => Err(GenerateError::TooLarge(n)),
        _ => Ok(()),
    }
}

/// A warning for trees beyond [`WARN_ABOVE_JOINTS`], `None` below it.
pub fn size_warning(model: &TreeModel) -> Option<String> {
    (model.dof() > WARN_ABOVE_JOINTS).then(|| {
        format!(
            "{} joints: unrolled code grows with about the square of the joints (measured on a chain: 16 joints give 10.6 MB of source and take 0.35 GB of memory to generate, 24 joints 23 MB and 0.75 GB); beyond {WARN_ABOVE_JOINTS}, consider the run-time model (hya_core::model::TreeModel)",
            model.dof()
        )
    })
}

fn type_ident(type_name: &str) -> Result<proc_macro2::Ident, GenerateError> {
    syn::parse_str::<proc_macro2::Ident>(type_name).map_err(|_| GenerateError::TypeName(type_name.to_owned()))
}

/// The header comment: what the file is, from which URDF (name and SHA-256), by which
/// generator. Every URDF-derived text is `escape_default`ed.
fn header(loaded: &LoadedModel, what: &str) -> String {
    format!(
        "// Generated by hya-codegen {version}: do not edit.\n\
         // {what} of robot `{robot}` ({dof} joints)\n\
         // from {file}, SHA-256 {sha}.\n\
         // Each function is hya-core's algorithm traced with every constant of the model folded;\n\
         // values are named after joints (q_, s_, c_ for sin and cos; ABA's d_ = S·I^A S and\n\
         // u_ = τ − S·p; outputs tau_, g_, cv_, ct_, qdd_, m_) and links (_v velocity,\n\
         // _a acceleration, _f force, _p bias force, _u = I^A S; w/v and n/f angular/linear parts).\n",
        version = env!("CARGO_PKG_VERSION"),
        robot = comment_safe(loaded.model.name()),
        dof = loaded.model.dof(),
        file = comment_safe(&loaded.source.file),
        sha = comment_safe(&loaded.source.sha256),
    )
}

/// Formats `tokens`, inserts a `//` comment before the statement each pass mark names (within
/// the function it belongs to), and ends each statement holding a model number (or a product
/// of two) with a comment saying which.
fn format(tokens: TokenStream, functions: &[Function], provenance: &Provenance) -> Result<String, GenerateError> {
    let file = syn::parse2::<syn::File>(tokens).map_err(|e| GenerateError::Syntax(e.to_string()))?;
    let formatted = prettyplease::unparse(&file);
    let mut out = String::with_capacity(formatted.len() * 11 / 10);
    let mut marks: &[(String, String)] = &[];
    for line in formatted.lines() {
        let trimmed = line.trim_start();
        // A kernel's statements follow its `impl Kernel<kernels::Marker, …` line.
        let marker = trimmed.strip_prefix("impl Kernel<kernels::").and_then(|rest| rest.split(',').next());
        if let Some(function) = marker.and_then(|m| functions.iter().find(|f| f.marker == m)) {
            marks = &function.pass_marks;
        }
        // A block's `let (…) = {` line names what the block hands on, not its first statement.
        let bound = Some(trimmed)
            .filter(|t| !t.ends_with('{'))
            .and_then(|t| t.strip_prefix("let "))
            .map(|rest| rest.trim_start_matches('('))
            .and_then(|rest| rest.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_')).next());
        if let Some((_, comment)) = bound.and_then(|name| marks.iter().find(|(first, _)| first == name)) {
            let indent = &line[..line.len() - trimmed.len()];
            out.push_str(&format!("{indent}// {comment}\n"));
        }
        out.push_str(line);
        if let Some(why) = bound.and(provenance.annotate(line)) {
            out.push_str(&format!(" // {why}"));
        }
        out.push('\n');
    }
    Ok(out)
}

/// A Rust string literal holding exactly `text`: every quote, backslash, control and
/// non-printable character escaped, so that no string from a URDF can leave the literal.
fn string_literal(text: &str) -> Literal {
    Literal::string(text)
}

/// A doc attribute whose text mentions `name` (a string from the URDF), escaped.
fn doc_naming(before: &str, name: &str, after: &str) -> TokenStream {
    let text = string_literal(&format!("{before}{}{after}", name.escape_debug()));
    quote! { #[doc = #text] }
}

/// Generates the zero-sized type `type_name` whose dynamics have every constant of the loaded
/// model folded in.
pub fn generate(loaded: &LoadedModel, type_name: &str) -> Result<Generated, GenerateError> {
    let model = &loaded.model;
    check_size(model)?;
    let tracer =
        Tracer { model, names: Names::new(model), source: InertiaSource::Constant, type_name: type_ident(type_name)? };
    let mut functions = tracer.dynamics_functions()?;
    let (poses, poses_method) = tracer.frame_poses()?;
    let (ident, dof) = (&tracer.type_name, tracer.dof());
    let names = model.joint_names().map(string_literal);
    let effort = model.bodies().iter().map(|b| match b.limits.effort {
        Some(v) => {
            let v = literal(v);
            quote! { Some(#v) }
        }
        None => quote! { None },
    });
    let frame_count = Literal::usize_unsuffixed(model.frames().len());
    let frame_names = model.frames().iter().map(|f| string_literal(&f.name));
    let doc = doc_naming(" Rigid-body dynamics of `", model.name(), &format!("` ({} joints).", model.dof()));
    let lints = allowed_lints();
    // The poses' kernel, then the tip's Jacobian and `J̇ q̇` and their `FrameKinematics` impl.
    let (mut frame_functions, frame_impl) = tracer.tip_kinematics()?.unwrap_or_default();
    frame_functions.insert(0, poses);
    let dynamics = dynamics_impl(&tracer, &functions, Some((&frame_functions, &frame_impl)));
    let tokens = quote! {
        #doc
        /// Generated by hya-codegen: constants folded, all joints' `sin_cos` in one call, loops
        /// unrolled, no allocation; each function written once over `hya_core::Arithmetic`, run on
        /// fused multiply-add where the CPU has it (`hya_core::lanes::single`) and on
        /// several states per vector register in batches (`hya_core::lanes::batch`).
        #[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
        pub struct #ident;
        impl #ident {
            /// Degrees of freedom.
            pub const DOF: usize = #dof;
            /// Joint names in the model's order.
            pub const JOINT_NAMES: [&'static str; #dof] = [#(#names),*];
            /// Effort limits from the description, N·m or N (`None` where it gives none).
            pub const EFFORT_LIMITS: [Option<f64>; #dof] = [#(#effort),*];
            /// Every link of the description, in the order of [`Self::frame_poses`].
            pub const FRAME_NAMES: [&'static str; #frame_count] = [#(#frame_names),*];
            #lints
            #poses_method
        }
        #dynamics
    };
    functions.extend(frame_functions);
    let source = header(loaded, "Rigid-body dynamics") + &format(tokens, &functions, &Provenance::of(model))?;
    Ok(Generated { source, stats: functions.iter().map(|f| (f.name, f.counts)).collect() })
}

/// Generates the parameter-holding type `type_name`: the kinematics of the loaded model folded
/// in as in [`generate()`], each body's ten inertial parameters read from the type's field, so
/// that one compiled function serves any masses, centres of mass and inertias (a perturbed
/// plant, an identified model, a payload).
pub fn generate_parametric(loaded: &LoadedModel, type_name: &str) -> Result<Generated, GenerateError> {
    let model = &loaded.model;
    check_size(model)?;
    let tracer = Tracer {
        model,
        names: Names::new(model),
        source: InertiaSource::Parameters,
        type_name: type_ident(type_name)?,
    };
    let mut functions = tracer.dynamics_functions()?;
    let (bodies, bodies_impl) = tracer.forward_dynamics_of_bodies()?;
    let (ident, dof) = (&tracer.type_name, tracer.dof());
    let doc = doc_naming(
        " Rigid-body dynamics of `",
        model.name(),
        &format!("` ({} joints) with the inertial parameters as data:", model.dof()),
    );
    let dynamics = dynamics_impl(&tracer, &functions, Some((std::slice::from_ref(&bodies), &bodies_impl)));
    functions.push(bodies);
    let tokens = quote! {
        #doc
        /// `self.0[i]` is body `i`'s `RigidBodyInertia::parameters()`, about its frame origin.
        #[derive(Debug, Clone, Copy, PartialEq)]
        pub struct #ident(pub [[f64; 10]; #dof]);
        impl #ident {
            /// From each body's spatial inertia about its body frame's origin, in joint order.
            pub fn new(inertias: &[::hya_core::spatial::RigidBodyInertia; #dof]) -> Self {
                Self(core::array::from_fn(|i| inertias[i].parameters()))
            }
        }
        #dynamics
    };
    let source =
        header(loaded, "Parametric rigid-body dynamics") + &format(tokens, &functions, &Provenance::of(model))?;
    Ok(Generated { source, stats: functions.iter().map(|f| (f.name, f.counts)).collect() })
}
