//! What the loader refuses ([`LoadError`]) and what it accepts with a remark ([`Warning`]).

use hya_core::Short;
use thiserror::Error;

use crate::name::escape_name;

/// A robot description that could not be loaded: the file, and the problem in it.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("{file}: {problem}")]
pub struct LoadError {
    /// The file (or other source) the description came from.
    pub file: String,
    /// What is wrong with it.
    pub problem: Problem,
}

impl LoadError {
    pub(crate) fn new(source: &str, problem: Problem) -> Self {
        Self { file: source.to_owned(), problem }
    }
}

/// One problem in a robot description, naming the joint or link at fault.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum Problem {
    /// The file could not be read.
    #[error("cannot read: {message}")]
    Read {
        /// The operating system's message.
        message: String,
    },
    /// The description is larger than the loader reads ([`crate::MAX_FILE_BYTES`]).
    #[error("{}: larger than the loader's limit of {} MiB ({limit} bytes, hya_urdf::MAX_FILE_BYTES)", size.map_or_else(|| "more bytes".to_owned(), |s| format!("{s} bytes")), limit >> 20)]
    TooLarge {
        /// The size, where known (a file's claimed or a text's real size); `None` when reading
        /// stopped at the limit.
        size: Option<u64>,
        /// The limit, bytes.
        limit: usize,
    },
    /// XML elements nested deeper than the loader accepts ([`crate::MAX_XML_DEPTH`]).
    #[error("XML elements nested more than {limit} deep: beyond the loader's limit (hya_urdf::MAX_XML_DEPTH)")]
    TooDeep {
        /// The deepest nesting accepted.
        limit: usize,
    },
    /// More joints, links, XML nodes or attributes than the loader accepts ([`crate::MAX_JOINTS`],
    /// [`crate::MAX_LINKS`], [`crate::MAX_XML_NODES`], [`crate::MAX_XML_ATTRIBUTES`]).
    #[error("more than {limit} {what}: beyond the loader's limit (hya_urdf::{})", limit_name(what))]
    TooMany {
        /// `joints`, `links`, `XML nodes` or `XML attributes (counted as `=` signs)`.
        what: &'static str,
        /// The most accepted.
        limit: usize,
    },
    /// The XML is not a URDF `urdf-rs` can parse.
    #[error("not a valid URDF: {message}")]
    Parse {
        /// The parser's message.
        message: String,
    },
    /// Two links share a name.
    #[error("link name `{link}` is used twice", link = escape_name(link))]
    DuplicateLink {
        /// The name.
        link: String,
    },
    /// Two joints share a name.
    #[error("joint name `{joint}` is used twice", joint = escape_name(joint))]
    DuplicateJoint {
        /// The name.
        joint: String,
    },
    /// A joint names a link that does not exist.
    #[error("joint `{joint}`: {role} link `{link}` does not exist", link = escape_name(link), joint = escape_name(joint))]
    UnknownLink {
        /// The joint.
        joint: String,
        /// `parent` or `child`.
        role: &'static str,
        /// The missing link's name.
        link: String,
    },
    /// A link is the child of two joints.
    #[error("link `{link}` is the child of two joints, `{}` and `{}`", escape_name(&joints[0]), escape_name(&joints[1]), link = escape_name(link))]
    SeveralParents {
        /// The link.
        link: String,
        /// The two joints.
        joints: [String; 2],
    },
    /// More than one link has no parent.
    #[error("several root links: {}; a model must be one tree", links.iter().map(|l| escape_name(l)).collect::<Vec<_>>().join(", "))]
    SeveralRoots {
        /// The parentless links.
        links: Vec<String>,
    },
    /// The joints form a cycle.
    #[error("link `{link}` lies on a cycle of joints (not reachable from a single root)", link = escape_name(link))]
    Cycle {
        /// A link on the cycle.
        link: String,
    },
    /// A joint type hya does not handle (yet).
    #[error("joint `{joint}`: {kind} joints are not supported", joint = escape_name(joint))]
    UnsupportedJoint {
        /// The joint.
        joint: String,
        /// Its type.
        kind: &'static str,
    },
    /// A joint's axis is the zero vector.
    #[error("joint `{joint}`: axis is zero", joint = escape_name(joint))]
    ZeroAxis {
        /// The joint.
        joint: String,
    },
    /// A number is NaN or infinite.
    #[error("{element}: {field} is {value}, not a finite number")]
    NonFinite {
        /// Where (`joint `j1` origin`, `link `l2` inertial`, ...).
        element: String,
        /// Which attribute.
        field: &'static str,
        /// The value.
        value: f64,
    },
    /// A link's mass is negative.
    #[error("link `{link}`: negative mass {} kg", Short(*mass), link = escape_name(link))]
    NegativeMass {
        /// The link.
        link: String,
        /// The mass.
        mass: f64,
    },
    /// A link's inertia tensor has a negative principal moment.
    #[error("link `{link}`: inertia has a negative principal moment {} kg·m²", Short(*moment), link = escape_name(link))]
    NegativePrincipalMoment {
        /// The link.
        link: String,
        /// The smallest principal moment.
        moment: f64,
    },
    /// A magnitude no robot has (a unit mistake or a corrupted file).
    #[error("{element}: {field} = {value:e} is beyond ±{limit:e}: no robot has that (check the units)")]
    Absurd {
        /// The element (`link `x` inertial`, `joint `y` origin`).
        element: String,
        /// The attribute.
        field: &'static str,
        /// The value.
        value: f64,
        /// The largest magnitude accepted.
        limit: f64,
    },
    /// A positive mass too small to be a body.
    #[error("link `{link}`: mass {} kg is positive but below 1e-9 kg; write 0 for a massless link", Short(*mass), link = escape_name(link))]
    TinyMass {
        /// The link.
        link: String,
        /// The mass, kg.
        mass: f64,
    },
    /// A joint that moves mass only along its own axis.
    #[error("joint `{joint}`: its subtree has no inertia about the joint's axis (M = {inertia:e} at q = 0), so the mass matrix is singular", joint = escape_name(joint))]
    SingularJoint {
        /// The joint.
        joint: String,
        /// Its diagonal entry of the mass matrix at `q = 0`, kg·m² or kg.
        inertia: f64,
    },
    /// A mass matrix at `q = 0` that is singular though every diagonal entry is not: the joint's
    /// motion moves no mass that the joints before it do not already move (two coaxial joints
    /// with only massless links between them, for one).
    #[error("joint `{joint}`: the mass matrix at q = 0 is singular here (Cholesky pivot {pivot:.3e} against diagonal {diagonal:.3e}): the joint moves no mass the joints before it do not (coaxial joints with no mass between them?)", joint = escape_name(joint))]
    NotPositiveDefinite {
        /// The joint whose Cholesky pivot failed.
        joint: String,
        /// The pivot left for it after the joints before it, kg·m² or kg.
        pivot: f64,
        /// Its diagonal entry of the mass matrix, kg·m² or kg.
        diagonal: f64,
    },
    /// A revolute or prismatic joint whose lower limit is above its upper limit.
    #[error("joint `{joint}`: lower limit {} is above upper limit {}", Short(*lower), Short(*upper), joint = escape_name(joint))]
    InvertedLimits {
        /// The joint.
        joint: String,
        /// The lower limit, rad or m.
        lower: f64,
        /// The upper limit, rad or m.
        upper: f64,
    },
    /// A revolute or prismatic joint whose lower and upper limits are equal (and not both 0,
    /// which reads as "no position limits": an omitted `lower` and `upper` reads as 0).
    #[error("joint `{joint}`: lower and upper limits are both {}: the joint cannot move (make it fixed)", Short(*value), joint = escape_name(joint))]
    EqualLimits {
        /// The joint.
        joint: String,
        /// Both limits, rad or m.
        value: f64,
    },
    /// The robot, a link or a joint has an empty name (nothing could name it in messages,
    /// outputs or generated code).
    #[error("{element} has an empty name")]
    EmptyName {
        /// Which: `the robot`, `link number 3`, `joint number 2 (from `a` to `b`)`.
        element: String,
    },
    /// A moving joint whose whole subtree carries no mass: the mass matrix would be singular.
    #[error("joint `{joint}` moves no mass at all (its whole subtree is massless)", joint = escape_name(joint))]
    MasslessJoint {
        /// The joint.
        joint: String,
    },
    /// The description has no revolute, continuous or prismatic joint.
    #[error("no moving joint: nothing to control")]
    NoMovingJoint,
    /// The model's own consistency check failed (a loader bug if it ever shows).
    #[error("inconsistent model: {message}")]
    Model {
        /// The model's message.
        message: String,
    },
}

/// The constant that sets the limit on `what`, as [`Problem::TooMany`] names it.
fn limit_name(what: &str) -> &'static str {
    match what {
        "joints" => "MAX_JOINTS",
        "links" => "MAX_LINKS, one more than MAX_JOINTS",
        "XML attributes (counted as `=` signs)" => "MAX_XML_ATTRIBUTES",
        _ => "MAX_XML_NODES",
    }
}

/// Something odd the loader accepted.
#[derive(Debug, Clone, PartialEq)]
pub enum Warning {
    /// Principal moments `a ≤ b ≤ c` with `a + b < c`: no real mass distribution has them, but
    /// real descriptions do (HyA's wrist among them), so the model is kept.
    TriangleInequality {
        /// The link.
        link: String,
        /// Its principal moments, ascending, kg·m².
        moments: [f64; 3],
    },
}

impl std::fmt::Display for Warning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Warning::TriangleInequality { link, moments: [a, b, c] } => write!(
                f,
                "link `{}`: principal moments ({a:.6}, {b:.6}, {c:.6}) kg·m² violate the triangle inequality",
                escape_name(link)
            ),
        }
    }
}
