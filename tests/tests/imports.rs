//! No two files of a crate import each other, directly or round a longer loop: every `crate::`
//! path in a file's code (a `use`, or a path written out) is an arrow to the file that holds the
//! module it names, and the arrows of each crate form no circle. Unit tests (from `#[cfg(test)]`
//! to the end of a file), comments and the crate root (`lib.rs`, `main.rs`: the crate's face,
//! which declares every module) are left aside. And hya-sim's files import only from their own
//! layer or the ones before it, as ARCHITECTURE.md's table of layers lists them.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// A module path from the crate root, `["config", "scenario"]`.
type Module = Vec<String>;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// Every `.rs` file under `folder`, recursively.
fn rust_files(folder: &Path, into: &mut Vec<PathBuf>) {
    let entries = std::fs::read_dir(folder).unwrap_or_else(|e| panic!("{}: {e}", folder.display()));
    for entry in entries.filter_map(Result::ok) {
        let path = entry.path();
        if path.is_dir() {
            rust_files(&path, into);
        } else if path.extension().is_some_and(|x| x == "rs") {
            into.push(path);
        }
    }
}

/// The module a source file under `src` holds: `a/b.rs` and `a/b/mod.rs` are `a::b`.
fn module_of(src: &Path, file: &Path) -> Module {
    let relative = file.strip_prefix(src).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
    let mut parts: Module = relative.iter().map(|p| p.to_string_lossy().into_owned()).collect();
    let last = parts.pop().unwrap_or_default();
    match last.trim_end_matches(".rs") {
        "mod" | "lib" | "main" if parts.is_empty() || last == "mod.rs" => {}
        stem => parts.push(stem.to_owned()),
    }
    parts
}

/// A file's code without its unit tests and comments.
fn code(text: &str) -> String {
    let text = text.split("#[cfg(test)]").next().unwrap_or_default();
    text.lines().map(|line| line.split("//").next().unwrap_or_default()).collect::<Vec<_>>().join("\n")
}

/// Every module path the code names after `crate::`, with grouped imports
/// (`crate::a::{b::C, d}`) expanded.
fn crate_paths(code: &str) -> Vec<Module> {
    let mut paths = Vec::new();
    let mut rest = code;
    while let Some(at) = rest.find("crate::") {
        let before = rest[..at].chars().next_back();
        rest = &rest[at + "crate::".len()..];
        if before.is_some_and(|c| c.is_alphanumeric() || c == '_') {
            continue; // `hya_crate::` or the like: not this crate
        }
        expand(&mut Vec::new(), rest, &mut paths);
    }
    paths
}

/// Reads one path at the start of `text` below `prefix`, and each branch of a `{…}` group.
fn expand(prefix: &mut Module, text: &str, paths: &mut Vec<Module>) {
    let mut segments = prefix.clone();
    let mut rest = text;
    loop {
        let end = rest.find(|c: char| !(c.is_alphanumeric() || c == '_')).unwrap_or(rest.len());
        if end > 0 {
            segments.push(rest[..end].to_owned());
        }
        rest = &rest[end..];
        match rest.strip_prefix("::") {
            Some(after) if after.starts_with('{') => {
                for branch in group(&after[1..]) {
                    expand(&mut segments.clone(), branch.trim(), paths);
                }
                return;
            }
            Some(after) => rest = after,
            None => break,
        }
    }
    paths.push(segments);
}

/// The top-level branches of a group whose `{` has been read, up to its matching `}`.
fn group(text: &str) -> Vec<&str> {
    let (mut depth, mut start, mut branches) = (0usize, 0usize, Vec::new());
    for (i, c) in text.char_indices() {
        match c {
            '{' => depth += 1,
            '}' if depth == 0 => {
                branches.push(&text[start..i]);
                return branches;
            }
            '}' => depth -= 1,
            ',' if depth == 0 => {
                branches.push(&text[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    branches
}

/// The arrows between one crate's files, by module.
fn arrows(src: &Path) -> BTreeMap<Module, BTreeSet<Module>> {
    let mut files = Vec::new();
    rust_files(src, &mut files);
    let modules: BTreeMap<Module, PathBuf> = files.iter().map(|f| (module_of(src, f), f.clone())).collect();
    let mut arrows = BTreeMap::new();
    for (module, file) in &modules {
        if module.is_empty() {
            continue;
        }
        let text = std::fs::read_to_string(file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        let targets: BTreeSet<Module> = crate_paths(&code(&text))
            .into_iter()
            .filter_map(|path| (1..=path.len()).rev().map(|n| path[..n].to_vec()).find(|m| modules.contains_key(m)))
            .filter(|target| target != module)
            .collect();
        arrows.insert(module.clone(), targets);
    }
    arrows
}

/// A loop of arrows, if any: depth first, a module met again on the current path closes one.
fn circle(arrows: &BTreeMap<Module, BTreeSet<Module>>) -> Option<Vec<Module>> {
    fn visit(
        at: &Module,
        arrows: &BTreeMap<Module, BTreeSet<Module>>,
        path: &mut Vec<Module>,
        done: &mut BTreeSet<Module>,
    ) -> Option<Vec<Module>> {
        if let Some(start) = path.iter().position(|m| m == at) {
            return Some(path[start..].to_vec());
        }
        if !done.insert(at.clone()) {
            return None;
        }
        path.push(at.clone());
        for next in arrows.get(at).into_iter().flatten() {
            if let Some(found) = visit(next, arrows, path, done) {
                return Some(found);
            }
        }
        path.pop();
        None
    }
    let mut done = BTreeSet::new();
    arrows.keys().find_map(|start| visit(start, arrows, &mut Vec::new(), &mut done))
}

#[test]
fn no_crate_has_an_import_circle_among_its_files() {
    let mut crates = Vec::new();
    for entry in std::fs::read_dir(root()).unwrap_or_else(|e| panic!("the repository's folder: {e}")) {
        let src = entry.unwrap_or_else(|e| panic!("the repository's folder: {e}")).path().join("src");
        if src.join("lib.rs").exists() || src.join("main.rs").exists() {
            crates.push(src);
        }
    }
    assert!(crates.len() >= 8, "found only {} crates' src folders", crates.len());
    for src in crates {
        if let Some(loop_) = circle(&arrows(&src)) {
            let names: Vec<String> = loop_.iter().map(|m| m.join("::")).collect();
            panic!("{}: the files of {} import each other in a circle", src.display(), names.join(" → "));
        }
    }
}

#[test]
fn grouped_imports_are_read_branch_by_branch() {
    let paths = crate_paths("use crate::config::{scenario::{Method, Task}, settings};\nlet x = crate::plant::MAX;");
    let names: Vec<String> = paths.iter().map(|p| p.join("::")).collect();
    assert_eq!(names, ["config::scenario::Method", "config::scenario::Task", "config::settings", "plant::MAX"]);
}

#[test]
fn a_circle_is_found_and_a_tree_is_not() {
    let m = |s: &str| -> Module { s.split("::").map(String::from).collect() };
    let mut arrows: BTreeMap<Module, BTreeSet<Module>> = BTreeMap::new();
    arrows.insert(m("a"), [m("b")].into());
    arrows.insert(m("b"), [m("c")].into());
    arrows.insert(m("c"), BTreeSet::new());
    assert_eq!(circle(&arrows), None);
    arrows.insert(m("c"), [m("a")].into());
    assert_eq!(circle(&arrows).map(|c| c.len()), Some(3));
}

#[test]
fn hya_sims_files_import_only_from_their_own_layer_or_the_ones_listed_before() {
    // The layer table of ARCHITECTURE.md: rows `| `layer` | what | `file or folder` |`, lowest first.
    let text =
        std::fs::read_to_string(root().join("ARCHITECTURE.md")).unwrap_or_else(|e| panic!("ARCHITECTURE.md: {e}"));
    let start = text.find("| layer | what | files |").unwrap_or_else(|| panic!("ARCHITECTURE.md: no layer table"));
    let layers: Vec<String> = text[start..]
        .lines()
        .skip(2)
        .take_while(|line| line.starts_with('|'))
        .filter_map(|line| line.split('`').nth(1).map(String::from))
        .collect();
    assert!(layers.len() >= 8, "ARCHITECTURE.md's layer table: {layers:?}");
    // A module's layer: the one whose path is the longest start of the module's.
    let rank = |module: &Module| {
        let starts = |layer: &String| {
            let path: Vec<&str> = layer.split("::").collect();
            path.len() <= module.len() && path.iter().zip(module).all(|(a, b)| a == b)
        };
        (0..layers.len()).filter(|&i| starts(&layers[i])).max_by_key(|&i| layers[i].split("::").count())
    };
    for (from, targets) in arrows(&root().join("hya-sim/src")) {
        let from_rank = rank(&from)
            .unwrap_or_else(|| panic!("hya-sim/src: `{}` is in no layer of ARCHITECTURE.md", from.join("::")));
        for to in targets {
            let to_rank = rank(&to)
                .unwrap_or_else(|| panic!("hya-sim/src: `{}` is in no layer of ARCHITECTURE.md", to.join("::")));
            assert!(
                to_rank <= from_rank,
                "hya-sim/src: `{}` (layer `{}`) imports `{}` of the later layer `{}`",
                from.join("::"),
                layers[from_rank],
                to.join("::"),
                layers[to_rank]
            );
        }
    }
}

#[test]
fn below_the_settings_no_hya_sim_file_names_a_scenario() {
    // The plant, the sensors, the loop and its metrics take the typed settings that
    // `config::settings` makes of a scenario once (`Setup`), never the scenario itself.
    let src = root().join("hya-sim/src");
    let mut files = Vec::new();
    for folder in ["run", "plant"] {
        rust_files(&src.join(folder), &mut files);
    }
    files.extend(["analysis/metrics.rs", "analysis/running.rs", "analysis/shadow.rs"].map(|f| src.join(f)));
    for file in files {
        let text = std::fs::read_to_string(&file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        // The word `Scenario` anywhere in the code (an import, a path, a type), but for the
        // error variant `SimError::Scenario`.
        let code = code(&text);
        let word = |c: Option<char>| c.is_some_and(|c| c.is_alphanumeric() || c == '_');
        let read = code.match_indices("Scenario").any(|(at, _)| {
            let (before, after) = (&code[..at], &code[at + "Scenario".len()..]);
            !word(before.chars().next_back()) && !word(after.chars().next()) && !before.ends_with("SimError::")
        });
        assert!(!read, "{}: reads a `Scenario` below `config`", file.display());
    }
}
