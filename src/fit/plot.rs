//! The fit's picture as SVG: the measured points, the run at the start (dashed) and the fitted
//! run (solid), in the measured units, with ticks at 1, 2 or 5 × 10ᵏ.

use std::fmt::Write;

/// One drawn series.
pub struct Series<'a> {
    pub label: &'a str,
    pub y: &'a [f64],
    pub colour: &'a str,
    /// Points (markers) instead of a line.
    pub points: bool,
    pub dashed: bool,
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

/// The SVG document of `series` against `x`, titled, with axis labels.
pub fn svg(title: &str, x_label: &str, y_label: &str, x: &[f64], series: &[Series<'_>]) -> String {
    let (w, h) = (760.0, 480.0);
    let (left, right, top, bottom) = (90.0, 20.0, 40.0, 60.0);
    let fin = |v: &&f64| v.is_finite();
    let xmin = x.iter().filter(fin).fold(f64::INFINITY, |a, v| a.min(*v));
    let xmax = x
        .iter()
        .filter(fin)
        .fold(f64::NEG_INFINITY, |a, v| a.max(*v));
    let all_y = series.iter().flat_map(|s| s.y.iter()).filter(fin);
    let (mut ymin, mut ymax) = all_y.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
        (a.min(*v), b.max(*v))
    });
    ymin = ymin.min(0.0);
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
        esc(title)
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
        esc(x_label)
    );
    let _ = writeln!(
        s,
        r#"<text transform="translate(22,{:.1}) rotate(-90)" text-anchor="middle">{}</text>"#,
        (top + h - bottom) / 2.0,
        esc(y_label)
    );
    for ser in series {
        let pts: Vec<(f64, f64)> = x
            .iter()
            .zip(ser.y)
            .filter(|(a, b)| a.is_finite() && b.is_finite())
            .map(|(a, b)| (px(*a), py(*b)))
            .collect();
        if ser.points {
            for (a, b) in &pts {
                let _ = writeln!(
                    s,
                    r#"<circle cx="{a:.1}" cy="{b:.1}" r="2.5" fill="{}"/>"#,
                    ser.colour
                );
            }
        } else {
            let path: Vec<String> = pts.iter().map(|(a, b)| format!("{a:.1},{b:.1}")).collect();
            let _ = writeln!(
                s,
                r#"<polyline points="{}" fill="none" stroke="{}" stroke-width="2"{}/>"#,
                path.join(" "),
                ser.colour,
                if ser.dashed {
                    r#" stroke-dasharray="6,4""#
                } else {
                    ""
                }
            );
        }
    }
    let _ = writeln!(
        s,
        r##"<rect x="{:.1}" y="{:.1}" width="192" height="{:.1}" fill="white" fill-opacity="0.85" stroke="#bbb"/>"##,
        w - right - 206.0,
        top + 6.0,
        18.0 * series.len() as f64 + 6.0
    );
    for (k, ser) in series.iter().enumerate() {
        let ly = top + 18.0 + 18.0 * k as f64;
        let lx = w - right - 200.0;
        let _ = writeln!(
            s,
            r#"<line x1="{lx}" y1="{ly}" x2="{}" y2="{ly}" stroke="{}" stroke-width="{}"{}/><text x="{}" y="{}">{}</text>"#,
            lx + 24.0,
            ser.colour,
            if ser.points { 5 } else { 2 },
            if ser.dashed {
                r#" stroke-dasharray="6,4""#
            } else {
                ""
            },
            lx + 30.0,
            ly + 4.0,
            esc(ser.label)
        );
    }
    s.push_str("</svg>\n");
    s
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
        let x = [0.0, 1.0, 2.0];
        let s = svg(
            "fit <a>",
            "u [mm]",
            "F [N]",
            &x,
            &[
                Series {
                    label: "measured",
                    y: &[0.0, 1.0, 0.5],
                    colour: "black",
                    points: true,
                    dashed: false,
                },
                Series {
                    label: "fitted",
                    y: &[0.0, 0.9, 0.6],
                    colour: "red",
                    points: false,
                    dashed: false,
                },
            ],
        );
        assert_eq!(s.matches("<circle").count(), 3);
        assert_eq!(s.matches("<polyline").count(), 1);
        assert!(s.contains("fit &lt;a&gt;"));
        let mut r = quick_xml::Reader::from_str(&s);
        loop {
            match r.read_event().expect("well-formed SVG") {
                quick_xml::events::Event::Eof => break,
                _ => continue,
            }
        }
    }
}
