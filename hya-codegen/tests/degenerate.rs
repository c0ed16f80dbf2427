//! Models at the edge: a joint that meets no inertia is refused with an error, never a panic;
//! names that collide once numbered still give each generated value its own identifier.
#![allow(clippy::unwrap_used)] // test helpers: a failed unwrap is a failed test

use hya_codegen::{generate, generate_parametric, GenerateError};
use hya_urdf::load_str;

fn link(name: &str, mass: f64) -> String {
    format!(
        r#"<link name="{name}"><inertial><mass value="{mass}"/><origin xyz="0.1 0.02 0"/><inertia ixx="0.01" iyy="0.02" izz="0.03" ixy="0" ixz="0" iyz="0"/></inertial></link>"#
    )
}

fn joint(name: &str, kind: &str, parent: &str, child: &str, axis: &str) -> String {
    format!(
        r#"<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/><origin xyz="0.3 0 0.1" rpy="0.2 0 0"/><axis xyz="{axis}"/><limit lower="-1" upper="1" effort="10" velocity="1"/></joint>"#
    )
}

#[test]
fn a_joint_without_inertia_along_its_axis_is_an_error_not_a_panic() {
    // Two collinear prismatic joints, the first carrying nothing: `D_1 = 0` at every pose.
    let urdf = format!(
        r#"<robot name="slides"><link name="base"/><link name="carriage"/>{}{}{}</robot>"#,
        link("slider", 1.0),
        joint("first", "prismatic", "base", "carriage", "1 0 0"),
        joint("second", "prismatic", "carriage", "slider", "1 0 0"),
    );
    // The loader accepts it (every M_ii is positive); the generator must refuse it.
    let loaded = load_str(&urdf, "slides.urdf").unwrap();
    match generate(&loaded, "Slides") {
        Err(GenerateError::NonFinite { function, .. }) => assert_eq!(function, "forward_dynamics"),
        other => panic!("expected a non-finite constant, got {:?}", other.map(|g| g.stats)),
    }
}

/// The `let` bindings of every function in `source`, with the function's name.
fn bindings(source: &str) -> Vec<(String, Vec<String>)> {
    let file = syn::parse_file(source).unwrap();
    let mut out = Vec::new();
    for item in file.items {
        if let syn::Item::Impl(block) = item {
            for member in block.items {
                if let syn::ImplItem::Fn(f) = member {
                    let mut names = Vec::new();
                    collect(&f.block, &mut names);
                    out.push((f.sig.ident.to_string(), names));
                }
            }
        }
    }
    out
}

/// The names each statement defines. A block's `let (a, b) = { …; (a, b) }` only hands on what
/// its statements defined, so it is not counted; of the two variants of a function,
/// `match with_fma(|| { fused }) { Some(values) => values, None => { plain } }`, which define
/// the same names, the plain one is read.
fn collect(block: &syn::Block, names: &mut Vec<String>) {
    for statement in &block.stmts {
        let syn::Stmt::Local(local) = statement else { continue };
        match local.init.as_ref().map(|init| init.expr.as_ref()) {
            Some(syn::Expr::Block(inner)) => collect(&inner.block, names),
            Some(syn::Expr::Match(variants)) => {
                for arm in &variants.arms {
                    if let syn::Expr::Block(plain) = arm.body.as_ref() {
                        collect(&plain.block, names);
                    }
                }
            }
            _ => pattern(&local.pat, names),
        }
    }
}

fn pattern(pat: &syn::Pat, names: &mut Vec<String>) {
    match pat {
        syn::Pat::Ident(i) => names.push(i.ident.to_string()),
        syn::Pat::Tuple(t) => t.elems.iter().for_each(|p| pattern(p, names)),
        _ => {}
    }
}

#[test]
fn every_generated_value_has_its_own_name_even_when_names_collide_once_numbered() {
    // `w` and `w_1` as joints, `W` as a link: `c_w`, `cv_w`, `w_1_v_wx`… must all stay distinct.
    let urdf = format!(
        r#"<robot name="clash"><link name="base"/>{}{}{}{}{}{}</robot>"#,
        link("r", 2.0),
        link("W", 1.5),
        link("w_1", 1.0),
        joint("r", "revolute", "base", "r", "0 0.6 0.8"),
        joint("w_1", "revolute", "r", "W", "0.6 0.8 0"),
        joint("w", "revolute", "W", "w_1", "0.8 0 0.6"),
    );
    let loaded = load_str(&urdf, "clash.urdf").unwrap();
    for source in [generate(&loaded, "Clash").unwrap().source, generate_parametric(&loaded, "ClashP").unwrap().source] {
        for (function, names) in bindings(&source) {
            let mut seen = std::collections::HashSet::new();
            for name in names.iter().filter(|n| n.as_str() != "_" && n.as_str() != "m") {
                let count = names.iter().filter(|n| *n == name).count();
                assert!(seen.insert(name.clone()), "{function}: `{name}` is defined {count} times");
            }
            if function == "inverse_dynamics" {
                assert!(names.len() > 10, "{function}: no definitions read");
            }
        }
    }
}
