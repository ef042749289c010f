//! `relief shadows`: renders a scene's shadow probe (each pixel's surface point and relief's
//! visible fraction of the light there), traces the exact scene reference for the same points,
//! prints the agreement, and writes both as `.npy` dumps.

use std::path::{Path, PathBuf};

use clap::Args;
use relief::bench::{measure_scene_shadows, write_npy_f32, SceneShadowConfig, SceneShadowRun};
use relief::render::{ShadowFilter, ShadowOptions};
use relief::scene::{ShadowScene, SHADOW_CASCADES, SHADOW_MAP_SIZES};

use super::{check_validation, open_device, parse_size};

#[derive(Args)]
pub struct ShadowsArgs {
    /// The scene: box-over-plane, slab-over-plane, box-over-relief, sphere-over-plane (generated), or default (the
    /// built-in default scene).
    #[arg(long, default_value = "default")]
    scene: String,
    /// Generated scenes: the sun's elevation in degrees.
    #[arg(long, value_name = "DEG", default_value_t = 25.0)]
    elevation: f32,
    /// The light's angular radius in degrees (0: hard; default: the scene's own, 0 for the
    /// generated scenes).
    #[arg(long, value_name = "DEG")]
    light_radius: Option<f32>,
    /// Probe image size.
    #[arg(long, value_name = "WxH", default_value = "240x135")]
    size: String,
    /// Texels per side of the shadow map.
    #[arg(long, value_name = "N", default_value_t = ShadowOptions::DEFAULT.map_size)]
    shadow_map_size: u32,
    /// Cascades of the directional light's map.
    #[arg(long, value_name = "N", default_value_t = ShadowOptions::DEFAULT.cascades)]
    shadow_cascades: u32,
    /// Filter: hard, pcf or pcss (default: pcss for a light with a size, else hard).
    #[arg(long, value_name = "FILTER")]
    shadow_filter: Option<ShadowFilter>,
    /// Exact reference rays per pixel per side for soft lights (N x N, stratified).
    #[arg(long, value_name = "N", default_value_t = 6)]
    samples: u32,
    /// Also trace the reference with relief casting as flat polygons, and compare.
    #[arg(long)]
    flat: bool,
    /// Also trace the light's rays by ray query through the scene's acceleration structures
    /// (relief prisms resolved by the exact height-field walk), and compare them with the exact
    /// reference too (the device must have ray queries).
    #[arg(long)]
    traced: bool,
    /// Write exact.npy, relief.npy (and flat.npy, traced.npy) here: rows x cols of visible fractions, -1 on
    /// the background, -2 where the surface faces away from the light; relief_maps.npy and
    /// relief_own.npy hold relief's two terms (shadow maps, the height field's own).
    #[arg(long, value_name = "DIR")]
    dump: Option<PathBuf>,
    /// Print the result as JSON.
    #[arg(long)]
    json: bool,
    /// Pick the Vulkan device whose name contains this text.
    #[arg(long, value_name = "SUBSTRING")]
    device: Option<String>,
}

pub fn run(args: &ShadowsArgs) -> anyhow::Result<()> {
    let (width, height) = parse_size("--size", &args.size)?;
    check_ranges(args)?;
    let config = config_of(args, width, height)?;
    let ctx = open_device(args.device.as_deref(), args.json)?;
    eprintln!("tracing the exact reference for {width}x{height} pixels ...");
    let run = measure_scene_shadows(&ctx, &config)?;
    check_validation(&ctx)?;
    if let Some(dir) = &args.dump {
        write_dumps(dir, [height as usize, width as usize], &run)?;
    }
    if args.json {
        println!("{}", serde_json::to_string_pretty(&run)?);
        return Ok(());
    }
    print_run(&run);
    if let Some(dir) = &args.dump {
        println!("wrote {}/exact.npy and relief.npy", dir.display());
    }
    Ok(())
}

/// Fails on the first option outside its range.
fn check_ranges(args: &ShadowsArgs) -> anyhow::Result<()> {
    if !SHADOW_MAP_SIZES.contains(&args.shadow_map_size) {
        anyhow::bail!("--shadow-map-size must be in 16..=8192");
    }
    if !SHADOW_CASCADES.contains(&args.shadow_cascades) {
        anyhow::bail!("--shadow-cascades must be in 1..=4");
    }
    if !(1..=64).contains(&args.samples) {
        anyhow::bail!("--samples must be in 1..=64");
    }
    if !(args.elevation.is_finite() && (0.0..=90.0).contains(&args.elevation)) {
        anyhow::bail!("--elevation must be in 0..=90 degrees");
    }
    if args
        .light_radius
        .is_some_and(|r| !(r.is_finite() && (0.0..=45.0).contains(&r)))
    {
        anyhow::bail!("--light-radius must be in 0..=45 degrees");
    }
    Ok(())
}

/// The measurement `args` ask for, of a `width` x `height` probe.
fn config_of(args: &ShadowsArgs, width: u32, height: u32) -> anyhow::Result<SceneShadowConfig> {
    let scene = match args.scene.as_str() {
        "default" => None,
        other => Some(other.parse::<ShadowScene>().map_err(anyhow::Error::msg)?),
    };
    Ok(SceneShadowConfig {
        scene,
        elevation_deg: args.elevation,
        radius_deg: args.light_radius,
        width,
        height,
        shadows: ShadowOptions::DEFAULT
            .with_map_size(args.shadow_map_size)
            .with_cascades(args.shadow_cascades)
            .with_filter(args.shadow_filter),
        samples_per_side: args.samples,
        flat_reference: args.flat,
        traced: args.traced,
    })
}

/// Writes `run`'s per-pixel dumps of `shape` (rows, columns) into `dir`.
fn write_dumps(dir: &Path, shape: [usize; 2], run: &SceneShadowRun) -> anyhow::Result<()> {
    std::fs::create_dir_all(dir)?;
    write_npy_f32(&dir.join("exact.npy"), &shape, &run.exact)?;
    write_npy_f32(&dir.join("relief.npy"), &shape, &run.relief)?;
    write_npy_f32(&dir.join("relief_maps.npy"), &shape, &run.maps)?;
    write_npy_f32(&dir.join("relief_own.npy"), &shape, &run.own)?;
    if !run.flat.is_empty() {
        write_npy_f32(&dir.join("flat.npy"), &shape, &run.flat)?;
    }
    if let Some(t) = &run.traced {
        write_npy_f32(&dir.join("traced.npy"), &shape, &t.visible)?;
    }
    Ok(())
}

/// Prints what `run` found, as text.
fn print_run(run: &SceneShadowRun) {
    println!(
        "scene {}: map {}^2 x {} cascade(s), {} filter, light radius {:.2} deg",
        run.scene, run.map_size, run.cascades, run.filter, run.light_radius_deg
    );
    println!("relief vs exact: {}", run.agreement);
    println!(
        "soft: mean |error| {:.4} over all {} receiver pixels, band included",
        run.everywhere.mean_abs_error, run.everywhere.pixels
    );
    println!("shadow-map term alone vs exact: {}", run.map_term);
    if let Some(flat) = &run.flat_caster {
        println!("flat casters (exact) vs exact: {flat}");
    }
    if let Some(d) = &run.caster_difference {
        println!(
            "{} pixels change verdict with flat casters; relief follows the displaced caster on {:.1}% of them",
            d.pixels,
            100.0 * d.relief_follows_displaced
        );
    }
    if let Some(t) = &run.traced {
        println!("ray-traced vs exact, band included: {}", t.everywhere);
        println!("ray-traced vs exact, outside the band: {}", t.outside_band);
        let s = &t.structures;
        println!(
            "ray queries: {} rays, {} prism tests ({} walk steps, {} capped), {:.3} gpu ms; structures: {} triangles, {} prisms, {:.1} KiB, built in {:.3} gpu ms",
            t.rays,
            t.prisms_tested,
            t.walk_steps,
            t.capped,
            t.trace_ms,
            s.triangles,
            s.prisms,
            s.structure_bytes as f64 / 1024.0,
            s.build_ms
        );
    }
    if run.non_finite > 0 {
        println!(
            "warning: {} pixel(s) had a visibility term that is not a number",
            run.non_finite
        );
    }
    println!(
        "gpu ms: shadow maps {:.3}, surface {:.3}",
        run.shadow_maps_ms, run.surface_ms
    );
}
