//! The cost curve over depth scale: every method at its default budget on one field, size and
//! view, at each depth scale of the sweep, with the exponent `k` of `cost ~ depth^k` fitted for
//! time, iterations and texel fetches. A deeper field lengthens every ray's path through the
//! slab, so a fixed-step march pays nothing more (its cap is fixed) while a walk that steps
//! texel by texel or node by node pays for the texels the ray now crosses.

use std::fmt::Write as _;

use super::cost_curve::fitted_exponent;
use super::results::{BenchResults, Run};
use super::runner::Section;
use crate::method::Method;

/// One method's curve: its points in increasing depth and the fitted exponents.
#[derive(Debug, Clone, PartialEq)]
pub struct DepthCurve {
    /// Method id.
    pub method: String,
    /// (depth scale, GPU ms median, mean steps per ray, mean fetches per ray), by depth.
    pub points: Vec<(f64, f64, f64, f64)>,
    /// k of time ~ depth^k; `None` with fewer than two depths.
    pub k_time: Option<f64>,
    /// k of the mean steps per ray.
    pub k_steps: Option<f64>,
    /// k of the mean texel fetches per ray (absent in files without fetch counts).
    pub k_fetches: Option<f64>,
}

/// Every method's curve from `results`' depth-curve runs, methods in table order.
pub fn depth_curves(results: &BenchResults) -> Vec<DepthCurve> {
    let runs: Vec<&Run> = results
        .runs
        .iter()
        .filter(|r| r.section == Section::DepthCurve)
        .collect();
    Method::all()
        .filter_map(|m| {
            let mut mine: Vec<&Run> = runs
                .iter()
                .copied()
                .filter(|r| r.method == m.id())
                .collect();
            if mine.is_empty() {
                return None;
            }
            mine.sort_by(|a, b| a.depth_scale.total_cmp(&b.depth_scale));
            let points: Vec<(f64, f64, f64, f64)> = mine
                .iter()
                .map(|r| (r.depth_scale, r.gpu_ms.median, r.steps.mean, r.fetches.mean))
                .collect();
            let fit = |value: fn(&(f64, f64, f64, f64)) -> f64| {
                let xy: Vec<(f64, f64)> = points.iter().map(|p| (p.0, value(p))).collect();
                fitted_exponent(&xy)
            };
            Some(DepthCurve {
                method: m.id().to_owned(),
                k_time: fit(|p| p.1),
                k_steps: fit(|p| p.2),
                k_fetches: fit(|p| p.3),
                points,
            })
        })
        .collect()
}

fn exponent(k: Option<f64>) -> String {
    k.map_or("-".into(), |k| format!("{k:.3}"))
}

/// The section's table: GPU ms per depth scale, and the three exponents.
pub fn report(md: &mut String, results: &BenchResults) {
    let curves = depth_curves(results);
    let Some(first) = results
        .runs
        .iter()
        .find(|r| r.section == Section::DepthCurve)
    else {
        return;
    };
    let depths: Vec<f64> = curves[0].points.iter().map(|p| p.0).collect();
    let _ = writeln!(md, "## Cost against depth scale\n");
    let _ = writeln!(
        md,
        "GPU ms of the timed pass with default budgets on {} {}^2 at {} deg, per depth scale; k is \
         the exponent of cost ~ depth^k fitted by least squares over every depth, for time, the \
         mean iterations per ray and the mean texel fetches per ray (0: the cost does not grow \
         with depth; 1: linear in it).\n",
        first.heightfield, first.size[0], first.angle_deg
    );
    let head: Vec<String> = depths.iter().map(|d| format!("{d}")).collect();
    let _ = writeln!(
        md,
        "| method | {} | k time | k steps | k fetches |",
        head.join(" | ")
    );
    let _ = writeln!(md, "|---|{}---|---|---|", "---|".repeat(depths.len()));
    for c in &curves {
        let cells: Vec<String> = depths
            .iter()
            .map(|d| {
                c.points
                    .iter()
                    .find(|p| p.0 == *d)
                    .map_or("-".into(), |p| format!("{:.3}", p.1))
            })
            .collect();
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} |",
            c.method,
            cells.join(" | "),
            exponent(c.k_time),
            exponent(c.k_steps),
            exponent(c.k_fetches)
        );
    }
    md.push('\n');
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bench::results_fixture::{device, results, run};

    #[test]
    fn each_method_gets_its_points_by_depth_and_their_exponents() {
        let point = |method: &str, depth: f64, ms: f64, steps: f64| {
            let mut r = run(method, 30.0, &[ms], 0.1);
            r.section = Section::DepthCurve;
            r.depth_scale = depth;
            r.steps.mean = steps;
            r.fetches.mean = 2.0 * steps;
            r
        };
        let results = results(
            device("lavapipe"),
            vec![
                point("qdm", 0.4, 8.0, 16.0),
                point("qdm", 0.1, 2.0, 8.0),
                point("pom", 0.1, 5.0, 32.0),
                point("pom", 0.4, 5.0, 32.0),
            ],
        );
        let curves = depth_curves(&results);
        assert_eq!(curves.len(), 2);
        assert_eq!(curves[0].method, "pom", "table order");
        assert_eq!(curves[0].k_time, Some(0.0));
        assert_eq!(curves[1].points[0].0, 0.1, "sorted by depth");
        assert!((curves[1].k_time.unwrap() - 1.0).abs() < 1e-12);
        assert!((curves[1].k_steps.unwrap() - 0.5).abs() < 1e-12);
        assert!((curves[1].k_fetches.unwrap() - 0.5).abs() < 1e-12);
        let mut md = String::new();
        report(&mut md, &results);
        assert!(
            md.contains("| qdm | 2.000 | 8.000 | 1.000 | 0.500 | 0.500 |"),
            "{md}"
        );
    }
}
