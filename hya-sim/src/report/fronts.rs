//! The main comparison: the Pareto fronts of a bandwidth sweep run inside `hya reproduce`. What
//! is equal is said first; then, per scenario, tracking RMSE and estimate error against command
//! noise for every method and pid ([`pareto_figure`]), and in words which method's
//! points no other point dominates beyond the 95 % intervals ([`crate::sweep::pareto_optimal`]).

use std::fmt::Write as _;

use crate::analysis::seeds::PairedRatio;
use crate::analysis::sweep::{dominates, front_points, pareto_optimal, scenarios, FrontPoint, Measure, Plan, Sweep};
use crate::config::scenario::{ChenGain, Method};
use crate::error::SimError;
use crate::io::svg::{marked_grid, Mark, MarkedPanel, Panel, Scale, Series, PALETTE};
use hya_core::Short;

/// The figure's file name.
pub const FIGURE: &str = "fronts.svg";

/// The sweep's file name: every seed's point, as `hya sweep` writes `sweep.json`.
pub const SWEEP_FILE: &str = "fronts_sweep.json";

/// The section on `sweep`, run on the grid `plan` of `robot`'s scenarios
/// ([`crate::studies::run`]): its markdown, and the figure and the sweep as `(file name, text)`.
pub fn section_of<const N: usize>(
    robot: &crate::robot::Robot<N>,
    plan: &Plan,
    sweep: &Sweep,
) -> Result<(String, Vec<(String, String)>), SimError> {
    let mut md = equal_text(plan);
    for scenario in scenarios(sweep) {
        md.push_str(&scenario_text(sweep, scenario));
    }
    md.push_str(&equal_delay_text(sweep, plan));
    md.push_str(&integral_text(robot, plan)?);
    let files =
        vec![(FIGURE.to_owned(), pareto_figure(sweep)), (SWEEP_FILE.to_owned(), serde_json::to_string_pretty(sweep)?)];
    Ok((md, files))
}

/// A method's colour, the same in every panel.
fn method_color(method: &str) -> &'static str {
    let order = ["none", "lu", "chen", "momentum", "eso", "pid"];
    PALETTE[order.iter().position(|m| *m == method).unwrap_or(order.len()) % PALETTE.len()]
}

/// One panel: `measure` against command noise on `scenario`, one line per method through its
/// swept values, each point's marker labelled with its value and whiskers of its intervals; log
/// axes where the means span more than a decade.
fn front_panel(sweep: &Sweep, scenario: &str, measure: Measure) -> MarkedPanel {
    let points = front_points(sweep, scenario, measure);
    let front = pareto_optimal(&points);
    let mut methods: Vec<&str> = points.iter().map(|p| p.method.as_str()).collect();
    methods.dedup();
    let (mut series, mut marks) = (Vec::new(), Vec::new());
    for (k, method) in methods.into_iter().enumerate() {
        let own: Vec<(usize, &FrontPoint)> = points.iter().enumerate().filter(|(_, p)| p.method == method).collect();
        series.push(Series {
            label: method.to_owned(),
            points: own.iter().map(|(_, p)| (p.noise.0, p.error.0)).collect(),
            color: method_color(method),
            // Every other method dashed: lines that coincide (chen's and momentum's, whose
            // designs agree) stay visible one through the other.
            dashed: k % 2 == 1,
            markers: false,
        });
        marks.push(
            own.iter()
                .map(|(i, p)| Mark {
                    label: format!("{}", Short(p.bandwidth_rad_s)),
                    x_half_width: p.noise.1,
                    y_half_width: p.error.1,
                    ringed: front.contains(i),
                })
                .collect(),
        );
    }
    MarkedPanel {
        panel: Panel { title: scenario.to_owned(), y_label: measure.label().into(), series },
        marks,
        x_scale: Scale::for_values(points.iter().map(|p| p.noise.0)),
        y_scale: Scale::for_values(points.iter().map(|p| p.error.0)),
    }
}

/// The Pareto figure: per scenario, tracking RMSE and estimate error against command noise, one
/// line per method through its swept values (means over seeds), each marker labelled with its
/// bandwidth in rad/s, whiskers of the 95 % intervals over seeds, log axes where the values span
/// more than a decade.
pub fn pareto_figure(sweep: &Sweep) -> String {
    let panels: Vec<MarkedPanel> = scenarios(sweep)
        .into_iter()
        .flat_map(|scenario| Measure::ALL.map(|measure| front_panel(sweep, scenario, measure)))
        .collect();
    marked_grid(
        "bandwidth sweep: error against command noise (labels: bandwidth, rad/s; pid: its integral's; ringed: the front)",
        "command-torque noise [N·m]",
        &panels,
        2,
    )
}

/// What is equal between the methods, and what was swept.
fn equal_text(plan: &Plan) -> String {
    let scenarios: Vec<String> =
        plan.scenarios.iter().map(|s| format!("`{}` ({} s)", s.name, Short(s.duration_s))).collect();
    let methods: Vec<&str> = plan.methods.iter().map(|m| m.name()).collect();
    let bandwidths: Vec<String> = plan.bandwidths_rad_s.iter().map(|w| format!("{}", Short(*w))).collect();
    let chen = match plan.scenarios.first().map(|s| s.controller.chen_gain) {
        Some(ChenGain::Scalar) => "scalar gain `Y = ω λmax(M(q0)) I` (slowest rate ω at the start pose)",
        _ => "`L = ω I` at the start pose",
    };
    let mut md = String::from("\n## Pareto fronts: error against command noise\n\n");
    let _ = writeln!(
        md,
        "What is equal: every run of a scenario has the same plant, task, sensors, PD gains (one gain rule for every method) and seeds; only the compensation and its bandwidth ω differ. At one ω: lu's filters have ζ = 0.8, ω1 = ω2 = ω; chen's {chen}; momentum's `K_O = ω`; eso's ω_o = ω; pid's integral `K_I = K_P / τ_d(ω)` with `τ_d = 1/ω + 2ζ/ω` (lu's low-frequency delay at ω), capped at half the Routh bound `½ K_D K_P / M_ii`. Swept: {} with {}, ω = {} rad/s, {} seed(s) each. Each point is the mean over seeds (and over joints) of the command-torque noise and of the error; whiskers are 95 % intervals over seeds{}.\n\n![Pareto fronts]({FIGURE})\n",
        scenarios.join(" and "),
        methods.join(", "),
        bandwidths.join(", "),
        plan.seeds,
        if plan.seeds < 2 { " (one seed: no interval, means compared)" } else { "" },
    );
    md.push_str(
        "\nA point is dominated when another is no worse in mean in both command noise and error and better beyond the 95 % intervals in one; the front is the points no other point dominates.\n",
    );
    md
}

/// The words for one scenario: per measure, the front from the quietest command up, and the
/// methods with no point on it.
fn scenario_text(sweep: &Sweep, scenario: &str) -> String {
    let mut md = format!("\n### `{scenario}`\n\n");
    for measure in Measure::ALL {
        let points = front_points(sweep, scenario, measure);
        if points.is_empty() {
            continue;
        }
        let _ = writeln!(md, "- {}: {}", measure.label(), front_text(&points, measure));
    }
    md
}

/// The paper's filter's low-frequency delay at `ω1 = ω2 = ω`, `ζ = 0.8`: `1/ω1 + 2ζ/ω2`, s.
fn paper_delay_s(omega: f64) -> f64 {
    (1.0 + 2.0 * hya_core::filter::PAPER_ZETA) / omega
}

/// Per seed, `measure` of `method` at `bandwidth` on `scenario`, keyed by seed.
fn per_seed(sweep: &Sweep, scenario: &str, method: &str, bandwidth: f64, measure: Measure) -> Vec<(u64, f64)> {
    let mut values: Vec<(u64, f64)> = sweep
        .entries
        .iter()
        .filter(|e| e.scenario == scenario && e.method == method && e.bandwidth_rad_s == bandwidth)
        .filter_map(|e| measure.of(e).map(|v| (e.seed, v)))
        .collect();
    values.sort_by_key(|(seed, _)| *seed);
    values
}

/// `method` at `bandwidth` over lu at `omega` on `scenario`, paired by seed; `None` where no seed
/// ran both.
fn ratio_to_lu(
    sweep: &Sweep,
    scenario: &str,
    (method, bandwidth): (&str, f64),
    omega: f64,
    measure: Measure,
) -> Option<(PairedRatio, usize)> {
    let (theirs, lus) =
        (per_seed(sweep, scenario, method, bandwidth, measure), per_seed(sweep, scenario, "lu", omega, measure));
    let (a, b): (Vec<f64>, Vec<f64>) =
        theirs.iter().filter_map(|(seed, v)| lus.iter().find(|(s, _)| s == seed).map(|(_, l)| (*v, *l))).unzip();
    (!a.is_empty()).then(|| (PairedRatio::of(&a, &b), a.len()))
}

/// The share of a log-ratio gap `ln r_poles` that matching the delay closes:
/// `1 − ln r_delay / ln r_poles` (1: closed; above 1: reversed; below 0: widened).
fn share_closed(at_poles: f64, at_delay: f64) -> f64 {
    1.0 - at_delay.ln() / at_poles.ln()
}

/// What matching the delay does to the tracking gaps that favoured a first-order observer at equal
/// poles, from `(at equal poles, at equal delay)` ratios to lu: how many it closes or reverses,
/// narrows (and by how much on a log scale) or widens.
fn gap_text(pairs: &[(f64, f64)], seeds: usize) -> String {
    let shares: Vec<f64> = pairs.iter().filter(|(poles, _)| *poles < 1.0).map(|&(p, d)| share_closed(p, d)).collect();
    if shares.is_empty() {
        return String::new();
    }
    let closed = shares.iter().filter(|&&x| x >= 1.0).count();
    let narrowed: Vec<f64> = shares.iter().copied().filter(|&x| (0.0..1.0).contains(&x)).collect();
    let widened = shares.len() - closed - narrowed.len();
    let mut parts = Vec::new();
    if closed > 0 {
        parts.push(format!("closes or reverses the gap in {closed}"));
    }
    if let (Some(low), Some(high)) =
        (narrowed.iter().copied().reduce(f64::min), narrowed.iter().copied().reduce(f64::max))
    {
        parts.push(format!(
            "narrows the gap in {} (closing {} of it on a log scale)",
            narrowed.len(),
            span(format!("{:.0} %", 100.0 * low), format!("{:.0} %", 100.0 * high))
        ));
    }
    if widened > 0 {
        parts.push(format!("widens the gap in {widened}"));
    }
    let on = match seeds {
        1 => "on the means of one seed, with no interval",
        _ => "on the means; the intervals above say whether what is left exceeds the seeds' spread",
    };
    let tail = if closed == shares.len() {
        format!(" ({on}): the low-frequency lag accounts for the whole gap there")
    } else {
        format!(
            "; it does not remove the whole gap ({on}). What is left is not explained here: the delays \
             match at low frequency only, and no run here tells lag at higher frequencies from any other \
             cause"
        )
    };
    format!(
        "\nOf the {} whose tracking error was below lu's at equal poles, matching the low-frequency delay {}{tail}.\n",
        match shares.len() {
            1 => "one pair".to_owned(),
            n => format!("{n} pairs"),
        },
        parts.join(", ")
    )
}

/// The first-order observers (chen, momentum) against lu at about equal low-frequency delay, from
/// the sweep's own points: lu at the scenarios' observer bandwidth ω (delay `2.6/ω`) against each
/// at the swept `β` whose delay `1/β` is nearest, tracking and estimate error as paired per-seed
/// ratios, beside the same ratio at equal poles (`β = ω`). The words (lower, higher,
/// indistinguishable) come from the ratios' intervals; how much of the tracking gap the delay
/// explains from the two ratios ([`gap_text`]).
fn equal_delay_text(sweep: &Sweep, plan: &Plan) -> String {
    let Some(omega) = plan.scenarios.first().map(|s| s.controller.observer_bandwidth_rad_s) else {
        return String::new();
    };
    let lu_delay = paper_delay_s(omega);
    let Some(beta) = plan
        .bandwidths_rad_s
        .iter()
        .copied()
        .min_by(|a, b| ((1.0 / a) - lu_delay).abs().total_cmp(&((1.0 / b) - lu_delay).abs()))
    else {
        return String::new();
    };
    let mut lines = Vec::new();
    let mut tracking_gaps = Vec::new();
    let mut paired_seeds = usize::MAX;
    for scenario in scenarios(sweep) {
        for method in ["chen", "momentum"] {
            let mut parts = Vec::new();
            for measure in Measure::ALL {
                let Some((ratio, seeds)) = ratio_to_lu(sweep, scenario, (method, beta), omega, measure) else {
                    continue;
                };
                let at_poles = ratio_to_lu(sweep, scenario, (method, omega), omega, measure);
                if let (Measure::Tracking, Some((poles, poles_seeds))) = (measure, at_poles) {
                    tracking_gaps.push((poles.ratio, ratio.ratio));
                    paired_seeds = paired_seeds.min(seeds.min(poles_seeds));
                }
                let word = if ratio.below_one() {
                    "lower than lu's"
                } else if ratio.above_one() {
                    "higher than lu's"
                } else {
                    "indistinguishable from lu's at these seeds"
                };
                let at_delay = match seeds {
                    1 => format!("{:.2}× (one seed: no interval)", ratio.ratio),
                    _ => format!("{:.2}× [{:.2}, {:.2}], {word}", ratio.ratio, ratio.low, ratio.high),
                };
                let poles = at_poles.map_or(String::new(), |(p, _)| format!(", at equal poles {:.2}×", p.ratio));
                parts.push(format!("{} {at_delay}{poles}", measure.label()));
            }
            if !parts.is_empty() {
                lines.push(format!("- `{scenario}`, {method} at β = {} rad/s: {}", Short(beta), parts.join("; ")));
            }
        }
    }
    if lines.is_empty() {
        return String::new();
    }
    format!(
        "
### At about equal delay

The runs above compare the observers at equal pole magnitude, where a first-order observer lags `1/ω` ({} ms at ω = {} rad/s) and lu's filter `1/ω1 + 2ζ/ω2` ({} ms). The sweep also holds the first-order observers at β = {} rad/s, whose delay `1/β` ({} ms) is the swept value nearest lu's at ω = {}. Their errors over lu's there, paired by seed (the geometric mean over seeds with its 95 % interval on the logarithms), each followed by the same ratio at equal poles (β = ω):

{}
{}
The claims that name chen are judged at every matching, equal −3 dB too, in \"Chen's observer by gain design and matching\".
",
        Short(1e3 / omega),
        Short(omega),
        Short(lu_delay * 1e3),
        Short(beta),
        Short(1e3 / beta),
        Short(omega),
        lines.join("\n"),
        gap_text(&tracking_gaps, paired_seeds)
    )
}

/// An error as printed: tracking in mrad, estimates in N·m.
fn error_text(value: f64, measure: Measure) -> String {
    match measure {
        Measure::Tracking => format!("{} mrad", Short(value * 1e3)),
        Measure::Estimate => format!("{} N·m", Short(value)),
    }
}

/// The front in order of command noise, grouped into runs of one method, then the methods off it.
fn front_text(points: &[FrontPoint], measure: Measure) -> String {
    let mut front: Vec<&FrontPoint> = pareto_optimal(points).into_iter().map(|i| &points[i]).collect();
    front.sort_by(|a, b| a.noise.0.total_cmp(&b.noise.0));
    let mut parts = Vec::new();
    for run in front.chunk_by(|a, b| a.method == b.method) {
        let (first, last) = (run[0], run[run.len() - 1]);
        let omegas: Vec<String> = run.iter().map(|p| format!("{}", Short(p.bandwidth_rad_s))).collect();
        let noise = span(format!("{}", Short(first.noise.0)), format!("{}", Short(last.noise.0)));
        let error = span(error_text(first.error.0, measure), error_text(last.error.0, measure));
        parts.push(format!(
            "{} at ω = {} rad/s (command noise {noise} N·m, error {error})",
            first.method,
            omegas.join(", ")
        ));
    }
    let mut text = format!("from the quietest command up, the front is {}.", parts.join("; then "));
    text.push_str(&within_intervals_text(points, &front));
    text.push_str(&near_tie_text(points, &front));
    text.push_str(&off_front_text(points, &front));
    text
}

/// How close two command noises must be, relative, for the report not to rank by them.
const NOISE_TIE: f64 = 0.01;

/// The front's points that are on it only by a command noise less than [`NOISE_TIE`] below that
/// of a point with lower error: a quieter command by so little does not separate them.
fn near_tie_text(points: &[FrontPoint], front: &[&FrontPoint]) -> String {
    let named = |p: &FrontPoint| format!("{}@{}", p.method, Short(p.bandwidth_rad_s));
    let tied: Vec<String> = front
        .iter()
        .filter_map(|p| {
            points
                .iter()
                .find(|q| q.error.0 < p.error.0 && q.noise.0 > p.noise.0 && q.noise.0 <= p.noise.0 * (1.0 + NOISE_TIE))
                .map(|q| format!("{} against {}", named(p), named(q)))
        })
        .collect();
    match tied.len() {
        0 => String::new(),
        k => format!(
            " {k} of these points {} on the front only by a command noise less than {} % below that of a point \
             with lower error ({}): a difference that small does not rank them.",
            if k == 1 { "is" } else { "are" },
            Short(100.0 * NOISE_TIE),
            tied.join(", ")
        ),
    }
}

/// The front's points that another point beats on both means, though not beyond the intervals:
/// on the front only because the seeds cannot tell them apart.
fn within_intervals_text(points: &[FrontPoint], front: &[&FrontPoint]) -> String {
    let beats = |q: &FrontPoint, p: &FrontPoint| {
        q.noise.0 <= p.noise.0 && q.error.0 <= p.error.0 && (q.noise.0 < p.noise.0 || q.error.0 < p.error.0)
    };
    let named = |p: &FrontPoint| format!("{}@{}", p.method, Short(p.bandwidth_rad_s));
    let beaten: Vec<String> = front
        .iter()
        .filter_map(|p| points.iter().find(|q| beats(q, p)).map(|q| format!("{} by {}", named(p), named(q))))
        .collect();
    match beaten.len() {
        0 => String::new(),
        k => format!(
            " {k} of these {} points have another point no worse on either mean and lower on one, within the \
             intervals: indistinguishable at these seeds, not better ({}).",
            front.len(),
            beaten.join(", ")
        ),
    }
}

/// `a–b`, or `a` alone when both read the same.
fn span(a: String, b: String) -> String {
    if a == b {
        a
    } else {
        format!("{a} to {b}")
    }
}

/// The methods with no point on the front, each with the method that dominates most of its points.
fn off_front_text(points: &[FrontPoint], front: &[&FrontPoint]) -> String {
    let mut methods: Vec<&str> = points.iter().map(|p| p.method.as_str()).collect();
    methods.dedup();
    let mut text = String::new();
    for method in methods.into_iter().filter(|m| front.iter().all(|p| p.method != *m)) {
        let own: Vec<&FrontPoint> = points.iter().filter(|p| p.method == method).collect();
        let count =
            |other: &str| own.iter().filter(|p| points.iter().any(|q| q.method == other && dominates(q, p))).count();
        let mut others: Vec<&str> = points.iter().map(|p| p.method.as_str()).filter(|m| *m != method).collect();
        others.dedup();
        if let Some(best) = others.into_iter().max_by_key(|m| count(m)) {
            let _ = write!(
                text,
                " No point of {method} is on the front; {best}'s points dominate {} of its {}{}.",
                count(best),
                own.len(),
                one_seed_margin(points, &own, best)
            );
        }
    }
    text
}

/// With one seed (no interval), how narrowly `by`'s points dominate `own`'s: per dominated point
/// the widest relative gap of its best dominator (`(b − a)/b` on the mean where it is lower),
/// and the least of those; empty with intervals, which already judge the gaps.
fn one_seed_margin(points: &[FrontPoint], own: &[&FrontPoint], by: &str) -> String {
    if own.iter().any(|p| p.noise.1.is_finite() || p.error.1.is_finite()) {
        return String::new();
    }
    let gap = |q: &FrontPoint, p: &FrontPoint| {
        ((p.noise.0 - q.noise.0) / p.noise.0.abs()).max((p.error.0 - q.error.0) / p.error.0.abs())
    };
    let least = own
        .iter()
        .filter_map(|p| points.iter().filter(|q| q.method == by && dominates(q, p)).map(|q| gap(q, p)).reduce(f64::max))
        .reduce(f64::min);
    match least {
        Some(least) => format!(
            " on the means alone, by as little as {:.1} % on the measure where they are lower (one seed: no interval \
             to judge the gaps by)",
            100.0 * least
        ),
        None => String::new(),
    }
}

/// Where pid's `K_I` meets its cap, per scenario and swept ω, at the start pose.
fn integral_text<const N: usize>(robot: &crate::robot::Robot<N>, plan: &Plan) -> Result<String, SimError> {
    if !plan.methods.contains(&Method::Pid) {
        return Ok(String::new());
    }
    let mut md = String::from(
        "\npid's `K_I` at its cap (half the Routh bound), by swept ω; on a capped joint `K_I` no longer grows with ω:\n\n",
    );
    for (i, s) in plan.scenarios.iter().enumerate() {
        let mut cells = Vec::new();
        for &omega in &plan.bandwidths_rad_s {
            let Some(scenario) = plan.scenario_at(i, Method::Pid, omega, 0) else { continue };
            let capped: Vec<String> =
                capped_joints(robot, &scenario)?.into_iter().map(|j| format!("{}", j + 1)).collect();
            let joints = if capped.is_empty() { "none".to_owned() } else { format!("joints {}", capped.join(", ")) };
            cells.push(format!("{} rad/s: {joints}", Short(omega)));
        }
        let _ = writeln!(md, "- `{}`: {}.", s.name, cells.join("; "));
    }
    Ok(md)
}

/// The joints (from 0) whose pid `K_I` is capped in `scenario`.
fn capped_joints<const N: usize>(
    robot: &crate::robot::Robot<N>,
    scenario: &crate::config::scenario::Scenario,
) -> Result<Vec<usize>, SimError> {
    let capped = super::loop_design(scenario, robot)?.capped;
    Ok((0..N).filter(|&j| capped[j]).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(method: &str, bandwidth: f64, noise: (f64, f64), error: (f64, f64)) -> FrontPoint {
        FrontPoint { method: method.into(), bandwidth_rad_s: bandwidth, noise, error }
    }

    #[test]
    fn front_points_beaten_on_the_means_are_called_indistinguishable() {
        // lu@20 is beaten on both means by pid@20, but their intervals overlap: both stay on the
        // front, and the words say the seeds cannot tell them apart.
        let points = vec![
            point("lu", 20.0, (1.00, 0.05), (2.0, 0.5)),
            point("pid", 20.0, (0.98, 0.05), (1.9, 0.5)),
            point("chen", 50.0, (3.0, 0.1), (1.0, 0.1)),
        ];
        let front: Vec<&FrontPoint> = pareto_optimal(&points).into_iter().map(|i| &points[i]).collect();
        assert_eq!(front.len(), 3);
        let text = within_intervals_text(&points, &front);
        assert!(text.contains("1 of these 3 points have another") && text.contains("lu@20 by pid@20"), "{text}");
        // Apart beyond the intervals, nothing is said.
        let apart = vec![point("lu", 20.0, (1.0, 0.01), (2.0, 0.01)), point("chen", 50.0, (3.0, 0.1), (1.0, 0.1))];
        let front: Vec<&FrontPoint> = pareto_optimal(&apart).into_iter().map(|i| &apart[i]).collect();
        assert!(within_intervals_text(&apart, &front).is_empty());
    }

    #[test]
    fn one_seed_domination_names_its_narrowest_margin() {
        let one = f64::INFINITY;
        let points = vec![
            point("chen", 50.0, (1.00, one), (0.99, one)),
            point("chen", 100.0, (2.0, one), (0.5, one)),
            point("momentum", 50.0, (1.00, one), (1.00, one)),
            point("momentum", 100.0, (2.2, one), (0.5, one)),
        ];
        let own: Vec<&FrontPoint> = points.iter().filter(|p| p.method == "momentum").collect();
        // momentum@50 is beaten by 1 % in error, momentum@100 by 9.1 % in noise: the least is 1 %.
        let text = one_seed_margin(&points, &own, "chen");
        assert!(text.contains("by as little as 1.0 %"), "{text}");
        // With intervals the margin is not stated: the intervals judge it.
        let seeded: Vec<FrontPoint> =
            points.iter().map(|p| FrontPoint { noise: (p.noise.0, 0.01), ..p.clone() }).collect();
        let own: Vec<&FrontPoint> = seeded.iter().filter(|p| p.method == "momentum").collect();
        assert!(one_seed_margin(&seeded, &own, "chen").is_empty());
    }

    #[test]
    fn matching_the_delay_is_said_to_close_narrow_or_widen_the_gap_from_the_ratios() {
        assert!((share_closed(0.5, 0.5) - 0.0).abs() < 1e-12 && (share_closed(0.5, 1.0) - 1.0).abs() < 1e-12);
        // Narrowed: 0.5 → 0.8 closes 1 − ln 0.8/ln 0.5 = 68 %; a gap in lu's favour is not counted.
        let text = gap_text(&[(0.5, 0.8), (1.2, 1.1)], 3);
        assert!(text.contains("Of the one pair") && text.contains("narrows the gap in 1 (closing 68 %"), "{text}");
        assert!(text.contains("it does not remove the whole gap (on the means;"), "{text}");
        let text = gap_text(&[(0.5, 1.05), (0.6, 0.4)], 1);
        assert!(text.contains("closes or reverses the gap in 1") && text.contains("widens the gap in 1"), "{text}");
        assert!(text.contains("one seed, with no interval"), "{text}");
        assert!(gap_text(&[(0.5, 1.0)], 3).contains("accounts for the whole gap"));
        assert!(gap_text(&[(1.3, 0.9)], 3).is_empty());
    }

    #[test]
    fn a_front_point_kept_by_a_near_tie_in_noise_is_named() {
        let one = f64::INFINITY;
        let points =
            vec![point("pid", 20.0, (1.677_238, one), (20.8, one)), point("lu", 20.0, (1.677_240, one), (17.7, one))];
        let front: Vec<&FrontPoint> = pareto_optimal(&points).into_iter().map(|i| &points[i]).collect();
        assert_eq!(front.len(), 2, "neither dominates on the means");
        let text = near_tie_text(&points, &front);
        assert!(text.contains("1 of these points") && text.contains("pid@20 against lu@20"), "{text}");
        let apart = vec![point("pid", 20.0, (1.5, one), (20.8, one)), point("lu", 20.0, (1.7, one), (17.7, one))];
        let front: Vec<&FrontPoint> = pareto_optimal(&apart).into_iter().map(|i| &apart[i]).collect();
        assert!(near_tie_text(&apart, &front).is_empty());
    }
}
