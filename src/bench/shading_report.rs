//! The shading part of `report.md`: per height field, each shadow mode's error against the exact
//! visible fraction over light elevations and sizes with the time it adds, and a summary per mode
//! (the numbers the shading acceptance reads: hard agreement, soft error at radii of 2 degrees and
//! more, light leaks, horizon against pom-soft time).

use std::fmt::Write as _;

use super::ao::AoRun;
use super::median::median;
use super::shading::ShadowRun;
use super::shadow_stability::ShadowStabilityCell;

fn distinct<T: PartialEq + Copy>(items: impl Iterator<Item = T>) -> Vec<T> {
    let mut out = Vec::new();
    for item in items {
        if !out.contains(&item) {
            out.push(item);
        }
    }
    out
}

/// Writes the shadow section (nothing when no shadow was measured).
pub fn shadows(md: &mut String, runs: &[ShadowRun]) {
    if runs.is_empty() {
        return;
    }
    let _ = writeln!(
        md,
        "## 6. Soft shadows against the exact visible fraction\n"
    );
    let first = &runs[0];
    let _ = writeln!(
        md,
        "Each hit of a QDM view at {} deg is shaded toward a directional light of angular radius r at azimuth \
         {} deg; the exact reference is the fraction of the light's disk seen from the bilinear surface at the \
         hit (docs/conventions.md), from many exact rays. Cells: mean absolute error of the visible fraction; \
         `leak` is the share of points the reference has below 0.05 and the mode above 0.5. `+ms` is the median \
         GPU time the shadow adds to the view at {}x{} rays.\n",
        first.view_angle_deg, first.light_azimuth_deg, first.resolution[0], first.resolution[1]
    );
    for field in distinct(runs.iter().map(|r| r.heightfield.as_str())) {
        field_table(md, runs, field);
    }
    summary(md, runs);
}

fn field_table(md: &mut String, runs: &[ShadowRun], field: &str) {
    let mine: Vec<&ShadowRun> = runs.iter().filter(|r| r.heightfield == field).collect();
    let elevations = distinct(mine.iter().map(|r| r.light_elevation_deg));
    let size = mine[0].size;
    let _ = writeln!(md, "### {field} {}x{}\n", size[0], size[1]);
    let heads: Vec<String> = elevations.iter().map(|e| format!("{e} deg")).collect();
    let _ = writeln!(
        md,
        "| mode | r (deg) | {} | worst p99 | worst leak | +ms |",
        heads.join(" | ")
    );
    let _ = writeln!(md, "|---|---|{}---|---|---|", "---|".repeat(heads.len()));
    for mode in distinct(mine.iter().map(|r| r.mode.as_str())) {
        for radius in distinct(mine.iter().map(|r| r.light_radius_deg)) {
            let row: Vec<&ShadowRun> = mine
                .iter()
                .copied()
                .filter(|r| r.mode == mode && r.light_radius_deg == radius)
                .collect();
            let cells: Vec<String> = elevations
                .iter()
                .map(|e| match row.iter().find(|r| r.light_elevation_deg == *e) {
                    Some(r) => format!("{:.4}", r.error.abs_error.mean),
                    None => "-".into(),
                })
                .collect();
            let p99 = row
                .iter()
                .map(|r| r.error.abs_error.p99)
                .fold(0.0, f64::max);
            let leak = row.iter().map(|r| r.error.leak_rate).fold(0.0, f64::max);
            let ms = median(row.iter().map(|r| r.shadow_ms));
            let _ = writeln!(
                md,
                "| {mode} | {radius} | {} | {p99:.3} | {:.2}% | {ms:.2} |",
                cells.join(" | "),
                100.0 * leak
            );
        }
    }
    md.push('\n');
}

fn summary(md: &mut String, runs: &[ShadowRun]) {
    let _ = writeln!(md, "### Per mode, over every field and light\n");
    let _ = writeln!(
        md,
        "| mode | steps | agreement at r = 0 (worst) | mean error at r >= 2 (worst light) | worst leak | +ms (median) |"
    );
    let _ = writeln!(md, "|---|---|---|---|---|---|");
    let mut times = Vec::new();
    for mode in distinct(runs.iter().map(|r| r.mode.as_str())) {
        let mine: Vec<&ShadowRun> = runs.iter().filter(|r| r.mode == mode).collect();
        let agree = mine
            .iter()
            .filter(|r| r.light_radius_deg == 0.0)
            .map(|r| r.error.agreement)
            .fold(1.0, f64::min);
        let soft = mine
            .iter()
            .filter(|r| r.light_radius_deg >= 2.0)
            .map(|r| r.error.abs_error.mean)
            .fold(0.0, f64::max);
        let leak = mine.iter().map(|r| r.error.leak_rate).fold(0.0, f64::max);
        let ms = median(mine.iter().map(|r| r.shadow_ms));
        times.push((mode, ms));
        let _ = writeln!(
            md,
            "| {mode} | {} | {:.2}% | {soft:.4} | {:.2}% | {ms:.2} |",
            mine[0].steps,
            100.0 * agree,
            100.0 * leak
        );
    }
    let time = |m: &str| times.iter().find(|(id, _)| *id == m).map(|(_, t)| *t);
    if let (Some(h), Some(p)) = (time("horizon"), time("pom-soft")) {
        if p > 0.0 {
            let _ = writeln!(
                md,
                "\nhorizon / pom-soft time: {:.2} (Drobot Table 1.5: 0.5 / 1.6 ms = 0.31).",
                h / p
            );
        }
    }
    md.push('\n');
}

/// Writes the shading rows of the stability matrix (nothing when they were not run).
pub fn shadow_stability(md: &mut String, cells: &[ShadowStabilityCell]) {
    if cells.is_empty() {
        return;
    }
    let modes = distinct(cells.iter().map(|c| c.mode.as_str()));
    let _ = writeln!(
        md,
        "### Shadows under extreme lights
"
    );
    let _ = writeln!(
        md,
        "QDM hits of a 16x16 ray grid, each mode's visible fraction against the exact one: mean / max \
         absolute error, `bad n` when n fractions are NaN or outside [0, 1], `FAILED` when the case could \
         not run.\n"
    );
    let _ = writeln!(md, "| case | {} |", modes.join(" | "));
    let _ = writeln!(md, "|---|{}", "---|".repeat(modes.len()));
    for case in distinct(cells.iter().map(|c| c.case.as_str())) {
        let row: Vec<String> = modes
            .iter()
            .map(
                |m| match cells.iter().find(|c| c.case == case && c.mode == *m) {
                    None => "-".into(),
                    Some(c) if c.failed.is_some() => "FAILED".into(),
                    Some(c) if c.bad_values > 0 => format!("bad {}", c.bad_values),
                    Some(c) => format!("{:.3} / {:.3}", c.mean_error, c.max_error),
                },
            )
            .collect();
        let _ = writeln!(md, "| {case} | {} |", row.join(" | "));
    }
    for c in cells.iter().filter(|c| c.failed.is_some()) {
        let _ = writeln!(
            md,
            "- {} on {}: {}",
            c.mode,
            c.case,
            c.failed.as_deref().unwrap_or("")
        );
    }
    md.push('\n');
}

/// Writes the AO table (nothing when AO was not measured).
pub fn ambient_occlusion(md: &mut String, runs: &[AoRun]) {
    if runs.is_empty() {
        return;
    }
    let _ = writeln!(md, "## 7. Ambient occlusion maps against the exact AO\n");
    let _ = writeln!(
        md,
        "Each mode's texture-space AO map, built on the GPU, against the exact AO at every texel centre \
         (docs/conventions.md: cosine-weighted over the hemisphere about the texel normal, from exact horizons). \
         Build times are GPU time of the one-off build.\n"
    );
    let _ = writeln!(
        md,
        "| field | mode | mean | p99 | max | build ms | build ms at main size |"
    );
    let _ = writeln!(md, "|---|---|---|---|---|---|---|");
    for r in runs {
        let main = match (r.main_size, r.main_build_ms) {
            (Some(size), Some(ms)) => format!("{ms:.1} ({}x{})", size[0], size[1]),
            _ => "-".into(),
        };
        let bad = if r.bad_values > 0 {
            format!(" (bad {})", r.bad_values)
        } else {
            String::new()
        };
        let _ = writeln!(
            md,
            "| {} {}x{} | {}{bad} | {:.4} | {:.4} | {:.4} | {:.1} | {main} |",
            r.heightfield,
            r.size[0],
            r.size[1],
            r.mode,
            r.error.mean,
            r.error.p99,
            r.error.max,
            r.build_ms
        );
    }
    md.push('\n');
}
