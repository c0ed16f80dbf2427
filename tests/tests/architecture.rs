//! ARCHITECTURE.md's drawing of the crates against their manifests: every arrow drawn is a
//! dependency (`─►`) or a build dependency (`═►`) in `cargo metadata` (and in
//! `hya-py/Cargo.toml`, outside the workspace), and every dependency between hya's crates is
//! reached by the arrows; and every repository path the README and ARCHITECTURE.md cite exists.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

type Edges = BTreeSet<(String, String)>;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The repository's file `path`.
fn read(path: &str) -> String {
    std::fs::read_to_string(root().join(path)).unwrap_or_else(|e| panic!("{path}: {e}"))
}

/// hya's crates' dependencies on each other: (normal, build).
fn manifests() -> (Edges, Edges) {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let output = std::process::Command::new(cargo)
        .args(["metadata", "--format-version", "1", "--no-deps", "--offline"])
        .current_dir(root())
        .output()
        .expect("cargo metadata runs");
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let metadata: serde_json::Value = serde_json::from_slice(&output.stdout).expect("cargo metadata's JSON");
    let packages = metadata["packages"].as_array().expect("packages");
    let ours: BTreeSet<String> = packages
        .iter()
        .filter_map(|p| p["name"].as_str())
        .filter(|n| n.starts_with("hya-"))
        .map(String::from)
        .collect();
    let (mut normal, mut build) = (Edges::new(), Edges::new());
    for package in packages {
        let Some(name) = package["name"].as_str().filter(|n| ours.contains(*n) && *n != "hya-tests") else { continue };
        for dependency in package["dependencies"].as_array().into_iter().flatten() {
            let Some(to) = dependency["name"].as_str().filter(|d| ours.contains(*d)) else { continue };
            match dependency["kind"].as_str() {
                None => normal.insert((name.to_owned(), to.to_owned())),
                Some("build") => build.insert((name.to_owned(), to.to_owned())),
                Some(_) => false,
            };
        }
    }
    // hya-py is built by maturin, outside the workspace: its own manifest's path dependencies.
    let py: toml::Value = read("hya-py/Cargo.toml").parse().unwrap_or_else(|e| panic!("hya-py/Cargo.toml: {e}"));
    let dependencies = py["dependencies"].as_table().unwrap_or_else(|| panic!("hya-py/Cargo.toml: no [dependencies]"));
    for (to, spec) in dependencies {
        if spec.get("path").is_some() {
            normal.insert(("hya-py".to_owned(), to.clone()));
        }
    }
    (normal, build)
}

/// The arrows of ARCHITECTURE.md's drawing: (normal, build).
fn drawing() -> (Edges, Edges) {
    let text = read("ARCHITECTURE.md");
    let block = text.split("```text").nth(1).and_then(|rest| rest.split("```").next()).expect("a text drawing");
    let crates = |group: &str| -> Vec<String> {
        group.split([',', ' ', '(']).filter(|w| w.starts_with("hya-")).map(String::from).collect()
    };
    let (mut normal, mut build) = (Edges::new(), Edges::new());
    for line in block.lines() {
        let (arrow, edges) = if line.contains('═') { ("═►", &mut build) } else { ("─►", &mut normal) };
        // A comment after the arrows, in parentheses, names no crate of the drawing.
        let line = line.split('(').next().unwrap_or_default();
        let groups: Vec<Vec<String>> = line.split(arrow).map(crates).collect();
        for pair in groups.windows(2) {
            for from in &pair[0] {
                for to in &pair[1] {
                    edges.insert((from.clone(), to.clone()));
                }
            }
        }
    }
    (normal, build)
}

/// Every crate reachable from `from` along `edges`.
fn reach(edges: &Edges, from: &str) -> BTreeSet<String> {
    let next: BTreeMap<&str, Vec<&str>> = edges.iter().fold(BTreeMap::new(), |mut m, (a, b)| {
        m.entry(a.as_str()).or_default().push(b.as_str());
        m
    });
    let (mut seen, mut todo) = (BTreeSet::new(), vec![from.to_owned()]);
    while let Some(c) = todo.pop() {
        for n in next.get(c.as_str()).into_iter().flatten() {
            if seen.insert((*n).to_owned()) {
                todo.push((*n).to_owned());
            }
        }
    }
    seen
}

#[test]
fn the_drawing_of_the_crates_matches_their_manifests() {
    let ((normal, build), (drawn, drawn_build)) = (manifests(), drawing());
    assert!(!drawn.is_empty(), "the drawing has arrows");
    for (from, to) in &drawn {
        assert!(
            normal.contains(&(from.clone(), to.clone())),
            "ARCHITECTURE.md draws {from} ─► {to}, which is no dependency"
        );
    }
    for (from, to) in &drawn_build {
        assert!(
            build.contains(&(from.clone(), to.clone())),
            "ARCHITECTURE.md draws {from} ═► {to}, which is no build dependency"
        );
    }
    for (from, to) in &normal {
        assert!(reach(&drawn, from).contains(to), "{from} depends on {to}; no arrow of ARCHITECTURE.md reaches it");
    }
    let all: Edges = drawn.union(&drawn_build).cloned().collect();
    for (from, to) in &build {
        assert!(reach(&all, from).contains(to), "{from} builds with {to}; no arrow of ARCHITECTURE.md reaches it");
    }
}

#[test]
fn every_path_the_readme_and_architecture_cite_exists() {
    // Back-quoted paths that start at one of the repository's own folders.
    let tops: Vec<String> = std::fs::read_dir(root())
        .unwrap_or_else(|e| panic!("the repository's folder: {e}"))
        .filter_map(|e| e.ok())
        .filter(|e| e.path().is_dir())
        .filter_map(|e| e.file_name().into_string().ok())
        .filter(|n| !n.starts_with('.') && n != "target")
        .collect();
    for file in ["README.md", "ARCHITECTURE.md"] {
        let text = read(file);
        for cited in text.split('`').skip(1).step_by(2) {
            let Some((top, _)) = cited.split_once('/') else { continue };
            if !tops.iter().any(|t| t == top) || cited.contains([' ', '*', '<']) {
                continue;
            }
            assert!(root().join(cited).exists(), "{file} cites `{cited}`, which does not exist");
        }
    }
}
