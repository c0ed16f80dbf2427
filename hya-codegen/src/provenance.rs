//! Where a folded constant of generated code comes from: the model's numbers (a body's mass,
//! first moment, centre of mass and inertia about its frame origin, a joint's origin, gravity),
//! and products of two of them. The generator appends the explanation to each statement that
//! holds such a literal, so `0.0027519999999057617f64` reads as `Shoulder_FE I_xy`.

use std::collections::HashMap;

use hya_core::model::TreeModel;

use crate::names::comment_safe;

/// The model's numbers by value.
#[derive(Debug, Clone, Default)]
pub struct Provenance {
    known: Vec<(f64, String)>,
    by_bits: HashMap<u64, usize>,
}

impl Provenance {
    /// The numbers of `model` that generated code may hold.
    pub fn of(model: &TreeModel) -> Self {
        let mut provenance = Self::default();
        provenance.add(-model.gravity_vector().z, "g".into());
        const PARAMETERS: [&str; 10] =
            ["mass", "m·c_x", "m·c_y", "m·c_z", "I_xx", "I_yy", "I_zz", "I_xy", "I_xz", "I_yz"];
        for body in model.bodies() {
            let link = comment_safe(&body.link);
            for (value, name) in body.inertia.parameters().into_iter().zip(PARAMETERS) {
                provenance.add(value, format!("{link} {name}"));
            }
            if body.inertia.mass > 0.0 {
                for (k, axis) in ["x", "y", "z"].into_iter().enumerate() {
                    provenance.add(body.inertia.first_moment[k] / body.inertia.mass, format!("{link} c_{axis}"));
                }
            }
            let joint = comment_safe(&body.joint);
            for (k, axis) in ["x", "y", "z"].into_iter().enumerate() {
                provenance.add(body.tree_transform.translation[k], format!("joint {joint} origin {axis}"));
            }
        }
        for frame in model.frames() {
            let name = comment_safe(&frame.name);
            for (k, axis) in ["x", "y", "z"].into_iter().enumerate() {
                provenance.add(frame.placement.translation[k], format!("frame {name} origin {axis}"));
            }
        }
        provenance
    }

    /// Records `name` for `|value|`; a value several numbers share lists them all (up to three).
    fn add(&mut self, value: f64, name: String) {
        let value = value.abs();
        if value == 0.0 || value == 1.0 || !value.is_finite() {
            return;
        }
        match self.by_bits.get(&value.to_bits()) {
            Some(&i) => {
                let names = &mut self.known[i].1;
                match names.matches(" or ").count() {
                    0 | 1 => *names = format!("{names} or {name}"),
                    2 => names.push_str(" or …"),
                    _ => {}
                }
            }
            None => {
                self.by_bits.insert(value.to_bits(), self.known.len());
                self.known.push((value, name));
            }
        }
    }

    /// What `value` is: one of the model's numbers, or the product of two.
    pub fn explain(&self, value: f64) -> Option<String> {
        let value = value.abs();
        if let Some(&i) = self.by_bits.get(&value.to_bits()) {
            return Some(self.known[i].1.clone());
        }
        self.known.iter().enumerate().find_map(|(i, (a, name_a))| {
            self.known[i..].iter().find(|(b, _)| a * b == value).map(|(_, name_b)| format!("{name_a} × {name_b}"))
        })
    }

    /// The explanations of the float literals in a line of generated code, joined.
    pub fn annotate(&self, line: &str) -> Option<String> {
        let explained: Vec<String> = literals(line)
            .filter_map(|(text, value)| self.explain(value).map(|why| format!("{} = {why}", short(text))))
            .collect();
        (!explained.is_empty()).then(|| explained.join("; "))
    }
}

/// The literal's digits to 4 significant places, for the comment.
fn short(text: &str) -> String {
    let value: f64 = text.parse().unwrap_or(f64::NAN);
    format!("{value:.4e}")
}

/// Every `…f64` literal of a line: its digits and value.
fn literals(line: &str) -> impl Iterator<Item = (&str, f64)> {
    line.match_indices("f64").filter_map(move |(end, _)| {
        let start = line[..end].rfind(|c: char| !(c.is_ascii_digit() || c == '.')).map_or(0, |i| i + 1);
        let text = &line[start..end];
        let boundary = line[end + 3..].chars().next().is_none_or(|c| !(c.is_ascii_alphanumeric() || c == '_'));
        let value = text.parse::<f64>().ok().filter(|_| boundary && !text.is_empty())?;
        // An identifier ending in digits (`t12f64` cannot occur, but be sure) is not a literal.
        let before = line[..start].chars().next_back();
        before.is_none_or(|c| !(c.is_ascii_alphanumeric() || c == '_')).then_some((text, value))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn literals_are_found_and_identifiers_are_not() {
        let found: Vec<f64> = literals("let t3 = 0.5f64 * x_f64 - -2f64 + elbow_f64;").map(|(_, v)| v).collect();
        assert_eq!(found, [0.5, 2.0]);
    }

    #[test]
    fn numbers_and_products_of_two_are_explained() {
        let mut p = Provenance::default();
        p.add(9.81, "g".into());
        p.add(2.0, "arm mass".into());
        assert_eq!(p.explain(-2.0).as_deref(), Some("arm mass"));
        assert_eq!(p.explain(2.0 * 9.81).as_deref(), Some("g × arm mass"));
        assert_eq!(p.explain(0.123), None);
        assert_eq!(p.annotate("let t0 = 19.62f64 * q;").as_deref(), Some("1.9620e1 = g × arm mass"));
    }
}
