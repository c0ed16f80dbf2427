//! Plain SVG figures: grids of line plots and grouped bar charts. Text is left to the viewer's
//! fonts, so nothing here needs a font file.

use std::fmt::Write;

/// Colours for successive series, colour-blind safe (Okabe–Ito).
pub const PALETTE: [&str; 7] = ["#000000", "#E69F00", "#0072B2", "#009E73", "#D55E00", "#CC79A7", "#56B4E9"];

/// One line on a plot.
#[derive(Debug, Clone)]
pub struct Series {
    /// Legend text.
    pub label: String,
    /// `(x, y)` points, in order of `x`.
    pub points: Vec<(f64, f64)>,
    /// Stroke colour.
    pub color: &'static str,
    /// Dashed rather than solid.
    pub dashed: bool,
    /// Drawn as unconnected dots (a scatter) rather than a line.
    pub markers: bool,
}

/// One plot of a grid.
#[derive(Debug, Clone)]
pub struct Panel {
    /// Title above the plot.
    pub title: String,
    /// Label of the y axis.
    pub y_label: String,
    /// Its lines.
    pub series: Vec<Series>,
}

const PANEL_W: f64 = 540.0;
const PANEL_H: f64 = 230.0;
const MARGIN_L: f64 = 62.0;
/// Room right of the plot for the legend, which stays off the data.
const MARGIN_R: f64 = 160.0;
const MARGIN_T: f64 = 26.0;
const MARGIN_B: f64 = 34.0;
/// At most this many points per series are drawn (evenly strided).
const MAX_POINTS: usize = 1500;

/// "Nice" tick positions covering `[lo, hi]`.
fn ticks(lo: f64, hi: f64) -> Vec<f64> {
    let span = (hi - lo).max(1e-12);
    let raw = span / 5.0;
    let magnitude = 10f64.powf(raw.log10().floor());
    let step =
        [1.0, 2.0, 5.0, 10.0].iter().map(|m| m * magnitude).find(|s| span / s <= 6.0).unwrap_or(10.0 * magnitude);
    let (first, last) = ((lo / step).ceil(), (hi / step).floor());
    // A span lost in the rounding of huge values gives no tick rather than billions.
    if !(first.is_finite() && last.is_finite() && last - first <= 20.0) {
        return Vec::new();
    }
    (first as i64..=last as i64).map(|k| k as f64 * step).collect()
}

fn escape(text: &str) -> String {
    text.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;")
}

/// The largest magnitude a plot's axes take in (the span of larger values overflows): points
/// beyond it, or not finite, are not drawn.
const MAX_PLOTTED: f64 = 1e150;

/// Text centred at `(x, y)`; `vertical` turns it to read upwards (a y-axis label).
fn centred_text(out: &mut String, x: f64, y: f64, size: u32, vertical: bool, text: &str) {
    let place = if vertical {
        format!(r#"transform="translate({x:.1},{y:.1}) rotate(-90)""#)
    } else {
        format!(r#"x="{x:.1}" y="{y:.1}""#)
    };
    let _ = writeln!(out, r#"<text {place} font-size="{size}" text-anchor="middle">{}</text>"#, escape(text));
}

fn range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.abs() <= MAX_PLOTTED)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(v), b.max(v)));
    if !lo.is_finite() {
        return (-1.0, 1.0);
    }
    let pad = ((hi - lo) * 0.05).max(1e-9);
    (lo - pad, hi + pad)
}

fn panel(out: &mut String, p: &Panel, x0: f64, y0: f64, x_label: &str) {
    let (xl, xh) = range(p.series.iter().flat_map(|s| s.points.iter().map(|pt| pt.0)));
    let (yl, yh) = range(p.series.iter().flat_map(|s| s.points.iter().map(|pt| pt.1)));
    let (w, h) = (PANEL_W - MARGIN_L - MARGIN_R, PANEL_H - MARGIN_T - MARGIN_B);
    let (left, top) = (x0 + MARGIN_L, y0 + MARGIN_T);
    let sx = |x: f64| left + (x - xl) / (xh - xl) * w;
    let sy = |y: f64| top + h - (y - yl) / (yh - yl) * h;
    let _ = writeln!(
        out,
        r##"<rect x="{left:.1}" y="{top:.1}" width="{w:.1}" height="{h:.1}" fill="none" stroke="#888"/>"##
    );
    centred_text(out, left + w / 2.0, y0 + 17.0, 13, false, &p.title);
    for t in ticks(xl, xh) {
        let x = sx(t);
        let _ = writeln!(
            out,
            r##"<line x1="{x:.1}" y1="{:.1}" x2="{x:.1}" y2="{:.1}" stroke="#eee"/><text x="{x:.1}" y="{:.1}" font-size="10" text-anchor="middle">{}</text>"##,
            top,
            top + h,
            top + h + 12.0,
            format_tick(t)
        );
    }
    for t in ticks(yl, yh) {
        let y = sy(t);
        let _ = writeln!(
            out,
            r##"<line x1="{left:.1}" y1="{y:.1}" x2="{:.1}" y2="{y:.1}" stroke="#eee"/><text x="{:.1}" y="{:.1}" font-size="10" text-anchor="end">{}</text>"##,
            left + w,
            left - 4.0,
            y + 3.0,
            format_tick(t)
        );
    }
    centred_text(out, left + w / 2.0, top + h + 27.0, 11, false, x_label);
    centred_text(out, x0 + 14.0, top + h / 2.0, 11, true, &p.y_label);
    for (k, s) in p.series.iter().enumerate() {
        let stride = s.points.len().div_ceil(MAX_POINTS).max(1);
        let path: Vec<String> = s
            .points
            .iter()
            .step_by(stride)
            .filter(|(x, y)| x.abs() <= MAX_PLOTTED && y.abs() <= MAX_PLOTTED)
            .map(|(x, y)| format!("{:.1},{:.1}", sx(*x), sy(*y)))
            .collect();
        let dash = if s.dashed { r#" stroke-dasharray="5,3""# } else { "" };
        if s.markers {
            // One path of zero-length round-capped segments: a dot per point, in one element.
            let dots: Vec<String> = path.iter().map(|p| format!("M{p}h0")).collect();
            let _ = writeln!(
                out,
                r#"<path fill="none" stroke="{}" stroke-width="3" stroke-linecap="round" stroke-opacity="0.5" d="{}"/>"#,
                s.color,
                dots.join("")
            );
        } else {
            let _ = writeln!(
                out,
                r#"<polyline fill="none" stroke="{}" stroke-width="1.2"{dash} points="{}"/>"#,
                s.color,
                path.join(" ")
            );
        }
        let ly = top + 8.0 + 13.0 * k as f64;
        let _ = writeln!(
            out,
            r#"<line x1="{:.1}" y1="{ly:.1}" x2="{:.1}" y2="{ly:.1}" stroke="{}" stroke-width="2"{dash}/><text x="{:.1}" y="{:.1}" font-size="10">{}</text>"#,
            left + w + 8.0,
            left + w + 26.0,
            s.color,
            left + w + 30.0,
            ly + 3.0,
            escape(&s.label)
        );
    }
}

fn format_tick(t: f64) -> String {
    if t == 0.0 || (t.abs() >= 1e-3 && t.abs() < 1e4) {
        let text = format!("{t:.4}");
        text.trim_end_matches('0').trim_end_matches('.').to_owned()
    } else {
        format!("{t:.1e}")
    }
}

fn document(width: f64, height: f64, title: &str, body: &str) -> String {
    format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width:.0}\" height=\"{height:.0}\" viewBox=\"0 0 {width:.0} {height:.0}\" font-family=\"sans-serif\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n<text x=\"{:.0}\" y=\"20\" font-size=\"15\" font-weight=\"bold\" text-anchor=\"middle\">{}</text>\n{body}</svg>\n",
        width / 2.0,
        escape(title)
    )
}

/// A grid of line plots sharing the x label.
pub fn line_grid(title: &str, x_label: &str, panels: &[Panel], columns: usize) -> String {
    let columns = columns.max(1);
    let rows = panels.len().div_ceil(columns);
    let mut body = String::new();
    for (i, p) in panels.iter().enumerate() {
        panel(&mut body, p, (i % columns) as f64 * PANEL_W, 30.0 + (i / columns) as f64 * PANEL_H, x_label);
    }
    document(columns as f64 * PANEL_W, 30.0 + rows as f64 * PANEL_H, title, &body)
}

/// Grouped bars on a log scale (values spanning decades, like RMSEs): one group per category,
/// one bar per series; a value that is not positive draws no bar.
pub fn bar_chart(title: &str, y_label: &str, categories: &[String], series: &[(String, Vec<f64>)]) -> String {
    let (width, height) = (160.0 + 110.0 * categories.len() as f64, 360.0);
    let (left, top, h) = (70.0, 40.0, 260.0);
    let w = width - left - 20.0;
    let positive = || series.iter().flat_map(|(_, v)| v.iter().copied()).filter(|v| *v > 0.0 && v.is_finite());
    let low = positive().fold(f64::INFINITY, f64::min);
    let high = positive().fold(0.0, f64::max);
    let (lo, hi) =
        if high > 0.0 { (low.log10().floor(), high.log10().ceil().max(low.log10().floor() + 1.0)) } else { (0.0, 1.0) };
    let sy = |v: f64| if v > 0.0 { top + h - (v.log10() - lo) / (hi - lo) * h } else { top + h };
    let mut body = String::new();
    for t in (lo as i32..=hi as i32).map(|e| 10f64.powi(e)) {
        let _ = writeln!(
            body,
            r##"<line x1="{left}" y1="{:.1}" x2="{:.1}" y2="{:.1}" stroke="#eee"/><text x="{:.1}" y="{:.1}" font-size="10" text-anchor="end">{}</text>"##,
            sy(t),
            left + w,
            sy(t),
            left - 4.0,
            sy(t) + 3.0,
            format_tick(t)
        );
    }
    let group = w / categories.len().max(1) as f64;
    let bar = group * 0.8 / series.len().max(1) as f64;
    for (c, name) in categories.iter().enumerate() {
        let gx = left + c as f64 * group;
        centred_text(&mut body, gx + group / 2.0, top + h + 15.0, 11, false, name);
        for (k, (_, values)) in series.iter().enumerate() {
            let v = values.get(c).copied().unwrap_or(0.0);
            let _ = writeln!(
                body,
                r#"<rect x="{:.1}" y="{:.1}" width="{:.1}" height="{:.1}" fill="{}"/>"#,
                gx + group * 0.1 + k as f64 * bar,
                sy(v),
                bar * 0.95,
                top + h - sy(v),
                PALETTE[k % PALETTE.len()]
            );
        }
    }
    for (k, (label, _)) in series.iter().enumerate() {
        let x = left + 10.0 + 110.0 * k as f64;
        let _ = writeln!(
            body,
            r#"<rect x="{x:.1}" y="{:.1}" width="12" height="12" fill="{}"/><text x="{:.1}" y="{:.1}" font-size="11">{}</text>"#,
            top + h + 28.0,
            PALETTE[k % PALETTE.len()],
            x + 16.0,
            top + h + 38.0,
            escape(label)
        );
    }
    let _ = writeln!(
        body,
        r##"<line x1="{left}" y1="{:.1}" x2="{:.1}" y2="{:.1}" stroke="#888"/>"##,
        top + h,
        left + w,
        top + h
    );
    centred_text(&mut body, 18.0, top + h / 2.0, 11, true, y_label);
    document(width, height, title, &body)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_are_round_and_cover_the_range() {
        assert_eq!(ticks(0.0, 1.0), [0.0, 0.2, 0.4, 0.6000000000000001, 0.8, 1.0]);
        assert!(ticks(1e300, 1e300 + 1e-12).is_empty(), "no billions of ticks for a lost span");
        assert!(ticks(-3.7, 12.2).iter().all(|t| (t / 5.0).fract() == 0.0));
    }

    #[test]
    fn documents_are_well_formed_and_escape_text() {
        let panel = Panel {
            title: "q <joint 1> & co".into(),
            y_label: "rad".into(),
            series: vec![Series {
                label: "a".into(),
                points: vec![(0.0, 1.0), (1.0, 2.0)],
                color: PALETTE[0],
                dashed: true,
                markers: false,
            }],
        };
        let svg = line_grid("t", "s", &[panel], 2);
        assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
        let huge = Panel {
            title: "huge".into(),
            y_label: "x".into(),
            series: vec![Series {
                label: "h".into(),
                points: vec![(1e308, 1e308), (-1e308, f64::NAN), (0.0, 1.0), (1.0, 2.0)],
                color: PALETTE[0],
                dashed: false,
                markers: true,
            }],
        };
        let huge = line_grid("t", "s", &[huge], 1);
        assert!(!huge.contains("NaN") && !huge.contains("inf"), "non-finite coordinates: {huge}");
        assert!(svg.contains("q &lt;joint 1&gt; &amp; co") && !svg.contains("<joint"));
        let bars = bar_chart("rmse", "rad", &["j1".into()], &[("none".into(), vec![0.5])]);
        assert_eq!(bars.matches("<rect").count(), 1 + 1 + 1); // background, bar, legend swatch
    }
}
