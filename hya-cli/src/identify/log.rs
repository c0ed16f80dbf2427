//! The log `hya identify` reads, filtered into samples `(q̂, q̂̇, q̂̈, τ̂)`.
//!
//! `q̂, q̂̇, q̂̈` come from the paper's third-order filter on `q` (no numerical differentiation)
//! and `τ̂` from the same filter on `τ`, so that both carry the same lag, as in the estimator.
//! With timestamps each step is filtered over its own length (first-order hold, as
//! [`hya_core::TimedEstimator`] does); a step longer than `--max-step` is a gap, across which
//! the derivatives would be guesses: both filters restart at rest on the row after it.
//!
//! After every (re)start the filters settle for `10/ω` seconds before a sample is taken; then one
//! sample is taken per `1/ω` seconds, the time over which the filters make neighbouring rows'
//! noise alike, so that the fit's residuals are near independent, as its standard deviations
//! assume.

use std::io::BufRead;

use hya_core::dispatch::ForJoints;
use hya_core::step_cache::DiscretisationCache;
use hya_core::{FilterParams, JointVector, Short, ThirdOrderFilter};
use hya_ident::Sample;

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

impl Layout {
    /// How long the filters settle after a start before samples are taken, `10/ω` s.
    pub fn settling_s(&self) -> f64 {
        10.0 / self.params.omega1_rad_s()
    }

    /// The time between samples taken, `1/ω` s.
    pub fn spacing_s(&self) -> f64 {
        1.0 / self.params.omega1_rad_s()
    }
}

/// The samples taken from a log.
pub struct Filtered {
    /// The samples, in time order.
    pub samples: Vec<Sample>,
    /// Each sample's time, s (from the log's timestamps, or `k · dt`).
    pub time_s: Vec<f64>,
    /// The rows read.
    pub rows: usize,
    /// The gaps across which the filters restarted.
    pub gaps: usize,
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

/// The two filters, on `q` and on `τ`.
struct Pair<const N: usize> {
    angles: ThirdOrderFilter<N>,
    torques: ThirdOrderFilter<N>,
}

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
    let dt = params.dt_s();
    let mut cache = DiscretisationCache::new(params);
    let mut filters: Option<Pair<N>> = None;
    let mut out = Filtered { samples: Vec::new(), time_s: Vec::new(), rows: 0, gaps: 0, dt_s: dt, max_step_s };
    let (mut previous_s, mut next_sample_s) = (0.0, 0.0);
    while let Some(line) = log.next_line() {
        let line = line?;
        let at_line = |e: hya_core::Error| CliError::Input(format!("line {line}: {e}"));
        let values = log.values();
        let t = if layout.timestamps { values[0] } else { out.rows as f64 * dt };
        out.rows += 1;
        let q = JointVector::<N>::from_column_slice(&values[offset..offset + N]);
        let tau = JointVector::<N>::from_column_slice(&values[offset + N..offset + 2 * N]);
        if !t.is_finite() {
            return Err(CliError::Input(format!("line {line}: t = {t}: times must be finite")));
        }
        let step = t - previous_s;
        match filters.as_mut() {
            Some(pair) if !layout.timestamps => {
                pair.angles.step(&q).map_err(at_line)?;
                pair.torques.step(&tau).map_err(at_line)?;
            }
            Some(_) if step <= 0.0 => {
                return Err(CliError::Input(format!(
                    "line {line}: t = {} s is not after the previous row's t = {} s: times must strictly increase",
                    Short(t),
                    Short(previous_s)
                )))
            }
            Some(pair) if step <= max_step_s => {
                let over = cache.get(step).map_err(at_line)?;
                let angles = pair.angles.peek_over(over, "q", &q).map_err(at_line)?;
                let torques = pair.torques.peek_over(over, "τ", &tau).map_err(at_line)?;
                pair.angles.commit(angles, q);
                pair.torques.commit(torques, tau);
            }
            _ => {
                if filters.is_some() {
                    out.gaps += 1;
                }
                let start = |x0| ThirdOrderFilter::<N>::new(params, x0).map_err(at_line);
                filters = Some(Pair { angles: start(q)?, torques: start(tau)? });
                next_sample_s = t + layout.settling_s();
            }
        }
        previous_s = t;
        // Half a row early counts as on time: `k · dt` need not meet `m / ω` exactly.
        if t >= next_sample_s - 0.5 * dt {
            if let Some(pair) = &filters {
                let state = pair.angles.state();
                out.samples.push(Sample {
                    q: state.x1.as_slice().to_vec(),
                    qd: state.x2.as_slice().to_vec(),
                    qdd: state.x3.as_slice().to_vec(),
                    tau: pair.torques.state().x1.as_slice().to_vec(),
                });
                out.time_s.push(t);
            }
            next_sample_s += layout.spacing_s();
        }
    }
    Ok(out)
}
