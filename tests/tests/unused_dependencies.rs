//! Every dependency a workspace crate declares is used: its crate name appears in the sources
//! that kind of dependency serves (`src/` for `[dependencies]`, `build.rs` for
//! `[build-dependencies]`, tests, benches, examples and `src/` for `[dev-dependencies]`). An
//! unused dependency costs every user its build time; `cargo-udeps` needs nightly, so this test
//! stands in for it. A dependency declared only to switch on a feature carries a comment
//! `# feature only` on its line.
#![allow(clippy::unwrap_used)] // test helpers: a failed unwrap is a failed test

use std::path::{Path, PathBuf};

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The text of every `.rs` file under `path` (or of `path` itself).
fn sources(path: &Path) -> String {
    if path.is_file() {
        return std::fs::read_to_string(path).unwrap_or_default();
    }
    let Ok(entries) = std::fs::read_dir(path) else { return String::new() };
    entries
        .flatten()
        .map(|entry| {
            let path = entry.path();
            if path.is_dir() {
                sources(&path)
            } else if path.extension().is_some_and(|e| e == "rs") {
                std::fs::read_to_string(&path).unwrap_or_default()
            } else {
                String::new()
            }
        })
        .collect()
}

fn mentions(text: &str, crate_name: &str) -> bool {
    text.match_indices(crate_name).any(|(at, _)| {
        let before = text[..at].chars().next_back();
        let after = text[at + crate_name.len()..].chars().next();
        let boundary = |c: Option<char>| c.is_none_or(|c| !(c.is_ascii_alphanumeric() || c == '_'));
        boundary(before) && boundary(after)
    })
}

#[test]
fn every_declared_dependency_is_used() {
    let root = workspace();
    let manifest: toml::Table = std::fs::read_to_string(root.join("Cargo.toml")).unwrap().parse().unwrap();
    let members = manifest["workspace"]["members"].as_array().unwrap();
    let mut unused = Vec::new();
    for member in members.iter().map(|m| m.as_str().unwrap()) {
        let dir = root.join(member);
        let text = std::fs::read_to_string(dir.join("Cargo.toml")).unwrap();
        let crate_manifest: toml::Table = text.parse().unwrap();
        let library = sources(&dir.join("src"));
        let build = sources(&dir.join("build.rs"));
        let extra: String = ["tests", "benches", "examples"].iter().map(|d| sources(&dir.join(d))).collect();
        for (section, searched) in
            [("dependencies", library.clone()), ("build-dependencies", build), ("dev-dependencies", library + &extra)]
        {
            let Some(dependencies) = crate_manifest.get(section).and_then(|d| d.as_table()) else { continue };
            for name in dependencies.keys() {
                let feature_only =
                    text.lines().any(|l| l.trim_start().starts_with(name.as_str()) && l.contains("# feature only"));
                if !feature_only && !mentions(&searched, &name.replace('-', "_")) {
                    unused.push(format!("{member}: [{section}] {name}"));
                }
            }
        }
    }
    assert!(unused.is_empty(), "declared but never named in the sources they serve:\n{}", unused.join("\n"));
}
