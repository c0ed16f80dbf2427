//! # hya-macros
//!
//! `robot!(Name, "path/to/robot.urdf")` generates, at compile time, a zero-sized type `Name`
//! implementing [`hya_core::Dynamics<N>`](https://docs.rs/hya-core) with the same unrolled code
//! as the shipped robots. The path is relative to the calling crate's `Cargo.toml`; the crate is
//! rebuilt when the file changes. A bad URDF is a compile error at the path, naming the problem.
//!
//! ```ignore
//! hya_macros::robot!(MyArm, "urdf/my_arm.urdf");
//!
//! use hya_core::Dynamics;
//! let tau = MyArm.gravity(&hya_core::JointVector::zeros());
//! ```
//!
//! The calling crate needs `hya-core` as a dependency (the generated code names `::hya_core`).
//!
//! `robot!(Name, urdf = "<robot …>…</robot>")` takes the description inline instead (for tests
//! and small examples). Errors name the path as written, so they read the same wherever the
//! crate is built. A bad description does not compile:
//!
//! ```compile_fail
//! // A revolute joint about a zero axis: "inline URDF: joint `j1`: axis is zero".
//! hya_macros::robot!(Bad, urdf = r#"<robot name="bad"><link name="base"/><link name="a">
//!   <inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
//!   <joint name="j1" type="revolute"><parent link="base"/><child link="a"/><axis xyz="0 0 0"/>
//!     <limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>"#);
//! ```

use std::path::PathBuf;

use proc_macro::TokenStream;
use quote::quote;
use syn::parse::{Parse, ParseStream};
use syn::{Ident, LitStr, Token};

/// Where the description comes from.
enum Source {
    /// A file, relative to the calling crate's `Cargo.toml`.
    Path(LitStr),
    /// The URDF text itself (`urdf = "…"`).
    Inline(LitStr),
}

struct RobotArgs {
    name: Ident,
    source: Source,
}

impl Parse for RobotArgs {
    fn parse(input: ParseStream<'_>) -> syn::Result<Self> {
        let name = input.parse()?;
        input.parse::<Token![,]>()?;
        let source = if input.peek(Ident) {
            let key: Ident = input.parse()?;
            if key != "urdf" {
                return Err(syn::Error::new(key.span(), "expected a path string or `urdf = \"…\"`"));
            }
            input.parse::<Token![=]>()?;
            Source::Inline(input.parse()?)
        } else {
            Source::Path(input.parse()?)
        };
        input.parse::<Option<Token![,]>>()?;
        Ok(Self { name, source })
    }
}

/// `robot!(Name, "robot.urdf")`: the robot's dynamics as a type `Name`; see the crate docs.
#[proc_macro]
pub fn robot(input: TokenStream) -> TokenStream {
    let args = syn::parse_macro_input!(input as RobotArgs);
    expand(&args).unwrap_or_else(|e| e.to_compile_error()).into()
}

fn expand(args: &RobotArgs) -> syn::Result<proc_macro2::TokenStream> {
    let (literal, tracked, loaded) = match &args.source {
        Source::Path(path) => {
            let error = |message: String| syn::Error::new(path.span(), message);
            let manifest = std::env::var_os("CARGO_MANIFEST_DIR")
                .ok_or_else(|| error("CARGO_MANIFEST_DIR is not set: build with cargo".into()))?;
            let full = PathBuf::from(manifest).join(path.value());
            let full = full.canonicalize().unwrap_or(full);
            // The error names the path as written, not where this build happens to run.
            let loaded = hya_urdf::load_file(&full).map_err(|e| error(format!("{}: {}", path.value(), e.problem)))?;
            (path, Some(full.to_string_lossy().into_owned()), loaded)
        }
        Source::Inline(text) => {
            let loaded = hya_urdf::load_str(&text.value(), "inline URDF")
                .map_err(|e| syn::Error::new(text.span(), format!("inline URDF: {}", e.problem)))?;
            (text, None, loaded)
        }
    };
    let error = |message: String| syn::Error::new(literal.span(), message);
    let generated = hya_codegen::generate(&loaded, &args.name.to_string()).map_err(|e| error(e.to_string()))?;
    let code: proc_macro2::TokenStream = generated.source.parse().map_err(|e| error(format!("{e}")))?;
    // Makes cargo rebuild the caller when the URDF file changes.
    let tracking = tracked.map(|file| quote! { const _: &str = include_str!(#file); });
    Ok(quote! {
        #tracking
        #code
    })
}

#[cfg(test)]
mod tests {
    //! The messages of bad invocations, through the macro's own parser and expansion (a
    //! `compile_fail` example in the crate docs shows they stop the build).
    use super::*;

    /// The message `robot!(<tokens>)` fails with.
    fn error_of(tokens: proc_macro2::TokenStream) -> String {
        match syn::parse2::<RobotArgs>(tokens).and_then(|args| expand(&args)) {
            Ok(_) => panic!("expanded"),
            Err(e) => e.to_string(),
        }
    }

    /// A one-link arm whose joints are `joints` (XML), inline.
    fn inline(joints: &str) -> proc_macro2::TokenStream {
        let urdf = format!(
            r#"<robot name="bad"><link name="base"/><link name="a"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>{joints}</robot>"#
        );
        quote!(Bad, urdf = #urdf)
    }

    const LIMIT: &str = r#"<limit lower="-1" upper="1" effort="1" velocity="1"/>"#;

    #[test]
    fn a_missing_child_link_is_named() {
        let joints = format!(
            r#"<joint name="j1" type="revolute"><parent link="base"/><child link="a"/><axis xyz="0 0 1"/>{LIMIT}</joint><joint name="j2" type="revolute"><parent link="a"/><child link="ghost"/><axis xyz="0 0 1"/>{LIMIT}</joint>"#
        );
        assert_eq!(error_of(inline(&joints)), "inline URDF: joint `j2`: child link `ghost` does not exist");
    }

    #[test]
    fn a_zero_axis_is_named() {
        let joints = format!(
            r#"<joint name="j1" type="revolute"><parent link="base"/><child link="a"/><axis xyz="0 0 0"/>{LIMIT}</joint>"#
        );
        assert_eq!(error_of(inline(&joints)), "inline URDF: joint `j1`: axis is zero");
    }

    #[test]
    fn a_missing_file_is_named_as_written() {
        // The operating system's own words follow; they differ between systems.
        let message = error_of(quote!(Bad, "tests/urdf/does_not_exist.urdf"));
        assert!(message.starts_with("tests/urdf/does_not_exist.urdf: cannot read: "), "{message}");
    }

    #[test]
    fn the_name_must_be_an_identifier_and_the_key_urdf() {
        assert_eq!(error_of(quote!("Bad", "tests/urdf/arm.urdf")), "expected identifier");
        assert_eq!(error_of(quote!(Bad, text = "<robot/>")), "expected a path string or `urdf = \"…\"`");
    }
}
