//! Models at the edge: a joint that meets no inertia is refused with an error, never a panic,
//! by the loader and, handed such a model anyway, by the generator;
//! names that collide once numbered still give each generated value its own identifier.
#![allow(clippy::unwrap_used)] // test helpers: a failed unwrap is a failed test

use hya_codegen::{generate, generate_parametric, GenerateError};
use hya_core::model::TreeModel;
use hya_core::spatial::RigidBodyInertia;
use hya_urdf::{load_str, LoadedModel, Problem, Source};

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

/// Two collinear prismatic joints, `first` moving a massless `carriage` that `second` slides
/// along the same axis: `D_1 = 0` at every pose. `carriage_mass` gives the carriage a body so
/// that the loader accepts it.
fn slides(carriage_mass: Option<f64>) -> String {
    let carriage = carriage_mass.map_or_else(|| r#"<link name="carriage"/>"#.to_owned(), |m| link("carriage", m));
    format!(
        r#"<robot name="slides"><link name="base"/>{carriage}{}{}{}</robot>"#,
        link("slider", 1.0),
        joint("first", "prismatic", "base", "carriage", "1 0 0"),
        joint("second", "prismatic", "carriage", "slider", "1 0 0"),
    )
}

#[test]
fn the_loader_refuses_coaxial_joints_with_no_mass_between_them_naming_the_joint() {
    // Every M_ii is positive, but M at q = 0 is singular: `second` moves only what `first` does.
    let refused = load_str(&slides(None), "slides.urdf").unwrap_err();
    assert_eq!(refused.file, "slides.urdf");
    match &refused.problem {
        Problem::NotPositiveDefinite { joint, pivot, diagonal } => {
            assert_eq!(joint, "second");
            assert!(*diagonal > 0.0 && pivot.abs() < 1e-10 * diagonal, "pivot {pivot:e}, diagonal {diagonal:e}");
        }
        other => panic!("expected a non-positive-definite mass matrix, got {other:?}"),
    }
    let message = refused.to_string();
    assert!(message.contains("joint `second`") && message.contains("singular"), "{message}");
}

#[test]
fn a_joint_without_inertia_along_its_axis_is_an_error_not_a_panic() {
    // The loader no longer hands the generator such a model, so build it by hand: load the
    // slides with a massive carriage, then take the carriage's inertia away again.
    let massive = load_str(&slides(Some(1.0)), "slides.urdf").unwrap();
    let mut bodies = massive.model.bodies().to_vec();
    assert_eq!((bodies[0].joint.as_str(), bodies[0].link.as_str()), ("first", "carriage"));
    bodies[0].inertia = RigidBodyInertia::zero();
    let model = TreeModel::new(massive.model.name(), bodies, massive.model.frames().to_vec())
        .unwrap()
        .with_gravity(massive.model.gravity_vector());
    let degenerate = LoadedModel {
        model,
        warnings: Vec::new(),
        source: Source { file: "slides.urdf".to_owned(), sha256: massive.source.sha256.clone() },
    };
    // The model really is the degenerate one: its mass matrix is singular.
    let mass = degenerate.model.mass_matrix(&[0.0, 0.0]).unwrap();
    assert!((mass[(0, 0)] * mass[(1, 1)] - mass[(0, 1)] * mass[(1, 0)]).abs() < 1e-12, "{mass}");
    // The massive version generates; the degenerate one is refused by the generator itself.
    assert!(generate(&massive, "Slides").is_ok());
    match generate(&degenerate, "Slides") {
        Err(GenerateError::NonFinite { function, .. }) => assert_eq!(function, "forward_dynamics"),
        other => panic!("expected a non-finite constant, got {:?}", other.map(|g| g.stats)),
    }
}

/// The `let` bindings of every function in `source`, with the function's name (a kernel's by
/// its marker: `InverseDynamics`), descending into the anonymous `const` block that holds the
/// kernels and the trait's implementation.
fn bindings(source: &str) -> Vec<(String, Vec<String>)> {
    fn walk(items: &[syn::Item], out: &mut Vec<(String, Vec<String>)>) {
        for item in items {
            match item {
                syn::Item::Impl(block) => {
                    // `impl Kernel<kernels::Marker, …> for Type`: named by its marker.
                    let marker =
                        block.trait_.as_ref().and_then(|(_, path, _)| match &path.segments.last()?.arguments {
                            syn::PathArguments::AngleBracketed(arguments) => match arguments.args.first()? {
                                syn::GenericArgument::Type(syn::Type::Path(t)) => {
                                    Some(t.path.segments.last()?.ident.to_string())
                                }
                                _ => None,
                            },
                            _ => None,
                        });
                    for member in &block.items {
                        if let syn::ImplItem::Fn(f) = member {
                            let mut names = Vec::new();
                            collect(&f.block, &mut names);
                            out.push((marker.clone().unwrap_or_else(|| f.sig.ident.to_string()), names));
                        }
                    }
                }
                syn::Item::Const(constant) => {
                    if let syn::Expr::Block(block) = constant.expr.as_ref() {
                        let inner: Vec<syn::Item> = block
                            .block
                            .stmts
                            .iter()
                            .filter_map(|s| match s {
                                syn::Stmt::Item(item) => Some(item.clone()),
                                _ => None,
                            })
                            .collect();
                        walk(&inner, out);
                    }
                }
                _ => {}
            }
        }
    }
    let file = syn::parse_file(source).unwrap();
    let mut out = Vec::new();
    walk(&file.items, &mut out);
    out
}

/// The names each statement defines. A block's `let (a, b) = { …; (a, b) }` only hands on what
/// its statements defined, so it is not counted.
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
            if function == "InverseDynamics" {
                assert!(names.len() > 10, "{function}: no definitions read");
            }
        }
        assert!(bindings(&source).iter().any(|(f, _)| f == "InverseDynamics"), "the kernels were not read");
    }
}
