//! The `hya` command's integration tests, in one binary: each runs the built `hya` and reads
//! what it prints and writes (one binary instead of fifteen saves their links).
#![allow(clippy::unwrap_used)] // test helpers: a failed unwrap is a failed test

mod common;

mod conventions;
mod dynamics_commands;
mod estimate_command;
mod excite_command;
mod filter_command;
mod hostile_files;
mod hostile_rows;
mod hostile_urdf;
mod identify_command;
mod output_folder;
mod pipes;
mod plant_command;
mod run_shards;
mod timestamps;
mod track_command;
