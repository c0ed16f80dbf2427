//! Strings from a URDF (robot, link and joint names) reach generated code only as escaped string
//! literals: a name that tries to close a comment or a literal and start code of its own stays
//! inside its literal, whatever characters it holds.
#![allow(clippy::unwrap_used)] // test helpers: a failed unwrap is a failed test

use hya_codegen::{generate, generate_parametric};
use hya_urdf::load_str;

/// XML-escaped: `&#10;` is a newline, `&#13;` a carriage return once the parser has read it.
const HOSTILE: &[&str] = &[
    "arm&#10;#[ctor] fn injected() { std::process::abort() }&#10;//",
    "arm&#13;fn injected() {}",
    "arm */ fn injected() {} /*",
    "arm&quot;; fn injected() {} const X: &amp;str = &quot;",
    "arm\\&quot;) } fn injected() { (&quot;",
    "arm\u{202E}fn injected() {}\u{2028}",
];

fn urdf(robot: &str, link: &str, joint: &str) -> String {
    format!(
        r#"<robot name="{robot}">
  <link name="base"/>
  <link name="{link}">
    <inertial><mass value="1"/><origin xyz="0.1 0 0"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
  </link>
  <joint name="{joint}" type="revolute">
    <parent link="base"/><child link="{link}"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="10" velocity="1"/>
  </joint>
</robot>"#
    )
}

/// The unescaped text the XML parser hands the loader.
fn unescaped(xml_text: &str) -> String {
    xml_text.replace("&#10;", "\n").replace("&#13;", "\r").replace("&quot;", "\"").replace("&amp;", "&")
}

/// Every string literal in `source`, in order.
fn string_literals(source: &str) -> Vec<String> {
    let tokens: proc_macro2::TokenStream = source.parse().unwrap();
    let mut out = Vec::new();
    collect(tokens, &mut out);
    out
}

fn collect(tokens: proc_macro2::TokenStream, out: &mut Vec<String>) {
    for tree in tokens {
        match tree {
            proc_macro2::TokenTree::Group(g) => collect(g.stream(), out),
            proc_macro2::TokenTree::Literal(l) => {
                if let Ok(syn::Lit::Str(s)) = syn::parse_str::<syn::Lit>(&l.to_string()) {
                    out.push(s.value());
                }
            }
            _ => {}
        }
    }
}

/// Each item's kind and the names of its members.
fn item_outline(source: &str) -> Vec<String> {
    let file = syn::parse_file(source).unwrap();
    file.items
        .iter()
        .map(|item| match item {
            syn::Item::Struct(s) => format!("struct {}", s.ident),
            syn::Item::Impl(i) => {
                let members: Vec<String> = i
                    .items
                    .iter()
                    .map(|m| match m {
                        syn::ImplItem::Fn(f) => format!("fn {}", f.sig.ident),
                        syn::ImplItem::Const(c) => format!("const {}", c.ident),
                        _ => "other".into(),
                    })
                    .collect();
                format!("impl {}", members.join(" "))
            }
            _ => "other item".into(),
        })
        .collect()
}

#[test]
fn urdf_names_stay_inside_their_literals() {
    let benign_model = load_str(&urdf("arm", "link", "joint"), "benign.urdf").unwrap();
    let benign_sources =
        [generate(&benign_model, "Arm").unwrap().source, generate_parametric(&benign_model, "ArmP").unwrap().source];
    for hostile in HOSTILE {
        let text = urdf(hostile, &format!("{hostile}_link"), &format!("{hostile}_joint"));
        let model = load_str(&text, "hostile.urdf").unwrap();
        let robot = unescaped(hostile);
        assert_eq!(model.model.name(), robot, "the loader keeps the name as written");
        let sources = [generate(&model, "Arm").unwrap().source, generate_parametric(&model, "ArmP").unwrap().source];
        for (source, benign) in sources.iter().zip(&benign_sources) {
            // The same items as for a benign name: nothing of the name's own became code.
            assert_eq!(item_outline(source), item_outline(benign), "a name left its literal:\n{source}");
            assert!(!source.contains('\r') && !source.contains('\u{202E}'), "raw control character in the source");
            let literals = string_literals(source);
            // The header names the robot, escaped.
            assert!(literals.iter().any(|l| l.contains(&robot.escape_debug().to_string())), "header lost the name");
        }
        let source = generate(&model, "Arm").unwrap().source;
        let literals = string_literals(&source);
        for name in [format!("{robot}_joint"), format!("{robot}_link")] {
            assert!(literals.contains(&name), "{name:?} is not among the literals, exactly as written");
        }
    }
}
