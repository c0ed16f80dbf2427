//! Records what built the `hya` binary, for the report's header: the git commit (with `-dirty`
//! for uncommitted changes, or "not a git checkout"), rustc's version, the profile and the flags.

use std::process::Command;

fn output(program: &str, args: &[&str]) -> Option<String> {
    let out = Command::new(program).args(args).output().ok().filter(|o| o.status.success())?;
    Some(String::from_utf8_lossy(&out.stdout).trim().to_owned()).filter(|s| !s.is_empty())
}

fn main() {
    let commit = match output("git", &["rev-parse", "--short=12", "HEAD"]) {
        Some(hash) => {
            let dirty = output("git", &["status", "--porcelain", "--untracked-files=no"]).is_some();
            if dirty {
                format!("{hash}-dirty")
            } else {
                hash
            }
        }
        None => "not a git checkout".to_owned(),
    };
    let rustc = std::env::var("RUSTC").unwrap_or_else(|_| "rustc".into());
    let version = output(&rustc, &["--version"]).unwrap_or_else(|| "unknown rustc".into());
    let flags = std::env::var("CARGO_ENCODED_RUSTFLAGS").unwrap_or_default().replace('\x1f', " ");
    println!("cargo:rustc-env=HYA_BUILD_COMMIT={commit}");
    println!("cargo:rustc-env=HYA_BUILD_RUSTC={version}");
    println!("cargo:rustc-env=HYA_BUILD_PROFILE={}", std::env::var("PROFILE").unwrap_or_default());
    println!("cargo:rustc-env=HYA_BUILD_RUSTFLAGS={}", if flags.is_empty() { "none".into() } else { flags });
    for path in ["../.git/HEAD", "../.git/index", "../.git/refs"] {
        println!("cargo:rerun-if-changed={path}");
    }
}
