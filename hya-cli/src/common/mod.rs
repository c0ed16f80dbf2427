//! What every command shares: its error, and the arm it works on. (The rows it reads and writes
//! are [`crate::table`].)

mod error;
mod robot;

pub use error::CliError;
pub use robot::{load, model, scenario, urdf_text, with_body_inertias};
