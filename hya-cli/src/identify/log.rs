//! The log `hya identify` reads: its table, in rows `[t] q τ`, fed to
//! [`hya_ident::log::LogFilter`], which filters them into samples `(q̂, q̂̇, q̂̈, τ̂)` (see there
//! for the filters, gaps, settling and the spacing of samples).

use std::io::BufRead;

use hya_core::dispatch::ForJoints;
use hya_core::FilterParams;
use hya_ident::log::{LogFilter, Timing};

use crate::table::names::{self, Joints, Unit};
use crate::table::{ColumnSpec, Table};
use crate::CliError;

/// How the log is laid out and filtered.
pub struct Layout {
    /// The filters, at the log's nominal sample time.
    pub params: FilterParams,
    /// Rows start with their time, s.
    pub timestamps: bool,
    /// With timestamps: the longest step that is not a gap, s.
    pub max_step_s: f64,
    /// The columns to read (t, q, τ), if not the whole row.
    pub columns: Option<ColumnSpec>,
    /// The nominal step is to be taken from the log (`--timestamps` without `--dt`), and the gap
    /// limit too unless `--max-step` gave it.
    pub step_from_log: Option<Option<f64>>,
    /// The model's joints, for the columns' names and units.
    pub joints: Joints,
}

/// The samples taken from a log, and how it was read.
pub struct Filtered {
    /// The samples, their times, the rows read and the gaps.
    pub log: hya_ident::log::Filtered,
    /// The nominal step the filters were designed at, s.
    pub dt_s: f64,
    /// The longest step that is not a gap, s.
    pub max_step_s: f64,
}

/// Filtering a log for an arm of `N` joints ([`ForJoints`]).
pub struct Filter<'a, R> {
    /// The rows.
    pub input: R,
    /// Their layout.
    pub layout: &'a Layout,
}

impl<R: BufRead> ForJoints for Filter<'_, R> {
    type Output = Result<Filtered, CliError>;
    fn call<const N: usize>(self) -> Self::Output {
        filter::<N>(self.input, self.layout)
    }
}

/// Reads the table and feeds its rows to [`hya_ident::log::LogFilter`], which filters them
/// (and refuses a row with the words Python's `identify` uses too; here with its line).
fn filter<const N: usize>(input: impl BufRead, layout: &Layout) -> Result<Filtered, CliError> {
    let offset = usize::from(layout.timestamps);
    let what = format!(
        "{}the {N} joint angles q (rad), then the {N} joint torques τ (N·m)",
        if layout.timestamps { "the time t (s), then " } else { "" }
    );
    let wanted = (layout.timestamps.then(names::time).into_iter())
        .chain(layout.joints.columns("q", Unit::Position))
        .chain(layout.joints.columns("tau", Unit::Effort))
        .collect();
    let mut log = Table::new(input, layout.columns.clone(), wanted, what)?;
    let (params, max_step_s) = match layout.step_from_log {
        None => (layout.params, layout.max_step_s),
        Some(max_step) => log.adopt_nominal_step(&layout.params, max_step)?,
    };
    let timing = match layout.timestamps {
        true => Timing::Stamped { max_step_s },
        false => Timing::Fixed,
    };
    let mut filter = LogFilter::<N>::new(params, timing).map_err(|e| CliError::Input(format!("--max-step: {e}")))?;
    while let Some(line) = log.next_line() {
        let line = line?;
        let values = log.values();
        let t = if layout.timestamps { values[0] } else { f64::NAN };
        filter
            .push(t, &values[offset..offset + N], &values[offset + N..offset + 2 * N])
            .map_err(|e| CliError::Input(format!("line {line}: {e}")))?;
    }
    Ok(Filtered { log: filter.finish(), dt_s: params.dt_s(), max_step_s })
}
