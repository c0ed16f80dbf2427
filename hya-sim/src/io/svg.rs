//! Plain SVG figures: grids of line plots and grouped bar charts. Text is left to the viewer's
//! fonts, so nothing here needs a font file.
//!
//! Why not plotters' SVG backend: plotters measures every label through a font implementation
//! before it places it, either `ttf` (font-kit, which finds fonts through fontconfig, a system
//! library hya must not need) or `ab_glyph` (a font file registered at run time, which hya would
//! have to ship). The figures need lines, dots, dashes, log axes and legends, which this writer
//! draws in about 600 lines as `<text>` the viewer lays out.

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

/// How an axis maps values to positions.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Scale {
    /// Evenly, with round ticks.
    #[default]
    Linear,
    /// By decades, with a tick at each; values that are not positive are not drawn.
    Log,
}

impl Scale {
    /// Log where every finite value is positive and they span more than a decade; else linear.
    pub fn for_values(values: impl Iterator<Item = f64>) -> Self {
        let (lo, hi) =
            values.filter(|v| v.is_finite()).fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(v), b.max(v)));
        if lo > 0.0 && hi.is_finite() && hi > 10.0 * lo {
            Scale::Log
        } else {
            Scale::Linear
        }
    }
}

/// A point's annotation on a [`MarkedPanel`]: a label beside its marker and the half-widths of
/// its interval (whiskers; none where not finite and positive).
#[derive(Debug, Clone, PartialEq)]
pub struct Mark {
    /// Text beside the marker.
    pub label: String,
    /// Half-width of the interval on x.
    pub x_half_width: f64,
    /// Half-width of the interval on y.
    pub y_half_width: f64,
    /// Drawn with a ring around the marker (a Pareto front's points).
    pub ringed: bool,
}

/// A panel whose points are drawn as markers, each with its label and whiskers, on chosen
/// scales; its series' lines join the markers.
#[derive(Debug, Clone)]
pub struct MarkedPanel {
    /// The plot.
    pub panel: Panel,
    /// Per series, per point (a point without a mark gets a bare marker).
    pub marks: Vec<Vec<Mark>>,
    /// The x axis's scale.
    pub x_scale: Scale,
    /// The y axis's scale.
    pub y_scale: Scale,
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

/// One axis of a panel: its range (decades' exponents on a log scale) and scale.
struct Axis {
    lo: f64,
    hi: f64,
    scale: Scale,
}

impl Axis {
    /// The axis covering `values` (padded when linear, whole decades when log).
    fn of(values: impl Iterator<Item = f64>, scale: Scale) -> Self {
        let (lo, hi) = match scale {
            Scale::Linear => range(values),
            Scale::Log => decades(values),
        };
        Self { lo, hi, scale }
    }

    /// Where `v` falls, 0 at the low end to 1 at the high end; `None` if it cannot be drawn.
    fn fraction(&self, v: f64) -> Option<f64> {
        let at = match self.scale {
            Scale::Linear if v.abs() <= MAX_PLOTTED => v,
            Scale::Log if v > 0.0 && v <= MAX_PLOTTED => v.log10(),
            _ => return None,
        };
        Some((at - self.lo) / (self.hi - self.lo))
    }

    /// As [`Self::fraction`], clamped to the axis: a whisker's end beyond it stops at the frame.
    fn clamped(&self, v: f64) -> Option<f64> {
        match (self.scale, v.is_nan()) {
            (_, true) => None,
            (Scale::Log, false) if v <= 0.0 => Some(0.0),
            _ => Some(self.fraction(v.clamp(-MAX_PLOTTED, MAX_PLOTTED))?.clamp(0.0, 1.0)),
        }
    }

    fn ticks(&self) -> Vec<f64> {
        match self.scale {
            Scale::Linear => ticks(self.lo, self.hi),
            Scale::Log => (self.lo as i32..=self.hi as i32).map(|e| 10f64.powi(e)).collect(),
        }
    }
}

/// The exponents of the whole decades covering the positive values (at least one decade).
fn decades(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| *v > 0.0 && *v <= MAX_PLOTTED)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(v), b.max(v)));
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    let (lo, hi) = (lo.log10().floor(), hi.log10().ceil());
    (lo, hi.max(lo + 1.0))
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

/// A panel's frame on the page: the plot's corner and size, and its two axes.
struct Frame {
    left: f64,
    top: f64,
    w: f64,
    h: f64,
    x: Axis,
    y: Axis,
}

impl Frame {
    fn sx(&self, f: f64) -> f64 {
        self.left + f * self.w
    }

    fn sy(&self, f: f64) -> f64 {
        self.top + self.h - f * self.h
    }

    /// The page position of a data point, if it can be drawn.
    fn at(&self, (x, y): (f64, f64)) -> Option<(f64, f64)> {
        Some((self.sx(self.x.fraction(x)?), self.sy(self.y.fraction(y)?)))
    }
}

/// Every value a panel's axis must cover: its points and the ends of their whiskers.
fn extent<'a>(p: &'a Panel, marks: &'a [Vec<Mark>], y: bool) -> impl Iterator<Item = f64> + 'a {
    p.series.iter().enumerate().flat_map(move |(k, s)| {
        s.points.iter().enumerate().flat_map(move |(i, &(px, py))| {
            let (v, half) = match (y, marks.get(k).and_then(|m| m.get(i))) {
                (true, m) => (py, m.map_or(0.0, |m| m.y_half_width)),
                (false, m) => (px, m.map_or(0.0, |m| m.x_half_width)),
            };
            let half = if half.is_finite() { half } else { 0.0 };
            [v, v - half, v + half]
        })
    })
}

fn panel(out: &mut String, p: &Panel, marks: &[Vec<Mark>], scales: (Scale, Scale), corner: (f64, f64), x_label: &str) {
    let (x0, y0) = corner;
    let frame = Frame {
        left: x0 + MARGIN_L,
        top: y0 + MARGIN_T,
        w: PANEL_W - MARGIN_L - MARGIN_R,
        h: PANEL_H - MARGIN_T - MARGIN_B,
        x: Axis::of(extent(p, marks, false), scales.0),
        y: Axis::of(extent(p, marks, true), scales.1),
    };
    let (left, top, w, h) = (frame.left, frame.top, frame.w, frame.h);
    let _ = writeln!(
        out,
        r##"<rect x="{left:.1}" y="{top:.1}" width="{w:.1}" height="{h:.1}" fill="none" stroke="#888"/>"##
    );
    centred_text(out, left + w / 2.0, y0 + 17.0, 13, false, &p.title);
    grid_lines(out, &frame);
    centred_text(out, left + w / 2.0, top + h + 27.0, 11, false, x_label);
    centred_text(out, x0 + 14.0, top + h / 2.0, 11, true, &p.y_label);
    let mut labels = Vec::new();
    for (k, s) in p.series.iter().enumerate() {
        series(out, &frame, s, marks.get(k).map_or(&[], |m| m.as_slice()), !marks.is_empty(), &mut labels);
        legend(out, &frame, s, k);
    }
}

/// The ticks of both axes with their grid lines.
fn grid_lines(out: &mut String, frame: &Frame) {
    let (left, top, w, h) = (frame.left, frame.top, frame.w, frame.h);
    for t in frame.x.ticks() {
        let Some(x) = frame.x.fraction(t).map(|f| frame.sx(f)) else { continue };
        let _ = writeln!(
            out,
            r##"<line x1="{x:.1}" y1="{:.1}" x2="{x:.1}" y2="{:.1}" stroke="#eee"/><text x="{x:.1}" y="{:.1}" font-size="10" text-anchor="middle">{}</text>"##,
            top,
            top + h,
            top + h + 12.0,
            format_tick(t)
        );
    }
    for t in frame.y.ticks() {
        let Some(y) = frame.y.fraction(t).map(|f| frame.sy(f)) else { continue };
        let _ = writeln!(
            out,
            r##"<line x1="{left:.1}" y1="{y:.1}" x2="{:.1}" y2="{y:.1}" stroke="#eee"/><text x="{:.1}" y="{:.1}" font-size="10" text-anchor="end">{}</text>"##,
            left + w,
            left - 4.0,
            y + 3.0,
            format_tick(t)
        );
    }
}

/// One series: its line (or dots), and with `marked` a marker, label and whiskers per point.
fn series(out: &mut String, frame: &Frame, s: &Series, marks: &[Mark], marked: bool, labels: &mut Vec<Label>) {
    let stride = if marked { 1 } else { s.points.len().div_ceil(MAX_POINTS).max(1) };
    let path: Vec<String> =
        s.points.iter().step_by(stride).filter_map(|pt| frame.at(*pt)).map(|(x, y)| format!("{x:.1},{y:.1}")).collect();
    let dash = if s.dashed { r#" stroke-dasharray="5,3""# } else { "" };
    if s.markers && !marked {
        // One path of zero-length round-capped segments: a dot per point, in one element.
        let dots: Vec<String> = path.iter().map(|p| format!("M{p}h0")).collect();
        let _ = writeln!(
            out,
            r#"<path fill="none" stroke="{}" stroke-width="3" stroke-linecap="round" stroke-opacity="0.5" d="{}"/>"#,
            s.color,
            dots.join("")
        );
    } else if !s.markers {
        let _ = writeln!(
            out,
            r#"<polyline fill="none" stroke="{}" stroke-width="1.2"{dash} points="{}"/>"#,
            s.color,
            path.join(" ")
        );
    }
    if marked {
        for (i, &pt) in s.points.iter().enumerate() {
            mark(out, frame, pt, marks.get(i), s.color, labels);
        }
    }
}

/// A mark label's box on the page: left, top, right, bottom.
type Label = (f64, f64, f64, f64);

/// Where a label of `chars` characters goes beside a marker at `(px, py)`: the first of a few
/// places around it that overlaps no label already placed in the panel (else the first place),
/// so that labels of coinciding points ("100" over "100") do not print over each other.
fn place_label(px: f64, py: f64, chars: usize, placed: &mut Vec<Label>) -> (f64, f64) {
    let (w, h) = (4.6 * chars as f64, 8.0);
    let spots = [(3.5, -3.5), (3.5, 9.5), (-3.5 - w, -3.5), (-3.5 - w, 9.5), (3.5, -12.5), (3.5, 18.5)];
    let boxed = |(dx, dy): (f64, f64)| (px + dx, py + dy - h, px + dx + w, py + dy);
    let free = |b: &Label| placed.iter().all(|p| b.2 <= p.0 || p.2 <= b.0 || b.3 <= p.1 || p.3 <= b.1);
    let spot = spots.iter().copied().find(|s| free(&boxed(*s))).unwrap_or(spots[0]);
    placed.push(boxed(spot));
    (px + spot.0, py + spot.1)
}

/// A point's marker, its whiskers and its label; nothing for a point that cannot be drawn.
fn mark(
    out: &mut String,
    frame: &Frame,
    (x, y): (f64, f64),
    mark: Option<&Mark>,
    color: &str,
    labels: &mut Vec<Label>,
) {
    let Some((px, py)) = frame.at((x, y)) else { return };
    if let Some(m) = mark {
        let whisker = |v: f64, half: f64, axis: &Axis| {
            (half.is_finite() && half > 0.0).then_some(())?;
            Some((axis.clamped(v - half)?, axis.clamped(v + half)?))
        };
        if let Some((a, b)) = whisker(y, m.y_half_width, &frame.y) {
            let (ya, yb) = (frame.sy(a), frame.sy(b));
            let _ = writeln!(
                out,
                r#"<path fill="none" stroke="{color}" stroke-width="1" d="M{px:.1},{ya:.1}V{yb:.1}M{:.1},{ya:.1}h5M{:.1},{yb:.1}h5"/>"#,
                px - 2.5,
                px - 2.5
            );
        }
        if let Some((a, b)) = whisker(x, m.x_half_width, &frame.x) {
            let (xa, xb) = (frame.sx(a), frame.sx(b));
            let _ = writeln!(
                out,
                r#"<path fill="none" stroke="{color}" stroke-width="1" d="M{xa:.1},{py:.1}H{xb:.1}M{xa:.1},{:.1}v5M{xb:.1},{:.1}v5"/>"#,
                py - 2.5,
                py - 2.5
            );
        }
    }
    let _ = writeln!(out, r#"<circle cx="{px:.1}" cy="{py:.1}" r="2.5" fill="{color}"/>"#);
    if mark.is_some_and(|m| m.ringed) {
        let _ = writeln!(
            out,
            r#"<circle class="front" cx="{px:.1}" cy="{py:.1}" r="5" fill="none" stroke="{color}" stroke-width="1"/>"#
        );
    }
    if let Some(m) = mark.filter(|m| !m.label.is_empty()) {
        let (lx, ly) = place_label(px, py, m.label.chars().count(), labels);
        let _ = writeln!(
            out,
            r#"<text class="mark" x="{lx:.1}" y="{ly:.1}" font-size="8" fill="{color}">{}</text>"#,
            escape(&m.label)
        );
    }
}

/// The `k`-th entry of the legend right of the plot: its line, or a dot for a series drawn as
/// dots.
fn legend(out: &mut String, frame: &Frame, s: &Series, k: usize) {
    let dash = if s.dashed { r#" stroke-dasharray="5,3""# } else { "" };
    let right = frame.left + frame.w;
    let ly = frame.top + 8.0 + 13.0 * k as f64;
    if s.markers {
        let _ = write!(out, r#"<circle cx="{:.1}" cy="{ly:.1}" r="2.5" fill="{}"/>"#, right + 17.0, s.color);
    } else {
        let _ = write!(
            out,
            r#"<line x1="{:.1}" y1="{ly:.1}" x2="{:.1}" y2="{ly:.1}" stroke="{}" stroke-width="2"{dash}/>"#,
            right + 8.0,
            right + 26.0,
            s.color
        );
    }
    let _ = writeln!(
        out,
        r#"<text x="{:.1}" y="{:.1}" font-size="10">{}</text>"#,
        right + 30.0,
        ly + 3.0,
        escape(&s.label)
    );
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
    line_grid_scaled(title, x_label, panels, columns, Scale::Linear)
}

/// [`line_grid`] with the x axis on `x_scale` (a logarithmic one for frequencies).
pub fn line_grid_scaled(title: &str, x_label: &str, panels: &[Panel], columns: usize, x_scale: Scale) -> String {
    grid(title, panels.len(), columns, |body, i, corner| {
        panel(body, &panels[i], &[], (x_scale, Scale::Linear), corner, x_label)
    })
}

/// A document of `count` panels in `columns`, each drawn by `draw(body, index, corner)`.
fn grid(title: &str, count: usize, columns: usize, mut draw: impl FnMut(&mut String, usize, (f64, f64))) -> String {
    let columns = columns.max(1);
    let rows = count.div_ceil(columns);
    let mut body = String::new();
    for i in 0..count {
        draw(&mut body, i, ((i % columns) as f64 * PANEL_W, 30.0 + (i / columns) as f64 * PANEL_H));
    }
    document(columns as f64 * PANEL_W, 30.0 + rows as f64 * PANEL_H, title, &body)
}

/// A grid of [`MarkedPanel`]s sharing the x label: every drawable point a marker (`<circle>`)
/// with its label (`<text class="mark">`) and whiskers.
pub fn marked_grid(title: &str, x_label: &str, panels: &[MarkedPanel], columns: usize) -> String {
    grid(title, panels.len(), columns, |body, i, corner| {
        let p = &panels[i];
        // A panel without marks still draws markers: one empty mark list per series.
        let marks = if p.marks.is_empty() { vec![Vec::new(); p.panel.series.len().max(1)] } else { p.marks.clone() };
        panel(body, &p.panel, &marks, (p.x_scale, p.y_scale), corner, x_label);
    })
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
    fn a_dotted_series_has_a_dot_in_the_legend_and_a_log_axis_decade_ticks() {
        let series = |label: &str, markers: bool| Series {
            label: label.into(),
            points: vec![(0.1, 1.0), (1.0, 0.5), (10.0, 0.1)],
            color: "#000",
            dashed: !markers,
            markers,
        };
        let panel = Panel {
            title: "t".into(),
            y_label: "gain".into(),
            series: vec![series("design", false), series("measured", true)],
        };
        let svg = line_grid_scaled("r", "frequency [Hz]", &[panel], 1, Scale::Log);
        assert_eq!(svg.matches("<circle").count(), 1, "one legend dot, for the dotted series");
        for tick in [">0.1<", ">1<", ">10<"] {
            assert!(svg.contains(tick), "no tick {tick}");
        }
    }

    #[test]
    fn labels_of_coinciding_points_do_not_print_over_each_other() {
        let mut placed = Vec::new();
        let first = place_label(100.0, 100.0, 3, &mut placed);
        let second = place_label(100.0, 100.0, 3, &mut placed);
        let third = place_label(101.0, 99.0, 3, &mut placed);
        assert!(first != second && second != third && first != third, "{first:?} {second:?} {third:?}");
        // Apart, a label keeps its usual place.
        assert_eq!(place_label(300.0, 300.0, 3, &mut placed), (303.5, 296.5));
    }

    #[test]
    fn log_axes_cover_whole_decades_and_refuse_what_they_cannot_draw() {
        let axis = Axis::of([0.002, 0.5, -1.0, f64::NAN, f64::INFINITY].into_iter(), Scale::Log);
        assert_eq!(axis.ticks(), [1e-3, 1e-2, 1e-1, 1.0]);
        assert_eq!(axis.fraction(0.01), Some(1.0 / 3.0));
        assert!(axis.fraction(0.0).is_none() && axis.fraction(f64::NAN).is_none());
        assert_eq!(axis.clamped(-3.0), Some(0.0));
        assert_eq!(Scale::for_values([1.0, 20.0].into_iter()), Scale::Log);
        assert_eq!(Scale::for_values([1.0, 9.0, f64::NAN].into_iter()), Scale::Linear);
        assert_eq!(Scale::for_values([0.0, 20.0].into_iter()), Scale::Linear);
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
