//! The units of work `relief bench --shard` splits: each job of the sweep, each cell of the
//! stability matrix, each field's shadows and AO, and the sections that run as one piece (level of
//! detail, terrain edits, blending, scene shadows, shadows under extreme lights), each with an
//! estimate of what it costs. Every measurement also has a step: its place in the order an unsharded
//! run takes, so that the shards' results can be put back in that order.
//!
//! Costs are rough seconds on lavapipe on two cores, from what drives each unit: rays per frame
//! times frames times the method's expected iterations, the reference's walk through the texels a
//! ray crosses, the map sizes built, and for the sections that run whole their measured time in
//! `--quick` (scaled for the full sweep). Only their ratios matter: they decide the split, never a
//! measurement.

use std::collections::HashMap;

use super::ao::AoConfig;
use super::runner::{Job, Section};
use super::shading::ShadingConfig;
use super::shard::UnitCost;
use super::stability::StiffCase;
use super::sweep::SweepConfig;
use crate::method::{MapKind, Method};

/// What an unsharded `relief bench` would measure, section by section.
#[derive(Debug, Clone)]
pub struct SweepSections {
    /// The sweep's jobs, in run order ([`crate::bench::plan_jobs`]), or none.
    pub jobs: Vec<Job>,
    /// The stability matrix's cases (each run with every method of the sweep), or none.
    pub cases: Vec<StiffCase>,
    /// The shading section's settings, when it runs (shadows and AO on every field).
    pub shading: Option<ShadingConfig>,
    /// The AO part of the shading section.
    pub ao: AoConfig,
    /// Whether shadows under extreme lights run.
    pub shadow_stability: bool,
    /// Whether the level-of-detail section runs.
    pub lod: bool,
    /// The terrain-edit section's field sides (empty: it does not run).
    pub edit_sizes: Vec<u32>,
    /// Whether the terrain-blending section runs.
    pub blending: bool,
    /// Whether the scene-shadow section runs.
    pub scene_shadows: bool,
    /// Whether the frame-feature section runs.
    pub frame_features: bool,
    /// Whether the silhouette section runs.
    pub silhouettes: bool,
    /// Whether the frame-cost section runs.
    pub frame_costs: bool,
}

/// A section that runs as one piece.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WholeSection {
    /// Shadows under extreme lights on degenerate fields.
    ShadowStability,
    /// Level of detail.
    Lod,
    /// Terrain edits and weight painting.
    Edits,
    /// Terrain blending.
    Blending,
    /// Scene shadows.
    SceneShadows,
    /// Frame features (anti-aliasing, tone mapping, image-based light).
    FrameFeatures,
    /// Silhouettes on curved meshes.
    Silhouettes,
    /// The frame's costs: looks against the plain frame, hidden relief, still shadow maps.
    FrameCosts,
}

/// The steps of a sweep, numbered in the order an unsharded run measures them: the jobs, then the
/// stability cells (case by case, every method), then each field's shadows and AO, then the
/// sections that run whole.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StepLayout {
    jobs: u32,
    methods: u32,
    cells: u32,
    fields: u32,
}

impl StepLayout {
    /// The layout of `sections` over `cfg`'s methods and fields.
    pub fn new(cfg: &SweepConfig, sections: &SweepSections) -> StepLayout {
        let methods = cfg.methods.len() as u32;
        StepLayout {
            jobs: sections.jobs.len() as u32,
            methods,
            cells: sections.cases.len() as u32 * methods,
            fields: cfg.fields.len() as u32,
        }
    }

    /// Job `index` of the sweep.
    pub fn job(&self, index: usize) -> u32 {
        index as u32
    }

    /// The stability cell of case `case` and method `method` (indices in the sweep's lists).
    pub fn cell(&self, case: usize, method: usize) -> u32 {
        self.jobs + case as u32 * self.methods + method as u32
    }

    /// Field `field`'s shadows.
    pub fn shadows(&self, field: usize) -> u32 {
        self.jobs + self.cells + 2 * field as u32
    }

    /// Field `field`'s AO.
    pub fn ao(&self, field: usize) -> u32 {
        self.shadows(field) + 1
    }

    /// A section that runs whole.
    pub fn whole(&self, section: WholeSection) -> u32 {
        self.jobs + self.cells + 2 * self.fields + section as u32
    }
}

/// One unit of work: the steps it measures (run in this order on one shard) and its cost.
#[derive(Debug, Clone)]
pub struct WorkUnit {
    /// Steps of [`StepLayout`], increasing.
    pub steps: Vec<u32>,
    /// What it is expected to cost.
    pub cost: UnitCost,
}

/// Every unit of `sections` over `cfg`, in step order. Jobs of one view of the depth-scale section
/// form one unit: the step baseline's larger caps run only while a smaller one has not matched the
/// tree baseline's error at that view (`depth_match::settled`), so they must see its runs.
pub fn work_units(cfg: &SweepConfig, sections: &SweepSections) -> Vec<WorkUnit> {
    let layout = StepLayout::new(cfg, sections);
    let mut units = job_units(cfg, sections, &layout);
    for (c, case) in sections.cases.iter().enumerate() {
        for (m, &method) in cfg.methods.iter().enumerate() {
            units.push(single(layout.cell(c, m), stiff_cost(case, method)));
        }
    }
    if let Some(shading) = &sections.shading {
        units.extend(shading_units(cfg, sections, shading, &layout));
    }
    units.extend(whole_section_units(cfg, sections, &layout));
    units
}

/// The units of the sweep's jobs: one per job, except that the jobs of one view of the
/// depth-scale section share one.
fn job_units(cfg: &SweepConfig, sections: &SweepSections, layout: &StepLayout) -> Vec<WorkUnit> {
    let mut units = Vec::new();
    let mut views: HashMap<String, usize> = HashMap::new();
    for (j, job) in sections.jobs.iter().enumerate() {
        let (cost, setups) = job_cost(cfg, job);
        if job.section == Section::DepthScale {
            let view = format!(
                "{} {} {} {}",
                job.field.name(),
                job.depth_scale,
                job.angle,
                job.azimuth
            );
            if let Some(&u) = views.get(&view) {
                let unit: &mut WorkUnit = &mut units[u];
                unit.steps.push(layout.job(j));
                unit.cost.cost += cost;
                for s in setups {
                    if !unit.cost.setups.iter().any(|t| t.0 == s.0) {
                        unit.cost.setups.push(s);
                    }
                }
                continue;
            }
            views.insert(view, units.len());
        }
        units.push(WorkUnit {
            steps: vec![layout.job(j)],
            cost: UnitCost { cost, setups },
        });
    }
    units
}

/// Each field's shadows and AO units of the shading section run with `shading`.
fn shading_units(
    cfg: &SweepConfig,
    sections: &SweepSections,
    shading: &ShadingConfig,
    layout: &StepLayout,
) -> Vec<WorkUnit> {
    // --quick's shadows take about 1.5 s a field, its AO about 1 s; the full settings grow
    // with lights times rays times reference samples, and the AO with its timed maps.
    let work = |s: &ShadingConfig| {
        (s.elevations.len() * s.radii.len() * (s.modes.len() + 1)) as f64
            * f64::from(s.error_grid.0 * s.error_grid.1)
            * s.reference_samples as f64
    };
    let shadows = 1.5 * work(shading) / work(&ShadingConfig::quick());
    let ao = if sections.ao.time_main_size {
        30.0
    } else {
        1.0
    };
    (0..cfg.fields.len())
        .flat_map(|f| [single(layout.shadows(f), shadows), single(layout.ao(f), ao)])
        .collect()
}

/// The units of the sections that run whole, those that run, in step order.
fn whole_section_units(
    cfg: &SweepConfig,
    sections: &SweepSections,
    layout: &StepLayout,
) -> Vec<WorkUnit> {
    // Measured with --quick on lavapipe (two cores); the full sections run much larger settings.
    let whole = |quick_s: f64, full_s: f64| if cfg.quick { quick_s } else { full_s };
    let edit_texels: f64 = sections
        .edit_sizes
        .iter()
        .map(|&s| f64::from(s).powi(2))
        .sum();
    let sections_whole = [
        (
            WholeSection::ShadowStability,
            sections.shadow_stability,
            whole(1.0, 5.0),
        ),
        (WholeSection::Lod, sections.lod, whole(3.0, 120.0)),
        (
            WholeSection::Edits,
            !sections.edit_sizes.is_empty(),
            // 256^2 and 1024^2 in about a second; the full rebuilds grow with the texels.
            1.0 * edit_texels / (256.0 * 256.0 + 1024.0 * 1024.0),
        ),
        (WholeSection::Blending, sections.blending, whole(1.0, 60.0)),
        (
            WholeSection::SceneShadows,
            sections.scene_shadows,
            whole(5.0, 180.0),
        ),
        (
            WholeSection::FrameFeatures,
            sections.frame_features,
            whole(3.0, 30.0),
        ),
        (
            WholeSection::Silhouettes,
            sections.silhouettes,
            whole(5.0, 150.0),
        ),
        (
            WholeSection::FrameCosts,
            sections.frame_costs,
            whole(4.0, 90.0),
        ),
    ];
    sections_whole
        .into_iter()
        .filter(|&(_, runs, _)| runs)
        .map(|(section, _, cost)| single(layout.whole(section), cost))
        .collect()
}

fn single(step: u32, cost: f64) -> WorkUnit {
    WorkUnit {
        steps: vec![step],
        cost: UnitCost {
            cost,
            setups: Vec::new(),
        },
    }
}

/// Seconds per GPU ray iteration on lavapipe (two cores), roughly.
const STEP_S: f64 = 4e-9;
/// Seconds per texel the exact CPU reference walks through.
const REFERENCE_CELL_S: f64 = 50e-9;
/// Fixed cost of one timed configuration: pipelines, submissions, read-backs.
const JOB_OVERHEAD_S: f64 = 0.03;
/// Seconds per texel of a max pyramid built on the GPU, and of generating a synthetic field.
const PYRAMID_TEXEL_S: f64 = 5e-9;
const GENERATE_TEXEL_S: f64 = 50e-9;

/// Texels a ray crosses from the top of the height volume to its floor: the horizontal distance
/// `depth / tan(angle)` in uv, in texels.
fn texels_crossed(size: u32, depth_scale: f64, angle_deg: f64) -> f64 {
    let run = depth_scale / angle_deg.to_radians().tan().max(1e-3);
    1.0 + f64::from(size) * run
}

/// Iterations a ray of `method` is expected to take: a fixed-step search its cap; a pyramid
/// traversal a few per level plus the nodes a long ray passes; a cone or quadric march about the
/// square root of the texels it crosses.
fn expected_steps(method: Method, max_steps: u32, size: u32, crossed: f64) -> f64 {
    let info = method.info();
    if info.fixed_step {
        f64::from(max_steps)
    } else if info.reads_pyramid() {
        4.0 * f64::from(size.max(2)).log2() + crossed.sqrt() * 2.0
    } else {
        8.0 + crossed.sqrt()
    }
}

/// CPU seconds per texel of a method map's CPU build (from the 4096^2 builds on two cores:
/// conservative cone about 75 s, quadric 100 s, relaxed cone ten minutes).
fn cpu_map_texel_s(kind: MapKind) -> f64 {
    match kind {
        MapKind::ConservativeCone => 4.5e-6,
        MapKind::RelaxedCone => 36e-6,
        MapKind::Quadric => 6e-6,
        MapKind::MaxPyramid => PYRAMID_TEXEL_S,
    }
}

/// A job's own cost and the setups it shares with others: its field's pyramid and its method's
/// map, each built once per field and size by a shard's runner (the map also three times on the
/// CPU and GPU for the build table, up to 1024^2).
fn job_cost(cfg: &SweepConfig, job: &Job) -> (f64, Vec<(String, f64)>) {
    let crossed = texels_crossed(job.size, job.depth_scale, job.angle);
    let steps = expected_steps(job.method, job.budget.max_steps, job.size, crossed);
    let (w, h) = cfg.resolution;
    let passes = cfg.effective_passes();
    let timed = f64::from(w * h) * f64::from(cfg.frames + passes * cfg.warmup) * steps * STEP_S;
    let (ew, eh) = cfg.error_grid;
    let error = f64::from(ew * eh) * (steps * STEP_S + crossed * REFERENCE_CELL_S);
    let field = job.field.name();
    let texels = f64::from(job.size).powi(2);
    let mut setups = vec![(
        format!("pyramid of {field} at {}", job.size),
        texels * (PYRAMID_TEXEL_S + GENERATE_TEXEL_S),
    )];
    if let Some(kind) = job.method.info().method_map() {
        let cpu = texels * cpu_map_texel_s(kind);
        let gpu = cpu / 8.0;
        let rounds = if job.size <= 1024 { 3.0 } else { 0.0 };
        setups.push((
            format!("{} of {field} at {}", kind.name(), job.size),
            gpu + rounds * (gpu + cpu),
        ));
    }
    (f64::from(passes) * JOB_OVERHEAD_S + timed + error, setups)
}

/// A stability cell: its field generated, its map built, 32x32 rays traced and checked.
fn stiff_cost(case: &StiffCase, method: Method) -> f64 {
    let (w, h) = case.size;
    let texels = f64::from(w) * f64::from(h);
    let side = w.max(h);
    let crossed = texels_crossed(side, case.depth_scale, case.angle).min(1e5);
    let steps = expected_steps(
        method,
        method.info().default_budget.max_steps,
        side,
        crossed,
    );
    let map = method
        .info()
        .method_map()
        .map_or(0.0, |k| texels * cpu_map_texel_s(k) / 8.0);
    JOB_OVERHEAD_S
        + texels * (GENERATE_TEXEL_S + PYRAMID_TEXEL_S)
        + map
        + 1024.0 * (steps * STEP_S + crossed * REFERENCE_CELL_S)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bench::{partition, plan_jobs, stiff_cases};

    /// The full default sweep with every section, on a device taking 8192^2 maps.
    fn full_sweep() -> (SweepConfig, SweepSections) {
        let cfg = SweepConfig::full();
        let sections = SweepSections {
            jobs: plan_jobs(&cfg),
            cases: stiff_cases(8192, false),
            shading: Some(ShadingConfig::full()),
            ao: AoConfig::full(),
            shadow_stability: true,
            lod: true,
            edit_sizes: vec![1024, 4096],
            blending: true,
            scene_shadows: true,
            frame_features: true,
            silhouettes: true,
            frame_costs: true,
        };
        (cfg, sections)
    }

    #[test]
    fn every_step_is_in_exactly_one_unit_and_units_run_in_step_order() {
        let (cfg, sections) = full_sweep();
        let units = work_units(&cfg, &sections);
        let mut steps: Vec<u32> = units.iter().flat_map(|u| u.steps.clone()).collect();
        assert!(units
            .iter()
            .all(|u| u.steps.windows(2).all(|p| p[0] < p[1])));
        steps.sort_unstable();
        let layout = StepLayout::new(&cfg, &sections);
        let total = layout.whole(WholeSection::FrameCosts) + 1;
        assert_eq!(steps, (0..total).collect::<Vec<_>>());
        assert!(units
            .iter()
            .all(|u| u.cost.cost > 0.0 && u.cost.cost.is_finite()));
    }

    #[test]
    fn a_depth_scale_view_stays_one_unit() {
        let (cfg, sections) = full_sweep();
        let units = work_units(&cfg, &sections);
        for (j, job) in sections.jobs.iter().enumerate() {
            if job.section != Section::DepthScale {
                continue;
            }
            let unit = units
                .iter()
                .find(|u| u.steps.contains(&(j as u32)))
                .unwrap();
            for &s in &unit.steps {
                let other = &sections.jobs[s as usize];
                assert_eq!(other.section, Section::DepthScale);
                assert_eq!(
                    (other.field.name(), other.depth_scale, other.angle),
                    (job.field.name(), job.depth_scale, job.angle)
                );
            }
            // Both baselines of the view are in it.
            let methods: std::collections::HashSet<Method> = unit
                .steps
                .iter()
                .map(|&s| sections.jobs[s as usize].method)
                .collect();
            assert_eq!(methods.len(), 2, "{job:?}");
        }
    }

    #[test]
    fn the_full_sweep_splits_into_shards_within_a_tenth_of_the_mean_load() {
        let (cfg, sections) = full_sweep();
        let units = work_units(&cfg, &sections);
        let costs: Vec<UnitCost> = units.iter().map(|u| u.cost.clone()).collect();
        for count in [2, 3, 4, 8] {
            let (shard_of, loads) = partition(&costs, count);
            assert_eq!(
                partition(&costs, count).0,
                shard_of,
                "same input, same split"
            );
            assert!(shard_of.iter().all(|&s| s < count));
            let mean = loads.iter().sum::<f64>() / f64::from(count);
            let (lo, hi) = loads
                .iter()
                .fold((f64::MAX, 0.0f64), |(lo, hi), &l| (lo.min(l), hi.max(l)));
            assert!(
                hi <= 1.1 * mean && lo >= 0.9 * mean,
                "{count} shards: loads {loads:?}, mean {mean}"
            );
        }
    }
}
