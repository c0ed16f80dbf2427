//! The one text format every row command reads and writes: a table of numbers, one row per line.
//!
//! - **Cells** are separated by commas (CSV: a cell may be quoted, `"q 1"`, with `""` for a
//!   quote inside), or, in a file whose first line that is not a comment holds no comma, by
//!   runs of spaces and tabs. One separator per file: a comma in a blank-separated file is
//!   refused with its line. Blanks around a cell are not part of it.
//! - **Comments**: a `#` outside quotes starts one, to the end of its line; blank lines are
//!   skipped.
//! - **A header** is optional: the first line that is not a comment, if its first cell is not a
//!   number. Each cell names a column, `name` or `name [unit]` (`t [s]`, `q_SAA [rad]`,
//!   `tau_SAA [N m]`); `--columns` and the commands look columns up by `name`. A unit that
//!   differs from the one a command reads (`q_SAA [deg]`) is refused, never converted.
//! - **Rows** hold finite decimal numbers, every row as many as the header names (or, without a
//!   header, as the first row holds): a row with a cell too few or too many, an empty cell
//!   (`1,,3`) or a cell that is not a number is refused with its line and column, as its values
//!   would otherwise stand under the wrong columns.
//!
//! Commands write the same format: comma-separated, a header naming every column with its unit
//! (`--no-header` leaves it out), each number in the shortest text that reads back to the same
//! `f64`. Columns are named after the model's joints: `t`, `q_J`, `qd_J`, `qdd_J`, `tau_J`
//! ([`names`]), so one command's output is the next one's input (`hya excite | hya track |
//! hya estimate`).
//!
//! Input is hostile until parsed: lines are read through a bounded buffer ([`MAX_LINE_BYTES`]),
//! rows hold at most [`MAX_ROW_VALUES`] values, and every value read or written is finite.
//! Messages show numbers in short form and echo at most [`ECHO_CHARS`] characters of what the
//! user wrote ([`echo`]).

mod columns;
mod lines;
pub mod names;
mod read;
mod write;

pub use columns::ColumnSpec;
pub use names::Column;
pub use read::Table;
pub use write::RowWriter;

use hya_core::{Clipped, Short};

use crate::CliError;

/// The longest line a row command reads, in bytes (1 MiB), newline excluded. A real row (a few
/// dozen numbers) is a few hundred bytes; a longer line is refused, naming it, as soon as its
/// first `MAX_LINE_BYTES + 1` bytes have been read, so memory stays bounded whatever the input
/// (`/dev/zero` included).
pub const MAX_LINE_BYTES: usize = 1 << 20;

/// The most values one row may hold (4096): the widest real row is `hya id`'s `3n` for an arm of
/// `n` joints, and `hya filter` keeps a filter per value of its first row, so this also caps
/// its channels (and the memory of their states).
pub const MAX_ROW_VALUES: usize = 4096;

/// The shortest sample or output interval `--dt` a row command accepts, s (1 µs).
pub const MIN_DT_S: f64 = 1e-6;

/// The longest sample or output interval `--dt` a row command accepts, s.
pub const MAX_DT_S: f64 = 1.0;

/// How many characters of a field that is not a number an error message echoes.
pub const ECHO_CHARS: usize = 40;

/// `--columns`, for every command that reads rows.
#[derive(Debug, Clone, Default, clap::Args)]
pub struct ColumnsArg {
    /// The columns to read, in the order the command reads them: header names (without their
    /// unit), positions from 1, or ranges of either, comma-separated (`t,q1-q6,tau1-tau6`,
    /// `1,2-7,14-19`, `q_SAA-q_WFE`: every column from the first to the second). Without it, a
    /// log whose header names the command's columns as hya writes them (`t`, `q_J`, `qd_J`,
    /// `qdd_J`, `tau_J` for the model's joints J) is read by those names, and any other log must
    /// hold exactly the command's columns.
    #[arg(long)]
    pub columns: Option<String>,
}

impl ColumnsArg {
    /// The parsed `--columns`, if given.
    pub fn spec(&self) -> Result<Option<ColumnSpec>, CliError> {
        self.columns.as_deref().map(ColumnSpec::parse).transpose()
    }
}

/// `--no-header`, for every command that writes rows.
#[derive(Debug, Clone, Copy, Default, clap::Args)]
pub struct HeaderArg {
    /// Write rows of numbers only, without the header line naming each column and its unit.
    #[arg(long)]
    pub no_header: bool,
}

impl HeaderArg {
    /// Whether to write the header.
    pub fn header(self) -> bool {
        !self.no_header
    }
}

/// User text for a message: quoted, control characters escaped, cut after [`ECHO_CHARS`]
/// characters with an ellipsis.
pub fn echo(text: &str) -> String {
    format!("\"{}\"", Clipped(text, ECHO_CHARS))
}

/// Checks an interval option (`--dt`): finite and within [`MIN_DT_S`] to [`MAX_DT_S`].
pub fn check_dt(option: &str, dt: f64) -> Result<f64, CliError> {
    if dt.is_finite() && (MIN_DT_S..=MAX_DT_S).contains(&dt) {
        Ok(dt)
    } else {
        Err(CliError::Input(format!(
            "{option} {}: must be between {} and {} s",
            Short(dt),
            Short(MIN_DT_S),
            Short(MAX_DT_S)
        )))
    }
}

/// `error` prefixed with `place` (`line 3`, `t = 0.5 s`) if it is an input error.
pub fn at(place: impl std::fmt::Display, error: CliError) -> CliError {
    match error {
        CliError::Input(message) => CliError::Input(format!("{place}: {message}")),
        other => other,
    }
}
