//! The error every command returns.

use std::io;

/// A failure the user can act on: printed as `hya: MESSAGE`, exit code 2.
#[derive(Debug, thiserror::Error)]
pub enum CliError {
    /// Bad input or parameters.
    #[error("{0}")]
    Input(String),
    /// Reading stdin or writing stdout failed.
    #[error("i/o: {0}")]
    Io(#[from] io::Error),
}

impl From<hya_sim::SimError> for CliError {
    fn from(e: hya_sim::SimError) -> Self {
        CliError::Input(e.to_string())
    }
}
