//! A plot as data, drawn as SVG or written as CSV: the fit's picture (`fit.svg`) and the
//! explorer's figures for slides (every plot's *save SVG* and *save CSV*). Series of points
//! (x, y), each a line (solid, dashed or dotted) or markers, in its colour; ticks at 1, 2 or
//! 5 × 10ᵏ.

use std::fmt::Write;

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Style {
    Solid,
    Dashed,
    Dotted,
    /// Markers at the points, no line.
    Points,
}

/// One drawn series.
#[derive(Debug, Clone, PartialEq)]
pub struct Trace {
    pub label: String,
    pub points: Vec<[f64; 2]>,
    /// sRGB.
    pub colour: [u8; 3],
    pub style: Style,
}

/// A plot: a title, the axes' labels and its series.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Figure {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub traces: Vec<Trace>,
}

/// Tick positions covering [lo, hi]: about five, at a step of 1, 2 or 5 × 10ᵏ.
pub fn ticks(lo: f64, hi: f64) -> Vec<f64> {
    if !(hi > lo) {
        return vec![lo];
    }
    let raw = (hi - lo) / 5.0;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * mag);
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    (first..=last).map(|k| k as f64 * step).collect()
}

/// A tick label: the shortest of `{}` and `{:e}` at 4 significant digits.
fn label(v: f64) -> String {
    let v = if v.abs() < 1e-300 { 0.0 } else { v };
    let plain = format!("{}", (v * 1e4).round() / 1e4);
    let sci = format!("{v:.3e}");
    if plain.len() <= 8 && (v == 0.0 || v.abs() >= 1e-3) {
        plain
    } else {
        sci
    }
}

/// Escapes the text of an SVG element.
fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

impl Figure {
    /// A series added to the figure.
    pub fn trace(&mut self, label: &str, points: Vec<[f64; 2]>, colour: [u8; 3], style: Style) {
        self.traces.push(Trace {
            label: label.to_string(),
            points,
            colour,
            style,
        });
    }

    /// The figure as CSV, one row per point: `series,x,y` with the axes' labels in the header
    /// (commas in a label are written as semicolons).
    pub fn csv(&self) -> String {
        let field = |s: &str| s.replace([',', '\n'], ";");
        let mut s = format!(
            "# {}\nseries,{},{}\n",
            field(&self.title),
            field(&self.x_label),
            field(&self.y_label)
        );
        for t in &self.traces {
            for [x, y] in &t.points {
                let _ = writeln!(s, "{},{x:?},{y:?}", field(&t.label));
            }
        }
        s
    }

    /// The SVG document of the figure: white background, the title, ticks, the axes' labels,
    /// every series and a legend. Non-finite points are left out.
    pub fn svg(&self) -> String {
        let (w, h) = (760.0, 480.0);
        let (left, right, top, bottom) = (90.0, 20.0, 40.0, 60.0);
        let finite = || {
            self.traces
                .iter()
                .flat_map(|t| t.points.iter())
                .filter(|p| p[0].is_finite() && p[1].is_finite())
        };
        let (xmin, xmax) = finite().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p[0]), b.max(p[0]))
        });
        let (mut ymin, mut ymax) = finite()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
                (a.min(p[1]), b.max(p[1]))
            });
        let xmin = if xmin.is_finite() { xmin } else { 0.0 };
        ymin = if ymin.is_finite() { ymin.min(0.0) } else { 0.0 };
        if !(ymax > ymin) {
            ymax = ymin + 1.0;
        }
        let pad = 0.05 * (ymax - ymin);
        let (ymin, ymax) = (ymin - if ymin < 0.0 { pad } else { 0.0 }, ymax + pad);
        let xmax = if xmax > xmin { xmax } else { xmin + 1.0 };
        let px = |v: f64| left + (v - xmin) / (xmax - xmin) * (w - left - right);
        let py = |v: f64| h - bottom - (v - ymin) / (ymax - ymin) * (h - top - bottom);
        let mut s = String::new();
        let _ = writeln!(
            s,
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="sans-serif" font-size="13">"#
        );
        let _ = writeln!(s, r#"<rect width="{w}" height="{h}" fill="white"/>"#);
        let _ = writeln!(
            s,
            r#"<text x="{}" y="24" text-anchor="middle" font-size="15">{}</text>"#,
            w / 2.0,
            esc(&self.title)
        );
        for t in ticks(xmin, xmax) {
            let x = px(t);
            let _ = writeln!(
                s,
                r##"<line x1="{x:.1}" y1="{top}" x2="{x:.1}" y2="{:.1}" stroke="#ddd"/><text x="{x:.1}" y="{:.1}" text-anchor="middle">{}</text>"##,
                h - bottom,
                h - bottom + 18.0,
                label(t)
            );
        }
        for t in ticks(ymin, ymax) {
            let y = py(t);
            let _ = writeln!(
                s,
                r##"<line x1="{left}" y1="{y:.1}" x2="{:.1}" y2="{y:.1}" stroke="#ddd"/><text x="{:.1}" y="{:.1}" text-anchor="end">{}</text>"##,
                w - right,
                left - 6.0,
                y + 4.0,
                label(t)
            );
        }
        let _ = writeln!(
            s,
            r#"<rect x="{left}" y="{top}" width="{:.1}" height="{:.1}" fill="none" stroke="black"/>"#,
            w - left - right,
            h - top - bottom
        );
        let _ = writeln!(
            s,
            r#"<text x="{:.1}" y="{:.1}" text-anchor="middle">{}</text>"#,
            (left + w - right) / 2.0,
            h - 16.0,
            esc(&self.x_label)
        );
        let _ = writeln!(
            s,
            r#"<text transform="translate(22,{:.1}) rotate(-90)" text-anchor="middle">{}</text>"#,
            (top + h - bottom) / 2.0,
            esc(&self.y_label)
        );
        let dash = |style: Style| match style {
            Style::Dashed => r#" stroke-dasharray="6,4""#,
            Style::Dotted => r#" stroke-dasharray="2,3""#,
            _ => "",
        };
        for t in &self.traces {
            let colour = hex(t.colour);
            let pts: Vec<(f64, f64)> = (t.points.iter())
                .filter(|p| p[0].is_finite() && p[1].is_finite())
                .map(|p| (px(p[0]), py(p[1])))
                .collect();
            if t.style == Style::Points {
                for (a, b) in &pts {
                    let _ = writeln!(
                        s,
                        r#"<circle cx="{a:.1}" cy="{b:.1}" r="2.5" fill="{colour}"/>"#
                    );
                }
            } else {
                let path: Vec<String> = pts.iter().map(|(a, b)| format!("{a:.1},{b:.1}")).collect();
                let _ = writeln!(
                    s,
                    r#"<polyline points="{}" fill="none" stroke="{colour}" stroke-width="2"{}/>"#,
                    path.join(" "),
                    dash(t.style)
                );
            }
        }
        let _ = writeln!(
            s,
            r##"<rect x="{:.1}" y="{:.1}" width="192" height="{:.1}" fill="white" fill-opacity="0.85" stroke="#bbb"/>"##,
            w - right - 206.0,
            top + 6.0,
            18.0 * self.traces.len() as f64 + 6.0
        );
        for (k, t) in self.traces.iter().enumerate() {
            let ly = top + 18.0 + 18.0 * k as f64;
            let lx = w - right - 200.0;
            let _ = writeln!(
                s,
                r#"<line x1="{lx}" y1="{ly}" x2="{}" y2="{ly}" stroke="{}" stroke-width="{}"{}/><text x="{}" y="{}">{}</text>"#,
                lx + 24.0,
                hex(t.colour),
                if t.style == Style::Points { 5 } else { 2 },
                dash(t.style),
                lx + 30.0,
                ly + 4.0,
                esc(&t.label)
            );
        }
        s.push_str("</svg>\n");
        s
    }
}

/// `#rrggbb`.
fn hex(c: [u8; 3]) -> String {
    format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_step_by_one_two_or_five() {
        assert_eq!(
            ticks(0.0, 1.0),
            [0.0, 0.2, 0.4, 0.6000000000000001, 0.8, 1.0]
        );
        // 3.3e-4 / 5 = 6.6e-5: the step is 1e-4.
        let t = ticks(0.0, 3.3e-4);
        assert_eq!(t.len(), 4);
        assert!((t[1] - 1e-4).abs() < 1e-20);
    }

    #[test]
    fn draws_every_series_and_parses_as_xml() {
        let mut f = Figure {
            title: "fit <a>".into(),
            x_label: "u [mm]".into(),
            y_label: "F [N]".into(),
            ..Default::default()
        };
        f.trace(
            "measured",
            vec![[0.0, 0.0], [1.0, 1.0], [2.0, 0.5]],
            [0, 0, 0],
            Style::Points,
        );
        f.trace(
            "fitted, run 2",
            vec![[0.0, 0.0], [1.0, 0.9], [2.0, f64::NAN]],
            [214, 39, 40],
            Style::Dashed,
        );
        let s = f.svg();
        assert_eq!(s.matches("<circle").count(), 3);
        assert_eq!(s.matches("<polyline").count(), 1);
        assert!(s.contains("fit &lt;a&gt;") && s.contains("#d62728"));
        let mut r = quick_xml::Reader::from_str(&s);
        loop {
            match r.read_event().expect("well-formed SVG") {
                quick_xml::events::Event::Eof => break,
                _ => continue,
            }
        }
        let csv = f.csv();
        let rows: Vec<&str> = csv.lines().collect();
        assert_eq!(rows[1], "series,u [mm],F [N]");
        assert_eq!(rows.len(), 2 + 6);
        assert_eq!(rows[3], "measured,1.0,1.0");
        assert_eq!(rows[7], "fitted; run 2,2.0,NaN");
    }
}
