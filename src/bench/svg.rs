//! Minimal SVG line plots for the bench report: series of (x, y) points, optional log axes,
//! a legend. Hand-written because a plotting crate would double the dependency tree.

use std::fmt::Write as _;

/// One named line of points.
#[derive(Debug, Clone)]
pub struct Series {
    pub name: String,
    pub points: Vec<(f64, f64)>,
}

/// A plot: title, axis labels, log scales, series.
#[derive(Debug, Clone)]
pub struct Plot {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub log_x: bool,
    pub log_y: bool,
    pub series: Vec<Series>,
}

const W: f64 = 720.0;
const H: f64 = 440.0;
const LEFT: f64 = 70.0;
const RIGHT: f64 = 170.0;
const TOP: f64 = 40.0;
const BOTTOM: f64 = 50.0;
const COLORS: [&str; 12] = [
    "#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f",
    "#bcbd22", "#17becf", "#000000", "#aa3377",
];

fn axis(v: f64, log: bool) -> Option<f64> {
    match (log, v) {
        (true, v) if v > 0.0 && v.is_finite() => Some(v.log10()),
        (false, v) if v.is_finite() => Some(v),
        _ => None,
    }
}

impl Plot {
    /// Renders the plot; points that cannot be drawn (log of 0, NaN) are left out.
    pub fn to_svg(&self) -> String {
        let pts: Vec<(f64, f64)> = self
            .series
            .iter()
            .flat_map(|s| s.points.iter())
            .filter_map(|&(x, y)| Some((axis(x, self.log_x)?, axis(y, self.log_y)?)))
            .collect();
        let (mut x0, mut x1, mut y0, mut y1) = pts.iter().fold(
            (f64::MAX, f64::MIN, f64::MAX, f64::MIN),
            |(a, b, c, d), &(x, y)| (a.min(x), b.max(x), c.min(y), d.max(y)),
        );
        if pts.is_empty() {
            (x0, x1, y0, y1) = (0.0, 1.0, 0.0, 1.0);
        }
        let pad = |lo: f64, hi: f64| {
            if hi - lo < 1e-12 {
                (lo - 0.5, hi + 0.5)
            } else {
                (lo, hi)
            }
        };
        let ((x0, x1), (y0, y1)) = (pad(x0, x1), pad(y0, y1));
        let px = |x: f64| LEFT + (x - x0) / (x1 - x0) * (W - LEFT - RIGHT);
        let py = |y: f64| H - BOTTOM - (y - y0) / (y1 - y0) * (H - TOP - BOTTOM);
        let mut out = format!(
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{W}\" height=\"{H}\" font-family=\"sans-serif\" font-size=\"12\">\n\
             <rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n\
             <text x=\"{}\" y=\"22\" text-anchor=\"middle\" font-size=\"15\">{}</text>\n",
            (W - RIGHT + LEFT) / 2.0,
            escape(&self.title)
        );
        self.write_axes(&mut out, (x0, x1, y0, y1), &px, &py);
        for (k, s) in self.series.iter().enumerate() {
            let color = COLORS[k % COLORS.len()];
            let line: Vec<String> = s
                .points
                .iter()
                .filter_map(|&(x, y)| {
                    Some(format!(
                        "{:.1},{:.1}",
                        px(axis(x, self.log_x)?),
                        py(axis(y, self.log_y)?)
                    ))
                })
                .collect();
            let _ = writeln!(
                out,
                "<polyline fill=\"none\" stroke=\"{color}\" stroke-width=\"1.5\" points=\"{}\"/>",
                line.join(" ")
            );
            for p in &line {
                let (x, y) = p.split_once(',').unwrap_or(("0", "0"));
                let _ = writeln!(
                    out,
                    "<circle cx=\"{x}\" cy=\"{y}\" r=\"3\" fill=\"{color}\"/>"
                );
            }
            let ly = TOP + 16.0 * k as f64;
            let _ = writeln!(
                out,
                "<rect x=\"{}\" y=\"{}\" width=\"12\" height=\"4\" fill=\"{color}\"/><text x=\"{}\" y=\"{}\">{}</text>",
                W - RIGHT + 15.0,
                ly - 4.0,
                W - RIGHT + 32.0,
                ly,
                escape(&s.name)
            );
        }
        out.push_str("</svg>\n");
        out
    }

    fn write_axes(
        &self,
        out: &mut String,
        (x0, x1, y0, y1): (f64, f64, f64, f64),
        px: &dyn Fn(f64) -> f64,
        py: &dyn Fn(f64) -> f64,
    ) {
        let (bx, by) = (H - BOTTOM, LEFT);
        let _ = writeln!(
            out,
            "<line x1=\"{LEFT}\" y1=\"{bx}\" x2=\"{}\" y2=\"{bx}\" stroke=\"black\"/>",
            W - RIGHT
        );
        let _ = writeln!(
            out,
            "<line x1=\"{by}\" y1=\"{TOP}\" x2=\"{by}\" y2=\"{bx}\" stroke=\"black\"/>"
        );
        for k in 0..=4 {
            let t = k as f64 / 4.0;
            let (xv, yv) = (x0 + t * (x1 - x0), y0 + t * (y1 - y0));
            let label = |v: f64, log: bool| {
                if log {
                    format_num(10f64.powf(v))
                } else {
                    format_num(v)
                }
            };
            let _ = writeln!(
                out,
                "<text x=\"{:.1}\" y=\"{}\" text-anchor=\"middle\">{}</text>",
                px(xv),
                bx + 16.0,
                label(xv, self.log_x)
            );
            let _ = writeln!(
                out,
                "<text x=\"{}\" y=\"{:.1}\" text-anchor=\"end\">{}</text>",
                by - 6.0,
                py(yv) + 4.0,
                label(yv, self.log_y)
            );
        }
        let log_note = |log: bool| if log { " (log)" } else { "" };
        let _ = writeln!(
            out,
            "<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">{}{}</text>",
            (W - RIGHT + LEFT) / 2.0,
            H - 12.0,
            escape(&self.x_label),
            log_note(self.log_x)
        );
        let _ = writeln!(
            out,
            "<text x=\"16\" y=\"{}\" text-anchor=\"middle\" transform=\"rotate(-90 16 {})\">{}{}</text>",
            H / 2.0,
            H / 2.0,
            escape(&self.y_label),
            log_note(self.log_y)
        );
    }
}

pub(crate) fn format_num(v: f64) -> String {
    if v == 0.0 {
        "0".into()
    } else if v.abs() >= 100.0 {
        format!("{v:.0}")
    } else if v.abs() >= 1.0 {
        format!("{v:.2}")
    } else {
        format!("{v:.3e}")
    }
}

pub(crate) fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plots_every_drawable_point() {
        let plot = Plot {
            title: "a < b".into(),
            x_label: "ms".into(),
            y_label: "error".into(),
            log_x: true,
            log_y: true,
            series: vec![
                Series {
                    name: "pom".into(),
                    points: vec![(1.0, 0.5), (2.0, 0.25), (0.0, 1.0)],
                },
                Series {
                    name: "qdm".into(),
                    points: vec![(3.0, f64::NAN), (4.0, 0.01)],
                },
            ],
        };
        let svg = plot.to_svg();
        assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
        assert!(svg.contains("a &lt; b"), "titles are escaped");
        // log(0) and NaN are dropped: 2 + 1 drawable points.
        assert_eq!(svg.matches("<circle").count(), 3);
        assert!(!svg.contains("NaN") && !svg.contains("inf"));
    }
}
