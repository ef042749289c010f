//! `report.md` and the SVG plots, from the measured results alone: error against run time with
//! the Pareto front per view, scaling with map size, the step baseline (POM) against the tree
//! baseline (QDM) over depth scales, the methods that read a cone or quadric map side by side,
//! and the stability matrix. Which methods those are is the method table's `bench_role` and
//! `needs`, never an id written here.

use std::collections::BTreeSet;
use std::fmt::Write as _;

use super::cost_curve::fitted_exponent;
use super::depth_match::{match_target, MAX_COST_RATIO, MAX_STEP_BUDGET};
use super::results::{BenchResults, Run, StabilityCell};
use super::runner::Section;
use super::svg::{Plot, Series};
use crate::method::{BenchRole, Method};

fn yes_no(b: bool) -> &'static str {
    if b {
        "yes"
    } else {
        "no"
    }
}

/// The report's Markdown and its plots as (file name, SVG).
pub fn render_report(results: &BenchResults) -> (String, Vec<(String, String)>) {
    let mut md = String::new();
    let d = &results.device;
    let _ = writeln!(md, "# relief bench\n");
    let _ = writeln!(
        md,
        "Device: **{}** ({}; Vulkan {}; timestamp period {} ns; ray queries {}, acceleration \
         structures {}).  ",
        d.name,
        d.driver,
        d.api,
        d.timestamp_period,
        yes_no(d.ray_query),
        yes_no(d.acceleration_structure)
    );
    if let Some(m) = &results.machine {
        let load = |l: Option<[f64; 3]>| {
            l.map_or("unknown".to_owned(), |[a, b, c]| {
                format!("{a:.2} {b:.2} {c:.2}")
            })
        };
        let _ = writeln!(
            md,
            "Machine: {} ({} CPUs; {}); load average {} before, {} after.  ",
            m.cpu_model,
            m.cpus,
            m.os,
            load(m.load_before),
            load(m.load_after)
        );
        if let Some(clocks) = &m.gpu_clocks {
            let _ = writeln!(md, "GPU clocks: `{clocks}`.  ");
        }
        if let Some(why) = &m.busy {
            let _ = writeln!(md, "**Warning: {why}.**  ");
        }
    }
    let _ = writeln!(md, "Command: `{}`  ", results.command);
    if let Some(sections) = &results.sections {
        let _ = writeln!(md, "{}", sections.line());
    }
    md.push('\n');
    let _ = writeln!(
        md,
        "Error is the uv distance in texels between each method's hit and the exact first hit of the bilinear \
         surface (docs/conventions.md), over a grid of parallel rays; gross = more than one texel off. GPU time \
         is the median of the timed full-screen frames.\n"
    );
    error_vs_time(&mut md, results);
    steps_maps(&mut md, results);
    scaling(&mut md, results);
    matched_scaling(&mut md, results);
    depth_scale(&mut md, results);
    super::depth_curve::report(&mut md, results);
    cone_vs_quadric(&mut md, results);
    maps(&mut md, results);
    stability(&mut md, &results.stability);
    super::shading_report::shadows(&mut md, &results.shadows);
    super::shading_report::shadow_stability(&mut md, &results.shadow_stability);
    super::shading_report::ambient_occlusion(&mut md, &results.ao);
    if let Some(lod) = &results.lod {
        super::lod::report(&mut md, lod);
    }
    super::edits::report(&mut md, &results.edits);
    super::paint_edits::report(&mut md, &results.paint_edits);
    if let Some(blending) = &results.blending {
        super::blending_report::report(&mut md, blending);
    }
    if let Some(shadows) = &results.scene_shadows {
        super::scene_shadow_section::report(&mut md, shadows);
    }
    if let Some(features) = &results.frame_features {
        super::frame_features::report(&mut md, features);
    }
    if let Some(silhouettes) = &results.silhouettes {
        super::silhouettes::report(&mut md, silhouettes);
    }
    if let Some(costs) = &results.frame_costs {
        super::frame_costs::report(&mut md, costs);
    }
    (md, plots(results))
}

fn runs(results: &BenchResults, section: Section) -> impl Iterator<Item = &Run> {
    results.runs.iter().filter(move |r| r.section == section)
}

fn budget_label(r: &Run) -> String {
    let steps = if r.budget.refine_steps > 0 {
        format!("{}+{}", r.budget.max_steps, r.budget.refine_steps)
    } else {
        r.budget.max_steps.to_string()
    };
    let choice = r
        .method
        .parse::<Method>()
        .is_ok_and(|m| m.info().leaf_choice);
    if choice {
        format!("{steps} {}", r.budget.leaf)
    } else {
        steps
    }
}

/// The ids of the step and tree baselines (POM and QDM), when the table names both.
fn baselines() -> Option<(&'static str, &'static str)> {
    let step = Method::with_role(BenchRole::StepBaseline)?;
    let tree = Method::with_role(BenchRole::TreeBaseline)?;
    Some((step.id(), tree.id()))
}

/// Runs not dominated in (GPU ms, mean error) by another run of the same group.
fn pareto(group: &[&Run]) -> Vec<bool> {
    group
        .iter()
        .map(|a| {
            !group.iter().any(|b| {
                let no_worse = b.gpu_ms.median <= a.gpu_ms.median
                    && b.error_texels.mean <= a.error_texels.mean;
                let better =
                    b.gpu_ms.median < a.gpu_ms.median || b.error_texels.mean < a.error_texels.mean;
                no_worse && better
            })
        })
        .collect()
}

fn error_vs_time(md: &mut String, results: &BenchResults) {
    let _ = writeln!(md, "## 1. Error against run time\n");
    let _ = writeln!(md, "Per height field and view elevation; **bold** rows are on the Pareto front (no other run is both faster and more accurate).\n");
    let keys: BTreeSet<(String, u64)> = runs(results, Section::ErrorVsTime)
        .map(|r| (r.heightfield.clone(), r.angle_deg.to_bits()))
        .collect();
    for (field, angle_bits) in keys {
        let angle = f64::from_bits(angle_bits);
        let mut group: Vec<&Run> = runs(results, Section::ErrorVsTime)
            .filter(|r| r.heightfield == field && r.angle_deg == angle)
            .collect();
        // Table order: methods as listed by `relief methods`, budgets ascending.
        let order = |r: &Run| {
            crate::method::Method::all()
                .position(|m| m.id() == r.method)
                .unwrap_or(usize::MAX)
        };
        group.sort_by_key(|r| (order(r), r.budget.max_steps));
        let Some(first) = group.first() else { continue };
        let _ = writeln!(
            md,
            "### {field} {}x{}, view {angle} deg, depth scale {}\n",
            first.size[0], first.size[1], first.depth_scale
        );
        let _ = writeln!(
            md,
            "| method | budget | error mean | p99 | max | gross | capped | steps | fetches | GPU ms |"
        );
        let _ = writeln!(md, "|---|---|---|---|---|---|---|---|---|---|");
        for (r, front) in group.iter().zip(pareto(&group)) {
            let b = if front { "**" } else { "" };
            let _ = writeln!(
                md,
                "| {b}{}{b} | {} | {b}{:.4}{b} | {:.3} | {:.2} | {:.2}% | {:.2}% | {:.1} | {:.1} | {b}{:.3}{b} |",
                r.method,
                budget_label(r),
                r.error_texels.mean,
                r.error_texels.p99,
                r.error_texels.max,
                100.0 * r.gross_rate,
                100.0 * r.capped_rate,
                r.steps.mean,
                r.fetches.mean,
                r.gpu_ms.median
            );
        }
        md.push('\n');
    }
}

/// Default-budget runs at 30 degrees across map sizes, from the scaling and main sections.
/// Where each method spends its steps: the heat maps `relief bench` writes beside the report.
fn steps_maps(md: &mut String, results: &BenchResults) {
    if results.steps_maps.is_empty() {
        return;
    }
    let _ = writeln!(
        md,
        "### Where the steps go
"
    );
    let _ = writeln!(md, "Each method's iterations per ray over the error grid of its first configuration above, at its default budget: black none, white its own most (the scale differs per method; the bar on the right runs from 0 at the bottom to the most at the top).
");
    let _ = writeln!(md, "| method | traced at | mean steps | most | map |");
    let _ = writeln!(md, "|---|---|---|---|---|");
    for m in &results.steps_maps {
        let _ = writeln!(
            md,
            "| {} | {} | {:.2} | {} | ![{} steps]({}) |",
            m.method,
            m.traced,
            m.mean(),
            m.most(),
            m.method,
            m.file()
        );
    }
    md.push('\n');
}

fn scaling_runs(results: &BenchResults) -> Vec<&Run> {
    let field = runs(results, Section::Scaling)
        .next()
        .map(|r| r.heightfield.clone());
    let mut list: Vec<&Run> = results
        .runs
        .iter()
        .filter(|r| Some(&r.heightfield) == field.as_ref() && r.angle_deg == 30.0)
        .filter(|r| {
            r.section == Section::Scaling
                || (r.section == Section::ErrorVsTime && is_default_budget(r))
        })
        .collect();
    list.sort_by_key(|r| (r.method.clone(), r.size[0]));
    list
}

/// The tree baseline's scaling beside the step baseline's at the cheapest cap that holds the
/// step baseline's error at the smallest size.
fn matched_scaling(md: &mut String, results: &BenchResults) {
    let Some((step_id, tree_id)) = baselines() else {
        return;
    };
    let (s, t) = (step_id.to_uppercase(), tree_id.to_uppercase());
    let step: Vec<&Run> = runs(results, Section::MatchedScaling).collect();
    let sizes: BTreeSet<u32> = step.iter().map(|r| r.size[0]).collect();
    let Some(&smallest) = sizes.first() else {
        return;
    };
    let at = |size: u32| step.iter().filter(move |r| r.size[0] == size);
    // The target: the step baseline's default cap at the smallest size.
    let Some(target) = at(smallest).min_by_key(|r| r.budget.max_steps) else {
        return;
    };
    let goal = target.error_texels.mean;
    let tree: Vec<&Run> = scaling_runs(results)
        .into_iter()
        .filter(|r| r.method == tree_id)
        .collect();
    let _ = writeln!(md, "### Matched for error\n");
    let _ = writeln!(md, "Per size, {s}'s cheapest cap (of those tried, up to its default grown in proportion to the map side) whose mean error is at most {goal:.4} texel, its error at {smallest}^2; next to {t} at its default budget. Growth is time over the smallest size's.\n");
    let _ = writeln!(
        md,
        "| size | {s} steps | {s} ms | {s} error | {s} growth | {t} ms | {t} error | {t} growth |"
    );
    let _ = writeln!(md, "|---|---|---|---|---|---|---|---|");
    let first_tree = tree
        .iter()
        .find(|q| q.size[0] == smallest)
        .map(|q| q.gpu_ms.median);
    for &size in &sizes {
        let matched = at(size)
            .filter(|r| r.error_texels.mean <= goal)
            .min_by_key(|r| r.budget.max_steps)
            .or_else(|| at(size).max_by_key(|r| r.budget.max_steps));
        let Some(r) = matched else {
            continue;
        };
        let q = tree.iter().find(|q| q.size[0] == size);
        let (qms, qerr, qgrowth) = q.map_or(("-".into(), "-".into(), "-".into()), |q| {
            (
                format!("{:.3}", q.gpu_ms.median),
                format!("{:.4}", q.error_texels.mean),
                first_tree.map_or("-".into(), |b| growth(q.gpu_ms.median, b)),
            )
        });
        let _ = writeln!(
            md,
            "| {size}^2 | {} | {:.3} | {:.4} | {} | {qms} | {qerr} | {qgrowth} |",
            r.budget.max_steps,
            r.gpu_ms.median,
            r.error_texels.mean,
            growth(r.gpu_ms.median, target.gpu_ms.median)
        );
    }
    md.push('\n');
}

fn is_default_budget(r: &Run) -> bool {
    r.method
        .parse::<Method>()
        .is_ok_and(|m| m.info().default_budget == r.budget)
}

fn scaling(md: &mut String, results: &BenchResults) {
    let list = scaling_runs(results);
    let Some(lanes) = list.first().map(|r| r.timed_steps.subgroup_size) else {
        return;
    };
    let _ = writeln!(md, "## 2. Scaling with map size\n");
    let _ = writeln!(md, "GPU ms at 30 deg with default budgets (mean error in brackets); growth is the largest size's time over the smallest's (Schroders and van Gulik, Table 1: about 1.5x for quadtree methods from 256^2 to 2048^2), and k the exponent of time ~ texels^k fitted by least squares over every size (that 1.5x is k = 0.097; linear in the map's side is 0.5).\n");
    size_table(
        md,
        &list,
        |r| format!("{:.3} ({:.3})", r.gpu_ms.median, r.error_texels.mean),
        |r| r.gpu_ms.median,
    );
    let _ = writeln!(md, "Iterations of the timed rays: the mean per ray, and in brackets the mean over subgroups of {lanes} lanes of the subgroup's slowest ray, which is what a SIMD device pays for the loop; the growth and k are those of the subgroup figure.\n");
    size_table(
        md,
        &list,
        |r| {
            let t = r.timed_steps;
            format!("{:.1} ({:.1})", t.mean, t.subgroup_mean_max)
        },
        |r| r.timed_steps.subgroup_mean_max,
    );
}

/// `t` over `base` as "1.23x", or "-" without a base.
fn growth(t: f64, base: f64) -> String {
    if base > 0.0 {
        format!("{:.2}x", t / base)
    } else {
        "-".into()
    }
}

/// One row per method, one column per map size, and the growth of `value` from the smallest
/// size to the largest.
fn size_table(
    md: &mut String,
    list: &[&Run],
    cell: impl Fn(&Run) -> String,
    value: impl Fn(&Run) -> f64,
) {
    let sizes: BTreeSet<u32> = list.iter().map(|r| r.size[0]).collect();
    let head: Vec<String> = sizes.iter().map(|s| format!("{s}^2")).collect();
    let _ = writeln!(md, "| method | {} | growth | k |", head.join(" | "));
    let _ = writeln!(md, "|---|{}---|---|", "---|".repeat(sizes.len()));
    let methods: BTreeSet<&str> = list.iter().map(|r| r.method.as_str()).collect();
    for m in methods {
        let row: Vec<Option<&&Run>> = sizes
            .iter()
            .map(|s| list.iter().find(|r| r.method == m && r.size[0] == *s))
            .collect();
        let cells: Vec<String> = row
            .iter()
            .map(|r| r.map_or("-".into(), |r| cell(r)))
            .collect();
        let values: Vec<f64> = row.iter().flatten().map(|r| value(r)).collect();
        let grew = match (values.first(), values.last()) {
            (Some(&a), Some(&b)) => growth(b, a),
            _ => "-".into(),
        };
        let points: Vec<(f64, f64)> = row
            .iter()
            .flatten()
            .map(|r| (f64::from(r.size[0]) * f64::from(r.size[1]), value(r)))
            .collect();
        let k = fitted_exponent(&points).map_or("-".into(), |k| format!("{k:.3}"));
        let _ = writeln!(md, "| {m} | {} | {grew} | {k} |", cells.join(" | "));
    }
    md.push('\n');
}

fn depth_scale(md: &mut String, results: &BenchResults) {
    let Some((step_id, tree_id)) = baselines() else {
        return;
    };
    let list: Vec<&Run> = runs(results, Section::DepthScale)
        .filter(|r| r.method == step_id || r.method == tree_id)
        .collect();
    if list.is_empty() {
        return;
    }
    // Views in run order of field and angle, each by increasing depth scale.
    let mut views: Vec<(String, u64, u64)> = Vec::new();
    for r in &list {
        let key = (
            r.heightfield.clone(),
            r.angle_deg.to_bits(),
            r.depth_scale.to_bits(),
        );
        if !views.contains(&key) {
            views.push(key);
        }
    }
    views.sort_by(|a, b| {
        let first = |k: &(String, u64, u64)| {
            list.iter()
                .position(|r| r.heightfield == k.0 && r.angle_deg.to_bits() == k.1)
        };
        first(a)
            .cmp(&first(b))
            .then(f64::from_bits(a.2).total_cmp(&f64::from_bits(b.2)))
    });
    depth_scale_head(md, &step_id.to_uppercase(), &tree_id.to_uppercase());
    for (field, angle_bits, bits) in views {
        let (s, angle) = (f64::from_bits(bits), f64::from_bits(angle_bits));
        let at: Vec<&Run> = list
            .iter()
            .copied()
            .filter(|r| r.depth_scale == s && r.heightfield == field && r.angle_deg == angle)
            .collect();
        let Some(target) = match_target(at.iter().copied()) else {
            continue;
        };
        let exact = at
            .iter()
            .find(|r| r.method == tree_id && is_default_budget(r));
        let mut step: Vec<&Run> = at.iter().copied().filter(|r| r.method == step_id).collect();
        step.sort_by_key(|r| r.budget.max_steps);
        let matched = step
            .iter()
            .filter(|r| r.error_texels.mean <= target.error_texels.mean)
            .min_by(|a, b| a.gpu_ms.median.total_cmp(&b.gpu_ms.median));
        let best = || {
            step.iter()
                .min_by(|a, b| a.error_texels.mean.total_cmp(&b.error_texels.mean))
        };
        let Some(p) = matched.or_else(best) else {
            continue;
        };
        let tried: Vec<String> = step
            .iter()
            .map(|r| r.budget.max_steps.to_string())
            .collect();
        let label = if matched.is_some() {
            budget_label(p)
        } else {
            format!("{} (not matched)", budget_label(p))
        };
        let ratio = |ms: f64| format!("{:.2}x", p.gpu_ms.median / ms.max(1e-9));
        let _ = writeln!(
            md,
            "| {field}, {angle} deg, depth {s} | {} | {:.3} | {:.4} | {label} | {:.3} | {:.4} | {} | {} | {} |",
            budget_label(target),
            target.gpu_ms.median,
            target.error_texels.mean,
            p.gpu_ms.median,
            p.error_texels.mean,
            ratio(target.gpu_ms.median),
            exact.map_or("-".into(), |e| format!(
                "{} ({:.3} ms)",
                ratio(e.gpu_ms.median),
                e.gpu_ms.median
            )),
            tried.join(", ")
        );
    }
    md.push('\n');
}

/// Title, text and table head of section 3, naming the step (`s`) and tree (`t`) baselines.
fn depth_scale_head(md: &mut String, s: &str, t: &str) {
    let _ = writeln!(md, "## 3. Depth scale: {s} against {t} at matched error\n");
    let _ = writeln!(md, "The first field at 30 deg over every depth scale, then a stiff view (one-texel spikes at a grazing 5 deg, the first depth scale); the shape of Drobot's Tables 1.3 and 1.4 (equal quality). The quality to match is {t} with the paper's refinement (Drobot's {t}; with the exact leaf {t}'s error is float rounding, which no fixed-step search reaches; its time is the last ratio), unless that misses grossly on more than 1% of rays (it does on one-texel spikes), then {t}'s default. {s}'s cap doubles up to {MAX_STEP_BUDGET} and stops at a depth scale once a cap matched or cost more than {MAX_COST_RATIO}x {t}'s time; the row shows the cheapest cap with no more mean error (or, marked not matched, the most accurate), and the caps run.\n");
    let _ = writeln!(
        md,
        "| view | {t} | {t} ms | {t} error | {s} budget | {s} ms | {s} error | {s} / {t} time | {s} / {t} exact leaf | {s} caps run |"
    );
    let _ = writeln!(md, "|---|---|---|---|---|---|---|---|---|---|");
}

/// The methods that read a cone or quadric map (binding 3), in table order.
fn cone_vs_quadric(md: &mut String, results: &BenchResults) {
    let ids: Vec<&str> = Method::all()
        .filter(|m| m.info().method_map().is_some())
        .map(|m| m.id())
        .collect();
    let list: Vec<&Run> = runs(results, Section::ErrorVsTime)
        .filter(|r| ids.contains(&r.method.as_str()) && is_default_budget(r))
        .collect();
    if list.is_empty() {
        return;
    }
    let field = list[0].heightfield.clone();
    let _ = writeln!(md, "## 4. Quadric against cone stepping\n");
    let _ = writeln!(
        md,
        "Mean steps and GPU ms by view angle on {field} (Kiglics et al., Figure 10 and Table 1).\n"
    );
    let _ = writeln!(
        md,
        "| angle | {} |",
        ids.iter()
            .map(|m| format!("{m} steps | {m} ms"))
            .collect::<Vec<_>>()
            .join(" | ")
    );
    let _ = writeln!(md, "|---|{}", "---|".repeat(2 * ids.len()));
    let angles: BTreeSet<u64> = list.iter().map(|r| r.angle_deg.to_bits()).collect();
    for bits in angles {
        let a = f64::from_bits(bits);
        let cells: Vec<String> = ids
            .iter()
            .map(|m| {
                list.iter()
                    .find(|r| r.method == *m && r.angle_deg == a && r.heightfield == field)
                    .map_or("- | -".into(), |r| {
                        format!("{:.1} | {:.3}", r.steps.mean, r.gpu_ms.median)
                    })
            })
            .collect();
        let _ = writeln!(md, "| {a} | {} |", cells.join(" | "));
    }
    md.push('\n');
}

fn maps(md: &mut String, results: &BenchResults) {
    if results.maps.is_empty() {
        return;
    }
    let _ = writeln!(md, "## Map build times\n");
    let _ = writeln!(
        md,
        "GPU ms for GPU builds, CPU wall ms for CPU builds. Where a map is built on both (sides up to 1024), the \
         {} GPU and {} CPU builds alternate and each row is their median.\n",
        super::runner::MAP_BUILD_ROUNDS,
        super::runner::MAP_BUILD_ROUNDS
    );
    let _ = writeln!(md, "| map | height field | size | built on | ms |");
    let _ = writeln!(md, "|---|---|---|---|---|");
    for m in &results.maps {
        let _ = writeln!(
            md,
            "| {} | {} | {}x{} | {} | {:.2} |",
            m.kind, m.heightfield, m.size[0], m.size[1], m.on, m.ms
        );
    }
    md.push('\n');
}

fn stability(md: &mut String, cells: &[StabilityCell]) {
    if cells.is_empty() {
        return;
    }
    let methods = unique_in_order(cells.iter().map(|c| c.method.as_str()));
    let cases = unique_in_order(cells.iter().map(|c| c.case.as_str()));
    let _ = writeln!(md, "## 5. Stability matrix\n");
    let _ = writeln!(md, "Each cell: gross rate and worst error in texels over 32x32 rays at default budgets (the accurate methods' cap grows with the ray's extent in texels, up to 8192 steps), then the trace's GPU time; `NaN n` and `capped x%` when they happen; `FAILED` with the reason below the table when the case could not run. Sparse spikes (one-texel spikes, a spike under every coarse pyramid node) at grazing views over deep fields are the cases where a fixed cap of 256 steps used to run out.\n");
    let _ = writeln!(md, "| case | {} |", methods.join(" | "));
    let _ = writeln!(md, "|---|{}", "---|".repeat(methods.len()));
    let mut failures = Vec::new();
    for case in &cases {
        let row: Vec<String> = methods
            .iter()
            .map(
                |m| match cells.iter().find(|c| c.case == *case && c.method == *m) {
                    None => "-".into(),
                    Some(c) => stability_cell(c, &mut failures),
                },
            )
            .collect();
        let _ = writeln!(md, "| {case} | {} |", row.join(" | "));
    }
    for f in failures {
        let _ = writeln!(md, "- {f}");
    }
    md.push('\n');
}

/// The distinct items, in order of first appearance.
fn unique_in_order<'a>(items: impl Iterator<Item = &'a str>) -> Vec<&'a str> {
    items.fold(Vec::new(), |mut seen, item| {
        if !seen.contains(&item) {
            seen.push(item);
        }
        seen
    })
}

fn stability_cell(c: &StabilityCell, failures: &mut Vec<String>) -> String {
    if let Some(why) = &c.failed {
        failures.push(format!("{} on {}: {why}", c.method, c.case));
        return "FAILED".into();
    }
    let mut text = format!("{:.1}% / {:.2}", 100.0 * c.gross_rate, c.max_error_texels);
    if c.capped_rate > 0.0 {
        let _ = write!(text, ", capped {:.1}%", 100.0 * c.capped_rate);
    }
    if let Some(ms) = c.gpu_ms {
        let _ = write!(text, ", {ms:.1} ms");
    }
    if c.nan_pixels > 0 {
        let _ = write!(text, ", **NaN {}**", c.nan_pixels);
    }
    text
}

fn plots(results: &BenchResults) -> Vec<(String, String)> {
    let main: Vec<&Run> = runs(results, Section::ErrorVsTime).collect();
    let field = main
        .first()
        .map(|r| r.heightfield.clone())
        .unwrap_or_default();
    let methods: BTreeSet<&str> = results.runs.iter().map(|r| r.method.as_str()).collect();
    let series = |f: &dyn Fn(&str) -> Vec<(f64, f64)>| -> Vec<Series> {
        methods
            .iter()
            .map(|m| Series {
                name: (*m).to_owned(),
                points: f(m),
            })
            .filter(|s| !s.points.is_empty())
            .collect()
    };
    // The view closest to 30 degrees, the middle view of the papers' comparisons.
    let middle = main
        .iter()
        .map(|r| r.angle_deg)
        .min_by(|a, b| (a - 30.0).abs().total_cmp(&(b - 30.0).abs()))
        .unwrap_or(30.0);
    let error_vs_ms = Plot {
        title: format!("Error against GPU time, {field}, {middle} deg"),
        x_label: "GPU ms".into(),
        y_label: "mean error (texels)".into(),
        log_x: true,
        log_y: true,
        series: series(&|m| {
            let mut points: Vec<(f64, f64)> = main
                .iter()
                .filter(|r| r.method == m && r.heightfield == field && r.angle_deg == middle)
                .map(|r| (r.gpu_ms.median, r.error_texels.mean))
                .collect();
            points.sort_by(|a, b| a.0.total_cmp(&b.0));
            points
        }),
    };
    let scaling = scaling_runs(results);
    let ms_vs_size = Plot {
        title: "GPU time against map size, 30 deg".into(),
        x_label: "map side (texels)".into(),
        y_label: "GPU ms".into(),
        log_x: true,
        log_y: true,
        series: series(&|m| {
            scaling
                .iter()
                .filter(|r| r.method == m)
                .map(|r| (f64::from(r.size[0]), r.gpu_ms.median))
                .collect()
        }),
    };
    let steps_vs_angle = Plot {
        title: format!("Mean steps against view angle, {field}"),
        x_label: "view elevation (deg)".into(),
        y_label: "mean steps".into(),
        log_x: false,
        log_y: false,
        series: series(&|m| {
            main.iter()
                .filter(|r| r.method == m && r.heightfield == field && is_default_budget(r))
                .map(|r| (r.angle_deg, r.steps.mean))
                .collect()
        }),
    };
    vec![
        ("error_vs_ms.svg".into(), error_vs_ms.to_svg()),
        ("ms_vs_size.svg".into(), ms_vs_size.to_svg()),
        ("steps_vs_angle.svg".into(), steps_vs_angle.to_svg()),
    ]
}
