//! Arbitrary text as a URDF: the loader accepts or refuses with an error, never panics; what it
//! accepts evaluates to finite numbers and generates (or is refused by the generator).
#![no_main]

use libfuzzer_sys::fuzz_target;

#[path = "common.rs"]
mod common;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        if let Ok(loaded) = hya_urdf::load_str(text, "fuzz.urdf") {
            common::check_loaded(&loaded);
        }
    }
});
