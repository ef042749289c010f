//! Runs a sweep: for each configuration, the GPU time of the full-screen pass and the error of
//! the same method traced against the exact reference; plus map build times. Height fields and
//! method maps are built once per field and size and reused.

use std::collections::HashMap;
use std::sync::Arc;
use std::time::Instant;

use anyhow::Context as _;

use super::depth_match::depth_budgets;
use super::median::median;
use super::results::{GpuMs, MapBuild, Run};
use super::steps_map::StepsMap;
use super::subgroup_steps::subgroup_steps;
use super::sweep::{FieldSource, SweepConfig};
use super::trace_stats::{ray_direction, trace_stats, StepStats};
use crate::heightfield::{build_method_map, Heightfield, LoadOptions, MapData};
use crate::method::{BenchRole, Budget, Method};
use crate::render::{
    build_method_map_with, build_pyramid_on_gpu, time_method, trace_counting_fetches, BenchRequest,
    HeightFormat, MapBuilder, TraceRequest,
};
use crate::vk::Context;

/// Which part of the report a run belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Section {
    /// Every method at every view: hit error against GPU time.
    ErrorVsTime,
    /// Time as the map side grows, over [`crate::bench::SweepConfig::sizes`].
    Scaling,
    /// POM at caps from its default up to the default grown in proportion to the map side: the
    /// report picks per size the cheapest cap that holds POM's error at the smallest size, the
    /// cost of a fixed-step method matched for error.
    MatchedScaling,
    /// Error and time as the depth scale grows, over [`crate::bench::SweepConfig::depth_scales`].
    DepthScale,
    /// Every method at its default budget at every depth scale: the cost curve over depth.
    DepthCurve,
}

/// POM's largest cap tried at map side `size`: `base` steps at side `smallest`, grown in
/// proportion (the ray's path in texels grows with the side).
pub fn matched_steps(base: u32, size: u32, smallest: u32) -> u32 {
    let scaled = u64::from(base) * u64::from(size) / u64::from(smallest.max(1));
    scaled.clamp(1, 4096) as u32
}

/// One configuration to measure.
#[derive(Debug, Clone)]
pub struct Job {
    /// The report section it belongs to.
    pub section: Section,
    /// The height field.
    pub field: FieldSource,
    /// Map side, in texels (square maps).
    pub size: u32,
    /// The method traced.
    pub method: Method,
    /// Its iteration budget.
    pub budget: Budget,
    /// View elevation above the surface plane, in degrees.
    pub angle: f64,
    /// View azimuth from +u toward +v, in degrees.
    pub azimuth: f64,
    /// Depth of height 0 below the top plane, in uv units.
    pub depth_scale: f64,
}

/// Section 3's stiff view: one-texel spikes (every coarse pyramid node holds one) seen at a
/// grazing 5 degrees, at the sweep's main depth scale.
const STIFF_FIELD: FieldSource = FieldSource::Synthetic(crate::heightfield::Generator::Spikes);
const STIFF_ANGLE: f64 = 5.0;
/// The view angle of sections 2 and 3, in degrees: neither grazing nor overhead.
const MIDDLE_ANGLE: f64 = 30.0;

/// Every job of `cfg`'s sweep, in run order.
pub fn plan_jobs(cfg: &SweepConfig) -> Vec<Job> {
    let base =
        |section, field: &FieldSource, size, method: Method, budget, angle, depth_scale| Job {
            section,
            field: field.clone(),
            size,
            method,
            budget,
            angle,
            azimuth: cfg.azimuths.first().copied().unwrap_or(0.0),
            depth_scale,
        };
    let first = cfg
        .fields
        .first()
        .cloned()
        .unwrap_or(FieldSource::Synthetic(crate::heightfield::Generator::Fbm));
    let mut jobs = error_vs_time_jobs(cfg, &base);
    jobs.extend(scaling_jobs(cfg, &base, &first));
    jobs.extend(depth_scale_jobs(cfg, &base, &first));
    jobs.extend(depth_curve_jobs(cfg, &base, &first));
    jobs
}

/// A job of the sweep at the first azimuth: (section, field, size, method, budget, angle, depth
/// scale).
type JobAt<'a> = dyn Fn(Section, &FieldSource, u32, Method, Budget, f64, f64) -> Job + 'a;

/// Section 1: every field, method, budget, angle and azimuth at the main size and depth scale.
fn error_vs_time_jobs(cfg: &SweepConfig, base: &JobAt) -> Vec<Job> {
    let mut jobs = Vec::new();
    let (size, depth) = (cfg.main_size(), cfg.main_depth_scale());
    for field in &cfg.fields {
        for &method in &cfg.methods {
            for budget in cfg.budgets_for(method) {
                for &angle in &cfg.angles {
                    for &azimuth in &cfg.azimuths {
                        let mut job = base(
                            Section::ErrorVsTime,
                            field,
                            size,
                            method,
                            budget,
                            angle,
                            depth,
                        );
                        job.azimuth = azimuth;
                        jobs.push(job);
                    }
                }
            }
        }
    }
    jobs
}

/// Section 2: every method on the first field at each further size, and the step baseline with
/// step caps grown to match the smallest size's.
fn scaling_jobs(cfg: &SweepConfig, base: &JobAt, first: &FieldSource) -> Vec<Job> {
    let mut jobs = Vec::new();
    let (size, depth) = (cfg.main_size(), cfg.main_depth_scale());
    for &method in &cfg.methods {
        let budget = method.info().default_budget;
        for &s in cfg.sizes.iter().skip(1) {
            jobs.push(base(
                Section::Scaling,
                first,
                s,
                method,
                budget,
                MIDDLE_ANGLE,
                depth,
            ));
        }
        let role = method.info().bench_role;
        if role == Some(BenchRole::StepBaseline) && cfg.sizes.len() > 1 {
            let smallest = cfg.sizes.iter().copied().min().unwrap_or(size);
            for &s in &cfg.sizes {
                let most = matched_steps(budget.max_steps, s, smallest);
                let caps = std::iter::successors(Some(budget.max_steps), |c| Some(c * 2))
                    .take_while(|c| *c <= most);
                for steps in caps {
                    let capped = Budget {
                        max_steps: steps,
                        ..budget
                    };
                    jobs.push(base(
                        Section::MatchedScaling,
                        first,
                        s,
                        method,
                        capped,
                        MIDDLE_ANGLE,
                        depth,
                    ));
                }
            }
        }
    }
    jobs
}

/// Section 3 at every depth scale (the first too: section 1 does not try the larger caps), the
/// tree baseline first: the step baseline's larger caps are skipped at run time once one has
/// matched it (`depth_match::settled`).
fn depth_scale_jobs(cfg: &SweepConfig, base: &JobAt, first: &FieldSource) -> Vec<Job> {
    let mut jobs = Vec::new();
    let (size, depth) = (cfg.main_size(), cfg.main_depth_scale());
    for role in [BenchRole::TreeBaseline, BenchRole::StepBaseline] {
        let Some(method) = Method::with_role(role).filter(|m| cfg.methods.contains(m)) else {
            continue;
        };
        let budgets = if cfg.quick {
            cfg.budgets_for(method)
        } else {
            depth_budgets(method, cfg.budgets_for(method))
        };
        for &d in &cfg.depth_scales {
            for b in budgets.iter().copied() {
                jobs.push(base(
                    Section::DepthScale,
                    first,
                    size,
                    method,
                    b,
                    MIDDLE_ANGLE,
                    d,
                ));
            }
        }
        for b in budgets.iter().copied() {
            jobs.push(base(
                Section::DepthScale,
                &STIFF_FIELD,
                size,
                method,
                b,
                STIFF_ANGLE,
                depth,
            ));
        }
    }
    jobs
}

/// The depth-scale cost curve: every method at its default budget on the first field, at the main
/// size and the middle angle, at every depth scale (the first too, so that the curve does not
/// depend on which angles section 1 ran).
fn depth_curve_jobs(cfg: &SweepConfig, base: &JobAt, first: &FieldSource) -> Vec<Job> {
    let size = cfg.main_size();
    let mut jobs = Vec::new();
    for &method in &cfg.methods {
        for &d in &cfg.depth_scales {
            let budget = method.info().default_budget;
            jobs.push(base(
                Section::DepthCurve,
                first,
                size,
                method,
                budget,
                MIDDLE_ANGLE,
                d,
            ));
        }
    }
    jobs
}

/// Measures jobs on one device, caching height fields and maps between them.
pub struct Runner {
    ctx: Arc<Context>,
    cfg: SweepConfig,
    fields: HashMap<(String, u32), Arc<Heightfield>>,
    maps: HashMap<(String, u32, Method), Option<Arc<MapData>>>,
    /// Every map built so far, with its build time, for [`crate::bench::BenchResults::maps`].
    pub map_builds: Vec<MapBuild>,
    /// Each method's steps per ray at its first error-against-time configuration with its
    /// default budget, for [`crate::bench::BenchResults::steps_maps`].
    pub steps_maps: Vec<StepsMap>,
}

impl Runner {
    /// A runner on `ctx`'s device for `cfg`, with empty caches; nothing is measured yet.
    pub fn new(ctx: Arc<Context>, cfg: SweepConfig) -> Runner {
        Runner {
            ctx,
            cfg,
            fields: HashMap::new(),
            maps: HashMap::new(),
            map_builds: Vec::new(),
            steps_maps: Vec::new(),
        }
    }

    /// The height field of `field` at `size`, as the GPU stores it (so the reference sees the same).
    pub fn field(&mut self, field: &FieldSource, size: u32) -> anyhow::Result<Arc<Heightfield>> {
        let key = (field.name(), size);
        if let Some(hf) = self.fields.get(&key) {
            return Ok(hf.clone());
        }
        let raw = match field {
            FieldSource::Synthetic(g) => g.generate(size, size, self.cfg.seed),
            FieldSource::File(path) => Heightfield::load_png(path, &LoadOptions::default())?,
        };
        raw.check_max_dimension(self.ctx.info().max_image_dimension_2d, &key.0)?;
        let stored = match self.cfg.format {
            HeightFormat::R16Unorm => raw.quantized_unorm16(),
            HeightFormat::R32Float => raw,
        };
        let (_, gpu_ms) =
            build_pyramid_on_gpu(&self.ctx, &stored, self.cfg.format, self.cfg.address)
                .with_context(|| format!("building the pyramid of {}", key.0))?;
        self.map_builds.push(MapBuild {
            kind: "max_pyramid".into(),
            heightfield: key.0.clone(),
            size: [stored.width(), stored.height()],
            ms: gpu_ms,
            on: "gpu".into(),
        });
        let hf = Arc::new(stored);
        self.fields.insert(key, hf.clone());
        Ok(hf)
    }

    /// The method's map, built once per field and size: on the GPU where a GPU builder exists
    /// (the entry in `map_builds` says which), then, for the table's comparison, once more on the
    /// CPU right after where [`cpu_reference_wanted`] (its map is dropped: the bench traces the
    /// GPU's).
    pub(crate) fn map(
        &mut self,
        field: &FieldSource,
        size: u32,
        method: Method,
        hf: &Heightfield,
    ) -> anyhow::Result<Option<Arc<MapData>>> {
        let key = (field.name(), size, method);
        if let Some(m) = self.maps.get(&key) {
            return Ok(m.clone());
        }
        let builder = MapBuilder::Gpu(&self.ctx);
        let Some(built) = build_method_map_with(method, hf, self.cfg.address, builder)
            .with_context(|| format!("building the {method} map of {}", key.0))?
        else {
            self.maps.insert(key, None);
            return Ok(None);
        };
        if built.on == "gpu" && cpu_reference_wanted(hf) {
            // GPU and CPU builds alternate, so that a machine whose speed drifts during the run (two shared
            // cores do) slows both alike; each side reports its median.
            let mut gpu = vec![built.ms];
            let mut cpu = Vec::new();
            for round in 0..MAP_BUILD_ROUNDS {
                if round > 0 {
                    let again = build_method_map_with(method, hf, self.cfg.address, builder)?;
                    gpu.extend(again.map(|b| b.ms));
                }
                if let Some((_, took)) = build_method_map(method, hf, self.cfg.address) {
                    cpu.push(took.as_secs_f64() * 1e3);
                }
            }
            self.record_map_build(method, field, hf, median(gpu), "gpu");
            if !cpu.is_empty() {
                self.record_map_build(method, field, hf, median(cpu), "cpu");
            }
        } else {
            self.record_map_build(method, field, hf, built.ms, built.on);
        }
        let data = Some(Arc::new(built.data));
        self.maps.insert(key, data.clone());
        Ok(data)
    }

    fn record_map_build(
        &mut self,
        method: Method,
        field: &FieldSource,
        hf: &Heightfield,
        ms: f64,
        on: &'static str,
    ) {
        let kind = method
            .info()
            .method_map()
            .map(|k| k.name())
            .unwrap_or_default();
        self.map_builds.push(MapBuild {
            kind: kind.to_owned(),
            heightfield: field.name(),
            size: [hf.width(), hf.height()],
            ms,
            on: on.to_owned(),
        });
    }

    /// Times and measures one job: its first pass's frames ([`SweepConfig::frames_in_pass`])
    /// and its error; [`Runner::time_again`] adds the later passes' frames.
    pub fn measure(&mut self, job: &Job) -> anyhow::Result<Run> {
        let hf = self.field(&job.field, job.size)?;
        let map = self.map(&job.field, job.size, job.method, &hf)?;
        let trace = self.trace_request(job, map.as_deref());
        let started = Instant::now();
        let timing = time_method(
            &self.ctx,
            &hf,
            &self.timed(trace, self.cfg.frames_in_pass(0)),
        )?;
        let cpu_ms = started.elapsed().as_secs_f64() * 1e3;
        let timed_steps = subgroup_steps(
            &timing.steps,
            self.cfg.resolution,
            self.ctx.info().subgroup_size,
        );
        // Counted, untimed: the counting would weigh on the timed frames.
        let traced = trace_counting_fetches(&self.ctx, &hf, &trace)?;
        let first_of_method = !self.steps_maps.iter().any(|m| m.method == job.method.id());
        let default_budget = job.budget == job.method.info().default_budget;
        if job.section == Section::ErrorVsTime && default_budget && first_of_method {
            self.steps_maps.push(StepsMap {
                method: job.method.id().to_owned(),
                traced: format!(
                    "{} {}^2, {} deg, depth scale {}",
                    job.field.name(),
                    hf.width(),
                    job.angle,
                    job.depth_scale
                ),
                grid: [self.cfg.error_grid.0, self.cfg.error_grid.1],
                steps: traced.steps.iter().map(|s| s[0]).collect(),
            });
        }
        let stats = trace_stats(
            &hf,
            &traced.hits,
            &traced.steps,
            // The depth the GPU traced with, rounded to f32 as it was.
            f64::from(trace.depth_scale),
            self.cfg.address,
        );
        Ok(Run {
            section: job.section,
            method: job.method.id().to_owned(),
            heightfield: job.field.name(),
            size: [hf.width(), hf.height()],
            depth_scale: job.depth_scale,
            angle_deg: job.angle,
            azimuth_deg: job.azimuth,
            address: self.cfg.address.to_string(),
            budget: job.budget,
            gpu_ms: GpuMs::of(&timing.frame_ms),
            frames: self.cfg.frames,
            resolution: [self.cfg.resolution.0, self.cfg.resolution.1],
            cpu_ms,
            error_texels: stats.error_texels,
            depth_error_texels: stats.depth_error_texels,
            gross_rate: stats.gross_rate,
            capped_rate: stats.capped_rate,
            nan_pixels: stats.nan_pixels,
            steps: stats.steps,
            fetches: StepStats::of(traced.fetches.iter().map(|f| f[0])),
            compute_invocations: timing.compute_invocations.first().copied(),
            timed_steps,
        })
    }

    /// Pass `pass`'s frames of a job [`Runner::measure`] ran, added to its run: the samples in
    /// the order they ran, the summary over all of them, the wall time summed.
    pub fn time_again(&mut self, job: &Job, pass: u32, run: &mut Run) -> anyhow::Result<()> {
        let frames = self.cfg.frames_in_pass(pass);
        if frames == 0 {
            return Ok(());
        }
        let hf = self.field(&job.field, job.size)?;
        let map = self.map(&job.field, job.size, job.method, &hf)?;
        let trace = self.trace_request(job, map.as_deref());
        let started = Instant::now();
        let timing = time_method(&self.ctx, &hf, &self.timed(trace, frames))?;
        run.cpu_ms += started.elapsed().as_secs_f64() * 1e3;
        let mut samples = std::mem::take(&mut run.gpu_ms.samples);
        samples.extend(timing.frame_ms);
        run.gpu_ms = GpuMs::of(&samples);
        Ok(())
    }

    /// The error measurement's trace of `job`; the timed one is the same at the timing grid.
    fn trace_request<'m>(&self, job: &Job, map: Option<&'m MapData>) -> TraceRequest<'m> {
        TraceRequest {
            method: job.method,
            dir: ray_direction(job.angle, job.azimuth).map(|x| x as f32),
            depth_scale: job.depth_scale as f32,
            grid: self.cfg.error_grid,
            budget: job.budget,
            address: self.cfg.address,
            format: self.cfg.format,
            map,
            shadow: None,
        }
    }

    fn timed<'m>(&self, trace: TraceRequest<'m>, frames: u32) -> BenchRequest<'m> {
        BenchRequest {
            trace: TraceRequest {
                grid: self.cfg.resolution,
                ..trace
            },
            warmup: self.cfg.warmup,
            frames,
            dispatches: self.cfg.dispatches_per_frame(trace.method),
        }
    }

    /// The device context.
    pub fn ctx(&self) -> &Arc<Context> {
        &self.ctx
    }

    /// The sweep being run.
    pub fn config(&self) -> &SweepConfig {
        &self.cfg
    }
}

/// The largest side at which the bench also builds a map on the CPU after its GPU build: beyond
/// it the CPU builders take minutes (at 4096^2 about 75 s for the conservative cone map, 100 s for
/// the quadric map and over ten minutes for the relaxed cone map) that only repeat the comparison
/// the smaller sizes already make.
const CPU_MAP_MAX_SIDE: u32 = 1024;

/// GPU and CPU builds of a map the table compares, taken in turns; the table shows each side's median.
pub(crate) const MAP_BUILD_ROUNDS: usize = 3;

/// Whether the bench rebuilds `hf`'s map on the CPU, after a GPU build, for the map table.
fn cpu_reference_wanted(hf: &Heightfield) -> bool {
    hf.width().max(hf.height()) <= CPU_MAP_MAX_SIDE
}
