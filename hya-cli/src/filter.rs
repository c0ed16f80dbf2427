//! `hya filter`: the third-order filter over rows of samples.

use std::io::{BufRead, Write};

use hya_core::{FilterParams, JointVector, Short, ThirdOrderFilter};

use crate::table::{self, Column, ColumnsArg, HeaderArg, RowWriter, Table};
use crate::CliError;

/// Parameters of `hya filter`.
#[derive(Debug, clap::Args)]
pub struct FilterArgs {
    /// Damping ratio ζ of the second-order factor.
    #[arg(long, default_value_t = 0.8)]
    zeta: f64,
    /// Corner frequency ω1 of the first-order factor, rad/s.
    #[arg(long, default_value_t = 50.0)]
    omega1: f64,
    /// Natural frequency ω2 of the second-order factor, rad/s.
    #[arg(long, default_value_t = 50.0)]
    omega2: f64,
    /// Sample time, s.
    #[arg(long, default_value_t = 0.001)]
    dt: f64,
    #[command(flatten)]
    columns: ColumnsArg,
    #[command(flatten)]
    header: HeaderArg,
}

/// The filter parameters of `hya filter` and `hya estimate`: `dt` within
/// [`table::MIN_DT_S`]–[`table::MAX_DT_S`] (a row command's sample interval), then hya-core's
/// checks (the same for Python and the C ABI); messages name the option and its value.
pub fn params(zeta: f64, omega1: f64, omega2: f64, dt: f64) -> Result<FilterParams, CliError> {
    // --dt first: a step beyond its range would otherwise be blamed on the frequency it
    // multiplies (`--dt 1000` once read "--omega1 50: must be such that it times dt_s …").
    table::check_dt("--dt", dt)?;
    let params = FilterParams::new(zeta, omega1, omega2, dt).map_err(|e| match e {
        hya_core::Error::InvalidParameter { name, value, requirement } => {
            let option = match name {
                "zeta" => "--zeta",
                "omega1_rad_s" => "--omega1",
                "omega2_rad_s" => "--omega2",
                _ => "--dt",
            };
            let requirement = requirement.replace("dt_s", "--dt");
            let step = match option {
                "--omega1" | "--omega2" => format!(" (--dt {})", Short(dt)),
                _ => String::new(),
            };
            CliError::Input(format!("{option} {}: must be {requirement}{step}", Short(value)))
        }
        other => CliError::Input(format!("filter parameters: {}", other)),
    })?;
    Ok(params)
}

/// The output columns for channels named `channels` (the header's, else `u1`, `u2`, …): all
/// `x1`, then all `x2` (per second), then all `x3` (per second squared), in the channels' unit.
fn output_columns(channels: Option<Vec<Column>>, count: usize) -> Vec<Column> {
    let channels = channels.unwrap_or_else(|| (1..=count).map(|k| Column::bare(format!("u{k}"))).collect());
    let mut columns = Vec::with_capacity(3 * count);
    for (state, per) in [("x1", ""), ("x2", "/s"), ("x3", "/s^2")] {
        columns.extend(channels.iter().map(|c| Column {
            name: format!("{state}_{}", c.name),
            unit: c.unit.as_ref().map(|u| format!("{u}{per}")),
        }));
    }
    columns
}

/// Filters every row of `input` and writes `x1…, x2…, x3…` per row to `output`.
pub fn run(args: &FilterArgs, input: impl BufRead, output: &mut impl Write) -> Result<(), CliError> {
    let params = params(args.zeta, args.omega1, args.omega2, args.dt)?;
    let mut table = Table::any(input, args.columns.spec()?);
    let mut channels: Vec<ThirdOrderFilter<1>> = Vec::new();
    let mut writer = RowWriter::unnamed(output, args.header.header());
    while let Some(line) = table.next_line() {
        let line = line?;
        let at_line = |e: hya_core::Error| CliError::Input(format!("line {line}: {e}"));
        if channels.is_empty() {
            channels = table
                .values()
                .iter()
                .map(|&u0| ThirdOrderFilter::new(params, JointVector::from([u0])))
                .collect::<Result<_, _>>()
                .map_err(at_line)?;
            writer.name_columns(output_columns(table.header_columns(), channels.len()));
        } else {
            for (filter, &u) in channels.iter_mut().zip(table.values()) {
                filter.step(&JointVector::from([u])).map_err(at_line)?;
            }
        }
        let states = channels.iter().map(|f| f.state());
        let x1 = states.clone().map(|s| s.x1[0]);
        let x2 = states.clone().map(|s| s.x2[0]);
        let x3 = states.map(|s| s.x3[0]);
        writer.write(x1.chain(x2).chain(x3)).map_err(|e| table::at(format_args!("line {line}"), e))?;
    }
    Ok(())
}
