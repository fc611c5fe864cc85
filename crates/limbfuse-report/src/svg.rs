//! A small SVG line-plot writer.
//!
//! Each plot is an outer `<svg>` (fixed 900 x 240 pixel box, scaled to the
//! page width) holding a title, a frame, an empty `<g class="axes">` that the
//! page's script fills with ticks, and an inner `<svg class="area">` whose
//! `viewBox` is in data units: x in `1/x_scale` units (milliseconds on time
//! plots), y in `1/y_scale` units, negated so that up is positive. Lines are
//! `<path>`s with integer relative coordinates (`M x y l dx dy dx dy ...`),
//! which keeps a long trial small; zooming changes only the `viewBox`.

use std::fmt::Write as _;

use crate::decimate::Points;

/// Outer box (px).
const WIDTH: f64 = 900.0;
const HEIGHT: f64 = 240.0;
/// Plot area inside the box (px): left, top, width, height.
const AREA: [f64; 4] = [64.0, 26.0, 824.0, 180.0];

/// One line of a plot.
#[derive(Debug, Clone)]
pub struct Line {
    /// `data-series` value: what the line is (`reference`, an estimate label, ...).
    pub key: String,
    /// Legend text.
    pub label: String,
    /// CSS colour.
    pub color: String,
    /// Points (decimated for display).
    pub points: Points,
    /// Drawn dashed (references of secondary quantities).
    pub dashed: bool,
}

/// A shaded band `(x, low, high)` (mean +- sd).
#[derive(Debug, Clone)]
pub struct Band {
    /// `data-series` value.
    pub key: String,
    /// CSS colour.
    pub color: String,
    /// Points.
    pub points: Vec<(f64, f64, f64)>,
}

/// A line plot.
#[derive(Debug, Clone)]
pub struct Plot {
    /// Element id (unique in the page).
    pub id: String,
    /// `data-plot` value: the kind of plot (`angle`, `cycle`, `imm-gait`, ...).
    pub kind: String,
    /// Title above the plot.
    pub title: String,
    /// x-axis label.
    pub x_label: String,
    /// y-axis label.
    pub y_label: String,
    /// x units per data unit (1000 for milliseconds on time plots).
    pub x_scale: f64,
    /// Whether the plot follows the page's time window (time plots).
    pub zoomable: bool,
    /// Lines.
    pub lines: Vec<Line>,
    /// Bands, drawn under the lines.
    pub bands: Vec<Band>,
    /// A y range clipped to leave out the estimates' start transient
    /// ([`crate::y_range`]): the clipped start is shaded and the page's
    /// script keeps the clipped range while the start is a small part of
    /// the window.
    pub y_clip: Option<crate::y_range::YClip>,
}

impl Plot {
    /// The (x, y) range of every finite value, padded by 5 % in y.
    fn ranges(&self) -> Option<([f64; 2], [f64; 2])> {
        let mut x = [f64::INFINITY, f64::NEG_INFINITY];
        let mut y = x;
        let mut see = |px: f64, py: f64| {
            if px.is_finite() && py.is_finite() {
                x = [x[0].min(px), x[1].max(px)];
                y = [y[0].min(py), y[1].max(py)];
            }
        };
        // A break (`None`) still spans time: a series that starts late
        // (an estimate that needs a window, a stride) keeps the plot's time
        // axis on the whole trial, as "whole trial" promises.
        let mut gaps = [f64::INFINITY, f64::NEG_INFINITY];
        for l in &self.lines {
            for (px, py) in &l.points {
                match py {
                    Some(py) => see(*px, *py),
                    None if px.is_finite() => gaps = [gaps[0].min(*px), gaps[1].max(*px)],
                    None => {}
                }
            }
        }
        for b in &self.bands {
            for (px, lo, hi) in &b.points {
                see(*px, *lo);
                see(*px, *hi);
            }
        }
        if !x[0].is_finite() {
            return None;
        }
        if let Some(c) = &self.y_clip {
            y = [c.lo, c.hi];
        }
        x = [x[0].min(gaps[0]), x[1].max(gaps[1])];
        if x[1] <= x[0] {
            x[1] = x[0] + 1.0;
        }
        let pad = 0.05 * (y[1] - y[0]).max(1e-9);
        // A spread below 1e-6 of the values is a constant written with
        // rounding (an independent simulator's fixed thigh, 1.57079633 rad
        // against the estimate's 1.570796327): scaled to it, the plot's
        // coordinates (9e11) went beyond a browser's float precision and no
        // line was drawn. It is plotted as a constant.
        let (lo, hi) = if y[1] - y[0] > 1e-6 * y[0].abs().max(y[1].abs()) {
            (y[0] - pad, y[1] + pad)
        } else {
            (y[0] - 0.5, y[0] + 0.5)
        };
        Some((x, [lo, hi]))
    }

    /// The SVG text of the plot.
    pub fn render(&self) -> String {
        let ([x0, x1], [y0, y1]) = self.ranges().unwrap_or(([0.0, 1.0], [0.0, 1.0]));
        let ys = y_scale(y1 - y0);
        let min_span = (min_y_span(y1 - y0) * ys).round();
        let xs = self.x_scale;
        // x as the paths round it (a time of 29.990000000005 s is 29990 ms
        // there, and the box ends with it)
        let (bx, by) = ((x0 * xs).round(), (-y1 * ys).floor());
        let (bw, bh) = (
            ((x1 * xs).round() - bx).max(1.0),
            ((-y0 * ys).ceil() - by).max(1.0),
        );
        let mut s = String::new();
        let clip_until = self.y_clip.as_ref().map_or(String::new(), |c| {
            format!(r#" data-clip-until="{}""#, (c.until_s * xs).round())
        });
        let _ = write!(
            s,
            r#"<svg class="plot{zoom}" id="{id}" data-plot="{kind}" data-x-scale="{xs}" data-y-scale="{ys}" data-min-y-span="{min_span}"{clip_until} data-x-label="{xl}" data-y-label="{yl}" viewBox="0 0 {WIDTH} {HEIGHT}" role="img" aria-label="{title}">"#,
            zoom = if self.zoomable { " time" } else { "" },
            id = esc(&self.id),
            kind = esc(&self.kind),
            xl = esc(&self.x_label),
            yl = esc(&self.y_label),
            title = esc(&self.title),
        );
        let [ax, ay, aw, ah] = AREA;
        let _ = write!(
            s,
            r#"<text class="title" x="{ax}" y="16">{}</text><rect class="frame" x="{ax}" y="{ay}" width="{aw}" height="{ah}"/><g class="axes"></g><svg class="area" x="{ax}" y="{ay}" width="{aw}" height="{ah}" viewBox="{bx} {by} {bw} {bh}" preserveAspectRatio="none" data-full="{bx} {by} {bw} {bh}">"#,
            esc(&self.title)
        );
        if let Some(c) = &self.y_clip {
            let (top, bottom) = ((-c.all[1] * ys).floor(), (-c.all[0] * ys).ceil());
            let _ = write!(
                s,
                r#"<rect class="clipped" x="{bx}" y="{top}" width="{}" height="{}"/>"#,
                ((c.until_s * xs).round() - bx).max(1.0),
                (bottom - top).max(1.0)
            );
        }
        for b in &self.bands {
            let _ = write!(
                s,
                r#"<path class="band" data-series="{}" fill="{}" d="{}"/>"#,
                esc(&b.key),
                esc(&b.color),
                band_d(&b.points, xs, ys)
            );
        }
        for l in &self.lines {
            let _ = write!(
                s,
                r#"<path class="line{}" data-series="{}" stroke="{}" d="{}"/>"#,
                if l.dashed { " dashed" } else { "" },
                esc(&l.key),
                esc(&l.color),
                line_d(&l.points, xs, ys)
            );
        }
        s.push_str("</svg></svg>");
        s
    }

    /// The legend (HTML), one entry per line.
    pub fn legend(&self) -> String {
        let mut s = String::from(r#"<div class="legend">"#);
        for l in &self.lines {
            let _ = write!(
                s,
                r#"<span class="key" data-series="{}"><i style="background:{}"></i>{}</span>"#,
                esc(&l.key),
                esc(&l.color),
                esc(&l.label)
            );
        }
        s.push_str("</div>");
        s
    }
}

/// The narrowest y range (data units) the page's script shows when it
/// refits the y axis to a time window: one unit (deg, m/s, ...), or the
/// plot's whole range `full_span` when that is smaller. A constant series
/// (plotted +-0.5 around it) keeps its 1-unit window; before (audit
/// 2026-12-05) the script refitted it to 2e-4 deg and no line was seen.
pub fn min_y_span(full_span: f64) -> f64 {
    if full_span.is_finite() && full_span > 0.0 {
        full_span.min(1.0)
    } else {
        1.0
    }
}

/// y units per data unit: about 10^4 levels over the plotted range, a power of ten.
fn y_scale(range: f64) -> f64 {
    let r = if range.is_finite() && range > 0.0 {
        range
    } else {
        1.0
    };
    10f64.powi(4 - r.log10().ceil() as i32)
}

/// `d` of a polyline: absolute integer start of each run, then relative
/// integer steps (the differences of the rounded absolute coordinates, so
/// rounding does not accumulate).
pub fn line_d(points: &Points, xs: f64, ys: f64) -> String {
    let mut d = String::with_capacity(points.len() * 8);
    let mut last: Option<(i64, i64)> = None;
    let mut run_len = 0usize;
    for (t, v) in points {
        let Some(v) = v.filter(|v| v.is_finite()) else {
            if run_len == 1 {
                d.push_str("h0");
            }
            last = None;
            run_len = 0;
            continue;
        };
        let p = ((t * xs).round() as i64, (-v * ys).round() as i64);
        match last {
            None => {
                let _ = write!(d, "M{} {}", p.0, p.1);
                run_len = 1;
            }
            Some(q) => {
                if run_len == 1 {
                    d.push('l');
                } else {
                    push_sep(&mut d, p.0 - q.0);
                }
                let _ = write!(d, "{}", p.0 - q.0);
                push_sep(&mut d, p.1 - q.1);
                let _ = write!(d, "{}", p.1 - q.1);
                run_len += 1;
            }
        }
        last = Some(p);
    }
    if run_len == 1 {
        d.push_str("h0");
    }
    d
}

/// A space before a non-negative number (a minus sign separates by itself).
fn push_sep(d: &mut String, v: i64) {
    if v >= 0 {
        d.push(' ');
    }
}

/// `d` of a closed band: the high edge forward, the low edge back.
fn band_d(points: &[(f64, f64, f64)], xs: f64, ys: f64) -> String {
    let mut d = String::new();
    let pt = |x: f64, y: f64| ((x * xs).round() as i64, (-y * ys).round() as i64);
    for (i, (x, _, hi)) in points.iter().enumerate() {
        let (a, b) = pt(*x, *hi);
        let _ = write!(d, "{}{a} {b}", if i == 0 { "M" } else { "L" });
    }
    for (x, lo, _) in points.iter().rev() {
        let (a, b) = pt(*x, *lo);
        let _ = write!(d, "L{a} {b}");
    }
    if !points.is_empty() {
        d.push('Z');
    }
    d
}

/// Escapes text for HTML/SVG content and attribute values.
pub fn esc(text: &str) -> String {
    let mut s = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => s.push_str("&amp;"),
            '<' => s.push_str("&lt;"),
            '>' => s.push_str("&gt;"),
            '"' => s.push_str("&quot;"),
            '\'' => s.push_str("&#39;"),
            c => s.push(c),
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Decodes a `line_d` string back to absolute integer points (the
    /// page's script does the same).
    fn decode(d: &str) -> Vec<Vec<(i64, i64)>> {
        let mut runs = Vec::new();
        let mut nums = Vec::new();
        let mut cur = String::new();
        let mut cmds = Vec::new();
        for c in d.chars() {
            if c.is_ascii_digit() {
                cur.push(c);
                continue;
            }
            if !cur.is_empty() && cur != "-" {
                nums.push(cur.parse::<i64>().unwrap());
            }
            cur.clear();
            if c == '-' {
                cur.push('-');
            } else if c.is_ascii_alphabetic() {
                cmds.push((c, nums.len()));
            }
        }
        if !cur.is_empty() {
            nums.push(cur.parse().unwrap());
        }
        cmds.push(('$', nums.len()));
        let mut run: Vec<(i64, i64)> = Vec::new();
        for w in cmds.windows(2) {
            let (c, a) = w[0];
            let b = w[1].1;
            match c {
                'M' => {
                    if !run.is_empty() {
                        runs.push(std::mem::take(&mut run));
                    }
                    run.push((nums[a], nums[a + 1]));
                }
                'l' => {
                    for k in (a..b).step_by(2) {
                        let (x, y) = *run.last().unwrap();
                        run.push((x + nums[k], y + nums[k + 1]));
                    }
                }
                'h' => {}
                _ => panic!("command {c}"),
            }
        }
        if !run.is_empty() {
            runs.push(run);
        }
        runs
    }

    #[test]
    fn line_paths_decode_to_the_rounded_points_with_breaks() {
        let pts: Points = vec![
            (0.0, Some(1.234)),
            (0.01, Some(-2.5)),
            (0.02, Some(0.004)),
            (0.03, None),
            (0.04, Some(7.0)),
            (0.05, None),
            (0.06, Some(1.0)),
            (0.07, Some(1.0)),
        ];
        let d = line_d(&pts, 1000.0, 100.0);
        let runs = decode(&d);
        assert_eq!(
            runs,
            vec![
                vec![(0, -123), (10, 250), (20, 0)],
                vec![(40, -700)],
                vec![(60, -100), (70, -100)],
            ],
            "{d}"
        );
    }

    #[test]
    fn rounding_does_not_accumulate() {
        let pts: Points = (0..1000)
            .map(|i| (i as f64 * 0.013, Some(0.0049)))
            .collect();
        let runs = decode(&line_d(&pts, 1000.0, 100.0));
        assert_eq!(runs[0].last(), Some(&(13 * 999, 0)));
    }

    #[test]
    fn y_scale_gives_about_ten_thousand_levels() {
        assert_eq!(y_scale(60.0), 100.0);
        assert_eq!(y_scale(1.0), 10_000.0);
        assert_eq!(y_scale(0.2), 10_000.0);
    }

    #[test]
    fn the_minimum_y_span_is_one_unit_or_the_whole_range() {
        assert_eq!(min_y_span(60.0), 1.0);
        assert_eq!(min_y_span(1.0), 1.0);
        assert_eq!(min_y_span(0.05), 0.05);
        assert_eq!(min_y_span(0.0), 1.0);
    }

    #[test]
    fn text_is_escaped() {
        assert_eq!(
            esc(r#"<a href="x">&'"#),
            "&lt;a href=&quot;x&quot;&gt;&amp;&#39;"
        );
    }

    #[test]
    fn a_series_that_starts_late_keeps_the_whole_time_axis() {
        let plot = Plot {
            id: "p".into(),
            kind: "speed".into(),
            title: String::new(),
            x_label: String::new(),
            y_label: String::new(),
            x_scale: 1.0,
            zoomable: true,
            lines: vec![Line {
                key: "e0".into(),
                label: String::new(),
                color: String::new(),
                points: vec![(0.0, None), (1.4, Some(1.0)), (2.0, Some(1.2)), (3.0, None)],
                dashed: false,
            }],
            bands: Vec::new(),
            y_clip: None,
        };
        let ([x0, x1], [y0, y1]) = plot.ranges().unwrap();
        assert_eq!((x0, x1), (0.0, 3.0));
        assert!(y0 <= 1.0 && y1 >= 1.2);
    }

    /// A constant written with rounding (reference 90.0000002 deg, estimate
    /// 89.99999998) is plotted as a constant: 90 +- 0.5, y scale 1e4 (it was
    /// 1e10, coordinates of 9e11 that a browser could not draw).
    #[test]
    fn a_constant_with_rounding_is_plotted_as_a_constant() {
        let line = |key: &str, v: f64| Line {
            key: key.into(),
            label: String::new(),
            color: String::new(),
            points: vec![(0.0, Some(v)), (1.0, Some(v))],
            dashed: false,
        };
        let plot = Plot {
            id: "p".into(),
            kind: "angle".into(),
            title: String::new(),
            x_label: String::new(),
            y_label: String::new(),
            x_scale: 1.0,
            zoomable: true,
            lines: vec![line("ref", 90.000_000_2), line("e0", 89.999_999_98)],
            bands: Vec::new(),
            y_clip: None,
        };
        let (_, [y0, y1]) = plot.ranges().unwrap();
        assert!(
            (y0 - 89.5).abs() < 1e-6 && (y1 - 90.5).abs() < 1e-6,
            "{y0} {y1}"
        );
        assert!(plot.render().contains(r#"data-y-scale="10000""#));
        // the page's script keeps that 1 deg window (1e4 y units)
        assert!(plot.render().contains(r#"data-min-y-span="10000""#));
        // a real spread keeps its own scale
        let mut small = plot.clone();
        small.lines[1] = line("e0", 89.99);
        let (_, [y0, y1]) = small.ranges().unwrap();
        assert!(y0 < 89.99 && y1 > 90.0 && y1 - y0 < 0.02, "{y0} {y1}");
    }
}
