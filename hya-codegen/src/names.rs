//! What generated code calls its values: joint inputs by joint (`q_sfe`, `s_sfe`, `c_sfe`),
//! body quantities by link and component (`elbow_fe_v_wz`, `wrist_r_f_nx`), outputs by joint.
//!
//! URDF names become identifiers by keeping ASCII letters and digits (lower-cased) and turning
//! every other run of characters into `_`; a name left empty or starting with a digit gets its
//! index, and a name already taken gets the first free `_1`, `_2`, … ([`unique_name`]), in the
//! fragments and again in each function's identifiers. Names reach comments only `escape_default`ed, so
//! no URDF string can end a comment.

use std::collections::HashSet;

use hya_core::model::TreeModel;
use hya_core::scalar::{Label, Pass, Quantity};
use proc_macro2::{Ident, Span};

use crate::trace::{Emitter, Op};

/// How the generated code names labelled values and marks passes.
pub trait Naming {
    /// The identifier for a labelled value (made unique by the renderer).
    fn label(&self, label: Label) -> String;
    /// The comment text opening `body`'s `pass`.
    fn pass(&self, body: usize, pass: Pass) -> String;
}

/// Identifiers for the statements that are read: inputs by their names, labelled statements
/// by `names` (made unique), the rest `t0, t1, …`; `None` for the others.
pub(crate) fn identifiers(
    emitter: &Emitter,
    ops: &[Op],
    live: &[bool],
    read: &[bool],
    names: &dyn Naming,
) -> Vec<Option<Ident>> {
    let mut used = HashSet::new();
    let mut temporaries = 0;
    let mut idents = vec![None; ops.len()];
    for (id, op) in ops.iter().enumerate().filter(|(id, _)| live[*id] && read[*id]) {
        let wanted = match (op, emitter.labels.get(&id)) {
            (Op::Input(name, _), _) => name.clone(),
            (_, Some(label)) => names.label(*label),
            _ => {
                temporaries += 1;
                format!("t{}", temporaries - 1)
            }
        };
        idents[id] = Some(Ident::new(&unique_name(&mut used, wanted), Span::call_site()));
    }
    idents
}

/// `name` as a lower-case identifier fragment; `None` if nothing usable is left.
fn identifier_fragment(name: &str) -> Option<String> {
    let mut out = String::new();
    for c in name.chars() {
        if c.is_ascii_alphanumeric() {
            out.push(c.to_ascii_lowercase());
        } else if !out.ends_with('_') {
            out.push('_');
        }
    }
    let trimmed = out.trim_matches('_');
    (!trimmed.is_empty() && !trimmed.starts_with(|c: char| c.is_ascii_digit())).then(|| trimmed.to_owned())
}

/// `wanted`, or the first of `wanted_1`, `wanted_2`, … that `taken` does not hold; recorded in
/// `taken`. Every name it returns is distinct from every other it returned.
pub fn unique_name(taken: &mut HashSet<String>, wanted: String) -> String {
    let mut candidate = wanted.clone();
    let mut k = 0;
    while taken.contains(&candidate) {
        k += 1;
        candidate = format!("{wanted}_{k}");
    }
    taken.insert(candidate.clone());
    candidate
}

/// One fragment per name, distinct: `fallback{i}` where a name gives none.
fn unique_fragments<'a>(names: impl Iterator<Item = &'a str>, fallback: &str) -> Vec<String> {
    let mut taken = HashSet::new();
    names
        .enumerate()
        .map(|(i, name)| unique_name(&mut taken, identifier_fragment(name).unwrap_or_else(|| format!("{fallback}{i}"))))
        .collect()
}

/// A URDF name safe inside a `//` comment: printable ASCII, everything else escaped
/// ([`hya_urdf::escape_name`], as the `hya` command prints names).
pub fn comment_safe(name: &str) -> String {
    hya_urdf::escape_name(name)
}

/// What a generated function's joint-space output is called.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Output {
    /// A vector, `{prefix}_{joint}`.
    Vector(&'static str),
    /// The mass matrix, `m_{row joint}_{column joint}` (the column in the label's component).
    Matrix,
}

/// Names for one robot's generated functions.
#[derive(Debug, Clone)]
pub struct Names {
    joints: Vec<String>,
    links: Vec<String>,
    joint_names: Vec<String>,
    link_names: Vec<String>,
    output: Output,
}

const MOTION: [&str; 6] = ["wx", "wy", "wz", "vx", "vy", "vz"];
const FORCE: [&str; 6] = ["nx", "ny", "nz", "fx", "fy", "fz"];

impl Names {
    /// Names for `model`'s joints and bodies.
    pub fn new(model: &TreeModel) -> Self {
        let bodies = model.bodies();
        Self {
            joints: unique_fragments(bodies.iter().map(|b| b.joint.as_str()), "joint"),
            links: unique_fragments(bodies.iter().map(|b| b.link.as_str()), "link"),
            joint_names: bodies.iter().map(|b| comment_safe(&b.joint)).collect(),
            link_names: bodies.iter().map(|b| comment_safe(&b.link)).collect(),
            output: Output::Vector("out"),
        }
    }

    /// The same names with the outputs called as `output` says.
    pub fn with_output(&self, output: Output) -> Self {
        Self { output, ..self.clone() }
    }

    /// `{prefix}_{joint}` for joint `i`: the name of an input such as `q_sfe`.
    pub fn joint_input(&self, prefix: &str, i: usize) -> String {
        format!("{prefix}_{}", self.joints[i])
    }

    /// `{link}_{suffix}` for body `i`: the name of a parameter such as `elbow_m`.
    pub fn body_input(&self, i: usize, suffix: &str) -> String {
        format!("{}_{suffix}", self.links[i])
    }
}

impl Naming for Names {
    fn label(&self, label: Label) -> String {
        let (joint, link) = (&self.joints[label.body], &self.links[label.body]);
        let component = usize::from(label.component);
        match label.quantity {
            Quantity::Sine | Quantity::Cosine | Quantity::JointInertia | Quantity::JointForce => {
                format!("{}_{joint}", label.quantity.short_name())
            }
            Quantity::Joint => match self.output {
                Output::Vector(prefix) => format!("{prefix}_{joint}"),
                Output::Matrix => format!("m_{joint}_{}", self.joints.get(component).map_or("", String::as_str)),
            },
            Quantity::Velocity | Quantity::Acceleration => {
                format!("{link}_{}_{}", label.quantity.short_name(), MOTION[component % 6])
            }
            Quantity::Force | Quantity::Bias | Quantity::InertiaTimesAxis => {
                format!("{link}_{}_{}", label.quantity.short_name(), FORCE[component % 6])
            }
        }
    }

    fn pass(&self, body: usize, pass: Pass) -> String {
        let what = match pass {
            Pass::Forward => "base to tip",
            Pass::Backward => "tip to base",
            Pass::Final => "base to tip, last pass",
        };
        format!("── link `{}`, joint `{}` ({what})", self.link_names[body], self.joint_names[body])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn urdf_names_become_distinct_identifier_fragments() {
        let names = ["Elbow_FE", "wrist-roll 2", "2nd", "", "Elbow FE", "\u{202E}x"];
        assert_eq!(
            unique_fragments(names.into_iter(), "j"),
            ["elbow_fe", "wrist_roll_2", "j2", "j3", "elbow_fe_1", "x"]
        );
        // A numbered name never meets a name that was written that way.
        assert_eq!(unique_fragments(["a", "a", "a_1", "A"].into_iter(), "j"), ["a", "a_1", "a_1_1", "a_2"]);
    }

    #[test]
    fn comment_text_cannot_hold_a_line_break() {
        let safe = comment_safe("a\nb\r\u{2028}*/");
        assert!(safe.chars().all(|c| c.is_ascii_graphic() || c == ' '), "{safe}");
    }
}
