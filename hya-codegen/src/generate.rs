//! Unrolled, const-sized Rust dynamics for one robot.
//!
//! Each entry point of [`hya_core::Dynamics`] is traced separately through the same recursions
//! as the runtime model (RNEA, CRBA, subtree momenta for `Cᵀq̇`), so each keeps only what it
//! needs: gravity has no velocity terms, velocity terms no gravity, and every constant of the
//! model is folded into literals.

use std::fmt::Write;

use hya_core::model::{Body, JointKind, TreeModel};

use crate::expr::{literal, Emitter, OpCounts, Rendered, Value, ZERO};
use crate::symbolic::{constant_vector, subspace, Inertia, JointXform, Spatial, Xform, ZERO3, ZERO6};

/// Generated source for one robot, with the operation count of each function.
#[derive(Debug, Clone)]
pub struct Generated {
    /// The Rust module text, formatted.
    pub source: String,
    /// `(function name, counts)` for each generated function.
    pub stats: Vec<(&'static str, OpCounts)>,
}

/// Beyond this many joints the generator warns: unrolled code grows faster than quadratically
/// with the joints of a chain (measured: 50 joints give 4.7 MB of source and 84 s of
/// compilation, 100 joints 15.8 MB and 13 minutes), and the run-time model
/// ([`hya_core::model::TreeModel`]) becomes the better tool.
pub const WARN_ABOVE_JOINTS: usize = 30;

/// The generator refuses trees with more joints than this; use the run-time model for them.
pub const MAX_JOINTS: usize = 128;

/// Why code could not be generated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GenerateError {
    /// The type name is not a Rust identifier.
    #[error("`{0}` is not a valid Rust type name")]
    TypeName(String),
    /// Too many joints for unrolled code ([`MAX_JOINTS`]).
    #[error("{0} joints: beyond {MAX_JOINTS}, unrolled code is tens of megabytes; use the run-time model (hya_core::model::TreeModel)")]
    TooLarge(usize),
    /// The emitted code did not parse (a generator bug).
    #[error("generated code does not parse: {0}")]
    Syntax(String),
}

/// Where the bodies' inertias come from in generated code.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum InertiaSource {
    /// Folded in as literals (the zero-sized type).
    Constant,
    /// Read from the type's field, `self.0[body][parameter]` (the parameter-holding type).
    Parameters,
}

/// Body `i`'s inertia, traced.
fn body_inertia(e: &mut Emitter, body: &Body, i: usize, source: InertiaSource) -> Inertia {
    match source {
        InertiaSource::Constant => Inertia::constant(&body.inertia),
        InertiaSource::Parameters => {
            Inertia::from_parameters(core::array::from_fn(|k| e.input(format!("self.0[{i}][{k}]"))))
        }
    }
}

/// Which rates an RNEA trace includes.
#[derive(Debug, Clone, Copy)]
struct RneaInputs {
    velocity: bool,
    acceleration: bool,
    gravity: bool,
}

/// The traced joint transforms of every body, one `sin_cos` per revolute joint.
fn joint_transforms(e: &mut Emitter, bodies: &[Body]) -> Vec<JointXform> {
    bodies
        .iter()
        .enumerate()
        .map(|(i, body)| {
            let q = e.input(format!("q[{i}]"));
            let sin_cos = (body.kind == JointKind::Revolute).then(|| e.sin_cos(q));
            JointXform::new(e, body, q, sin_cos)
        })
        .collect()
}

fn rnea(e: &mut Emitter, model: &TreeModel, inputs: RneaInputs, source: InertiaSource) -> Vec<Value> {
    let bodies = model.bodies();
    let xforms = joint_transforms(e, bodies);
    let gravity = if inputs.gravity { constant_vector(&-model.gravity_vector()) } else { ZERO3 };
    let base_acceleration = Spatial { angular: ZERO3, linear: gravity };
    let mut velocity: Vec<Spatial> = Vec::with_capacity(bodies.len());
    let mut force: Vec<Spatial> = Vec::with_capacity(bodies.len());
    let mut acceleration: Vec<Spatial> = Vec::with_capacity(bodies.len());
    for (i, body) in bodies.iter().enumerate() {
        let s = subspace(body);
        let qd = if inputs.velocity { e.input(format!("qd[{i}]")) } else { ZERO };
        let qdd = if inputs.acceleration { e.input(format!("qdd[{i}]")) } else { ZERO };
        let (parent_velocity, parent_acceleration) =
            body.parent.map_or((ZERO6, base_acceleration), |p| (velocity[p], acceleration[p]));
        let joint_velocity = e.scale6(&s, qd);
        let carried = xforms[i].apply_motion(e, &parent_velocity);
        let v = e.add6(&carried, &joint_velocity);
        let carried = xforms[i].apply_motion(e, &parent_acceleration);
        let driven = e.scale6(&s, qdd);
        let coriolis = e.cross_motion(&v, &joint_velocity);
        let partial = e.add6(&carried, &driven);
        let a = e.add6(&partial, &coriolis);
        let inertia = body_inertia(e, body, i, source);
        let ia = e.apply_inertia(&inertia, &a);
        let momentum = e.apply_inertia(&inertia, &v);
        let gyroscopic = e.cross_force(&v, &momentum);
        force.push(e.add6(&ia, &gyroscopic));
        velocity.push(v);
        acceleration.push(a);
    }
    backward_projection(e, bodies, &xforms, &mut force, |e, i, f| e.dot6(&subspace(&bodies[i]), f))
}

/// Leaves first: `out_i = project(i, f_i)`, then `f_λ += X_iᵀ f_i`.
fn backward_projection(
    e: &mut Emitter,
    bodies: &[Body],
    xforms: &[JointXform],
    force: &mut [Spatial],
    project: impl Fn(&mut Emitter, usize, &Spatial) -> Value,
) -> Vec<Value> {
    let mut out = vec![ZERO; bodies.len()];
    for (i, body) in bodies.iter().enumerate().rev() {
        out[i] = project(e, i, &force[i]);
        if let Some(p) = body.parent {
            let carried = xforms[i].apply_transpose_force(e, &force[i]);
            force[p] = e.add6(&force[p], &carried);
        }
    }
    out
}

fn coriolis_transpose(e: &mut Emitter, model: &TreeModel, source: InertiaSource) -> Vec<Value> {
    let bodies = model.bodies();
    let xforms = joint_transforms(e, bodies);
    let mut velocity: Vec<Spatial> = Vec::with_capacity(bodies.len());
    let mut momentum: Vec<Spatial> = Vec::with_capacity(bodies.len());
    for (i, body) in bodies.iter().enumerate() {
        let qd = e.input(format!("qd[{i}]"));
        let parent_velocity = body.parent.map_or(ZERO6, |p| velocity[p]);
        let carried = xforms[i].apply_motion(e, &parent_velocity);
        let joint_velocity = e.scale6(&subspace(body), qd);
        let v = e.add6(&carried, &joint_velocity);
        let inertia = body_inertia(e, body, i, source);
        momentum.push(e.apply_inertia(&inertia, &v));
        velocity.push(v);
    }
    backward_projection(e, bodies, &xforms, &mut momentum, |e, i, h| {
        let rate = e.cross_motion(&velocity[i], &subspace(&bodies[i]));
        e.dot6(&rate, h)
    })
}

/// The lower triangle of `M(q)`, row-major (`(i, j)` with `j ≤ i`).
fn crba(e: &mut Emitter, model: &TreeModel, source: InertiaSource) -> Vec<(usize, usize, Value)> {
    let bodies = model.bodies();
    let xforms = joint_transforms(e, bodies);
    let mut composite: Vec<Inertia> = bodies.iter().enumerate().map(|(i, b)| body_inertia(e, b, i, source)).collect();
    for (i, body) in bodies.iter().enumerate().rev() {
        if let Some(p) = body.parent {
            let carried = xforms[i].inertia_in_parent(e, &composite[i]);
            composite[p] = e.add_inertia(&composite[p], &carried);
        }
    }
    let mut entries = Vec::new();
    for (i, body) in bodies.iter().enumerate() {
        let mut force = e.apply_inertia(&composite[i], &subspace(body));
        entries.push((i, i, e.dot6(&subspace(body), &force)));
        let mut j = i;
        while let Some(p) = bodies[j].parent {
            force = xforms[j].apply_transpose_force(e, &force);
            j = p;
            entries.push((i, j, e.dot6(&subspace(&bodies[j]), &force)));
        }
    }
    entries
}

/// One generated method: its signature, body statements and returned expression.
struct Method {
    name: &'static str,
    doc: &'static str,
    arguments: &'static str,
    returns: &'static str,
    body: String,
    counts: OpCounts,
}

fn vector_method(
    name: &'static str,
    doc: &'static str,
    arguments: &'static str,
    dof: usize,
    trace: impl FnOnce(&mut Emitter) -> Vec<Value>,
) -> Method {
    let mut e = Emitter::new();
    let outputs = trace(&mut e);
    let Rendered { code: mut body, counts, outputs } = e.render(&outputs);
    let _ = write!(body, "::hya_core::JointVector::<{dof}>::from([{}])", outputs.join(", "));
    Method { name, doc, arguments, returns: "::hya_core::JointVector", body, counts }
}

fn mass_matrix_method(model: &TreeModel, source: InertiaSource) -> Method {
    let mut e = Emitter::new();
    let entries = crba(&mut e, model, source);
    let outputs: Vec<Value> = entries.iter().map(|(_, _, v)| *v).collect();
    let Rendered { code: mut body, counts, outputs } = e.render(&outputs);
    let dof = model.dof();
    let _ = writeln!(body, "let mut m = ::hya_core::JointMatrix::<{dof}>::zeros();");
    for ((i, j, _), value) in entries.iter().zip(&outputs).filter(|((_, _, v), _)| *v != ZERO) {
        let _ = writeln!(body, "m[({i}, {j})] = {value};");
        if i != j {
            let _ = writeln!(body, "m[({j}, {i})] = {value};");
        }
    }
    body.push('m');
    Method {
        name: "mass_matrix",
        doc: "Mass matrix `M(q)` by the composite-rigid-body algorithm, unrolled.",
        arguments: "q: &::hya_core::JointVector<N>",
        returns: "::hya_core::JointMatrix",
        body,
        counts,
    }
}

fn methods(model: &TreeModel, source: InertiaSource) -> Vec<Method> {
    let dof = model.dof();
    let q = "q: &::hya_core::JointVector<N>";
    let q_qd = "q: &::hya_core::JointVector<N>, qd: &::hya_core::JointVector<N>";
    let all = RneaInputs { velocity: true, acceleration: true, gravity: true };
    vec![
        vector_method(
            "inverse_dynamics",
            "Inverse dynamics `M(q) q̈ + C(q, q̇) + G(q)` by RNEA, unrolled.",
            "q: &::hya_core::JointVector<N>, qd: &::hya_core::JointVector<N>, qdd: &::hya_core::JointVector<N>",
            dof,
            |e| rnea(e, model, all, source),
        ),
        vector_method("gravity", "Gravity torques `G(q)`.", q, dof, |e| {
            rnea(e, model, RneaInputs { velocity: false, acceleration: false, gravity: true }, source)
        }),
        vector_method("velocity_terms", "Coriolis and centripetal torques `C(q, q̇)`.", q_qd, dof, |e| {
            rnea(e, model, RneaInputs { velocity: true, acceleration: false, gravity: false }, source)
        }),
        vector_method(
            "coriolis_transpose_times_velocity",
            "`C_matᵀ q̇ = Ṁ q̇ − C` from the subtree momenta.",
            q_qd,
            dof,
            |e| coriolis_transpose(e, model, source),
        ),
        mass_matrix_method(model, source),
    ]
}

/// `frame_poses(q)`: every named frame's pose in the base, as `Transform`s from the base
/// (`E` rotates base coordinates into the frame's, `r` is its origin), traced through the same
/// folded joint transforms as the dynamics.
fn frame_poses_method(model: &TreeModel) -> (String, OpCounts) {
    let mut e = Emitter::new();
    let xforms = joint_transforms(&mut e, model.bodies());
    let mut body_poses: Vec<Xform> = Vec::with_capacity(model.dof());
    for (i, body) in model.bodies().iter().enumerate() {
        let parent = body.parent.map_or_else(Xform::identity, |p| body_poses[p]);
        let step = xforms[i].combined(&mut e);
        body_poses.push(e.compose(&parent, &step));
    }
    let frame_poses: Vec<Xform> = model
        .frames()
        .iter()
        .map(|f| {
            let body = f.body.map_or_else(Xform::identity, |b| body_poses[b]);
            e.compose(&body, &Xform::constant(&f.placement))
        })
        .collect();
    let outputs: Vec<Value> = frame_poses
        .iter()
        .flat_map(|x| {
            let (rotation, translation) = x.parts();
            rotation.iter().flatten().chain(translation.iter()).copied().collect::<Vec<_>>()
        })
        .collect();
    let Rendered { code: mut body, counts, outputs } = e.render(&outputs);
    let poses: Vec<String> = outputs
        .chunks(12)
        .map(|p| {
            format!(
                "::hya_core::spatial::Transform::from_arrays([[{}, {}, {}], [{}, {}, {}], [{}, {}, {}]], [{}, {}, {}])",
                p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], p[8], p[9], p[10], p[11]
            )
        })
        .collect();
    let _ = write!(body, "[{}]", poses.join(", "));
    (body, counts)
}

/// `impl Dynamics<N> for {type_name}` with every entry point, traced for `source`.
fn dynamics_impl(model: &TreeModel, type_name: &str, source: InertiaSource) -> (String, Vec<(&'static str, OpCounts)>) {
    let dof = model.dof();
    let methods = methods(model, source);
    let mut code = format!(
        "#[allow(clippy::approx_constant, clippy::excessive_precision, clippy::unreadable_literal, \
         clippy::let_and_return, clippy::neg_multiply, unused_variables)]\n\
         impl ::hya_core::Dynamics<{dof}> for {type_name} {{\n"
    );
    for m in &methods {
        let arguments = m.arguments.replace("<N>", &format!("<{dof}>"));
        let _ = write!(
            code,
            "/// {doc}\n#[inline]\nfn {name}(&self, {arguments}) -> {returns}<{dof}> {{\n{body}\n}}\n",
            doc = m.doc,
            name = m.name,
            returns = m.returns,
            body = m.body,
        );
    }
    code.push_str("}\n");
    (code, methods.iter().map(|m| (m.name, m.counts)).collect())
}

/// A Rust string literal holding exactly `text`: every quote, backslash, control and
/// non-printable character escaped, so that no string from a URDF can leave the literal.
fn string_literal(text: &str) -> String {
    proc_macro2::Literal::string(text).to_string()
}

/// A doc attribute whose text mentions `name` (a string from the URDF): the name is shown
/// escaped (`escape_debug`), so the text holds no line break, carriage return or other control
/// character, and it is emitted as a string literal, never spliced into a comment.
fn doc_naming(before: &str, name: &str, after: &str) -> String {
    let text = format!("{before}{}{after}", name.escape_debug());
    format!("#[doc = {}]", string_literal(&text))
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
            "{} joints: unrolled code grows faster than quadratically with the joints (50 joints: 4.7 MB of source, 84 s to compile); beyond {WARN_ABOVE_JOINTS}, consider the run-time model (hya_core::model::TreeModel)",
            model.dof()
        )
    })
}

fn check_type_name(type_name: &str) -> Result<(), GenerateError> {
    match syn::parse_str::<syn::Ident>(type_name) {
        Ok(_) => Ok(()),
        Err(_) => Err(GenerateError::TypeName(type_name.to_owned())),
    }
}

fn format(source: &str, stats: Vec<(&'static str, OpCounts)>) -> Result<Generated, GenerateError> {
    let file = syn::parse_file(source).map_err(|e| GenerateError::Syntax(e.to_string()))?;
    Ok(Generated { source: prettyplease::unparse(&file), stats })
}

/// Generates the zero-sized type `type_name` whose dynamics have every constant of `model`
/// folded in.
pub fn generate(model: &TreeModel, type_name: &str) -> Result<Generated, GenerateError> {
    check_type_name(type_name)?;
    check_size(model)?;
    let dof = model.dof();
    let names: Vec<String> = model.joint_names().map(string_literal).collect();
    let effort: Vec<String> = model
        .bodies()
        .iter()
        .map(|b| b.limits.effort.map_or("None".into(), |v| format!("Some({})", literal(v))))
        .collect();
    let (body, mut stats) = dynamics_impl(model, type_name, InertiaSource::Constant);
    let (poses, pose_counts) = frame_poses_method(model);
    stats.push(("frame_poses", pose_counts));
    let frames = model.frames().len();
    let frame_names: Vec<String> = model.frames().iter().map(|f| string_literal(&f.name)).collect();
    let source = format!(
        "{header}\n\
         /// Generated by hya-codegen: constants folded, one `sin_cos` per revolute joint, loops\n\
         /// unrolled, no allocation.\n\
         #[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]\n\
         pub struct {type_name};\n\
         impl {type_name} {{\n\
         /// Degrees of freedom.\n\
         pub const DOF: usize = {dof};\n\
         /// Joint names in the model's order.\n\
         pub const JOINT_NAMES: [&'static str; {dof}] = [{names}];\n\
         /// Effort limits from the description, N·m or N (`None` where it gives none).\n\
         pub const EFFORT_LIMITS: [Option<f64>; {dof}] = [{effort}];\n\
         /// Every link of the description, in the order of [`Self::frame_poses`].\n\
         pub const FRAME_NAMES: [&'static str; {frames}] = [{frame_names}];\n\
         /// The pose of every frame of [`Self::FRAME_NAMES`] in the base at `q`, as the transform\n\
         /// from the base to the frame (its `translation` is the frame's origin).\n\
         #[allow(clippy::approx_constant, clippy::excessive_precision, clippy::unreadable_literal, unused_variables)]\n\
         pub fn frame_poses(&self, q: &::hya_core::JointVector<{dof}>) -> [::hya_core::spatial::Transform; {frames}] {{\n\
         {poses}\n\
         }}\n\
         }}\n{body}",
        header = doc_naming(" Rigid-body dynamics of `", model.name(), &format!("` ({dof} joints).")),
        names = names.join(", "),
        effort = effort.join(", "),
        frame_names = frame_names.join(", "),
    );
    format(&source, stats)
}

/// Generates the parameter-holding type `type_name`: the kinematics of `model` folded in as in
/// [`generate`], each body's ten inertial parameters read from the type's field, so that one
/// compiled function serves any masses, centres of mass and inertias (a perturbed plant, an
/// identified model, a payload).
pub fn generate_parametric(model: &TreeModel, type_name: &str) -> Result<Generated, GenerateError> {
    check_type_name(type_name)?;
    check_size(model)?;
    let dof = model.dof();
    let (body, stats) = dynamics_impl(model, type_name, InertiaSource::Parameters);
    let source = format!(
        "{header}\n\
         /// `self.0[i]` is body `i`'s `RigidBodyInertia::parameters()`, about its frame origin.\n\
         #[derive(Debug, Clone, Copy, PartialEq)]\n\
         pub struct {type_name}(pub [[f64; 10]; {dof}]);\n\
         impl {type_name} {{\n\
         /// From each body's spatial inertia about its body frame's origin, in joint order.\n\
         pub fn new(inertias: &[::hya_core::spatial::RigidBodyInertia; {dof}]) -> Self {{\n\
         Self(core::array::from_fn(|i| inertias[i].parameters()))\n\
         }}\n\
         }}\n{body}",
        header = doc_naming(
            " Rigid-body dynamics of `",
            model.name(),
            &format!("` ({dof} joints) with the inertial parameters as data:")
        ),
    );
    format(&source, stats)
}
