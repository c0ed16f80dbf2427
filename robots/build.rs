//! Generates the dynamics of every robot in `robots.list` from `urdf/<module>.urdf` into
//! `OUT_DIR/<module>.rs`, which `src/lib.rs` includes: the zero-sized `TypeName` with every
//! constant folded, and `TypeNameParametric`, which reads the inertial parameters from its field.

use std::path::Path;

fn main() {
    let manifest = Path::new(env!("CARGO_MANIFEST_DIR"));
    let out = std::path::PathBuf::from(std::env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    println!("cargo:rerun-if-changed=robots.list");
    let list = std::fs::read_to_string(manifest.join("robots.list")).expect("robots.list is readable");
    for line in list.lines().map(str::trim).filter(|l| !l.is_empty() && !l.starts_with('#')) {
        let (module, type_name) = line.split_once(' ').expect("robots.list lines are `module TypeName`");
        let urdf = manifest.join("urdf").join(format!("{module}.urdf"));
        println!("cargo:rerun-if-changed={}", urdf.display());
        let loaded = hya_urdf::load_file(&urdf).unwrap_or_else(|e| panic!("{e}"));
        let type_name = type_name.trim();
        let fixed = hya_codegen::generate(&loaded, type_name).unwrap_or_else(|e| panic!("{module}: {e}"));
        let parametric = hya_codegen::generate_parametric(&loaded, &format!("{type_name}Parametric"))
            .unwrap_or_else(|e| panic!("{module}: {e}"));
        let source = fixed.source + "\n" + &parametric.source;
        std::fs::write(out.join(format!("{module}.rs")), source).expect("OUT_DIR is writable");
    }
}
