//! Names from a URDF as hya shows them: escaped, so that no name can break a line of output, a
//! message or a generated comment.

/// `name` in printable ASCII: line breaks, control, non-ASCII and bidirectional characters,
/// quotes and backslashes escaped as Rust's `escape_default` does (`a\nb` prints as `a\\nb`).
/// The `hya` command prints URDF names this way, the loader's messages show them this way, and
/// generated code's comments hold them this way.
pub fn escape_name(name: &str) -> String {
    name.escape_default().to_string()
}
