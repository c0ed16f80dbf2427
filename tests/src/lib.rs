//! Cross-crate integration tests of hya live in `tests/`; this library compiles the README's
//! examples as doctests, so the README cannot drift from the code.
#![doc = include_str!("../../README.md")]
