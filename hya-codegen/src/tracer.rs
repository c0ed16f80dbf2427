//! Each generated function: `hya-core`'s algorithm traced on [`Value`]s into one kernel generic
//! over `hya_core::Arithmetic`, and the entry points that run it.
//!
//! For a function `f` of the `Dynamics` trait the generated code holds
//! - `impl Kernel<kernels::F, N, IN, OUT> for Type { fn run<A: Arithmetic>(…) -> [A; OUT] }`:
//!   the statements, once; `OUT` counts the outputs that are not constants;
//! - `fn f_of(v: &[f64; OUT]) -> T`: the kernel's numbers as the trait's type, constants
//!   filled in (a mass matrix mirrored, forward dynamics' check of `D_i > 0`);
//! - `fn f(&self, …) -> T { f_of(&single(self, kernels::F, […])) }` and, where the trait has
//!   one, `fn f_batch(&self, …) { batch(self, kernels::F, […], n, |k, v| …f_of(&v)…) }`.

use hya_core::model::algorithms::{self, Inertias, ModelInertias};
use hya_core::model::derivatives;
use hya_core::model::{BodyState, ModelError, TreeModel};
use hya_core::scalar::{Label, Quantity};
use hya_core::spatial::{RigidBodyInertia, Transform};
use hya_core::Real;
use proc_macro2::{Ident, Literal, TokenStream};
use quote::{format_ident, quote};

use crate::error::GenerateError;
use crate::names::{Names, Output};
use crate::render::{literal, render, OpCounts, Rendered};
use crate::trace::{self, input, Value};

/// Where the bodies' inertias come from in generated code.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum InertiaSource {
    /// Folded in as literals (the zero-sized type).
    Constant,
    /// Read from the type's field, `self.0[body][parameter]` (the parameter-holding type).
    Parameters,
    /// Read from the kernel's inputs, `bodies_{parameter}[body]`, a lane value per state (the
    /// parameter-holding type's `BodiesBatch`).
    Inputs,
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

/// One generated function.
pub(crate) struct Function {
    /// Its name in the trait (or the type, for `frame_poses`).
    pub name: &'static str,
    /// Its marker in `hya_core::lanes::kernels`, which names its kernel.
    pub marker: &'static str,
    /// The kernel's `impl`.
    pub kernel: TokenStream,
    /// `fn f_of`, the kernel's numbers as the entry points' type.
    pub conversion: TokenStream,
    /// The entry points.
    pub entry: TokenStream,
    /// The comments opening each body's pass, by the statement they precede.
    pub pass_marks: Vec<(String, String)>,
    /// Its operation counts.
    pub counts: OpCounts,
}

/// A traced function's outputs: the kernel returns the variables, the entry points read them
/// from `v` and write the constants as literals.
struct Outputs {
    /// The kernel's return values, `A` expressions.
    returned: Vec<TokenStream>,
    /// Each output as an `f64` expression: `v[k]` or a literal.
    slots: Vec<TokenStream>,
}

impl Outputs {
    fn new(values: &[Value], rendered: &Rendered) -> Self {
        let (mut returned, mut slots) = (Vec::new(), Vec::new());
        for (value, expression) in values.iter().zip(&rendered.outputs) {
            match value {
                Value::Const(c) => slots.push(literal(*c)),
                Value::Var { .. } => {
                    let k = Literal::usize_unsuffixed(returned.len());
                    slots.push(quote! { v[#k] });
                    returned.push(expression.clone());
                }
            }
        }
        Self { returned, slots }
    }

    fn count(&self) -> Literal {
        Literal::usize_unsuffixed(self.returned.len())
    }
}

/// A batch entry point's outputs: their parameters, the first one (whose length is the batch's),
/// a check of the others' lengths, and the statement storing state `k`'s numbers `v`.
struct Batch {
    outputs: TokenStream,
    first: Ident,
    check: TokenStream,
    store: TokenStream,
}

impl Batch {
    /// One output slice `name`, stored by `store`.
    fn one(outputs: TokenStream, name: &str, store: TokenStream) -> Self {
        Self { outputs, first: format_ident!("{name}"), check: TokenStream::new(), store }
    }
}

/// Traces `hya-core`'s algorithms for one robot.
pub(crate) struct Tracer<'a> {
    pub model: &'a TreeModel,
    pub names: Names,
    pub source: InertiaSource,
    /// The generated type.
    pub type_name: Ident,
}

/// What one trace produced.
struct Traced {
    rendered: Rendered,
    outputs: Outputs,
    /// The traced output values, in order.
    values: Vec<Value>,
    /// The kernel's `impl`.
    kernel: TokenStream,
}

impl<'a> Tracer<'a> {
    pub fn dof(&self) -> Literal {
        Literal::usize_unsuffixed(self.model.dof())
    }

    /// The inertias of the source; parameters become inputs `{link}_{parameter}`, read as
    /// `parameters[k][body]` for [`InertiaSource::Inputs`].
    fn inertias(&self, parameters: &[Vec<Value>]) -> TracedInertias<'a> {
        let read = |i: usize, k: usize| {
            let (body, parameter) = (Literal::usize_unsuffixed(i), Literal::usize_unsuffixed(k));
            input(self.names.body_input(i, PARAMETERS[k]), quote! { A::from(self.0[#body][#parameter]) })
        };
        match self.source {
            InertiaSource::Constant => TracedInertias::Model(ModelInertias(self.model)),
            InertiaSource::Parameters | InertiaSource::Inputs => TracedInertias::Parameters(
                (0..self.model.dof())
                    .map(|i| {
                        RigidBodyInertia::from_parameters(&core::array::from_fn(|k| match parameters.get(k) {
                            Some(column) => column[i],
                            None => read(i, k),
                        }))
                    })
                    .collect(),
            ),
        }
    }

    /// The ten parameter inputs of [`InertiaSource::Inputs`], one vector of bodies per
    /// parameter (`bodies_m[i]` body `i`'s mass); none for the other sources.
    fn parameter_inputs(&self) -> Vec<Vec<Value>> {
        if self.source != InertiaSource::Inputs {
            return Vec::new();
        }
        PARAMETERS
            .iter()
            .map(|parameter| {
                self.per_body(&format_ident!("bodies_{parameter}"), |i| self.names.body_input(i, parameter))
            })
            .collect()
    }

    /// The joint inputs of `arguments`, one vector per argument: `q_sfe` from `q[1]`.
    fn joint_inputs(&self, arguments: Arguments) -> Vec<Vec<Value>> {
        arguments
            .iter()
            .map(|argument| self.per_body(&format_ident!("{argument}"), |i| self.names.joint_input(argument, i)))
            .collect()
    }

    /// One input per joint (or body) `i`, named `name(i)`, read from `array[i]`.
    fn per_body(&self, array: &Ident, name: impl Fn(usize) -> String) -> Vec<Value> {
        (0..self.model.dof())
            .map(|i| {
                let index = Literal::usize_unsuffixed(i);
                input(name(i), quote! { #array[#index] })
            })
            .collect()
    }

    /// Traces `algorithm` (which labels its outputs), renders its statements and writes the
    /// kernel `marker` from them.
    fn trace(
        &self,
        (function, marker): (&'static str, &'static str),
        arguments: Arguments,
        output: Output,
        algorithm: impl FnOnce(&[Vec<Value>], &TracedInertias, &mut [BodyState<Value>]) -> Result<Vec<Value>, ModelError>,
    ) -> Result<Traced, GenerateError> {
        let ((values, inputs, parameters), emitter) = trace::trace(|| {
            let parameters = self.parameter_inputs();
            let inertias = self.inertias(&parameters);
            let inputs = self.joint_inputs(arguments);
            (algorithm(&inputs, &inertias, &mut vec![BodyState::new(); self.model.dof()]), inputs, parameters)
        });
        let values = values?;
        if let Some(value) = emitter.non_finite_constant(&values) {
            return Err(GenerateError::NonFinite { function, value });
        }
        let rendered = render(&emitter, &values, &self.names.with_output(output));
        let outputs = Outputs::new(&values, &rendered);
        // An argument none of whose joints (or bodies) is read is bound to `_`.
        let columns = parameters.iter().zip(PARAMETERS).map(|(c, p)| (format_ident!("bodies_{p}"), c));
        let bound: Vec<Ident> = arguments
            .iter()
            .zip(&inputs)
            .map(|(argument, joints)| (format_ident!("{argument}"), joints))
            .chain(columns)
            .map(|(name, read)| if read.iter().any(|v| rendered.reads(*v)) { name } else { format_ident!("_") })
            .collect();
        let (marker_ident, type_name, dof) = (format_ident!("{marker}"), &self.type_name, self.dof());
        let (count, arity) = (outputs.count(), Literal::usize_unsuffixed(bound.len()));
        let (statements, returned) = (&rendered.statements, &outputs.returned);
        let kernel = quote! {
            impl Kernel<kernels::#marker_ident, #dof, #arity, #count> for #type_name {
                #[inline(always)]
                fn run<A: Arithmetic>(&self, [#(#bound),*]: [&[A; #dof]; #arity]) -> [A; #count] {
                    #statements
                    [#(#returned),*]
                }
            }
        };
        Ok(Traced { rendered, outputs, values, kernel })
    }

    /// `(q: &JointVector<N>, …)` and `[q, …]`, or with slices for a batch.
    fn parameters(&self, arguments: Arguments, batch: bool) -> (TokenStream, TokenStream) {
        let dof = self.dof();
        let names: Vec<Ident> = arguments.iter().map(|a| format_ident!("{a}")).collect();
        let declared = if batch {
            quote! { #(#names: &[JointVector<#dof>]),* }
        } else {
            quote! { #(#names: &JointVector<#dof>),* }
        };
        (declared, quote! { [#(#names),*] })
    }

    /// `fn f_of`, `fn f` and `fn f_batch` (if `batch` names its output) around a traced kernel.
    fn entry_points(
        &self,
        (name, marker, doc): (&'static str, &'static str, &str),
        arguments: Arguments,
        (output_type, conversion): (TokenStream, TokenStream),
        batch: Option<Batch>,
        traced: &Traced,
    ) -> (TokenStream, TokenStream) {
        let (name_ident, of, marker) = (format_ident!("{name}"), format_ident!("{name}_of"), format_ident!("{marker}"));
        let count = traced.outputs.count();
        let (declared, passed) = self.parameters(arguments, false);
        // Not `#[inline]`: the kernels are compiled once, with their arm, rather than again in
        // every crate that calls them; a call costs a few ns against 50 ns and more of kernel.
        let single = quote! {
            #[doc = #doc]
            fn #name_ident(&self, #declared) -> #output_type {
                #of(&single(self, kernels::#marker, #passed))
            }
        };
        let batch = batch.map(|Batch { outputs, first, check, store }| {
            let batch_name = format_ident!("{name}_batch");
            let (declared, passed) = self.parameters(arguments, true);
            quote! {
                fn #batch_name(&self, #declared, #outputs) -> Result<(), Error> {
                    #check
                    batch(self, kernels::#marker, #passed, #first.len(), |k, v| { #store; Ok(()) })
                }
            }
        });
        // A function whose outputs are all constants reads no number.
        let v = if traced.outputs.returned.is_empty() { format_ident!("_") } else { format_ident!("v") };
        let conversion = quote! {
            #[inline(always)]
            fn #of(#v: &[f64; #count]) -> #output_type {
                #conversion
            }
        };
        (conversion, quote! { #single #batch })
    }

    /// A function returning a joint vector, `prefix_{joint}` for each joint.
    fn vector_function(
        &self,
        (name, marker, doc): (&'static str, &'static str, &str),
        arguments: Arguments,
        prefix: &'static str,
        batch: bool,
        algorithm: impl FnOnce(
            &[Vec<Value>],
            &TracedInertias,
            &mut [BodyState<Value>],
            &mut [Value],
        ) -> Result<(), ModelError>,
    ) -> Result<Function, GenerateError> {
        let traced = self.trace((name, marker), arguments, Output::Vector(prefix), |inputs, inertias, states| {
            let mut out = vec![Value::zero(); self.model.dof()];
            algorithm(inputs, inertias, states, &mut out)?;
            Ok(out)
        })?;
        let (dof, slots) = (self.dof(), &traced.outputs.slots);
        let output_type = quote! { JointVector<#dof> };
        let conversion = quote! { JointVector::<#dof>::from([#(#slots),*]) };
        let out = format_ident!("{prefix}");
        let batch = batch.then(|| {
            let of = format_ident!("{name}_of");
            Batch::one(quote! { #out: &mut [JointVector<#dof>] }, prefix, quote! { #out[k] = #of(&v) })
        });
        let entry = self.entry_points((name, marker, doc), arguments, (output_type, conversion), batch, &traced);
        Ok(self.function(name, marker, traced, entry))
    }

    fn function(
        &self,
        name: &'static str,
        marker: &'static str,
        traced: Traced,
        (conversion, entry): (TokenStream, TokenStream),
    ) -> Function {
        let Traced { rendered, kernel, .. } = traced;
        let (pass_marks, counts) = (rendered.pass_marks, rendered.counts);
        Function { name, marker, kernel, conversion, entry, pass_marks, counts }
    }

    fn inverse_dynamics(&self) -> Result<Function, GenerateError> {
        let doc = " Inverse dynamics `τ = M(q) q̈ + C(q, q̇) + G(q)` by RNEA, unrolled.";
        let name = ("inverse_dynamics", "InverseDynamics", doc);
        self.vector_function(name, &["q", "qd", "qdd"], "tau", true, |x, inertias, states, tau| {
            algorithms::inverse_dynamics(self.model, inertias, (&x[0], &x[1], &x[2]), states, tau)
        })
    }

    fn gravity(&self) -> Result<Function, GenerateError> {
        let name = ("gravity", "Gravity", " Gravity torques `G(q)`.");
        self.vector_function(name, &["q"], "g", true, |x, inertias, states, tau| {
            algorithms::gravity(self.model, inertias, &x[0], states, tau)
        })
    }

    fn velocity_terms(&self) -> Result<Function, GenerateError> {
        let name = ("velocity_terms", "VelocityTerms", " Coriolis and centripetal torques `C(q, q̇)`.");
        self.vector_function(name, &["q", "qd"], "cv", false, |x, inertias, states, tau| {
            algorithms::velocity_terms(self.model, inertias, (&x[0], &x[1]), states, tau)
        })
    }

    fn coriolis_transpose(&self) -> Result<Function, GenerateError> {
        let doc = " `C_matᵀ q̇ = Ṁ q̇ − C` from the subtree momenta.";
        let name = ("coriolis_transpose_times_velocity", "CoriolisTranspose", doc);
        self.vector_function(name, &["q", "qd"], "ct", false, |x, inertias, states, out| {
            algorithms::coriolis_transpose_times_velocity(self.model, inertias, (&x[0], &x[1]), states, out)
        })
    }

    fn mass_matrix(&self) -> Result<Function, GenerateError> {
        let mut cells = Vec::new();
        let traced = self.trace(("mass_matrix", "MassMatrix"), &["q"], Output::Matrix, |x, inertias, states| {
            algorithms::mass_matrix(self.model, inertias, &x[0], states, |i, j, value| {
                let label = Label { body: i, quantity: Quantity::Joint, component: j as u8 };
                cells.push((i, j, value.labelled(label)));
            })?;
            Ok(cells.iter().map(|e| e.2).collect())
        })?;
        // The lower triangle, and its mirror image above the diagonal.
        let lower: Vec<_> =
            cells.iter().zip(&traced.outputs.slots).map(|((i, j, value), slot)| (*i, *j, *value, slot)).collect();
        let mirrored = lower.iter().filter(|(i, j, _, _)| i != j).map(|&(i, j, v, slot)| (j, i, v, slot));
        let stores = matrix_stores(&format_ident!("m"), lower.iter().copied().chain(mirrored).collect());
        let dof = self.dof();
        let output_type = quote! { JointMatrix<#dof> };
        let conversion = quote! {
            let mut m = JointMatrix::<#dof>::zeros();
            #(#stores)*
            m
        };
        let doc = " Mass matrix `M(q)` by the composite-rigid-body algorithm, unrolled.";
        let batch = Batch::one(quote! { m: &mut [JointMatrix<#dof>] }, "m", quote! { m[k] = mass_matrix_of(&v) });
        let entry = self.entry_points(
            ("mass_matrix", "MassMatrix", doc),
            &["q"],
            (output_type, conversion),
            Some(batch),
            &traced,
        );
        Ok(self.function("mass_matrix", "MassMatrix", traced, entry))
    }

    /// ABA, returning `Err(SingularMassMatrix)` unless every `D_i` that is not a positive
    /// constant is positive at run time.
    fn forward_dynamics(&self) -> Result<Function, GenerateError> {
        let (traced, joint_inertias) = self.forward_dynamics_traced(("forward_dynamics", "ForwardDynamics"))?;
        let (output_type, conversion) = self.forward_dynamics_conversion(&traced, &joint_inertias);
        let dof = self.dof();
        let doc = " Forward dynamics `q̈ = M(q)⁻¹ (τ − C − G)` by the articulated-body algorithm, unrolled; \
                   an error if a joint meets no positive inertia `D_i`.";
        let batch =
            Batch::one(quote! { qdd: &mut [JointVector<#dof>] }, "qdd", quote! { qdd[k] = forward_dynamics_of(&v)? });
        let name = ("forward_dynamics", "ForwardDynamics", doc);
        let entry = self.entry_points(name, &["q", "qd", "tau"], (output_type, conversion), Some(batch), &traced);
        Ok(self.function("forward_dynamics", "ForwardDynamics", traced, entry))
    }

    /// ABA traced as `(function, marker)`: the accelerations, then each joint's articulated
    /// inertia `D_i`; and the traced `D_i`.
    fn forward_dynamics_traced(
        &self,
        (function, marker): (&'static str, &'static str),
    ) -> Result<(Traced, Vec<Value>), GenerateError> {
        let dof = self.model.dof();
        let mut joint_inertias = Vec::new();
        let traced =
            self.trace((function, marker), &["q", "qd", "tau"], Output::Vector("qdd"), |x, inertias, states| {
                let mut qdd = vec![Value::zero(); dof];
                algorithms::forward_dynamics(self.model, inertias, (&x[0], &x[1], &x[2]), states, &mut qdd)?;
                joint_inertias = states.iter().map(BodyState::joint_inertia).collect();
                Ok(qdd.into_iter().chain(joint_inertias.iter().copied()).collect())
            })?;
        Ok((traced, joint_inertias))
    }

    /// ABA's numbers as `Result<JointVector<N>, Error>`: `Err(SingularMassMatrix)` unless every
    /// `D_i` that is not a positive constant is positive at run time.
    fn forward_dynamics_conversion(&self, traced: &Traced, joint_inertias: &[Value]) -> (TokenStream, TokenStream) {
        let (qdd, d) = traced.outputs.slots.split_at(self.model.dof());
        let checks: Vec<TokenStream> = joint_inertias
            .iter()
            .zip(d)
            .filter_map(|(value, slot)| match value {
                Value::Const(c) if *c > 0.0 => None,
                Value::Const(_) => Some(quote! { false }),
                Value::Var { .. } => Some(quote! { #slot > 0.0 }),
            })
            .collect();
        let guard = (!checks.is_empty()).then(|| {
            quote! {
                if !(#(#checks)&&*) {
                    return Err(Error::SingularMassMatrix);
                }
            }
        });
        let dof = self.dof();
        let output_type = quote! { Result<JointVector<#dof>, Error> };
        let conversion = quote! {
            #guard
            Ok(JointVector::<#dof>::from([#(#qdd),*]))
        };
        (output_type, conversion)
    }

    /// `BodiesBatch` for the parameter-holding type: ABA with each state's bodies read from the
    /// kernel's inputs (`forward_dynamics_of_bodies_of` converts its numbers as
    /// `forward_dynamics_of` does). The function and the `impl`.
    pub fn forward_dynamics_of_bodies(&self) -> Result<(Function, TokenStream), GenerateError> {
        let (name, marker) = ("forward_dynamics_of_bodies", "ForwardDynamicsOfBodies");
        let inputs = Tracer {
            source: InertiaSource::Inputs,
            names: self.names.clone(),
            type_name: self.type_name.clone(),
            ..*self
        };
        let (traced, joint_inertias) = inputs.forward_dynamics_traced((name, marker))?;
        let (output_type, conversion) = self.forward_dynamics_conversion(&traced, &joint_inertias);
        let count = traced.outputs.count();
        let (type_name, dof) = (&self.type_name, self.dof());
        let columns = (0..PARAMETERS.len()).map(Literal::usize_unsuffixed);
        let implementation = quote! {
            #[inline(always)]
            fn forward_dynamics_of_bodies_of(v: &[f64; #count]) -> #output_type {
                #conversion
            }
            impl ::hya_core::BodiesBatch<#dof> for #type_name {
                fn forward_dynamics_of_bodies_batch(
                    &self,
                    bodies: ::hya_core::BodyColumns<'_, #dof>,
                    q: &[JointVector<#dof>],
                    qd: &[JointVector<#dof>],
                    tau: &[JointVector<#dof>],
                    qdd: &mut [JointVector<#dof>],
                ) -> Result<(), Error> {
                    batch(
                        self,
                        kernels::ForwardDynamicsOfBodies,
                        [q, qd, tau, #(bodies[#columns]),*],
                        qdd.len(),
                        |k, v| {
                            qdd[k] = forward_dynamics_of_bodies_of(&v)?;
                            Ok(())
                        },
                    )
                }
            }
        };
        Ok((self.function(name, marker, traced, Default::default()), implementation))
    }

    /// Every body's placement in the base at the traced `q` ([`algorithms::body_placements`]).
    fn placements(&self, q: &[Value], states: &mut [BodyState<Value>]) -> Result<Vec<Transform<Value>>, ModelError> {
        let mut placements = vec![Transform::<Value>::identity(); self.model.dof()];
        algorithms::body_placements(self.model, q, states, &mut placements)?;
        Ok(placements)
    }

    /// `frame_poses(q)`: every named frame's pose in the base, as `Transform`s from the base
    /// (`E` rotates base coordinates into the frame's, `r` is its origin). Its kernel and the
    /// inherent method that runs it.
    pub fn frame_poses(&self) -> Result<(Function, TokenStream), GenerateError> {
        let frames = self.model.frames();
        let traced = self.trace(("frame_poses", "FramePoses"), &["q"], Output::Vector("pose"), |x, _, states| {
            let placements = self.placements(&x[0], states)?;
            Ok(frames
                .iter()
                .flat_map(|f| {
                    let pose = hya_core::model::kinematics::frame_placement(f, &placements);
                    (0..12).map(move |k| if k < 9 { pose.rotation[(k / 3, k % 3)] } else { pose.translation[k - 9] })
                })
                .collect())
        })?;
        let poses = traced.outputs.slots.chunks(12).map(|p| {
            let (r0, r1, r2, t) = (&p[0..3], &p[3..6], &p[6..9], &p[9..12]);
            quote! { ::hya_core::spatial::Transform::from_arrays([[#(#r0),*], [#(#r1),*], [#(#r2),*]], [#(#t),*]) }
        });
        let (count, dof) = (Literal::usize_unsuffixed(frames.len()), self.dof());
        let method = quote! {
            /// The pose of every frame of [`Self::FRAME_NAMES`] in the base at `q`, as the transform
            /// from the base to the frame (its `translation` is the frame's origin).
            pub fn frame_poses(&self, q: &::hya_core::JointVector<#dof>) -> [::hya_core::spatial::Transform; #count] {
                let v = ::hya_core::lanes::single(self, ::hya_core::lanes::kernels::FramePoses, [q]);
                [#(#poses),*]
            }
        };
        Ok((self.function("frame_poses", "FramePoses", traced, Default::default()), method))
    }

    /// `FrameKinematics` of the model's last link (`TreeModel::tip_frame`): the Jacobian and
    /// `J̇ q̇` traced from `hya-core`'s kinematics, and the `impl` whose pose reads
    /// `frame_poses`. `None` for a model without links.
    pub fn tip_kinematics(&self) -> Result<Option<(Vec<Function>, TokenStream)>, GenerateError> {
        let Some(tip) = self.model.tip_frame() else { return Ok(None) };
        let (n, dof, frames) = (self.model.dof(), self.dof(), self.model.frames().len());
        let (name, marker) = ("frame_jacobian", "FrameJacobian");
        let traced = self.trace((name, marker), &["q"], Output::Vector("j"), |x, _, states| {
            let mut jacobian = vec![Value::zero(); 6 * n];
            hya_core::model::kinematics::frame_jacobian(
                self.model,
                tip,
                &self.placements(&x[0], states)?,
                &mut jacobian,
            )?;
            Ok(jacobian)
        })?;
        let cells = (0..6 * n).map(|k| (k / n, k % n, traced.values[k], &traced.outputs.slots[k])).collect();
        let stores = matrix_stores(&format_ident!("jacobian"), cells);
        let output_type = quote! { ::hya_core::FrameJacobian<#dof> };
        let conversion = quote! {
            let mut jacobian = ::hya_core::FrameJacobian::<#dof>::zeros();
            #(#stores)*
            jacobian
        };
        let doc = " The tip's geometric Jacobian, world-aligned, linear rows first; unrolled.";
        let batch = Batch::one(
            quote! { jacobian: &mut [::hya_core::FrameJacobian<#dof>] },
            "jacobian",
            quote! { jacobian[k] = frame_jacobian_of(&v) },
        );
        let entry = self.entry_points((name, marker, doc), &["q"], (output_type, conversion), Some(batch), &traced);
        let jacobian = self.function(name, marker, traced, entry);

        let (name, marker) = ("frame_acceleration_bias", "FrameAccelerationBias");
        let traced = self.trace((name, marker), &["q", "qd"], Output::Vector("a"), |x, _, states| {
            let placements = self.placements(&x[0], states)?;
            Ok(hya_core::model::kinematics::frame_acceleration_bias(self.model, tip, &placements, &x[1])?.to_vec())
        })?;
        let slots = &traced.outputs.slots;
        let output_type = quote! { ::hya_core::FrameVector };
        let conversion = quote! { ::hya_core::FrameVector::new(#(#slots),*) };
        let doc = " The tip's `J̇ q̇`: its origin's classical acceleration and its angular acceleration at `q̈ = 0`.";
        let batch = Batch {
            outputs: quote! { bias: &mut [::hya_core::FrameVector] },
            first: format_ident!("bias"),
            check: TokenStream::new(),
            store: quote! { bias[k] = frame_acceleration_bias_of(&v) },
        };
        let entry =
            self.entry_points((name, marker, doc), &["q", "qd"], (output_type, conversion), Some(batch), &traced);
        let bias = self.function(name, marker, traced, entry);

        let (tip_name, last, type_name) =
            (Literal::string(&tip.name), Literal::usize_unsuffixed(frames - 1), &self.type_name);
        let (jacobian_entry, bias_entry) = (&jacobian.entry, &bias.entry);
        let implementation = quote! {
            impl ::hya_core::FrameKinematics<#dof> for #type_name {
                fn frame_name(&self) -> &'static str {
                    #tip_name
                }
                fn frame_pose(&self, q: &JointVector<#dof>) -> ::hya_core::spatial::Transform {
                    self.frame_poses(q)[#last]
                }
                #jacobian_entry
                #bias_entry
            }
        };
        Ok(Some((vec![jacobian, bias], implementation)))
    }

    /// `(∂τ/∂q, ∂τ/∂q̇)`: `hya-core`'s analytic derivative pass (one pass over the bodies in base
    /// coordinates, then six-vector products per pair of related joints), traced.
    fn inverse_dynamics_derivatives(&self) -> Result<Function, GenerateError> {
        let n = self.model.dof();
        let (name, marker) = ("inverse_dynamics_derivatives", "InverseDynamicsDerivatives");
        let arguments: Arguments = &["q", "qd", "qdd"];
        let traced = self.trace((name, marker), arguments, Output::Vector("tau"), |x, inertias, _| {
            let mut outputs = vec![Value::zero(); 2 * n * n];
            let (d_dq, d_dqd) = outputs.split_at_mut(n * n);
            derivatives::inverse_dynamics_derivatives(
                self.model,
                inertias,
                (&x[0], &x[1], &x[2]),
                &mut vec![derivatives::DerivativeState::new(); n],
                &mut vec![Value::zero(); n],
                (d_dq, d_dqd),
            )?;
            Ok(outputs)
        })?;
        // Row-major cells `k = i n + j` of each matrix.
        let cells = |range: core::ops::Range<usize>| {
            range.map(|k| ((k % (n * n)) / n, k % n, traced.values[k], &traced.outputs.slots[k])).collect::<Vec<_>>()
        };
        let (by_q, by_qd) = (format_ident!("d_dq"), format_ident!("d_dqd"));
        let (q_stores, qd_stores) =
            (matrix_stores(&by_q, cells(0..n * n)), matrix_stores(&by_qd, cells(n * n..2 * n * n)));
        let dof = self.dof();
        let output_type = quote! { (JointMatrix<#dof>, JointMatrix<#dof>) };
        let conversion = quote! {
            let mut #by_q = JointMatrix::<#dof>::zeros();
            let mut #by_qd = JointMatrix::<#dof>::zeros();
            #(#q_stores)*
            #(#qd_stores)*
            (#by_q, #by_qd)
        };
        let doc = " `(∂τ/∂q, ∂τ/∂q̇)` of inverse dynamics by the analytic derivative pass, unrolled; row `i` \
                   of each is `∂τ_i`.";
        let batch = Batch {
            outputs: quote! { d_dq: &mut [JointMatrix<#dof>], d_dqd: &mut [JointMatrix<#dof>] },
            first: by_q.clone(),
            check: quote! { check_batch(&[d_dqd.len()], d_dq.len())?; },
            store: quote! { (d_dq[k], d_dqd[k]) = inverse_dynamics_derivatives_of(&v) },
        };
        let entry = self.entry_points((name, marker, doc), arguments, (output_type, conversion), Some(batch), &traced);
        Ok(self.function(name, marker, traced, entry))
    }

    /// The `Dynamics` entry points.
    pub fn dynamics_functions(&self) -> Result<Vec<Function>, GenerateError> {
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
fn matrix_stores(matrix: &Ident, cells: Vec<(usize, usize, Value, &TokenStream)>) -> Vec<TokenStream> {
    cells
        .into_iter()
        .filter(|(_, _, value, _)| *value != Value::zero())
        .map(|(i, j, _, expression)| {
            let (i, j) = (Literal::usize_unsuffixed(i), Literal::usize_unsuffixed(j));
            quote! { #matrix[(#i, #j)] = #expression; }
        })
        .collect()
}
