//! Structured mutations of the shipped arms' URDFs: attribute values replaced by arbitrary
//! numbers (NaN, infinities, huge, tiny, negative) or strings, elements dropped or doubled.
#![no_main]

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;

#[path = "common.rs"]
mod common;

const BASES: [&str; 5] = [
    include_str!("../../robots/urdf/hya.urdf"),
    include_str!("../../robots/urdf/ur5.urdf"),
    include_str!("../../robots/urdf/panda.urdf"),
    include_str!("../../robots/urdf/iiwa14.urdf"),
    include_str!("../../robots/urdf/planar2.urdf"),
];

#[derive(Debug, Arbitrary)]
enum Value {
    Number(f64),
    Special(u8),
    Text(String),
}

#[derive(Debug, Arbitrary)]
enum Mutation {
    /// Replace the k-th attribute value.
    Attribute { index: u16, value: Value },
    /// Remove the k-th line.
    DropLine { index: u16 },
    /// Repeat the k-th line.
    DoubleLine { index: u16 },
}

#[derive(Debug, Arbitrary)]
struct Input {
    base: u8,
    mutations: Vec<Mutation>,
}

fn render(value: &Value) -> String {
    match value {
        Value::Number(x) => format!("{x:?}"),
        Value::Special(k) => {
            ["NaN", "inf", "-inf", "1e308", "-1e308", "1e-320", "0", "-0", "1e200 0 0", ""][*k as usize % 10].to_owned()
        }
        Value::Text(s) => s.replace(['"', '<', '&'], ""),
    }
}

/// The byte ranges of every `="…"` attribute value in `text`.
fn attribute_values(text: &str) -> Vec<(usize, usize)> {
    let mut spans = Vec::new();
    let mut from = 0;
    while let Some(start) = text[from..].find("=\"").map(|i| from + i + 2) {
        let Some(end) = text[start..].find('"').map(|i| start + i) else { break };
        spans.push((start, end));
        from = end + 1;
    }
    spans
}

fuzz_target!(|input: Input| {
    let mut text = BASES[input.base as usize % BASES.len()].to_owned();
    for mutation in input.mutations.iter().take(16) {
        match mutation {
            Mutation::Attribute { index, value } => {
                let spans = attribute_values(&text);
                if spans.is_empty() {
                    continue;
                }
                let (start, end) = spans[*index as usize % spans.len()];
                text.replace_range(start..end, &render(value));
            }
            Mutation::DropLine { index } | Mutation::DoubleLine { index } => {
                let mut lines: Vec<&str> = text.lines().collect();
                if lines.is_empty() {
                    continue;
                }
                let k = *index as usize % lines.len().max(1);
                if matches!(mutation, Mutation::DropLine { .. }) {
                    lines.remove(k);
                } else {
                    lines.insert(k, lines[k]);
                }
                text = lines.join("\n");
            }
        }
    }
    if let Ok(loaded) = hya_urdf::load_str(&text, "mutated.urdf") {
        common::check_loaded(&loaded);
    }
});
