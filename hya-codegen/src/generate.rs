//! Unrolled, const-sized Rust dynamics for one robot.
//!
//! Each entry point of [`hya_core::Dynamics`] is `hya-core`'s own algorithm
//! ([`hya_core::model::algorithms`]) run on the tracing number type [`Value`]: every constant
//! of the model folds into the code, every operation on a joint input becomes one named
//! statement, and each function keeps only what its outputs need (gravity has no velocity
//! terms, velocity terms no gravity). Emitted through `quote`, formatted by prettyplease, with
//! a comment where each body's pass begins.

use hya_core::model::algorithms::{self, Inertias, ModelInertias};
use hya_core::model::derivatives;
use hya_core::model::{BodyState, ModelError, TreeModel};
use hya_core::scalar::{Label, Quantity};
use hya_core::spatial::{RigidBodyInertia, Transform};
use hya_core::Real;
use proc_macro2::{Literal, TokenStream};
use quote::{format_ident, quote};

use crate::expr::{self, input, literal, OpCounts, Rendered, Value};
use crate::names::{comment_safe, Names, Output};
use crate::provenance::Provenance;
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
        let mut table = format!("{:<36} {:>7} {:>7} {:>5} {:>5}\n", "function", "adds", "muls", "divs", "trig");
        for (function, c) in &self.stats {
            table += &format!("{function:<36} {:>7} {:>7} {:>5} {:>5}\n", c.adds, c.muls, c.divs, c.trig);
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

/// The generator refuses trees with more joints than this, so that generating (in `hya generate`
/// or a `robot!` macro at compile time) stays under about a gigabyte of memory (24 joints:
/// 0.75 GB, 0.8 GB for the parametric twin; see [`WARN_ABOVE_JOINTS`]); use the run-time model
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

/// Where the bodies' inertias come from in generated code.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum InertiaSource {
    /// Folded in as literals (the zero-sized type).
    Constant,
    /// Read from the type's field, `self.0[body][parameter]` (the parameter-holding type).
    Parameters,
}

/// Names of the ten inertial parameters, in `RigidBodyInertia::parameters` order.
const PARAMETERS: [&str; 10] = ["m", "hx", "hy", "hz", "ixx", "iyy", "izz", "ixy", "ixz", "iyz"];

/// Body inertias as a traced function sees them.
enum TracedInertias<'a> {
    /// The model's, as constants.
    Model(ModelInertias<'a>),
    /// Read from the parameter-holding type's field.
    Parameters(Vec<RigidBodyInertia<Value>>),
}

impl Inertias<Value> for TracedInertias<'_> {
    fn inertia(&self, body: usize) -> RigidBodyInertia<Value> {
        match self {
            TracedInertias::Model(model) => model.inertia(body),
            TracedInertias::Parameters(parameters) => parameters[body],
        }
    }
}

/// The joint-vector arguments a function takes, by name: `q`, `qd`, `qdd`, `tau`.
type Arguments = &'static [&'static str];

/// One generated function: its tokens, the comments opening each body's pass, its counts.
struct Function {
    name: &'static str,
    tokens: TokenStream,
    pass_marks: Vec<(String, String)>,
    counts: OpCounts,
}

/// Traces `hya-core`'s algorithms for one robot.
struct Tracer<'a> {
    model: &'a TreeModel,
    names: Names,
    source: InertiaSource,
}

impl<'a> Tracer<'a> {
    fn dof(&self) -> Literal {
        Literal::usize_unsuffixed(self.model.dof())
    }

    /// The inertias of the source; parameters become inputs `{link}_{parameter}`.
    fn inertias(&self) -> TracedInertias<'a> {
        match self.source {
            InertiaSource::Constant => TracedInertias::Model(ModelInertias(self.model)),
            InertiaSource::Parameters => TracedInertias::Parameters(
                (0..self.model.dof())
                    .map(|i| {
                        RigidBodyInertia::from_parameters(&core::array::from_fn(|k| {
                            let (body, parameter) = (Literal::usize_unsuffixed(i), Literal::usize_unsuffixed(k));
                            input(self.names.body_input(i, PARAMETERS[k]), quote! { self.0[#body][#parameter] })
                        }))
                    })
                    .collect(),
            ),
        }
    }

    /// The joint inputs of `arguments`, one vector per argument: `q_sfe` from `q[1]`.
    fn joint_inputs(&self, arguments: Arguments) -> Vec<Vec<Value>> {
        arguments
            .iter()
            .map(|argument| {
                let ident = format_ident!("{argument}");
                (0..self.model.dof())
                    .map(|i| {
                        let index = Literal::usize_unsuffixed(i);
                        input(self.names.joint_input(argument, i), quote! { #ident[#index] })
                    })
                    .collect()
            })
            .collect()
    }

    /// `name(&self, arguments…)` for joint vectors of the robot's size.
    fn signature(&self, name: &str, arguments: Arguments) -> TokenStream {
        let (name, dof) = (format_ident!("{name}"), self.dof());
        let arguments = arguments.iter().map(|a| format_ident!("{a}"));
        quote! { fn #name(&self, #(#arguments: &::hya_core::JointVector<#dof>),*) }
    }

    /// Traces `algorithm` (which labels its outputs) and renders its statements.
    fn trace(
        &self,
        function: &'static str,
        arguments: Arguments,
        output: Output,
        algorithm: impl FnOnce(&[Vec<Value>], &TracedInertias, &mut [BodyState<Value>]) -> Result<Vec<Value>, ModelError>,
    ) -> Result<(Rendered, Vec<Value>), GenerateError> {
        let (outputs, emitter) = expr::trace(|| {
            let inertias = self.inertias();
            let inputs = self.joint_inputs(arguments);
            algorithm(&inputs, &inertias, &mut vec![BodyState::new(); self.model.dof()])
        });
        let outputs = outputs?;
        if let Some(value) = emitter.non_finite_constant(&outputs) {
            return Err(GenerateError::NonFinite { function, value });
        }
        Ok((emitter.render(&outputs, &self.names.with_output(output)), outputs))
    }

    /// A function returning a joint vector, `prefix_{joint}` for each joint.
    fn vector_function(
        &self,
        (name, doc): (&'static str, &str),
        arguments: Arguments,
        prefix: &'static str,
        algorithm: impl FnOnce(
            &[Vec<Value>],
            &TracedInertias,
            &mut [BodyState<Value>],
            &mut [Value],
        ) -> Result<(), ModelError>,
    ) -> Result<Function, GenerateError> {
        let (rendered, _) = self.trace(name, arguments, Output::Vector(prefix), |inputs, inertias, states| {
            let mut out = vec![Value::zero(); self.model.dof()];
            algorithm(inputs, inertias, states, &mut out)?;
            Ok(out)
        })?;
        let (signature, dof) = (self.signature(name, arguments), self.dof());
        let Rendered { statements, outputs, pass_marks, counts } = rendered;
        let tokens = quote! {
            #[doc = #doc]
            #[inline]
            #signature -> ::hya_core::JointVector<#dof> {
                #statements
                ::hya_core::JointVector::<#dof>::from([#(#outputs),*])
            }
        };
        Ok(Function { name, tokens, pass_marks, counts })
    }

    fn inverse_dynamics(&self) -> Result<Function, GenerateError> {
        let doc = " Inverse dynamics `τ = M(q) q̈ + C(q, q̇) + G(q)` by RNEA, unrolled.";
        self.vector_function(("inverse_dynamics", doc), &["q", "qd", "qdd"], "tau", |x, inertias, states, tau| {
            algorithms::inverse_dynamics(self.model, inertias, (&x[0], &x[1], &x[2]), states, tau)
        })
    }

    fn gravity(&self) -> Result<Function, GenerateError> {
        self.vector_function(("gravity", " Gravity torques `G(q)`."), &["q"], "g", |x, inertias, states, tau| {
            algorithms::gravity(self.model, inertias, &x[0], states, tau)
        })
    }

    fn velocity_terms(&self) -> Result<Function, GenerateError> {
        let doc = " Coriolis and centripetal torques `C(q, q̇)`.";
        self.vector_function(("velocity_terms", doc), &["q", "qd"], "cv", |x, inertias, states, tau| {
            algorithms::velocity_terms(self.model, inertias, (&x[0], &x[1]), states, tau)
        })
    }

    fn coriolis_transpose(&self) -> Result<Function, GenerateError> {
        let doc = " `C_matᵀ q̇ = Ṁ q̇ − C` from the subtree momenta.";
        let name = ("coriolis_transpose_times_velocity", doc);
        self.vector_function(name, &["q", "qd"], "ct", |x, inertias, states, out| {
            algorithms::coriolis_transpose_times_velocity(self.model, inertias, (&x[0], &x[1]), states, out)
        })
    }

    fn mass_matrix(&self) -> Result<Function, GenerateError> {
        let mut entries = Vec::new();
        let (rendered, _) = self.trace("mass_matrix", &["q"], Output::Matrix, |x, inertias, states| {
            algorithms::mass_matrix(self.model, inertias, &x[0], states, |i, j, value| {
                let label = Label { body: i, quantity: Quantity::Joint, component: j as u8 };
                entries.push((i, j, value.labelled(label)));
            })?;
            Ok(entries.iter().map(|e| e.2).collect())
        })?;
        let Rendered { statements, outputs, pass_marks, counts } = rendered;
        // The lower triangle, and its mirror image above the diagonal.
        let lower = entries.iter().zip(&outputs).map(|((i, j, value), out)| (*i, *j, *value, out));
        let mirrored = lower.clone().filter(|(i, j, _, _)| i != j).map(|(i, j, v, out)| (j, i, v, out));
        let stores = matrix_stores(&format_ident!("m"), lower.chain(mirrored).collect());
        let (signature, dof) = (self.signature("mass_matrix", &["q"]), self.dof());
        let tokens = quote! {
            /// Mass matrix `M(q)` by the composite-rigid-body algorithm, unrolled.
            #[inline]
            #signature -> ::hya_core::JointMatrix<#dof> {
                #statements
                let mut m = ::hya_core::JointMatrix::<#dof>::zeros();
                #(#stores)*
                m
            }
        };
        Ok(Function { name: "mass_matrix", tokens, pass_marks, counts })
    }

    /// ABA, returning `Err(SingularMassMatrix)` unless every `D_i` that is not a positive
    /// constant is positive at run time.
    fn forward_dynamics(&self) -> Result<Function, GenerateError> {
        let dof = self.model.dof();
        let mut joint_inertias = Vec::new();
        let (rendered, _) =
            self.trace("forward_dynamics", &["q", "qd", "tau"], Output::Vector("qdd"), |x, inertias, states| {
                let mut qdd = vec![Value::zero(); dof];
                algorithms::forward_dynamics(self.model, inertias, (&x[0], &x[1], &x[2]), states, &mut qdd)?;
                joint_inertias = states.iter().map(BodyState::joint_inertia).collect();
                Ok(qdd.into_iter().chain(joint_inertias.iter().copied()).collect())
            })?;
        let Rendered { statements, outputs, pass_marks, counts } = rendered;
        let (qdd, d) = outputs.split_at(dof);
        let checks: Vec<TokenStream> = joint_inertias
            .iter()
            .zip(d)
            .filter_map(|(value, tokens)| match value {
                Value::Const(c) if *c > 0.0 => None,
                Value::Const(_) => Some(quote! { false }),
                Value::Var { .. } => Some(quote! { #tokens > 0.0 }),
            })
            .collect();
        let guard = (!checks.is_empty()).then(|| {
            quote! {
                if !(#(#checks)&&*) {
                    return Err(::hya_core::Error::SingularMassMatrix);
                }
            }
        });
        let (signature, dof) = (self.signature("forward_dynamics", &["q", "qd", "tau"]), self.dof());
        let tokens = quote! {
            /// Forward dynamics `q̈ = M(q)⁻¹ (τ − C − G)` by the articulated-body algorithm,
            /// unrolled; an error if a joint meets no positive inertia `D_i`.
            #[inline]
            #signature -> Result<::hya_core::JointVector<#dof>, ::hya_core::Error> {
                #statements
                #guard
                Ok(::hya_core::JointVector::<#dof>::from([#(#qdd),*]))
            }
        };
        Ok(Function { name: "forward_dynamics", tokens, pass_marks, counts })
    }

    /// `frame_poses(q)`: every named frame's pose in the base, as `Transform`s from the base
    /// (`E` rotates base coordinates into the frame's, `r` is its origin).
    fn frame_poses(&self) -> Result<Function, GenerateError> {
        let frames = self.model.frames();
        let (rendered, _) = self.trace("frame_poses", &["q"], Output::Vector("pose"), |x, _, states| {
            let mut placements = vec![Transform::<Value>::identity(); self.model.dof()];
            algorithms::body_placements(self.model, &x[0], states, &mut placements)?;
            Ok(frames
                .iter()
                .flat_map(|f| {
                    let body = f.body.map_or_else(Transform::identity, |b| placements[b]);
                    let pose = body.then(&Transform::constant(&f.placement));
                    (0..12).map(move |k| if k < 9 { pose.rotation[(k / 3, k % 3)] } else { pose.translation[k - 9] })
                })
                .collect())
        })?;
        let Rendered { statements, outputs, pass_marks, counts } = rendered;
        let poses = outputs.chunks(12).map(|p| {
            let (r0, r1, r2, t) = (&p[0..3], &p[3..6], &p[6..9], &p[9..12]);
            quote! { ::hya_core::spatial::Transform::from_arrays([[#(#r0),*], [#(#r1),*], [#(#r2),*]], [#(#t),*]) }
        });
        let (count, dof) = (Literal::usize_unsuffixed(frames.len()), self.dof());
        let tokens = quote! {
            /// The pose of every frame of [`Self::FRAME_NAMES`] in the base at `q`, as the transform
            /// from the base to the frame (its `translation` is the frame's origin).
            pub fn frame_poses(&self, q: &::hya_core::JointVector<#dof>) -> [::hya_core::spatial::Transform; #count] {
                #statements
                [#(#poses),*]
            }
        };
        Ok(Function { name: "frame_poses", tokens, pass_marks, counts })
    }

    /// `(∂τ/∂q, ∂τ/∂q̇)`: `hya-core`'s dual-number derivative traced once per direction in one
    /// trace, so the primal RNEA is shared and each direction adds only its tangent statements.
    fn inverse_dynamics_derivatives(&self) -> Result<Function, GenerateError> {
        let n = self.model.dof();
        let (rendered, values) = self.trace(
            "inverse_dynamics_derivatives",
            &["q", "qd", "qdd"],
            Output::Vector("tau"),
            |x, inertias, _| {
                let mut outputs = vec![Value::zero(); 2 * n * n];
                let (d_dq, d_dqd) = outputs.split_at_mut(n * n);
                derivatives::inverse_dynamics_derivatives(
                    self.model,
                    inertias,
                    (&x[0], &x[1], &x[2]),
                    &mut vec![BodyState::new(); n],
                    &mut vec![hya_core::dual::Dual::fixed(Value::zero()); 4 * n],
                    &mut vec![Value::zero(); n],
                    &mut vec![Value::zero(); n],
                    (d_dq, d_dqd),
                )?;
                Ok(outputs)
            },
        )?;
        let Rendered { statements, outputs, pass_marks, counts } = rendered;
        // Row-major cells `k = i n + j` of each matrix.
        let cells = |range: core::ops::Range<usize>| {
            range.map(|k| ((k % (n * n)) / n, k % n, values[k], &outputs[k])).collect::<Vec<_>>()
        };
        let (by_q, by_qd) = (format_ident!("d_dq"), format_ident!("d_dqd"));
        let (q_stores, qd_stores) =
            (matrix_stores(&by_q, cells(0..n * n)), matrix_stores(&by_qd, cells(n * n..2 * n * n)));
        let (signature, dof) = (self.signature("inverse_dynamics_derivatives", &["q", "qd", "qdd"]), self.dof());
        let tokens = quote! {
            /// `(∂τ/∂q, ∂τ/∂q̇)` of inverse dynamics by forward-mode dual numbers, unrolled; row `i`
            /// of each is `∂τ_i`.
            #[inline]
            #signature -> (::hya_core::JointMatrix<#dof>, ::hya_core::JointMatrix<#dof>) {
                #statements
                let mut #by_q = ::hya_core::JointMatrix::<#dof>::zeros();
                let mut #by_qd = ::hya_core::JointMatrix::<#dof>::zeros();
                #(#q_stores)*
                #(#qd_stores)*
                (#by_q, #by_qd)
            }
        };
        Ok(Function { name: "inverse_dynamics_derivatives", tokens, pass_marks, counts })
    }

    /// The `Dynamics` entry points.
    fn dynamics_functions(&self) -> Result<Vec<Function>, GenerateError> {
        Ok(vec![
            self.inverse_dynamics()?,
            self.gravity()?,
            self.velocity_terms()?,
            self.coriolis_transpose()?,
            self.mass_matrix()?,
            self.forward_dynamics()?,
            self.inverse_dynamics_derivatives()?,
        ])
    }
}

/// `matrix[(i, j)] = value;` for every cell whose value is not a folded zero.
fn matrix_stores(matrix: &proc_macro2::Ident, cells: Vec<(usize, usize, Value, &TokenStream)>) -> Vec<TokenStream> {
    cells
        .into_iter()
        .filter(|(_, _, value, _)| *value != Value::zero())
        .map(|(i, j, _, expression)| {
            let (i, j) = (Literal::usize_unsuffixed(i), Literal::usize_unsuffixed(j));
            quote! { #matrix[(#i, #j)] = #expression; }
        })
        .collect()
}

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
            clippy::neg_cmp_op_on_partial_ord,
            unused_variables
        )]
    }
}

/// `impl Dynamics<N> for Type` from the traced functions.
fn dynamics_impl(type_name: &proc_macro2::Ident, dof: &Literal, functions: &[Function]) -> TokenStream {
    let lints = allowed_lints();
    let bodies = functions.iter().map(|f| &f.tokens);
    quote! {
        #lints
        impl ::hya_core::Dynamics<#dof> for #type_name {
            #(#bodies)*
        }
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
        if let Some(function) = functions.iter().find(|f| {
            trimmed
                .strip_prefix("fn ")
                .or_else(|| trimmed.strip_prefix("pub fn "))
                .is_some_and(|rest| rest.strip_prefix(f.name).is_some_and(|after| after.starts_with('(')))
        }) {
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
    let ident = type_ident(type_name)?;
    check_size(model)?;
    let tracer = Tracer { model, names: Names::new(model), source: InertiaSource::Constant };
    let mut functions = tracer.dynamics_functions()?;
    let poses = tracer.frame_poses()?;
    let dof = tracer.dof();
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
    let poses_tokens = &poses.tokens;
    let dynamics = dynamics_impl(&ident, &dof, &functions);
    let tokens = quote! {
        #doc
        /// Generated by hya-codegen: constants folded, all joints' `sin_cos` in one call, loops
        /// unrolled, no allocation; products fused into sums where the CPU has FMA
        /// (`hya_core::with_fma`).
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
            #poses_tokens
        }
        #dynamics
    };
    functions.push(poses);
    let source = header(loaded, "Rigid-body dynamics") + &format(tokens, &functions, &Provenance::of(model))?;
    Ok(Generated { source, stats: functions.iter().map(|f| (f.name, f.counts)).collect() })
}

/// Generates the parameter-holding type `type_name`: the kinematics of the loaded model folded
/// in as in [`generate`], each body's ten inertial parameters read from the type's field, so
/// that one compiled function serves any masses, centres of mass and inertias (a perturbed
/// plant, an identified model, a payload).
pub fn generate_parametric(loaded: &LoadedModel, type_name: &str) -> Result<Generated, GenerateError> {
    let model = &loaded.model;
    let ident = type_ident(type_name)?;
    check_size(model)?;
    let tracer = Tracer { model, names: Names::new(model), source: InertiaSource::Parameters };
    let functions = tracer.dynamics_functions()?;
    let dof = tracer.dof();
    let doc = doc_naming(
        " Rigid-body dynamics of `",
        model.name(),
        &format!("` ({} joints) with the inertial parameters as data:", model.dof()),
    );
    let dynamics = dynamics_impl(&ident, &dof, &functions);
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
