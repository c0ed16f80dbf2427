//! `hya filter`: the third-order filter over rows of samples.

use std::io::{BufRead, Write};

use hya_core::{FilterParams, JointVector, ThirdOrderFilter};

use crate::{read_rows, rows, CliError};

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
}

/// Filters every row of `input` and writes `x1…, x2…, x3…` per row to `output`.
pub fn run(args: &FilterArgs, input: impl BufRead, output: &mut impl Write) -> Result<(), CliError> {
    let params = FilterParams::new(args.zeta, args.omega1, args.omega2, args.dt)
        .map_err(|e| CliError::Input(format!("filter parameters: {e}")))?;
    let mut channels: Vec<ThirdOrderFilter<1>> = Vec::new();
    for row in read_rows(input) {
        let row = row?;
        if channels.is_empty() {
            channels = row
                .values
                .iter()
                .map(|&u0| ThirdOrderFilter::new(params, JointVector::from([u0])))
                .collect::<Result<_, _>>()
                .map_err(|e| CliError::Input(format!("line {}: {e}", row.line)))?;
        } else {
            rows::expect_width(&row, channels.len(), "one per channel, as on the first row")?;
            for (filter, &u) in channels.iter_mut().zip(&row.values) {
                filter.step(&JointVector::from([u])).map_err(|e| CliError::Input(format!("line {}: {e}", row.line)))?;
            }
        }
        let states = channels.iter().map(|f| f.state());
        let x1 = states.clone().map(|s| s.x1[0]);
        let x2 = states.clone().map(|s| s.x2[0]);
        let x3 = states.map(|s| s.x3[0]);
        rows::write(output, x1.chain(x2).chain(x3))?;
    }
    Ok(())
}
