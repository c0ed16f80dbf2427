//! Generates, for every robot in `robots.list`, its dynamics from `urdf/<name>.urdf` into
//! `OUT_DIR/<name>.rs` (the zero-sized `TypeName` with every constant folded, and
//! `TypeNameParametric`, which reads the inertial parameters from its field), and
//! `OUT_DIR/registry.rs`: the macro `for_each_robot!` over the list.

use std::fmt::Write;
use std::path::Path;

/// One line of `robots.list`.
struct Entry {
    name: String,
    type_name: String,
    home: Vec<f64>,
    description: String,
}

fn parse(line: &str, number: usize) -> Entry {
    let fields: Vec<&str> = line.split('|').map(str::trim).collect();
    let [head, home, description] = fields[..] else {
        panic!("robots.list line {number}: expected `name TypeName | home pose | description`")
    };
    let Some((name, type_name)) = head.split_once(char::is_whitespace) else {
        panic!("robots.list line {number}: expected `name TypeName` before the first `|`")
    };
    let home = home
        .split_whitespace()
        .map(|v| v.parse().unwrap_or_else(|_| panic!("robots.list line {number}: `{v}` is not a number")))
        .collect();
    Entry { name: name.into(), type_name: type_name.trim().into(), home, description: description.into() }
}

fn main() {
    let manifest = Path::new(env!("CARGO_MANIFEST_DIR"));
    let out = std::path::PathBuf::from(std::env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    println!("cargo:rerun-if-changed=robots.list");
    let list = std::fs::read_to_string(manifest.join("robots.list")).expect("robots.list is readable");
    let entries: Vec<Entry> = list
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'))
        .map(|(i, l)| parse(l, i + 1))
        .collect();
    let mut registry = String::new();
    for entry in &entries {
        let Entry { name, type_name, home, description } = entry;
        let urdf = manifest.join("urdf").join(format!("{name}.urdf"));
        println!("cargo:rerun-if-changed={}", urdf.display());
        let loaded = hya_urdf::load_file(&urdf).unwrap_or_else(|e| panic!("{e}"));
        let dof = loaded.model.dof();
        assert_eq!(home.len(), dof, "robots.list: {name}'s home pose has {} values for {dof} joints", home.len());
        for (body, q) in loaded.model.bodies().iter().zip(home) {
            let (lower, upper) = (body.limits.lower.unwrap_or(f64::MIN), body.limits.upper.unwrap_or(f64::MAX));
            assert!(
                (lower..=upper).contains(q),
                "robots.list: {name}'s home {q} is outside joint {}'s limits",
                body.joint
            );
        }
        let fixed = hya_codegen::generate(&loaded, type_name).unwrap_or_else(|e| panic!("{name}: {e}"));
        let parametric = hya_codegen::generate_parametric(&loaded, &format!("{type_name}Parametric"))
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let source = fixed.source + "\n" + &parametric.source;
        std::fs::write(out.join(format!("{name}.rs")), source).expect("OUT_DIR is writable");
        let home: Vec<String> = home.iter().map(|v| format!("{v:?}")).collect();
        let _ = writeln!(
            registry,
            "        {name} {type_name} {type_name}Parametric {dof} [{}] {description:?};",
            home.join(", ")
        );
    }
    let registry = format!(
        "/// Calls `$callback! {{ … }}` with one entry per shipped robot, in `robots.list` order:\n\
         /// `name Type TypeParametric dof [home pose] \"description\";`.\n\
         #[macro_export]\n\
         macro_rules! for_each_robot {{\n    ($callback:ident) => {{\n        $callback! {{\n{registry}        }}\n    }};\n}}\n"
    );
    std::fs::write(out.join("registry.rs"), registry).expect("OUT_DIR is writable");
}
