//! `relief bench`: every method's error against its GPU time on one device, how cost grows with
//! map size and depth scale, and the stability matrix; writes results.json, report.md and plots.

use std::sync::Arc;

use anyhow::Context as _;
use std::io::IsTerminal;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use relief::bench::{
    blending_notes, measure_ao, measure_shadows, render_report, run_blending_section,
    run_edit_section, run_frame_cost_section, run_frame_feature_section, run_lod_section,
    run_paint_section, run_scene_shadow_section, run_silhouette_section, run_stiff_case,
    utc_now_rfc3339, AoRun, BenchResults, BlendingConfig, BlendingSection, EditCost, FieldSource,
    FrameCostSection, FrameFeatureSection, LodConfig, LodSection, MachineAtStart, PaintCost,
    ReliefBuild, Runner, SceneShadowSection, SectionsRun, ShadowRun, ShadowStabilityCell,
    SilhouetteSection, StabilityCell, StepOrigins, StiffCase, SweepConfig, SweepSections,
    WholeSection, SCHEMA_VERSION,
};

/// The brush radius of the terrain-edit section, in texels (the stroke).
const EDIT_RADIUS: f32 = 32.0;
use relief::heightfield::MAX_SIDE;
use relief::method::Method;
use relief::render::{timeline_trace, HeightFormat, TraceHeader, TracedFrame};
use relief::scene::AoMode;
use relief::vk::Context;

use super::bench_args::{parse_resolution, BenchArgs, BenchCommand};
use super::bench_merge;
use super::bench_runs::measure_runs;
use super::bench_sections::{sections, sections_record};
use super::bench_shard::{self, StepPlan};
use super::scene_args::FormatArg;

fn config(args: &BenchArgs) -> anyhow::Result<SweepConfig> {
    let mut cfg = if args.quick {
        SweepConfig::quick()
    } else {
        SweepConfig::full()
    };
    if !args.methods.is_empty() {
        cfg.methods = args
            .methods
            .iter()
            .map(|m| m.parse::<Method>())
            .collect::<Result<_, _>>()?;
    }
    if !args.fields.is_empty() {
        cfg.fields = args
            .fields
            .iter()
            .map(|g| FieldSource::Synthetic(*g))
            .collect();
    }
    cfg.fields
        .extend(args.heightmap.iter().cloned().map(FieldSource::File));
    let set = |dst: &mut Vec<f64>, src: &[f64]| {
        if !src.is_empty() {
            *dst = src.to_vec()
        }
    };
    set(&mut cfg.angles, &args.angles);
    set(&mut cfg.azimuths, &args.azimuths);
    set(&mut cfg.depth_scales, &args.depth_scales);
    if !args.sizes.is_empty() {
        cfg.sizes = args.sizes.clone();
    }
    if !args.budgets.is_empty() {
        cfg.budgets = args.budgets.clone();
    }
    if let Some(r) = &args.resolution {
        cfg.resolution = parse_resolution(r)?;
    }
    cfg.frames = args.frames.unwrap_or(cfg.frames).max(1);
    cfg.passes = args.passes.unwrap_or(cfg.passes).max(1);
    cfg.stability &= !args.no_stability;
    cfg.slow_down = args.slow_down.clone();
    cfg.address = args.address;
    cfg.format = match args.height_format {
        FormatArg::R16 => HeightFormat::R16Unorm,
        FormatArg::R32f => HeightFormat::R32Float,
    };
    validate(&cfg)?;
    // The strokes (radius EDIT_RADIUS, an eighth of it on the splat map) must fit the field.
    if let Some(s) = args
        .edit_sizes
        .iter()
        .find(|s| !(32..=MAX_SIDE).contains(*s))
    {
        anyhow::bail!("--edit-sizes must lie in 32..={MAX_SIDE}, got {s}");
    }
    Ok(cfg)
}

fn validate(cfg: &SweepConfig) -> anyhow::Result<()> {
    if let Some(a) = cfg.angles.iter().find(|a| !(**a > 0.0 && **a <= 90.0)) {
        anyhow::bail!("--angles must lie in (0, 90] degrees, got {a}");
    }
    if let Some(s) = cfg
        .depth_scales
        .iter()
        .find(|s| !(s.is_finite() && **s > 0.0))
    {
        anyhow::bail!("--depth-scales must be finite and above 0, got {s}");
    }
    if let Some(s) = cfg.sizes.iter().find(|s| **s == 0 || **s > MAX_SIDE) {
        anyhow::bail!("--sizes must lie in 1..={MAX_SIDE}, got {s}");
    }
    if cfg.methods.is_empty()
        || cfg.fields.is_empty()
        || cfg.angles.is_empty()
        || cfg.azimuths.is_empty()
    {
        anyhow::bail!("nothing to measure: give at least one method, field, angle and azimuth");
    }
    Ok(())
}

/// A progress bar on a terminal; one plain line per step when stderr is a log file, so runs
/// piped to a file still show how far they are; nothing with --json.
fn progress(total: usize, quiet: bool) -> ProgressBar {
    if quiet {
        return ProgressBar::hidden();
    }
    if !std::io::stderr().is_terminal() {
        let bar = ProgressBar::with_draw_target(Some(total as u64), ProgressDrawTarget::hidden());
        return bar;
    }
    let bar = ProgressBar::new(total as u64);
    let style = ProgressStyle::with_template("{elapsed_precise} [{bar:30}] {pos}/{len} {msg}")
        .map(|s| s.progress_chars("=> "))
        .unwrap_or_else(|_| ProgressStyle::default_bar());
    bar.set_style(style);
    bar
}

/// The stability matrix: every method on every stiff case the plan wants.
fn measure_stability(
    ctx: &Arc<Context>,
    cases: &[StiffCase],
    methods: &[Method],
    plan: &StepPlan,
    origins: &mut StepOrigins,
    bar: &ProgressBar,
    quiet: bool,
) -> Vec<StabilityCell> {
    let mut stability = Vec::new();
    for (c, case) in cases.iter().enumerate() {
        for (m, &method) in methods.iter().enumerate() {
            let step = plan.layout.cell(c, m);
            if !plan.wants(step) {
                continue;
            }
            note(bar, &format!("stability: {method} on {}", case.name), quiet);
            stability.push(run_stiff_case(ctx, case, method));
            origins.stability.push(step);
            bar.inc(1);
        }
    }
    stability
}

/// Shadows and AO on every field the plan wants them on, when the shading section runs.
fn measure_shading(
    runner: &mut Runner,
    sections: &SweepSections,
    fields: &[FieldSource],
    plan: &StepPlan,
    origins: &mut StepOrigins,
    bar: &ProgressBar,
    quiet: bool,
) -> anyhow::Result<(Vec<ShadowRun>, Vec<AoRun>)> {
    let mut shadows = Vec::new();
    let mut ao = Vec::new();
    let Some(shading) = &sections.shading else {
        return Ok((shadows, ao));
    };
    for (f, field) in fields.iter().enumerate() {
        let mut note_step = |what: &str| {
            note(bar, what, quiet);
            bar.inc(1);
        };
        let step = plan.layout.shadows(f);
        if plan.wants(step) {
            let rows = measure_shadows(runner, shading, field, &mut note_step)
                .with_context(|| format!("measuring shadows on {}", field.name()))?;
            origins
                .shadows
                .extend(std::iter::repeat_n(step, rows.len()));
            origins.note_maps(step, runner.map_builds.len());
            shadows.extend(rows);
        }
        let step = plan.layout.ao(f);
        if plan.wants(step) {
            let rows = measure_ao(runner, &sections.ao, field, &mut note_step)
                .with_context(|| format!("measuring AO on {}", field.name()))?;
            origins.ao.extend(std::iter::repeat_n(step, rows.len()));
            origins.note_maps(step, runner.map_builds.len());
            ao.extend(rows);
        }
    }
    Ok((shadows, ao))
}

pub(super) fn note(bar: &ProgressBar, what: &str, quiet: bool) {
    if !quiet && !std::io::stderr().is_terminal() {
        eprintln!(
            "[{}/{}] {what}",
            bar.position() + 1,
            bar.length().unwrap_or(0)
        );
    }
    bar.set_message(what.to_owned());
}

/// Whether a section that runs whole runs here: asked for, and in this run's shard.
fn whole_wanted(asked: bool, plan: &StepPlan, section: WholeSection) -> bool {
    asked && plan.wants(plan.layout.whole(section))
}

/// The progress bar's length: one step per job and pass, stability case and method, shading
/// measurement, and one or two per other section, of those the plan wants.
fn progress_steps(s: &SweepSections, cfg: &SweepConfig, plan: &StepPlan) -> usize {
    let l = &plan.layout;
    let count = |steps: &mut dyn Iterator<Item = u32>| steps.filter(|&t| plan.wants(t)).count();
    let jobs = count(&mut (0..s.jobs.len()).map(|j| l.job(j))) * cfg.effective_passes() as usize;
    let cells = count(
        &mut (0..s.cases.len()).flat_map(|c| (0..cfg.methods.len()).map(move |m| l.cell(c, m))),
    );
    let (shadows, ao) = s.shading.as_ref().map_or((0, 0), |sh| {
        let fields = 0..cfg.fields.len();
        (
            count(&mut fields.clone().map(|f| l.shadows(f)))
                * sh.elevations.len()
                * sh.radii.len()
                * (sh.modes.len() + 1),
            count(&mut fields.map(|f| l.ao(f))) * AoMode::all().len(),
        )
    });
    let whole = |asked: bool, section| usize::from(whole_wanted(asked, plan, section));
    jobs + cells
        + shadows
        + ao
        + whole(s.shadow_stability, WholeSection::ShadowStability)
        + whole(s.lod, WholeSection::Lod)
        + 2 * whole(!s.edit_sizes.is_empty(), WholeSection::Edits)
        + whole(s.blending, WholeSection::Blending)
        + whole(s.scene_shadows, WholeSection::SceneShadows)
        + whole(s.frame_features, WholeSection::FrameFeatures)
        + whole(s.silhouettes, WholeSection::Silhouettes)
        + whole(s.frame_costs, WholeSection::FrameCosts)
}

pub fn run(args: &BenchArgs) -> anyhow::Result<()> {
    match &args.command {
        Some(BenchCommand::Compare(a)) => return super::bench_compare::run(a),
        Some(BenchCommand::Merge(a)) => return bench_merge::run(a),
        Some(BenchCommand::Gate(a)) => return super::bench_gate::run(a),
        None => {}
    }
    let Some(out) = &args.out else {
        anyhow::bail!("relief bench needs --out DIR");
    };
    check_timeline_path(args)?;
    let cfg = config(args)?;
    // Read before any measuring, so that a bad file fails the run at once.
    let extra_mesh = silhouette_mesh(args.silhouette_mesh.as_deref())?;
    let ctx = super::open_device(args.device.as_deref(), args.json)?;
    let machine = MachineAtStart::read();
    let sections = sections(args, &cfg, &ctx);
    if args.timeline.is_some() && !sections.frame_costs {
        return Err(super::usage(
            "--timeline lays out the frame-cost section's frames, which this run leaves out; add --sections frame-costs or --frame-costs-only",
        ));
    }
    let sections_run = sections_record(args, &sections);
    let plan = StepPlan::new(args.shard, &cfg, &sections);
    announce_run(args, &sections_run, &plan);
    let bar = progress(progress_steps(&sections, &cfg, &plan), args.json);
    let mut origins = StepOrigins::default();
    let mut runner = Runner::new(ctx.clone(), cfg.clone());
    let (quiet, o) = (args.json, &mut origins);
    let runs = measure_runs(&mut runner, &sections.jobs, &plan, o, &bar, quiet)?;
    let stability = measure_stability(&ctx, &sections.cases, &cfg.methods, &plan, o, &bar, quiet);
    let (shadows, ao) =
        measure_shading(&mut runner, &sections, &cfg.fields, &plan, o, &bar, quiet)?;
    let whole = measure_whole(
        args,
        &cfg,
        &ctx,
        &sections,
        &plan,
        &bar,
        extra_mesh.as_ref(),
    )?;
    bar.finish_and_clear();
    super::check_validation(&ctx)?;
    let lod = lod_config(args, &cfg);
    let blending = blending_config(args, &cfg);
    let fingerprint = bench_shard::fingerprint(&cfg, &sections, &lod, &blending);
    let argv = command_words();
    let results = BenchResults {
        schema_version: SCHEMA_VERSION,
        relief: ReliefBuild::current(),
        date: utc_now_rfc3339(),
        device: ctx.info().into(),
        command: argv.join(" "),
        argv,
        options: (&cfg).into(),
        runs,
        maps: runner.map_builds,
        stability,
        shadows,
        shadow_stability: whole.shadow_stability,
        ao,
        lod: whole.lod,
        edits: whole.edits,
        paint_edits: whole.paint_edits,
        blending: whole.blending,
        scene_shadows: whole.scene_shadows,
        frame_features: whole.frame_features,
        silhouettes: whole.silhouettes,
        frame_costs: whole.frame_costs,
        shard: plan.info(fingerprint, origins),
        machine: Some(machine.finish()),
        sections: Some(sections_run),
        steps_maps: runner.steps_maps,
    };
    if let (Some(why), false) = (
        results.machine.as_ref().and_then(|m| m.busy.as_ref()),
        args.json,
    ) {
        eprintln!("relief: warning: {why}");
    }
    if let (Some(path), Some(costs)) = (&args.timeline, &results.frame_costs) {
        write_bench_timeline(path, &ctx, costs)?;
    }
    write_outputs(out, &results, args.json)
}

/// Fails unless `--timeline`, when given, names a `.json` file.
fn check_timeline_path(args: &BenchArgs) -> anyhow::Result<()> {
    if let Some(path) = &args.timeline {
        if !path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("json"))
        {
            return Err(super::usage(format!(
                "--timeline writes trace-event JSON; {} does not end in .json",
                path.display()
            )));
        }
    }
    Ok(())
}

/// Says on stderr, unless the run prints JSON, which sections it leaves out and what share of
/// the work its shard takes.
fn announce_run(args: &BenchArgs, sections_run: &SectionsRun, plan: &StepPlan) {
    if !args.json && !sections_run.skipped.is_empty() {
        eprintln!("relief bench: {}", sections_run.line());
    }
    if let (Some(shard), Some((mine, all, load, most)), false) =
        (args.shard, plan.estimate, args.json)
    {
        eprintln!(
            "shard {shard}: {mine} of {all} units, an estimated {load:.0} s on lavapipe (the largest shard {most:.0} s)"
        );
    }
}

/// The command line's words, for the record: a path need not be UTF-8, and the record shows
/// such a word lossily rather than failing.
fn command_words() -> Vec<String> {
    std::env::args_os()
        .map(|a| a.to_string_lossy().into_owned())
        .collect()
}

/// Writes the frame-cost section's frames to `path` as trace-event JSON.
fn write_bench_timeline(
    path: &std::path::Path,
    ctx: &Context,
    costs: &FrameCostSection,
) -> anyhow::Result<()> {
    let header = TraceHeader {
        title: "relief bench: frame costs".into(),
        device: ctx.describe(),
        other: serde_json::json!({
            "command": std::env::args().collect::<Vec<_>>().join(" "),
            "commit": env!("RELIEF_GIT_COMMIT"),
        }),
    };
    let frames: Vec<TracedFrame> = costs
        .timelines
        .iter()
        .flat_map(|(label, timelines)| {
            timelines
                .iter()
                .zip(1..)
                .map(|(timeline, number)| TracedFrame {
                    label,
                    number,
                    timeline,
                })
        })
        .collect();
    let bytes = serde_json::to_vec(&timeline_trace(&header, &frames))?;
    super::frame_files::write_whole(path, &bytes)
        .with_context(|| format!("writing the timeline {}", path.display()))
}

/// What the sections that run as one piece measured.
struct Whole {
    shadow_stability: Vec<ShadowStabilityCell>,
    lod: Option<LodSection>,
    edits: Vec<EditCost>,
    paint_edits: Vec<PaintCost>,
    blending: Option<BlendingSection>,
    scene_shadows: Option<SceneShadowSection>,
    frame_features: Option<FrameFeatureSection>,
    silhouettes: Option<SilhouetteSection>,
    frame_costs: Option<FrameCostSection>,
}

/// Runs the sections that run as one piece, those asked for and in this run's shard.
/// The first mesh with triangles of `--silhouette-mesh`'s file, or none without the flag.
fn silhouette_mesh(path: Option<&std::path::Path>) -> anyhow::Result<Option<relief::scene::Mesh>> {
    let Some(path) = path else {
        return Ok(None);
    };
    let scene = relief::scene::load_gltf(path, &relief::scene::SceneOptions::default())
        .with_context(|| format!("--silhouette-mesh {}", path.display()))?;
    let mesh = scene
        .meshes
        .into_iter()
        .find(|m| !m.indices.is_empty())
        .with_context(|| {
            format!(
                "--silhouette-mesh {}: the file has no triangles",
                path.display()
            )
        })?;
    if mesh.mean_depth_length().is_none() {
        anyhow::bail!(
            "--silhouette-mesh {}: mesh {:?} has no texture coordinates to hang a height map from",
            path.display(),
            mesh.name
        );
    }
    Ok(Some(mesh))
}

fn measure_whole(
    args: &BenchArgs,
    cfg: &SweepConfig,
    ctx: &Arc<Context>,
    sections: &SweepSections,
    plan: &StepPlan,
    bar: &ProgressBar,
    extra_mesh: Option<&relief::scene::Mesh>,
) -> anyhow::Result<Whole> {
    let quiet = args.json;
    let shadow_stability = if whole_wanted(
        sections.shadow_stability,
        plan,
        WholeSection::ShadowStability,
    ) {
        note(bar, "stability: shadows under extreme lights", quiet);
        let rows = relief::bench::shadow_stability(ctx);
        bar.inc(1);
        rows
    } else {
        Vec::new()
    };
    let lod = if whole_wanted(sections.lod, plan, WholeSection::Lod) {
        note(bar, "level of detail", quiet);
        let section = run_lod_section(ctx, &lod_config(args, cfg)).context("the LOD section")?;
        bar.inc(1);
        Some(section)
    } else {
        None
    };
    let sizes = &sections.edit_sizes;
    let (edits, paint_edits) = if whole_wanted(!sizes.is_empty(), plan, WholeSection::Edits) {
        note(bar, "terrain edits", quiet);
        let costs = run_edit_section(ctx, sizes, EDIT_RADIUS, cfg.format)
            .context("the terrain-edit section")?;
        bar.inc(1);
        note(bar, "terrain edits: painting weights", quiet);
        let paint = run_paint_section(ctx, sizes, EDIT_RADIUS, cfg.format)
            .context("the weight-painting section")?;
        bar.inc(1);
        (costs, paint)
    } else {
        (Vec::new(), Vec::new())
    };
    let blending = if whole_wanted(sections.blending, plan, WholeSection::Blending) {
        note(bar, "terrain blending", quiet);
        let section = run_blending_section(ctx, &blending_config(args, cfg))
            .context("the terrain-blending section")?;
        bar.inc(1);
        Some(section)
    } else {
        None
    };
    let scene_shadows = if whole_wanted(sections.scene_shadows, plan, WholeSection::SceneShadows) {
        let section = run_scene_shadow_section(ctx, cfg.quick, |what| note(bar, what, quiet))
            .context("the scene-shadow section")?;
        bar.inc(1);
        Some(section)
    } else {
        None
    };
    let frame_features = if whole_wanted(sections.frame_features, plan, WholeSection::FrameFeatures)
    {
        let section = run_frame_feature_section(ctx, cfg.quick, |what| note(bar, what, quiet))
            .context("the frame-feature section")?;
        bar.inc(1);
        Some(section)
    } else {
        None
    };
    let silhouettes = if whole_wanted(sections.silhouettes, plan, WholeSection::Silhouettes) {
        let section =
            run_silhouette_section(ctx, cfg.quick, extra_mesh, |what| note(bar, what, quiet))
                .context("the silhouette section")?;
        bar.inc(1);
        Some(section)
    } else {
        None
    };
    let frame_costs = if whole_wanted(sections.frame_costs, plan, WholeSection::FrameCosts) {
        let section = run_frame_cost_section(ctx, cfg.quick, |what| note(bar, what, quiet))
            .context("the frame-cost section")?;
        bar.inc(1);
        Some(section)
    } else {
        None
    };
    Ok(Whole {
        shadow_stability,
        lod,
        edits,
        paint_edits,
        blending,
        scene_shadows,
        frame_features,
        silhouettes,
        frame_costs,
    })
}

/// The LOD section's settings: quick or full, with the sweep's methods when --methods names
/// some, and its height format.
fn lod_config(args: &BenchArgs, cfg: &SweepConfig) -> LodConfig {
    let mut lod = if args.quick {
        LodConfig::quick()
    } else {
        LodConfig::full()
    };
    if !args.methods.is_empty() {
        lod.methods = cfg.methods.clone();
    }
    lod.format = cfg.format;
    lod
}

/// The blending section's settings: quick or full, with the sweep's methods when --methods names
/// some, and the sweep's angles when --angles does.
fn blending_config(args: &BenchArgs, cfg: &SweepConfig) -> BlendingConfig {
    let mut blending = if args.quick {
        BlendingConfig::quick()
    } else {
        BlendingConfig::full()
    };
    if !args.methods.is_empty() {
        blending.methods = cfg.methods.clone();
    }
    if !args.angles.is_empty() {
        blending.angles = cfg.angles.clone();
    }
    blending
}

pub(super) fn write_outputs(
    out: &std::path::Path,
    results: &BenchResults,
    json: bool,
) -> anyhow::Result<()> {
    std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;
    let text = serde_json::to_string_pretty(results)?;
    let write = |name: &str, body: &str| {
        let path = out.join(name);
        std::fs::write(&path, body).with_context(|| format!("writing {}", path.display()))
    };
    write("results.json", &text)?;
    let (report, plots) = render_report(results);
    write("report.md", &report)?;
    for (name, svg) in &plots {
        write(name, svg)?;
    }
    for map in &results.steps_maps {
        let path = out.join(map.file());
        let [w, h] = map.grid;
        let png = super::cost_map::heat_map_png(&map.steps, w, h)?;
        std::fs::write(&path, png).with_context(|| format!("writing {}", path.display()))?;
    }
    for strip in results.silhouettes.iter().flat_map(|s| &s.strips) {
        let path = out.join(&strip.file);
        let [w, h] = strip.size;
        image::save_buffer(&path, &strip.rgba, w, h, image::ColorType::Rgba8)
            .with_context(|| format!("writing {}", path.display()))?;
    }
    if json {
        println!("{text}");
    } else {
        if let Some(blending) = &results.blending {
            for line in blending_notes(blending) {
                eprintln!("blending: {line}");
            }
        }
        eprintln!(
            "wrote {} runs and {} stability cells to {}/results.json, report.md and {} plots",
            results.runs.len(),
            results.stability.len(),
            out.display(),
            plots.len()
        );
    }
    Ok(())
}
