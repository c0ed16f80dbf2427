//! How much the loader reads at most, so that no description can exhaust the stack, memory or
//! time of whoever loads it.
//!
//! `urdf-rs` reads XML into a tree of elements, recursively, so deeply nested XML overflows the
//! stack, and it keeps every node in memory. Before it sees any text, a check runs the
//! same XML tokenizer it uses (`RustyXML`'s, event by event, never recursing) and refuses a text
//! beyond any of these limits; [`crate::load_file`] reads at most [`MAX_FILE_BYTES`] + 1 bytes of
//! a file, whatever size the file claims (`/dev/zero` and pipes claim 0).

use crate::error::Problem;

/// Largest URDF the loader reads, in bytes (16 MiB; the shipped arms' are 6 to 14 kB).
pub const MAX_FILE_BYTES: usize = 16 * 1024 * 1024;

/// Deepest nesting of XML elements accepted, `<robot>` being depth 1 (URDFs nest 5 deep,
/// `<robot><link><visual><geometry><mesh>`; `<gazebo>` plugins a few more).
pub const MAX_XML_DEPTH: usize = 64;

/// Most XML nodes accepted: elements plus text runs, comments, CDATA sections and processing
/// instructions (the indentation between two tags is a text run). An arm takes a few hundred,
/// a chain of [`MAX_JOINTS`] joints with visuals and collisions about 45,000; at the limit
/// `urdf-rs` takes about 100 MB.
pub const MAX_XML_NODES: usize = 100_000;

/// Most XML attributes accepted, counted as `=` signs anywhere in the text (each attribute has
/// one, so this bounds them before any is parsed; `=` in comments and text counts too). A chain
/// of [`MAX_JOINTS`] joints with visuals and collisions has about 30,000; at the limit `urdf-rs`
/// takes about 60 MB.
pub const MAX_XML_ATTRIBUTES: usize = 500_000;

/// Most `<joint>` elements of a `<robot>`, of any type (fixed ones too). Loading checks the mass
/// matrix at the zero pose, O(n²) in memory and O(n³) in time; at this cap that takes well
/// under a second and a few megabytes. Generating code has a lower cap of its own
/// (`hya_codegen::MAX_JOINTS`).
pub const MAX_JOINTS: usize = 1024;

/// Most `<link>` elements of a `<robot>`: one tree of [`MAX_JOINTS`] joints has one link more.
pub const MAX_LINKS: usize = MAX_JOINTS + 1;

/// Characters handed to the tokenizer at a time (it copies its input into a queue of `char`s).
const CHUNK_BYTES: usize = 64 * 1024;

/// Refuses `text` if it is longer than [`MAX_FILE_BYTES`], holds more than
/// [`MAX_XML_ATTRIBUTES`] `=` signs, nests elements deeper than [`MAX_XML_DEPTH`], holds more
/// than [`MAX_XML_NODES`] nodes or has more than [`MAX_JOINTS`] joints or [`MAX_LINKS`] links. Malformed XML passes: `urdf-rs` reports it with the same
/// tokenizer's message, and stops where this pass stops.
pub(crate) fn check_text(text: &str) -> Result<(), Problem> {
    if text.len() > MAX_FILE_BYTES {
        return Err(Problem::TooLarge { size: Some(text.len() as u64), limit: MAX_FILE_BYTES });
    }
    too_many(text.bytes().filter(|&b| b == b'=').count(), MAX_XML_ATTRIBUTES, "XML attributes (counted as `=` signs)")?;
    let mut parser = xml::Parser::new();
    let mut counts = Counts::default();
    let mut start = 0;
    while start < text.len() {
        let mut end = (start + CHUNK_BYTES).min(text.len());
        while !text.is_char_boundary(end) {
            end += 1;
        }
        parser.feed_str(&text[start..end]);
        start = end;
        for event in parser.by_ref() {
            match event {
                Ok(event) => counts.add(&event)?,
                Err(_) => return Ok(()),
            }
        }
    }
    Ok(())
}

/// What the events so far add up to.
#[derive(Default)]
struct Counts {
    depth: usize,
    nodes: usize,
    joints: usize,
    links: usize,
}

impl Counts {
    fn add(&mut self, event: &xml::Event) -> Result<(), Problem> {
        match event {
            xml::Event::ElementStart(tag) => {
                self.depth += 1;
                if self.depth > MAX_XML_DEPTH {
                    return Err(Problem::TooDeep { limit: MAX_XML_DEPTH });
                }
                // `urdf-rs` takes a robot's links and joints from its root's children only.
                if self.depth == 2 && tag.name == "joint" {
                    self.joints += 1;
                    too_many(self.joints, MAX_JOINTS, "joints")?;
                }
                if self.depth == 2 && tag.name == "link" {
                    self.links += 1;
                    too_many(self.links, MAX_LINKS, "links")?;
                }
            }
            xml::Event::ElementEnd(_) => {
                self.depth = self.depth.saturating_sub(1);
                return Ok(());
            }
            _ => {}
        }
        self.nodes += 1;
        too_many(self.nodes, MAX_XML_NODES, "XML nodes")
    }
}

fn too_many(count: usize, limit: usize, what: &'static str) -> Result<(), Problem> {
    if count > limit {
        return Err(Problem::TooMany { what, limit });
    }
    Ok(())
}
