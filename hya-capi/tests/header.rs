//! The committed header `include/hya.h` is what cbindgen makes of `src/` with `cbindgen.toml`:
//! this test regenerates it and fails on any difference, so the header cannot drift from the
//! ABI. After changing the ABI, rewrite it with `HYA_WRITE_HEADER=1 cargo test -p hya-capi --test
//! header`.

use std::path::Path;

#[test]
fn committed_header_matches_the_code() {
    let crate_dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let config = cbindgen::Config::from_file(crate_dir.join("cbindgen.toml")).expect("cbindgen.toml parses");
    let bindings = cbindgen::Builder::new()
        .with_crate(crate_dir)
        .with_config(config)
        .generate()
        .expect("cbindgen reads hya-capi's sources");
    let mut generated = Vec::new();
    bindings.write(&mut generated);
    let generated = String::from_utf8(generated).expect("the header is UTF-8");

    let path = crate_dir.join("include/hya.h");
    if std::env::var_os("HYA_WRITE_HEADER").is_some() {
        std::fs::write(&path, &generated).expect("include/hya.h is writable");
    }
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        committed == generated,
        "hya-capi/include/hya.h differs from what cbindgen makes of src/; run \
         `HYA_WRITE_HEADER=1 cargo test -p hya-capi --test header` and commit the header"
    );
}
