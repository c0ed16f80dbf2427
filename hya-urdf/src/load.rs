//! URDF to a validated [`TreeModel`].
//!
//! `urdf-rs` parses the XML but accepts many descriptions that make no physical sense; every such
//! problem is refused here with a [`LoadError`] naming the file and the joint or link. Fixed
//! joints are merged into their parent body (inertia combined by the parallel-axis theorem),
//! joint axes are normalised, and the joint order is the tree's depth-first order from the root,
//! children in file order.

use std::collections::HashMap;
use std::path::Path;

use hya_core::model::{Body, Frame, JointKind, JointLimits, TreeModel};
use hya_core::spatial::{roll_pitch_yaw, RigidBodyInertia, Transform};
use nalgebra::{Matrix3, Vector3};
use urdf_rs::{JointType, Robot};

use crate::error::{LoadError, Problem, Warning};
use crate::limits::{check_text, MAX_FILE_BYTES};
use crate::name::escape_name;

/// A loaded model and what the loader noticed but accepted.
#[derive(Debug, Clone)]
pub struct LoadedModel {
    /// The validated model.
    pub model: TreeModel,
    /// Accepted oddities, such as a violated triangle inequality of principal moments.
    pub warnings: Vec<Warning>,
    /// Where the description came from.
    pub source: Source,
}

/// The description a model was loaded from, as generated code's header names it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Source {
    /// The file's name (without its directory), or what the caller called the text.
    pub file: String,
    /// SHA-256 of the text, lower-case hex.
    pub sha256: String,
}

impl Source {
    fn of(text: &str, source: &str) -> Self {
        use sha2::Digest;
        let file =
            Path::new(source).file_name().map_or_else(|| source.to_owned(), |f| f.to_string_lossy().into_owned());
        let sha256 = sha2::Sha256::digest(text.as_bytes()).iter().map(|b| format!("{b:02x}")).collect();
        Self { file, sha256 }
    }
}

/// Reads and validates the URDF file at `path`: at most [`MAX_FILE_BYTES`] bytes, whatever size
/// the file claims, then as [`load_str`].
pub fn load_file(path: impl AsRef<Path>) -> Result<LoadedModel, LoadError> {
    let path = path.as_ref();
    load_str(&read_file(path)?, &path.display().to_string())
}

/// The URDF file's text, as [`load_file`] reads it (at most [`MAX_FILE_BYTES`]): for a caller
/// that keeps the text beside the model (to write it back with other inertias).
pub fn read_file(path: impl AsRef<Path>) -> Result<String, LoadError> {
    let path = path.as_ref();
    read_bounded(path).map_err(|problem| LoadError::new(&path.display().to_string(), problem))
}

/// The file's text: a regular file of at most [`MAX_FILE_BYTES`] ([`crate::file::read_text`]).
fn read_bounded(path: &Path) -> Result<String, Problem> {
    crate::file::read_text(path, MAX_FILE_BYTES as u64).map_err(|e| match e {
        crate::file::ReadError::TooLarge { size, .. } => Problem::TooLarge { size, limit: MAX_FILE_BYTES },
        crate::file::ReadError::Io(message) => Problem::Read { message },
        other => Problem::Read { message: other.to_string() },
    })
}

/// Validates URDF text; `source` names it in errors (a file path, usually). Text beyond the
/// limits of [`crate::limits`] (size, XML nesting and nodes, joints, links) is refused before it
/// is parsed.
pub fn load_str(text: &str, source: &str) -> Result<LoadedModel, LoadError> {
    check_text(text).map_err(|problem| LoadError::new(source, problem))?;
    let robot = urdf_rs::read_from_string(text)
        .map_err(|e| LoadError::new(source, Problem::Parse { message: e.to_string() }))?;
    let mut loaded = build(&robot).map_err(|problem| LoadError::new(source, problem))?;
    loaded.source = Source::of(text, source);
    Ok(loaded)
}

fn build(robot: &Robot) -> Result<LoadedModel, Problem> {
    check_names(robot)?;
    let links =
        index_unique(robot.links.iter().map(|l| l.name.as_str()), |name| Problem::DuplicateLink { link: name })?;
    index_unique(robot.joints.iter().map(|j| j.name.as_str()), |name| Problem::DuplicateJoint { joint: name })?;
    let mut parent_joint: Vec<Option<usize>> = vec![None; robot.links.len()];
    let mut children: Vec<Vec<usize>> = vec![Vec::new(); robot.links.len()];
    for (j, joint) in robot.joints.iter().enumerate() {
        check_joint_type(joint)?;
        let find = |link: &str, role: &'static str| {
            links.get(link).copied().ok_or_else(|| Problem::UnknownLink {
                joint: joint.name.clone(),
                role,
                link: link.to_owned(),
            })
        };
        let parent = find(&joint.parent.link, "parent")?;
        let child = find(&joint.child.link, "child")?;
        if let Some(previous) = parent_joint[child] {
            return Err(Problem::SeveralParents {
                link: joint.child.link.clone(),
                joints: [robot.joints[previous].name.clone(), joint.name.clone()],
            });
        }
        parent_joint[child] = Some(j);
        children[parent].push(j);
    }
    let roots: Vec<usize> = (0..robot.links.len()).filter(|&l| parent_joint[l].is_none()).collect();
    let root = match roots.as_slice() {
        [root] => *root,
        [] => {
            return Err(robot.links.first().map_or(Problem::NoMovingJoint, |l| Problem::Cycle { link: l.name.clone() }))
        }
        several => {
            return Err(Problem::SeveralRoots { links: several.iter().map(|&l| robot.links[l].name.clone()).collect() })
        }
    };

    let mut builder = TreeBuilder {
        robot,
        bodies: Vec::new(),
        frames: Vec::new(),
        reached: vec![false; robot.links.len()],
        warnings: Vec::new(),
    };
    builder.attach_link(root, None, Transform::identity())?;
    let mut stack: Vec<(usize, Option<usize>, Transform)> =
        children[root].iter().rev().map(|&j| (j, None, Transform::identity())).collect();
    while let Some((j, body, parent_placement)) = stack.pop() {
        let joint = &robot.joints[j];
        let child = links[joint.child.link.as_str()];
        let origin =
            parent_placement.then(&pose(&joint.origin, || format!("joint `{}` origin", escape_name(&joint.name)))?);
        let (child_body, child_placement) = match joint.joint_type {
            JointType::Fixed => (body, origin),
            _ => (Some(builder.add_body(j, body, origin)?), Transform::identity()),
        };
        builder.attach_link(child, child_body, child_placement)?;
        stack.extend(children[child].iter().rev().map(|&c| (c, child_body, child_placement)));
    }
    // Stack order visits every link reachable from the root; the rest sit on a cycle.
    if let Some(orphan) = builder.reached.iter().position(|reached| !reached) {
        return Err(Problem::Cycle { link: robot.links[orphan].name.clone() });
    }
    builder.finish()
}

/// Refuses an empty robot, link or joint name.
fn check_names(robot: &Robot) -> Result<(), Problem> {
    let element = if robot.name.is_empty() {
        "the robot".to_owned()
    } else if let Some(i) = robot.links.iter().position(|l| l.name.is_empty()) {
        format!("link number {} in the file", i + 1)
    } else if let Some((i, j)) = robot.joints.iter().enumerate().find(|(_, j)| j.name.is_empty()) {
        format!(
            "joint number {} in the file (from `{}` to `{}`)",
            i + 1,
            escape_name(&j.parent.link),
            escape_name(&j.child.link)
        )
    } else {
        return Ok(());
    };
    Err(Problem::EmptyName { element })
}

/// Name → index, refusing the first name that appears twice.
fn index_unique<'a>(
    names: impl Iterator<Item = &'a str>,
    duplicate: impl Fn(String) -> Problem,
) -> Result<HashMap<&'a str, usize>, Problem> {
    let mut index = HashMap::new();
    for (i, name) in names.enumerate() {
        if index.insert(name, i).is_some() {
            return Err(duplicate(name.to_owned()));
        }
    }
    Ok(index)
}

fn check_joint_type(joint: &urdf_rs::Joint) -> Result<(), Problem> {
    let unsupported = match joint.joint_type {
        JointType::Floating => "floating (fixed-base models only)",
        JointType::Planar => "planar (fixed-base models only)",
        JointType::Spherical => "spherical",
        _ if joint.mimic.is_some() => "mimic",
        _ => return Ok(()),
    };
    Err(Problem::UnsupportedJoint { joint: joint.name.clone(), kind: unsupported })
}

/// `<origin xyz rpy>` as the transform from the parent frame to the placed frame.
fn pose(origin: &urdf_rs::Pose, what: impl Fn() -> String) -> Result<Transform, Problem> {
    let xyz = finite_vector(&origin.xyz, "xyz", &what)?;
    plausible(xyz.as_slice(), "xyz", MAX_LENGTH_M, &what)?;
    let rpy = finite_vector(&origin.rpy, "rpy", &what)?;
    plausible(rpy.as_slice(), "rpy", 1e3, &what)?;
    Ok(Transform::from_pose(roll_pitch_yaw(&rpy), xyz))
}

/// Largest accepted length in a description, m (origins, centres of mass).
const MAX_LENGTH_M: f64 = 1e3;
/// Largest accepted link mass, kg.
const MAX_MASS_KG: f64 = 1e5;
/// Largest accepted inertia entry, kg·m².
const MAX_INERTIA_KG_M2: f64 = 1e5;
/// Smallest positive link mass, kg (below it, a rounding remnant rather than a body).
const MIN_MASS_KG: f64 = 1e-9;
/// A joint whose subtree's inertia about its axis is below this (kg·m² or kg) at `q = 0`
/// makes the mass matrix singular.
const MIN_JOINT_INERTIA: f64 = 1e-12;

fn finite_vector(v: &[f64; 3], field: &'static str, what: &impl Fn() -> String) -> Result<Vector3<f64>, Problem> {
    match v.iter().find(|x| !x.is_finite()) {
        None => Ok(Vector3::from(*v)),
        Some(&value) => Err(Problem::NonFinite { element: what(), field, value }),
    }
}

/// `Ok` if every entry is at most `limit` in magnitude.
fn plausible(values: &[f64], field: &'static str, limit: f64, what: &impl Fn() -> String) -> Result<(), Problem> {
    match values.iter().find(|x| x.abs() > limit) {
        None => Ok(()),
        Some(&value) => Err(Problem::Absurd { element: what(), field, value, limit }),
    }
}

struct TreeBuilder<'r> {
    robot: &'r Robot,
    bodies: Vec<Body>,
    frames: Vec<Frame>,
    /// Per link: attached as a frame yet.
    reached: Vec<bool>,
    warnings: Vec<Warning>,
}

impl TreeBuilder<'_> {
    /// A new body moved by joint `j`, whose joint frame sits at `origin` in the parent body.
    fn add_body(&mut self, j: usize, parent: Option<usize>, origin: Transform) -> Result<usize, Problem> {
        let joint = &self.robot.joints[j];
        let what = || format!("joint `{}` axis", escape_name(&joint.name));
        let axis = finite_vector(&joint.axis.xyz, "xyz", &what)?;
        let length = axis.norm();
        if length < 1e-12 {
            return Err(Problem::ZeroAxis { joint: joint.name.clone() });
        }
        let kind = if joint.joint_type == JointType::Prismatic { JointKind::Prismatic } else { JointKind::Revolute };
        self.bodies.push(Body {
            link: joint.child.link.clone(),
            joint: joint.name.clone(),
            parent,
            kind,
            axis: axis / length,
            tree_transform: origin,
            inertia: RigidBodyInertia::zero(),
            limits: limits(joint)?,
        });
        Ok(self.bodies.len() - 1)
    }

    /// Records link `l` as a frame of `body` at `placement`, adding its inertia to the body.
    fn attach_link(&mut self, l: usize, body: Option<usize>, placement: Transform) -> Result<(), Problem> {
        let link = &self.robot.links[l];
        let inertia = self.link_inertia(link)?;
        if let Some(b) = body {
            self.bodies[b].inertia += inertia.expressed_in_parent(&placement);
        }
        self.frames.push(Frame { name: link.name.clone(), body, placement });
        self.reached[l] = true;
        Ok(())
    }

    /// The link's `<inertial>` about its own frame's origin, after checking it.
    fn link_inertia(&mut self, link: &urdf_rs::Link) -> Result<RigidBodyInertia, Problem> {
        let inertial = &link.inertial;
        let what = || format!("link `{}` inertial", escape_name(&link.name));
        let mass = inertial.mass.value;
        if !mass.is_finite() {
            return Err(Problem::NonFinite { element: what(), field: "mass", value: mass });
        }
        if mass < 0.0 {
            return Err(Problem::NegativeMass { link: link.name.clone(), mass });
        }
        if mass > 0.0 && mass < MIN_MASS_KG {
            return Err(Problem::TinyMass { link: link.name.clone(), mass });
        }
        plausible(&[mass], "mass", MAX_MASS_KG, &what)?;
        let i = &inertial.inertia;
        let entries = [("ixx", i.ixx), ("iyy", i.iyy), ("izz", i.izz), ("ixy", i.ixy), ("ixz", i.ixz), ("iyz", i.iyz)];
        if let Some(&(field, value)) = entries.iter().find(|(_, v)| !v.is_finite()) {
            return Err(Problem::NonFinite { element: what(), field, value });
        }
        if let Some(&(field, value)) = entries.iter().find(|(_, v)| v.abs() > MAX_INERTIA_KG_M2) {
            return Err(Problem::Absurd { element: what(), field, value, limit: MAX_INERTIA_KG_M2 });
        }
        let tensor = Matrix3::new(i.ixx, i.ixy, i.ixz, i.ixy, i.iyy, i.iyz, i.ixz, i.iyz, i.izz);
        let mut moments = tensor.symmetric_eigenvalues();
        moments.as_mut_slice().sort_by(f64::total_cmp);
        let scale = moments.amax().max(f64::MIN_POSITIVE);
        if moments[0] < -1e-9 * scale {
            return Err(Problem::NegativePrincipalMoment { link: link.name.clone(), moment: moments[0] });
        }
        if moments[0] + moments[1] < moments[2] * (1.0 - 1e-9) {
            self.warnings.push(Warning::TriangleInequality { link: link.name.clone(), moments: moments.into() });
        }
        let com_frame = pose(&inertial.origin, what)?;
        let about_com = com_frame.orientation() * tensor * com_frame.rotation;
        Ok(RigidBodyInertia::from_centre_of_mass(mass, com_frame.translation, about_com))
    }

    fn finish(self) -> Result<LoadedModel, Problem> {
        if self.bodies.is_empty() {
            return Err(Problem::NoMovingJoint);
        }
        // A joint whose whole subtree is massless makes the mass matrix singular.
        let mut subtree_moves_mass: Vec<bool> = self.bodies.iter().map(|b| !b.inertia.is_zero()).collect();
        for (i, body) in self.bodies.iter().enumerate().rev() {
            if let (Some(p), true) = (body.parent, subtree_moves_mass[i]) {
                subtree_moves_mass[p] = true;
            }
        }
        if let Some(i) = subtree_moves_mass.iter().position(|moves| !moves) {
            return Err(Problem::MasslessJoint { joint: self.bodies[i].joint.clone() });
        }
        let model = TreeModel::new(self.robot.name.clone(), self.bodies, self.frames)
            .map_err(|e| Problem::Model { message: e.to_string() })?;
        // Mass on a joint's axis only (a point mass on a revolute axis) still leaves M singular.
        let mass = model.mass_matrix(&vec![0.0; model.dof()]).map_err(|e| Problem::Model { message: e.to_string() })?;
        if let Some(i) = (0..model.dof()).find(|&i| mass[(i, i)].is_nan() || mass[(i, i)] < MIN_JOINT_INERTIA) {
            return Err(Problem::SingularJoint { joint: model.bodies()[i].joint.clone(), inertia: mass[(i, i)] });
        }
        // Each diagonal entry alone is fine; the whole matrix must be positive definite too.
        if let Err((i, pivot, diagonal)) = cholesky_pivots(mass) {
            return Err(Problem::NotPositiveDefinite { joint: model.bodies()[i].joint.clone(), pivot, diagonal });
        }
        Ok(LoadedModel {
            model,
            warnings: self.warnings,
            source: Source { file: String::new(), sha256: String::new() },
        })
    }
}

/// A Cholesky pivot below this fraction of its diagonal entry means a singular mass matrix
/// (rounding leaves about 1e-16 of it where two joints move exactly the same masses).
const MIN_RELATIVE_PIVOT: f64 = 1e-10;

/// Factors the symmetric `m` in place (its upper triangle becomes `U`, `m = Uᵀ U`, column by
/// column so that every dot product runs over contiguous memory); `Err((i, pivot, diagonal))` at
/// the first joint whose pivot is below [`MIN_RELATIVE_PIVOT`] of its diagonal entry (or NaN).
fn cholesky_pivots(mut m: nalgebra::DMatrix<f64>) -> Result<(), (usize, f64, f64)> {
    let n = m.nrows();
    let a = m.as_mut_slice();
    for k in 0..n {
        // Column k's rows 0..k hold U's entries above the diagonal, done already.
        let (done, rest) = a.split_at_mut((k + 1) * n);
        let column_k = &mut done[k * n..];
        let diagonal = column_k[k];
        let pivot = diagonal - column_k[..k].iter().map(|u| u * u).sum::<f64>();
        if pivot.is_nan() || pivot <= MIN_RELATIVE_PIVOT * diagonal {
            return Err((k, pivot, diagonal));
        }
        let root = pivot.sqrt();
        column_k[k] = root;
        for column_i in rest.chunks_exact_mut(n) {
            let dot: f64 = column_k[..k].iter().zip(&column_i[..k]).map(|(u, v)| u * v).sum();
            column_i[k] = (column_i[k] - dot) / root;
        }
    }
    Ok(())
}

/// The joint's `<limit>`; `urdf-rs` fills an absent element with zeros, which means "no limits".
fn limits(joint: &urdf_rs::Joint) -> Result<JointLimits, Problem> {
    let l = &joint.limit;
    if [l.lower, l.upper, l.effort, l.velocity].iter().any(|v| v.is_nan()) {
        return Err(Problem::NonFinite {
            element: format!("joint `{}` limit", escape_name(&joint.name)),
            field: "limit",
            value: f64::NAN,
        });
    }
    if l.lower == 0.0 && l.upper == 0.0 && l.effort == 0.0 && l.velocity == 0.0 {
        return Ok(JointLimits::default());
    }
    let finite = |v: f64| v.is_finite().then_some(v);
    // `lower = upper = 0` is also what an omitted `lower` and `upper` read as: no position limits.
    let bounded = joint.joint_type != JointType::Continuous && !(l.lower == 0.0 && l.upper == 0.0);
    if bounded && l.lower > l.upper {
        return Err(Problem::InvertedLimits { joint: joint.name.clone(), lower: l.lower, upper: l.upper });
    }
    if bounded && l.lower == l.upper {
        return Err(Problem::EqualLimits { joint: joint.name.clone(), value: l.lower });
    }
    Ok(JointLimits {
        lower: finite(l.lower).filter(|_| bounded),
        upper: finite(l.upper).filter(|_| bounded),
        velocity: finite(l.velocity).filter(|v| *v > 0.0),
        effort: finite(l.effort).filter(|v| *v > 0.0),
    })
}
