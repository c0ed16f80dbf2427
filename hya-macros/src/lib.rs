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
//! crate is built.

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
