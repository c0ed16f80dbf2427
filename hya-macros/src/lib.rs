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

use std::path::PathBuf;

use proc_macro::TokenStream;
use quote::quote;
use syn::parse::{Parse, ParseStream};
use syn::{Ident, LitStr, Token};

struct RobotArgs {
    name: Ident,
    path: LitStr,
}

impl Parse for RobotArgs {
    fn parse(input: ParseStream<'_>) -> syn::Result<Self> {
        let name = input.parse()?;
        input.parse::<Token![,]>()?;
        let path = input.parse()?;
        input.parse::<Option<Token![,]>>()?;
        Ok(Self { name, path })
    }
}

/// `robot!(Name, "robot.urdf")`: the robot's dynamics as a type `Name`; see the crate docs.
#[proc_macro]
pub fn robot(input: TokenStream) -> TokenStream {
    let args = syn::parse_macro_input!(input as RobotArgs);
    expand(&args).unwrap_or_else(|e| e.to_compile_error()).into()
}

fn expand(args: &RobotArgs) -> syn::Result<proc_macro2::TokenStream> {
    let error = |message: String| syn::Error::new(args.path.span(), message);
    let manifest = std::env::var_os("CARGO_MANIFEST_DIR")
        .ok_or_else(|| error("CARGO_MANIFEST_DIR is not set: build with cargo".into()))?;
    let path = PathBuf::from(manifest).join(args.path.value());
    let path = path.canonicalize().unwrap_or(path);
    let loaded = hya_codegen::load_file(&path).map_err(|e| error(e.to_string()))?;
    let generated = hya_codegen::generate(&loaded.model, &args.name.to_string()).map_err(|e| error(e.to_string()))?;
    let code: proc_macro2::TokenStream = generated.source.parse().map_err(|e| error(format!("{e}")))?;
    let tracked = path.to_string_lossy().into_owned();
    Ok(quote! {
        // Makes cargo rebuild the caller when the URDF changes.
        const _: &str = include_str!(#tracked);
        #code
    })
}
