//! The bench's level-of-detail section: a large plane seen at a grazing angle (distant pixels
//! are minified, so LOD stops their traversal early), rendered by the full renderer per method
//! with and without LOD. It records the surface pass's GPU time both ways and the image error of
//! each against a 4x4 supersampled render without LOD, plus QDM's large-map / small-map time
//! ratio with LOD on and off (Schroders and van Gulik Table 1's scaling question).

use std::fmt::Write as _;
use std::sync::Arc;

use glam::Vec3;
use serde::{Deserialize, Serialize};

use super::results::GpuMs;
use crate::environment::EnvironmentSource;
use crate::heightfield::{Address, Generator, Heightfield};
use crate::method::Method;
use crate::render::{
    FrameRequest, HeightFormat, Lighting, Pass, RenderError, RenderOptions, Renderer,
    ShadowOptions, ToneMapping,
};
use crate::scene::{quad_mesh, Camera, Light, Lod, Material, Relief, Scene};
use crate::vk::Context;

/// What the section measures.
#[derive(Debug, Clone)]
pub struct LodConfig {
    /// Methods rendered with and without LOD.
    pub methods: Vec<Method>,
    /// The generator of the plane's height field.
    pub field: Generator,
    /// Side of that height field, in texels.
    pub size: u32,
    /// QDM's map sides for the scaling ratio (small, large).
    pub scaling_sizes: (u32, u32),
    /// Image size of each render, in pixels (width, height).
    pub resolution: (u32, u32),
    /// Side of the supersampling grid of the reference render.
    pub supersample: u32,
    /// Elevation of the view above the plane at the image centre, in degrees.
    pub elevation_deg: f32,
    /// Depth of height 0 below the top plane, in uv units.
    pub depth_scale: f32,
    /// Timed frames per render (after one untimed warm-up frame).
    pub frames: u32,
    /// Texel format of the height image.
    pub format: HeightFormat,
    /// The LOD settings of the LOD renders (factor, bias, averaged levels); the fade comes from `fade`.
    pub lod: Lod,
    /// The fade (start, end) of the third render, in world units from the eye (the eye is 1
    /// unit above the plane; the plane's far edge is about 39 units away).
    pub fade: (f32, f32),
}

impl LodConfig {
    /// Every method with an LOD path beyond the fade, at a moderate size.
    pub fn full() -> LodConfig {
        let ids = ["qdm", "pdm", "maxmip", "qrm", "pom", "relief", "steep"];
        LodConfig {
            methods: ids.iter().filter_map(|id| id.parse().ok()).collect(),
            field: Generator::Fbm,
            size: 512,
            scaling_sizes: (256, 4096),
            resolution: (640, 360),
            supersample: 4,
            elevation_deg: 15.0,
            depth_scale: 0.05,
            frames: 12,
            format: HeightFormat::R16Unorm,
            lod: Lod::default(),
            fade: (3.0, 6.0),
        }
    }

    /// One pyramid method and one linear search, small images (seconds on lavapipe).
    pub fn quick() -> LodConfig {
        let ids = ["qdm", "pom"];
        LodConfig {
            methods: ids.iter().filter_map(|id| id.parse().ok()).collect(),
            size: 256,
            resolution: (160, 90),
            frames: 3,
            ..LodConfig::full()
        }
    }
}

/// Mean and 99th percentile of the per-channel absolute difference of two RGB images, in 8-bit
/// sRGB steps.
#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq)]
pub struct ImageError {
    /// Mean over all pixels and channels, in 8-bit sRGB steps.
    pub mean: f64,
    /// 99th percentile over all pixels and channels, in 8-bit sRGB steps.
    pub p99: f64,
}

/// One method with and without LOD.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct LodRun {
    /// The method's name.
    pub method: String,
    /// Frame times without LOD.
    pub off: FrameMs,
    /// Frame times with LOD, no fade.
    pub on: FrameMs,
    /// LOD with the fade to normal mapping (nothing traced beyond its end).
    pub fade: FrameMs,
    /// 1 - on/off of the fastest wall times.
    pub time_saved: f64,
    /// 1 - fade/off of the fastest wall times.
    pub time_saved_fade: f64,
    /// LOD render against the supersampled render without LOD.
    pub error_on: ImageError,
    /// The plain render against the same reference, for contrast (its aliasing).
    pub error_off: ImageError,
    /// The LOD render with the fade against the reference.
    pub error_fade: ImageError,
}

/// QDM's surface time on the large map over the small one.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct LodScaling {
    /// The method's name (QDM).
    pub method: String,
    /// The small and large map sides, in texels.
    pub sizes: [u32; 2],
    /// Fastest frame wall times (see `FrameMs`), small map then large.
    pub wall_ms_off: [f64; 2],
    /// The same with LOD, small map then large.
    pub wall_ms_on: [f64; 2],
    /// Large over small fastest wall time without LOD.
    pub ratio_off: f64,
    /// Large over small fastest wall time with LOD.
    pub ratio_on: f64,
}

/// The section as results.json holds it.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct LodSection {
    /// The height field's name.
    pub heightfield: String,
    /// Its side, in texels.
    pub size: u32,
    /// Depth of height 0 below the top plane, in uv units.
    pub depth_scale: f32,
    /// View elevation above the plane at the image centre, in degrees.
    pub elevation_deg: f32,
    /// Image size, in pixels.
    pub resolution: [u32; 2],
    /// Side of the reference render's supersampling grid.
    pub supersample: u32,
    /// Timed frames per render.
    pub frames: u32,
    /// LOD factor: multiplies the pixel's mip level to give the traversal's stop level.
    pub factor: f32,
    /// Stop levels below this end on the averaged pyramid; 0 never.
    pub average_below: u32,
    /// The fade's start and end, in world units from the eye.
    pub fade: [f32; 2],
    /// One per method.
    pub runs: Vec<LodRun>,
    /// QDM's time on a large map over a small one; `None` when it was not measured.
    pub scaling: Option<LodScaling>,
}

/// A render's frame times: the surface pass between its timestamps, and the wall time from
/// submission to the fence. llvmpipe (lavapipe) rasterizes after the closing timestamp, so there
/// only the wall time holds the fragment work; on other GPUs the timestamps are the measure.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct FrameMs {
    pub gpu: GpuMs,
    pub wall: GpuMs,
}

/// A 40 x 40 plane tiled once per unit, seen from 1 unit above it at `elevation_deg` at the image
/// centre; the far half of the image is strongly minified. One directional light, no shadows.
pub fn receding_plane(
    method: Method,
    lod: Option<Lod>,
    depth_scale: f32,
    elevation_deg: f32,
) -> Scene {
    let relief = Relief {
        lod,
        ..Relief::new(depth_scale, method)
    };
    let material = Material {
        name: "plane".into(),
        base_color: [0.7, 0.55, 0.4, 1.0],
        relief: Some(relief),
        ..Material::default()
    };
    let eye = Vec3::new(0.0, 1.0, 19.0);
    let run = 1.0 / elevation_deg.to_radians().tan();
    let target = eye + Vec3::new(0.0, -1.0, -run);
    let light = Light {
        casts_shadows: false,
        ..Light::default_light()
    };
    Scene {
        meshes: vec![quad_mesh("receding plane", 40.0, 40.0, 40.0, 0)],
        materials: vec![material],
        camera: Some(Camera::look_at(
            eye,
            target,
            50f32.to_radians(),
            0.05,
            100.0,
        )),
        lights: vec![light],
        ..Scene::default()
    }
}

/// Renders `scene` at `size` once untimed, then `frames` times; the last frame's pixels (sRGB
/// RGBA8) and the surface pass's times.
pub fn render_timed(
    ctx: &Arc<Context>,
    scene: &Scene,
    hf: &Heightfield,
    size: (u32, u32),
    frames: u32,
    format: HeightFormat,
) -> Result<(Vec<u8>, FrameMs), RenderError> {
    let mut out = render_interleaved(ctx, std::slice::from_ref(scene), hf, size, frames, format)?;
    out.pop()
        .ok_or_else(|| RenderError::Vulkan(crate::vk::VkError::Invalid("no render".into())))
}

/// [`render_timed`] for several scenes at once, their frames taken in turn (one of each, then
/// the next round), so a machine whose load changes during the run slows them alike.
pub fn render_interleaved(
    ctx: &Arc<Context>,
    scenes: &[Scene],
    hf: &Heightfield,
    size: (u32, u32),
    frames: u32,
    format: HeightFormat,
) -> Result<Vec<(Vec<u8>, FrameMs)>, RenderError> {
    let opts = RenderOptions {
        width: size.0,
        height: size.1,
        height_format: format,
        address: Address::Repeat,
        cells: None,
        paintable_layers: false,
        shadows: ShadowOptions::DEFAULT,
        shadow_probe: None,
        msaa: 1,
        tone_mapping: ToneMapping::NONE,
        keep_radiance: false,
        // Timing runs measure the methods, not the ambient light.
        environment: EnvironmentSource::Flat,
        background: crate::environment::Background::Colour,
        supersample: 1,
        occluders: true,
        gbuffer: false,
        count_work: false,
        lighting: Lighting::Forward,
        traced_shadows: false,
    };
    let mut renderers = scenes
        .iter()
        .map(|scene| Renderer::new(ctx, scene, Some(hf), &opts))
        .collect::<Result<Vec<_>, _>>()?;
    let mut gpu = vec![Vec::new(); scenes.len()];
    let mut wall = vec![Vec::new(); scenes.len()];
    let mut pixels = vec![Vec::new(); scenes.len()];
    for k in 0..=frames {
        for (j, renderer) in renderers.iter_mut().enumerate() {
            let camera = renderer.default_camera();
            let started = std::time::Instant::now();
            let out = renderer.draw(&FrameRequest {
                camera,
                read_back: k == frames,
            })?;
            let elapsed = started.elapsed().as_secs_f64() * 1e3;
            let surface = out.timings.iter().find(|t| t.pass == Pass::Surface);
            // Frame 0 builds the pyramids and pays the shader JIT; the last reads pixels back.
            if let (true, Some(t)) = (k > 0, surface) {
                gpu[j].push(t.gpu_ms);
                if k < frames || frames == 1 {
                    wall[j].push(elapsed);
                }
            }
            if let Some(rgba) = out.rgba {
                pixels[j] = rgba;
            }
        }
    }
    let times = gpu.iter().zip(&wall).map(|(g, w)| FrameMs {
        gpu: GpuMs::of(g),
        wall: GpuMs::of(w),
    });
    Ok(pixels.into_iter().zip(times).collect())
}

/// `rgba` (sRGB, `w` x `h`) averaged over `k` x `k` blocks in linear light, as a supersampled
/// pixel would be; alpha is dropped (opaque output).
pub fn downsample(rgba: &[u8], w: u32, h: u32, k: u32) -> Vec<u8> {
    let (ow, oh) = (w / k, h / k);
    let mut out = Vec::with_capacity((ow * oh * 4) as usize);
    for y in 0..oh {
        for x in 0..ow {
            let mut sum = [0.0f64; 3];
            for (dx, dy) in (0..k * k).map(|i| (i % k, i / k)) {
                let p = (((y * k + dy) * w + x * k + dx) * 4) as usize;
                for (c, s) in sum.iter_mut().enumerate() {
                    *s += crate::srgb::decode_f64(f64::from(rgba[p + c]) / 255.0);
                }
            }
            let n = f64::from(k * k);
            out.extend(sum.map(|s| (crate::srgb::encode_f64(s / n) * 255.0).round() as u8));
            out.push(255);
        }
    }
    out
}

/// Per-channel (RGB) absolute difference of two same-sized RGBA8 images.
pub fn image_error(a: &[u8], b: &[u8]) -> ImageError {
    let mut diffs: Vec<u8> = a
        .chunks_exact(4)
        .zip(b.chunks_exact(4))
        .flat_map(|(p, q)| (0..3).map(move |c| p[c].abs_diff(q[c])))
        .collect();
    if diffs.is_empty() {
        return ImageError {
            mean: 0.0,
            p99: 0.0,
        };
    }
    let mean = diffs.iter().map(|&d| f64::from(d)).sum::<f64>() / diffs.len() as f64;
    diffs.sort_unstable();
    let p99 = f64::from(diffs[((diffs.len() - 1) as f64 * 0.99).round() as usize]);
    ImageError { mean, p99 }
}

/// Measures every configured method, then QDM's scaling ratio.
pub fn run_lod_section(ctx: &Arc<Context>, cfg: &LodConfig) -> Result<LodSection, RenderError> {
    let hf = cfg.field.generate(cfg.size, cfg.size, 1);
    let runs = cfg
        .methods
        .iter()
        .map(|&m| measure_method(ctx, cfg, &hf, m))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(LodSection {
        heightfield: cfg.field.to_string(),
        size: cfg.size,
        depth_scale: cfg.depth_scale,
        elevation_deg: cfg.elevation_deg,
        resolution: [cfg.resolution.0, cfg.resolution.1],
        supersample: cfg.supersample,
        frames: cfg.frames,
        factor: cfg.lod.factor,
        average_below: cfg.lod.average_below,
        fade: [cfg.fade.0, cfg.fade.1],
        runs,
        scaling: measure_scaling(ctx, cfg)?,
    })
}

fn measure_method(
    ctx: &Arc<Context>,
    cfg: &LodConfig,
    hf: &Heightfield,
    method: Method,
) -> Result<LodRun, RenderError> {
    let (w, h) = cfg.resolution;
    let k = cfg.supersample.max(1);
    let scene = |lod| receding_plane(method, lod, cfg.depth_scale, cfg.elevation_deg);
    let (big, _) = render_timed(ctx, &scene(None), hf, (w * k, h * k), 0, cfg.format)?;
    let reference = downsample(&big, w * k, h * k, k);
    let faded = Lod {
        fade_start: cfg.fade.0,
        fade_end: cfg.fade.1,
        ..cfg.lod
    };
    let scenes = [scene(None), scene(Some(cfg.lod)), scene(Some(faded))];
    let shots = render_interleaved(ctx, &scenes, hf, (w, h), cfg.frames, cfg.format)?;
    let [(off, ms_off), (on, ms_on), (fade, ms_fade)] = <[_; 3]>::try_from(shots)
        .map_err(|_| RenderError::Vulkan(crate::vk::VkError::Invalid("3 renders".into())))?;
    let saved = |ms: &FrameMs| 1.0 - ms.wall.min / ms_off.wall.min.max(1e-9);
    Ok(LodRun {
        method: method.id().into(),
        time_saved: saved(&ms_on),
        time_saved_fade: saved(&ms_fade),
        off: ms_off,
        on: ms_on,
        fade: ms_fade,
        error_on: image_error(&on, &reference),
        error_off: image_error(&off, &reference),
        error_fade: image_error(&fade, &reference),
    })
}

fn measure_scaling(ctx: &Arc<Context>, cfg: &LodConfig) -> Result<Option<LodScaling>, RenderError> {
    let qdm = Method::QDM;
    let (small, large) = cfg.scaling_sizes;
    let large = large.min(ctx.info().max_image_dimension_2d);
    let mut off = [0.0; 2];
    let mut on = [0.0; 2];
    for (i, side) in [small, large].into_iter().enumerate() {
        let hf = cfg.field.generate(side, side, 1);
        let scenes = [None, Some(cfg.lod)]
            .map(|lod| receding_plane(qdm, lod, cfg.depth_scale, cfg.elevation_deg));
        let shots = render_interleaved(ctx, &scenes, &hf, cfg.resolution, cfg.frames, cfg.format)?;
        off[i] = shots[0].1.wall.min;
        on[i] = shots[1].1.wall.min;
    }
    Ok(Some(LodScaling {
        method: qdm.id().into(),
        sizes: [small, large],
        ratio_off: off[1] / off[0].max(1e-9),
        ratio_on: on[1] / on[0].max(1e-9),
        wall_ms_off: off,
        wall_ms_on: on,
    }))
}

/// The section of report.md.
pub fn report(md: &mut String, s: &LodSection) {
    let _ = writeln!(md, "\n## Level of detail\n");
    let _ = writeln!(
        md,
        "A {}^2 {} field (depth scale {}) on a 40 x 40 plane tiled once per unit, seen at {} degrees \
         elevation at the image centre, {}x{} pixels; LOD factor {}, averaged pyramid below level {}; \
         +fade: LOD with the fade to normal mapping from {} to {} units from the eye (1 unit above \
         the plane). Error: per-channel |difference| in 8-bit sRGB steps (mean / p99) against a {}x{} \
         supersampled render without LOD. Time: the fastest of {} frames' wall time from submission \
         to fence (llvmpipe rasterizes after the surface pass's closing timestamp, so only the wall \
         time holds the fragment work there; results.json has the timestamps too).\n",
        s.size, s.heightfield, s.depth_scale, s.elevation_deg, s.resolution[0], s.resolution[1],
        s.factor, s.average_below, s.fade[0], s.fade[1], s.supersample, s.supersample, s.frames
    );
    let _ = writeln!(
        md,
        "| method | ms off | ms LOD | saved | ms +fade | saved | error off | error LOD | error +fade |"
    );
    let _ = writeln!(md, "|---|---|---|---|---|---|---|---|---|");
    let err = |e: &ImageError| format!("{:.2} / {:.0}", e.mean, e.p99);
    for r in &s.runs {
        let _ = writeln!(
            md,
            "| {} | {:.2} | {:.2} | {:.0}% | {:.2} | {:.0}% | {} | {} | {} |",
            r.method,
            r.off.wall.min,
            r.on.wall.min,
            r.time_saved * 100.0,
            r.fade.wall.min,
            r.time_saved_fade * 100.0,
            err(&r.error_off),
            err(&r.error_on),
            err(&r.error_fade)
        );
    }
    if let Some(c) = &s.scaling {
        let _ = writeln!(
            md,
            "\n{} surface time {}^2 / {}^2: {:.2}x without LOD ({:.2} / {:.2} ms), {:.2}x with LOD \
             ({:.2} / {:.2} ms).",
            c.method, c.sizes[1], c.sizes[0], c.ratio_off, c.wall_ms_off[1], c.wall_ms_off[0],
            c.ratio_on, c.wall_ms_on[1], c.wall_ms_on[0]
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn downsampling_averages_in_linear_light() {
        // Black and white halves average to linear 0.5, which is sRGB 188, not 128.
        let mut img = Vec::new();
        for v in [0u8, 255, 0, 255] {
            img.extend([v, v, v, 255]);
        }
        let out = downsample(&img, 2, 2, 2);
        assert_eq!(out, vec![188, 188, 188, 255]);
    }

    #[test]
    fn image_error_counts_rgb_only() {
        let a = [10u8, 20, 30, 0, 10, 20, 30, 0];
        let b = [12u8, 20, 30, 255, 10, 20, 30, 255];
        let e = image_error(&a, &b);
        assert!((e.mean - 2.0 / 6.0).abs() < 1e-12);
        assert_eq!(e.p99, 2.0);
    }

    #[test]
    fn the_view_is_grazing() {
        let s = receding_plane(Method::POM, Some(Lod::default()), 0.05, 15.0);
        assert!(s.materials[0].relief.is_some_and(|r| r.lod.is_some()));
        assert!(s.lights.iter().all(|l| !l.casts_shadows));
    }
}
