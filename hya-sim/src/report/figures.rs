//! The report's figures per scenario (first seed's traces; bars over all seeds): tracking error,
//! the paper's view of the angles, each observer's estimate against the true disturbance, the
//! weight drop and removal up close, and the tracking RMSE on a log scale.

use hya_core::JointVector;

use crate::analysis::seeds::MetricTable;
use crate::analysis::simulate::RunOutcome;
use crate::config::scenario::{Method, Scenario};
use crate::io::svg::{bar_chart, line_grid, Panel, Series, PALETTE};
use crate::run::trace::Trace;

use super::summary::aggregate;

type Signal<const N: usize> = fn(&Trace<N>) -> Vec<JointVector<N>>;

/// The controllers a tracking figure compares: `none`, `pid` and `lu` where they ran, else
/// every method.
fn featured<'a, const N: usize>(runs: &[&'a RunOutcome<N>]) -> Vec<&'a RunOutcome<N>> {
    let chosen: Vec<&RunOutcome<N>> =
        runs.iter().copied().filter(|o| matches!(o.method, Method::None | Method::Pid | Method::Lu)).collect();
    if chosen.is_empty() {
        runs.to_vec()
    } else {
        chosen
    }
}

fn series<const N: usize>(
    o: &RunOutcome<N>,
    joint: usize,
    values: &[JointVector<N>],
    label: String,
    color: &'static str,
    dashed: bool,
) -> Series {
    Series {
        label,
        points: o.trace.time.iter().zip(values).map(|(t, v)| (*t, v[joint])).collect(),
        color,
        dashed,
        markers: false,
    }
}

fn color(method: Method) -> &'static str {
    let index = [Method::None, Method::Pid, Method::Lu, Method::Chen, Method::Momentum, Method::Eso]
        .iter()
        .position(|m| *m == method)
        .unwrap_or(0);
    PALETTE[(index + 1) % PALETTE.len()]
}

/// One panel per joint in `joints`, within `window` (s): for every run, `signal` (and, if given,
/// the first run's `reference`, dashed).
fn per_joint<const N: usize>(
    title: String,
    y_label: &str,
    shown: &[&RunOutcome<N>],
    joints: &[usize],
    window: (f64, f64),
    reference: Option<(&str, Signal<N>)>,
    signal: (&str, Signal<N>),
) -> String {
    let clip = |mut s: Series| {
        s.points.retain(|(t, _)| *t >= window.0 && *t <= window.1);
        s
    };
    let panels: Vec<Panel> = joints
        .iter()
        .map(|&j| {
            let mut lines = Vec::new();
            if let (Some((name, f)), Some(first)) = (reference, shown.first()) {
                lines.push(clip(series(first, j, &f(&first.trace), name.into(), PALETTE[0], true)));
            }
            for o in shown {
                let label = format!("{} ({})", signal.0, o.method.name());
                lines.push(clip(series(o, j, &(signal.1)(&o.trace), label, color(o.method), false)));
            }
            Panel { title: format!("joint {}", j + 1), y_label: y_label.into(), series: lines }
        })
        .collect();
    line_grid(&title, "t [s]", &panels, 3.min(joints.len()).max(1))
}

fn error<const N: usize>(t: &Trace<N>) -> Vec<JointVector<N>> {
    t.q.iter().zip(&t.q_des).map(|(q, r)| q - r).collect()
}

/// Every figure of scenario `s`: `(file name, SVG)`.
pub fn scenario_figures<const N: usize>(
    s: &Scenario,
    runs: &[&RunOutcome<N>],
    table: &MetricTable,
) -> Vec<(String, String)> {
    let name = &s.name;
    let end = runs.first().and_then(|o| o.trace.time.last().copied()).unwrap_or(s.duration_s);
    let whole = (0.0, end);
    let mut figures = vec![
        (
            format!("{name}_error.svg"),
            per_joint(
                format!("{name}: tracking error q − q_des"),
                "rad",
                &featured(runs),
                &(0..N).collect::<Vec<_>>(),
                whole,
                None,
                ("e", error),
            ),
        ),
        (
            format!("{name}_joints.svg"),
            per_joint(
                format!("{name}: joint angles against the reference"),
                "rad",
                &featured(runs),
                &(0..N).collect::<Vec<_>>(),
                whole,
                Some(("q_des", |t| t.q_des.clone())),
                ("q", |t| t.q.clone()),
            ),
        ),
    ];
    for o in runs.iter().filter(|o| o.method.estimates()) {
        figures.push((
            format!("{name}_disturbance_{}.svg", o.method.name()),
            per_joint(
                format!("{name}: d̂ of {} against the true disturbance", o.method.name()),
                "N·m",
                &[o],
                &(0..N).collect::<Vec<_>>(),
                whole,
                Some(("d (true)", |t| t.d_true.clone())),
                ("d̂", |t| t.d_hat.clone()),
            ),
        ));
    }
    if let Some(drop) = &s.loads.weight_drop {
        let mut events = vec![("drop", drop.drop_s)];
        events.extend(drop.remove_s.map(|r| ("removal", r)));
        for (event, at) in events {
            figures.push((
                format!("{name}_joint2_{event}.svg"),
                per_joint(
                    format!("{name}: joint 2 around the weight's {event} at {at} s"),
                    "rad",
                    &featured(runs),
                    &[1],
                    (at - 1.0, at + 3.0),
                    None,
                    ("e", error),
                ),
            ));
        }
    }
    figures.push((format!("{name}_rmse.svg"), rmse_figure(s, runs, table)));
    figures
}

/// Tracking RMSE per joint and method, mean over seeds, on a log scale.
fn rmse_figure<const N: usize>(s: &Scenario, runs: &[&RunOutcome<N>], table: &MetricTable) -> String {
    let joints: Vec<String> = (1..=N).map(|j| format!("joint {j}")).collect();
    let bars: Vec<(String, Vec<f64>)> = runs
        .iter()
        .map(|o| {
            let mean =
                aggregate(table, &s.name, o.method, "rmse_q").map_or_else(|| o.metrics.rmse_q.clone(), |(m, _)| m);
            (o.method.name().to_owned(), mean)
        })
        .collect();
    bar_chart(&format!("{}: tracking RMSE (mean over seeds)", s.name), "RMSE [rad], log scale", &joints, &bars)
}
