//! The comparison as an SVG: one row per cell, its ratio NEW/BASE as a dot on a log axis with
//! its interval as a bar, the band of no practical change shaded and 1 marked, colour by verdict.

use std::fmt::Write as _;

use super::{Comparison, Verdict};
use crate::bench::svg::{escape, format_num};

const WIDTH: f64 = 980.0;
const LABEL_W: f64 = 470.0;
const RIGHT: f64 = 30.0;
const TOP: f64 = 50.0;
const ROW: f64 = 16.0;
const BOTTOM: f64 = 50.0;

fn colour(verdict: Verdict, same_device: bool) -> &'static str {
    match (same_device, verdict) {
        (false, _) => "#1f77b4",
        (true, Verdict::Slower) => "#d62728",
        (true, Verdict::Faster) => "#2ca02c",
        (true, Verdict::WithinNoise) => "#7f7f7f",
    }
}

/// The plot; cells without a ratio get a row with its label and no mark.
pub fn ratio_plot(c: &Comparison) -> String {
    let up = 1.0 + c.min_effect;
    let finite = |v: f64| v.is_finite() && v > 0.0;
    let ends = c
        .cells
        .iter()
        .filter_map(|x| x.interval)
        .flat_map(|i| [i.low, i.high, i.ratio])
        .filter(|v| finite(*v));
    let (lo, hi) = ends.fold((1.0 / up, up), |(a, b), v| (a.min(v), b.max(v)));
    let (x0, x1) = ((lo / 1.1).ln(), (hi * 1.1).ln());
    let plot_w = WIDTH - LABEL_W - RIGHT;
    let px = |v: f64| LABEL_W + (v.clamp(lo / 1.1, hi * 1.1).ln() - x0) / (x1 - x0) * plot_w;
    let height = TOP + ROW * c.cells.len().max(1) as f64 + BOTTOM;
    let bottom = height - BOTTOM;
    let mut out = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{WIDTH}\" height=\"{height}\" font-family=\"sans-serif\" font-size=\"11\">\n\
         <rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n\
         <text x=\"{}\" y=\"22\" text-anchor=\"middle\" font-size=\"14\">{}</text>\n",
        WIDTH / 2.0,
        escape(&format!(
            "NEW/BASE GPU time per cell: {} vs {}",
            c.new.device.name, c.base.device.name
        ))
    );
    let _ = writeln!(
        out,
        "<rect x=\"{:.1}\" y=\"{TOP}\" width=\"{:.1}\" height=\"{:.1}\" fill=\"#eeeeee\"/>",
        px(1.0 / up),
        px(up) - px(1.0 / up),
        bottom - TOP
    );
    let _ = writeln!(
        out,
        "<line x1=\"{0:.1}\" y1=\"{TOP}\" x2=\"{0:.1}\" y2=\"{bottom}\" stroke=\"black\"/>",
        px(1.0)
    );
    for k in 0..=4 {
        let v = (x0 + (x1 - x0) * f64::from(k) / 4.0).exp();
        let _ = writeln!(
            out,
            "<text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"middle\">{}</text>",
            px(v),
            bottom + 16.0,
            format_num(v)
        );
    }
    let _ = writeln!(
        out,
        "<text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"middle\">NEW/BASE (log), shaded: within +-{:.0}%</text>",
        LABEL_W + plot_w / 2.0,
        height - 12.0,
        100.0 * c.min_effect
    );
    for (k, cell) in c.cells.iter().enumerate() {
        let y = TOP + ROW * (k as f64 + 0.5);
        let _ = writeln!(
            out,
            "<text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"end\">{}</text>",
            LABEL_W - 8.0,
            y + 4.0,
            escape(&cell.key.to_string())
        );
        let Some(i) = cell.interval else { continue };
        let col = colour(cell.verdict, c.same_device);
        let _ = writeln!(
            out,
            "<line x1=\"{:.1}\" y1=\"{y:.1}\" x2=\"{:.1}\" y2=\"{y:.1}\" stroke=\"{col}\" stroke-width=\"2\"/>\
             <circle cx=\"{:.1}\" cy=\"{y:.1}\" r=\"3.5\" fill=\"{col}\"/>",
            px(i.low),
            px(i.high),
            px(i.ratio)
        );
    }
    out.push_str("</svg>\n");
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bench::compare::compare;
    use crate::bench::results_fixture::{device, results, run};

    #[test]
    fn every_cell_gets_a_labelled_row_and_slower_ones_are_red() {
        let base = results(
            device("gpu"),
            vec![
                run("pom", 30.0, &[1.0, 1.01, 0.99, 1.0, 1.0, 1.0], 0.1),
                run("qdm", 30.0, &[1.0, 1.0], 0.1),
            ],
        );
        let new = results(
            device("gpu"),
            vec![
                run("pom", 30.0, &[2.0, 2.02, 1.98, 2.0, 2.0, 2.0], 0.1),
                run("qdm", 30.0, &[1.0, 1.0], 0.1),
            ],
        );
        let svg = ratio_plot(&compare(&base, &new, 0.05));
        assert!(svg.starts_with("<svg") && svg.ends_with("</svg>\n"));
        assert!(svg.contains("error_vs_time pom") && svg.contains("error_vs_time qdm"));
        assert_eq!(svg.matches("<circle").count(), 2);
        assert!(svg.contains("#d62728"), "the slower cell is red");
        assert!(!svg.contains("NaN") && !svg.contains("inf"));
    }
}
