//! Names from a URDF as hya shows them: escaped, so that no name can break a line of output, a
//! message or a generated comment.

/// `name` in printable ASCII: line breaks, control, non-ASCII and bidirectional characters,
/// quotes and backslashes escaped as Rust's `escape_default` does (`a\nb` prints as `a\\nb`).
/// The `hya` command prints URDF names this way, the loader's messages show them this way, and
/// generated code's comments hold them this way.
pub fn escape_name(name: &str) -> String {
    name.escape_default().to_string()
}

/// How many names [`name_list`] shows before it says how many there are in all.
pub const LISTED_NAMES: usize = 12;
/// How many characters of one escaped name [`name_list`] shows.
pub const LISTED_NAME_CHARS: usize = 40;

/// Names for a message or a comment: each escaped ([`escape_name`]) and cut after
/// [`LISTED_NAME_CHARS`] characters, joined by `, `; past [`LISTED_NAMES`] names the rest are
/// counted, not shown. So a URDF of a thousand 500-character joint names cannot make a message
/// of half a megabyte, nor a name with a line break forge a line.
pub fn name_list<'a>(names: impl IntoIterator<Item = &'a str>) -> String {
    let mut shown = Vec::new();
    let mut count = 0;
    for name in names {
        count += 1;
        if count <= LISTED_NAMES {
            let escaped = escape_name(name);
            shown.push(match escaped.char_indices().nth(LISTED_NAME_CHARS) {
                Some((cut, _)) => format!("{}…", &escaped[..cut]),
                None => escaped,
            });
        }
    }
    if count > LISTED_NAMES {
        shown.push(format!("… ({count} in all)"));
    }
    shown.join(", ")
}

/// Why `model` cannot stand in for `reference` (an identified model for the nominal one), if its
/// joints are not `reference`'s, in order: `its joints [..] are not {whose} [..]`, both lists as
/// [`name_list`] shows them.
pub fn joints_differ(
    model: &hya_core::model::TreeModel,
    reference: &hya_core::model::TreeModel,
    whose: &str,
) -> Option<String> {
    if model.joint_names().eq(reference.joint_names()) {
        None
    } else {
        let (theirs, ours) = (name_list(model.joint_names()), name_list(reference.joint_names()));
        Some(format!("its joints [{theirs}] are not {whose} [{ours}]"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lists_escape_cut_and_count() {
        assert_eq!(name_list(["a", "b\n[x]"]), "a, b\\n[x]");
        let long = "y".repeat(500);
        let names: Vec<&str> = (0..1000).map(|_| long.as_str()).collect();
        let list = name_list(names);
        assert!(list.len() < 600 && list.ends_with("… (1000 in all)"), "{list}");
        assert!(!list.contains('\n'));
    }
}
