//! The cost gate: a small fixed sweep whose counts of work do not depend on the device's speed
//! (iterations and texel fetches per ray, the slowest ray's, rays stopped by their cap), compared against a baseline
//! kept in the repository. Times move with the machine; these move only when a method's walk
//! changes, so a change that makes a method take more steps or fetch more fails the suite and names the
//! method, field and view.

use std::sync::Arc;

use serde::{Deserialize, Serialize};

use super::trace_stats::{ray_direction, trace_stats, StepStats};
use crate::heightfield::{Address, Generator};
use crate::method::Method;
use crate::render::{
    build_method_map_with, trace_counting_fetches, HeightFormat, MapBuilder, TraceRequest,
};
use crate::vk::{Context, VkResult};

/// The fields the gate traces: smooth, bricked and sparse spikes (what coarse steps skip).
pub const GATE_FIELDS: [Generator; 3] = [Generator::Fbm, Generator::Bricks, Generator::Spikes];
/// View elevations in degrees (azimuth 30): grazing, oblique, near vertical.
pub const GATE_ELEVATIONS: [f64; 3] = [20.0, 45.0, 80.0];
const GATE_AZIMUTH: f64 = 30.0;
/// The map's side in texels.
pub const GATE_SIZE: u32 = 64;
/// Depth of height 0 below the top plane, in uv units.
pub const GATE_DEPTH_SCALE: f64 = 0.1;
/// Rays per cell.
pub const GATE_RAYS: (u32, u32) = (16, 16);

/// How much a count may grow before the gate fails: the mean by 5% (and at least 0.25 steps or
/// 1 fetch), the slowest ray by 10% (and at least 2 steps or 4 fetches), capped rays by 2 of the
/// cell's 256.
pub const MEAN_GROWTH: f64 = 0.05;
const MEAN_SLACK: f64 = 0.25;
/// See [`MEAN_GROWTH`].
pub const MAX_GROWTH: f64 = 0.10;
const MAX_SLACK: u32 = 2;
const MEAN_FETCH_SLACK: f64 = 1.0;
const MAX_FETCH_SLACK: u32 = 4;
const CAPPED_SLACK: u32 = 2;

/// One method on one field from one view.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GateCell {
    /// Method id.
    pub method: String,
    /// Generator name.
    pub field: String,
    /// "elevation 45", in degrees (azimuth 30).
    pub view: String,
    /// Iterations per ray, mean over the cell's rays.
    pub mean_steps: f64,
    /// The slowest ray's iterations.
    pub max_steps: u32,
    /// Rays whose method ran out of iterations.
    pub capped: u32,
    /// Texel fetches per ray (height map, pyramid and method map; a gather is one), mean over
    /// the cell's rays.
    pub mean_fetches: f64,
    /// The most fetches one ray made.
    pub max_fetches: u32,
}

/// A gate run: its fixed setup and every cell.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GateCounts {
    /// What the cells were measured on (for reading; the counts do not depend on it).
    pub device: String,
    /// Map side, depth scale and rays per cell, as measured.
    pub setup: String,
    /// Every cell, methods in table order.
    pub cells: Vec<GateCell>,
}

/// A count that grew beyond its tolerance, or a cell the baseline has and the run lacks (or the
/// other way round).
#[derive(Debug, Clone, PartialEq)]
pub struct GateFinding {
    /// Method, field and view.
    pub cell: String,
    /// What moved, with the baseline's and the run's values.
    pub what: String,
}

/// The gate's setup in words, stored with the counts: a baseline of another setup is refused.
pub fn gate_setup() -> String {
    format!(
        "{GATE_SIZE}^2 maps, depth scale {GATE_DEPTH_SCALE}, {}x{} rays per cell, azimuth {GATE_AZIMUTH}",
        GATE_RAYS.0, GATE_RAYS.1
    )
}

/// Measures every cell of `methods`. `waste` doubles one method's iteration cap, a test-only
/// switch that makes its fixed-step search take twice the steps, to show the gate trips.
pub fn measure_gate(
    ctx: &Arc<Context>,
    methods: &[Method],
    waste: Option<Method>,
    mut progress: impl FnMut(&GateCell),
) -> VkResult<GateCounts> {
    let mut cells = Vec::new();
    for &method in methods {
        for field in GATE_FIELDS {
            let hf = field.generate(GATE_SIZE, GATE_SIZE, 1).quantized_unorm16();
            let address = Address::Repeat;
            let map = build_method_map_with(method, &hf, address, MapBuilder::Gpu(ctx))?;
            let mut budget = method.info().default_budget;
            if waste == Some(method) {
                budget.max_steps *= 2;
            }
            for elevation in GATE_ELEVATIONS {
                let req = TraceRequest {
                    method,
                    dir: ray_direction(elevation, GATE_AZIMUTH).map(|x| x as f32),
                    depth_scale: GATE_DEPTH_SCALE as f32,
                    grid: GATE_RAYS,
                    budget,
                    address,
                    format: HeightFormat::R16Unorm,
                    map: map.as_ref().map(|m| &m.data),
                    shadow: None,
                };
                let out = trace_counting_fetches(ctx, &hf, &req)?;
                let stats = trace_stats(&hf, &out.hits, &out.steps, GATE_DEPTH_SCALE, address);
                let fetches = StepStats::of(out.fetches.iter().map(|f| f[0]));
                let cell = GateCell {
                    method: method.id().to_owned(),
                    field: field.name().to_owned(),
                    view: format!("elevation {elevation}"),
                    mean_steps: (stats.steps.mean * 1e4).round() / 1e4,
                    max_steps: stats.steps.max,
                    capped: out.steps.iter().filter(|s| s[1] != 0).count() as u32,
                    mean_fetches: (fetches.mean * 1e4).round() / 1e4,
                    max_fetches: fetches.max,
                };
                progress(&cell);
                cells.push(cell);
            }
        }
    }
    Ok(GateCounts {
        device: format!("{} ({})", ctx.info().name, ctx.info().driver.trim()),
        setup: gate_setup(),
        cells,
    })
}

fn key(c: &GateCell) -> (&str, &str, &str) {
    (&c.method, &c.field, &c.view)
}

/// "mean steps 20.00 -> 40.00 (+100.0%)" when a mean grew beyond [`MEAN_GROWTH`] and `slack`.
fn mean_grew(what: &str, was: f64, now: f64, slack: f64) -> Option<String> {
    let limit = (was * (1.0 + MEAN_GROWTH)).max(was + slack);
    (now > limit).then(|| {
        format!(
            "mean {what} {was:.2} -> {now:.2} (+{:.1}%)",
            100.0 * (now / was.max(1e-9) - 1.0)
        )
    })
}

/// "slowest ray's steps 40 -> 80" when the most grew beyond [`MAX_GROWTH`] and `slack`.
fn most_grew(what: &str, was: u32, now: u32, slack: u32) -> Option<String> {
    let limit = ((f64::from(was) * (1.0 + MAX_GROWTH)).floor() as u32).max(was + slack);
    (now > limit).then(|| format!("slowest ray's {what} {was} -> {now}"))
}

/// What `run` does worse than `baseline`, over the methods `run` measured. Counts that fell are
/// not findings (the baseline is then merely out of date).
pub fn check_gate(baseline: &GateCounts, run: &GateCounts) -> Vec<GateFinding> {
    let mut findings = Vec::new();
    let name = |c: &GateCell| format!("{} on {} at {}", c.method, c.field, c.view);
    if baseline.setup != run.setup {
        findings.push(GateFinding {
            cell: "the whole run".into(),
            what: format!(
                "the baseline was measured with {}, this run with {}",
                baseline.setup, run.setup
            ),
        });
        return findings;
    }
    for now in &run.cells {
        let Some(was) = baseline.cells.iter().find(|b| key(b) == key(now)) else {
            findings.push(GateFinding {
                cell: name(now),
                what: "not in the baseline".into(),
            });
            continue;
        };
        let mut grew = Vec::new();
        grew.extend(mean_grew(
            "steps",
            was.mean_steps,
            now.mean_steps,
            MEAN_SLACK,
        ));
        grew.extend(most_grew("steps", was.max_steps, now.max_steps, MAX_SLACK));
        grew.extend(mean_grew(
            "fetches",
            was.mean_fetches,
            now.mean_fetches,
            MEAN_FETCH_SLACK,
        ));
        grew.extend(most_grew(
            "fetches",
            was.max_fetches,
            now.max_fetches,
            MAX_FETCH_SLACK,
        ));
        if now.capped > was.capped + CAPPED_SLACK {
            grew.push(format!("capped rays {} -> {}", was.capped, now.capped));
        }
        if !grew.is_empty() {
            findings.push(GateFinding {
                cell: name(now),
                what: grew.join("; "),
            });
        }
    }
    let measured: Vec<&str> = run.cells.iter().map(|c| c.method.as_str()).collect();
    for was in &baseline.cells {
        let method_run = measured.contains(&was.method.as_str());
        if method_run && !run.cells.iter().any(|c| key(c) == key(was)) {
            findings.push(GateFinding {
                cell: name(was),
                what: "in the baseline but not measured".into(),
            });
        }
    }
    findings
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cell(method: &str, mean: f64, max: u32, capped: u32) -> GateCell {
        GateCell {
            method: method.into(),
            field: "fbm".into(),
            view: "elevation 45".into(),
            mean_steps: mean,
            max_steps: max,
            capped,
            mean_fetches: 2.0 * mean,
            max_fetches: 2 * max,
        }
    }

    fn counts(cells: Vec<GateCell>) -> GateCounts {
        GateCounts {
            device: "d".into(),
            setup: gate_setup(),
            cells,
        }
    }

    #[test]
    fn growth_within_tolerance_passes_and_beyond_it_names_the_cell() {
        let base = counts(vec![cell("pom", 20.0, 40, 0), cell("qdm", 8.0, 15, 0)]);
        let close = counts(vec![cell("pom", 20.9, 43, 2), cell("qdm", 7.0, 12, 0)]);
        assert!(check_gate(&base, &close).is_empty());
        let worse = counts(vec![cell("pom", 40.0, 80, 5), cell("qdm", 8.0, 15, 0)]);
        let found = check_gate(&base, &worse);
        assert_eq!(found.len(), 1);
        assert_eq!(found[0].cell, "pom on fbm at elevation 45");
        assert!(found[0]
            .what
            .contains("mean steps 20.00 -> 40.00 (+100.0%)"));
        assert!(found[0].what.contains("slowest ray's steps 40 -> 80"));
        assert!(found[0].what.contains("capped rays 0 -> 5"));
        assert!(found[0].what.contains("mean fetches 40.00 -> 80.00"));
        assert!(found[0].what.contains("slowest ray's fetches 80 -> 160"));
    }

    #[test]
    fn fetches_alone_trip_the_gate() {
        let base = counts(vec![cell("qdm", 8.0, 15, 0)]);
        let mut fetching = base.clone();
        fetching.cells[0].mean_fetches = 20.0;
        fetching.cells[0].max_fetches = 36;
        let found = check_gate(&base, &fetching);
        assert_eq!(found.len(), 1, "{found:?}");
        assert_eq!(
            found[0].what,
            "mean fetches 16.00 -> 20.00 (+25.0%); slowest ray's fetches 30 -> 36"
        );
        fetching.cells[0].mean_fetches = 16.8;
        fetching.cells[0].max_fetches = 33;
        assert!(check_gate(&base, &fetching).is_empty(), "within tolerance");
    }

    #[test]
    fn missing_and_new_cells_are_findings_only_for_methods_measured() {
        let base = counts(vec![cell("pom", 20.0, 40, 0), cell("qdm", 8.0, 15, 0)]);
        let only_pom = counts(vec![cell("pom", 20.0, 40, 0)]);
        assert!(check_gate(&base, &only_pom).is_empty(), "qdm was not run");
        let new = counts(vec![cell("cone", 9.0, 20, 0)]);
        assert_eq!(check_gate(&base, &new)[0].what, "not in the baseline");
        let mut other = counts(vec![]);
        other.setup = "another".into();
        assert_eq!(check_gate(&base, &other).len(), 1);
    }
}
