//! One frame, offscreen, for callers that need a single image: what to render, what a frame
//! returns, and the errors; the work is done by a [`Renderer`] made for the one frame.

use std::borrow::Cow;
use std::sync::Arc;

use serde::Serialize;

use super::renderer::{FrameRequest, Renderer};
use crate::environment::{Background, EnvironmentSource};
use crate::heightfield::{Address, Heightfield, LoadOptions};
use crate::render::cells::cells_pass::{BuiltComplex, CellsOptions};
use crate::render::kit::gpu_heightfield::HeightFormat;
use crate::render::kit::pass_timer::PassTiming;
use crate::render::kit::render_error::RenderError;
use crate::render::kit::tone_curves::ToneMapping;
use crate::render::lighting::Lighting;
use crate::render::plan::frame_plan::{HeightKey, HeightPlan, Plan};
use crate::render::shadows::shadow_plan::ShadowOptions;
use crate::scene::Scene;
use crate::vk::{Context, VkError};

/// What to render. Built from [`RenderOptions::default`] or [`RenderOptions::finished`] and
/// the `with_*` setters; new options may be added without a breaking change.
#[derive(Debug, Clone)]
#[non_exhaustive]
pub struct RenderOptions {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// How every planned height map is stored on the GPU.
    pub height_format: HeightFormat,
    /// What lies outside the frame's height map (`--heightmap`); scene images take theirs from
    /// their sampler's wrap modes, layered fields clamp.
    pub address: Address,
    /// Meshes drawn through cell complexes (`--cells`), none when `None`.
    pub cells: Option<CellsOptions>,
    /// Keep each layered material's blend inputs on the GPU, so that its weights can be painted
    /// (`Renderer::paint_layers`); otherwise they are dropped once the blended field is built.
    pub paintable_layers: bool,
    /// The lights' shadow maps: on or off, size, cascades, filter.
    pub shadows: ShadowOptions,
    /// Write light `k`'s visibility instead of shading it (the shadow probe behind `relief
    /// shadows`): red the shadow maps' term, green the height field's own, blue 1 where the
    /// surface faces the light; and read the depth back with the colours.
    pub shadow_probe: Option<usize>,
    /// Samples per pixel of the raster passes: 1 (none), 2, 4 or 8. More than the device takes
    /// is clamped, and the plan's `msaa` says so; relief is still traced once per pixel.
    pub msaa: u32,
    /// Exposure and curve from the frame's linear radiance to its colours
    /// ([`ToneMapping::NONE`]: clamped, as timing runs want).
    pub tone_mapping: ToneMapping,
    /// Read-back frames also return their linear radiance before tone mapping
    /// (`FrameOutput::radiance`, `--hdr-out`).
    pub keep_radiance: bool,
    /// The ambient light: flat (no maps built, as timing runs want), the built-in sky, or an
    /// environment image (`--environment`).
    pub environment: EnvironmentSource,
    /// Supersampling (`--supersample`): the scene is drawn this many times larger along each
    /// axis and each pixel averages its block, which smooths what MSAA cannot (the relief's own
    /// silhouettes and steps, shading); 1 to 4, 1 for none.
    pub supersample: u32,
    /// What shows where no surface is drawn: a colour, or the environment (`--background`).
    pub background: Background,
    /// Lay down the occluder pass's bounds first, so relief hidden behind nearer surfaces is
    /// not traced (`--occluders`; on by default, off draws every relief fragment's trace as the
    /// forward path always did).
    pub occluders: bool,
    /// The surface pass writes its G-buffer (normal, uv, distance, mesh, steps: see
    /// [`GBufferChannels`](super::gbuffer::GBufferChannels)) beside the radiance, and read-back
    /// frames return it. Not with supersampling.
    pub gbuffer: bool,
    /// Relief fragments count their traces and steps per pixel, and every frame returns the
    /// counts ([`WorkCounts`](super::work_counters::WorkCounts)); off, the counting is compiled
    /// out. Needs `fragmentStoresAndAtomics`.
    pub count_work: bool,
    /// Where surfaces are lit: in their fragments as they are drawn (forward, the default), or
    /// once per pixel by a lighting pass after the scene is drawn (`--lighting deferred`).
    pub lighting: Lighting,
    /// Every shadow-casting light is tested by rays through the scene's acceleration
    /// structures, the receiver's own relief included, instead of shadow maps and the height
    /// field's own walk (`--traced-shadows`; needs deferred lighting and ray queries).
    pub traced_shadows: bool,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            width: 960,
            height: 540,
            height_format: HeightFormat::R16Unorm,
            address: Address::Repeat,
            cells: None,
            paintable_layers: false,
            shadows: ShadowOptions::DEFAULT,
            shadow_probe: None,
            msaa: 1,
            tone_mapping: ToneMapping::NONE,
            keep_radiance: false,
            environment: EnvironmentSource::Flat,
            background: Background::Colour,
            supersample: 1,
            occluders: true,
            gbuffer: false,
            count_work: false,
            lighting: Lighting::Forward,
            traced_shadows: false,
        }
    }
}

with_setters!(RenderOptions {
    with_width => width: u32,
    with_height => height: u32,
    with_height_format => height_format: HeightFormat,
    with_address => address: Address,
    with_cells => cells: Option<CellsOptions>,
    with_paintable_layers => paintable_layers: bool,
    with_shadows => shadows: ShadowOptions,
    with_shadow_probe => shadow_probe: Option<usize>,
    with_msaa => msaa: u32,
    with_tone_mapping => tone_mapping: ToneMapping,
    with_keep_radiance => keep_radiance: bool,
    with_environment => environment: EnvironmentSource,
    with_supersample => supersample: u32,
    with_background => background: Background,
    with_occluders => occluders: bool,
    with_gbuffer => gbuffer: bool,
    with_count_work => count_work: bool,
    with_lighting => lighting: Lighting,
    with_traced_shadows => traced_shadows: bool,
});

impl RenderOptions {
    /// The same options at `width` x `height`.
    #[must_use]
    pub fn with_size(self, width: u32, height: u32) -> RenderOptions {
        self.with_width(width).with_height(height)
    }

    /// The look `relief render` draws by default at `width` x `height`: 4x MSAA, PBR Neutral
    /// tone mapping, the built-in sky lighting the scene and shown behind it. The plain
    /// [`RenderOptions::default`] is the frame the bench times (one sample, flat ambient light,
    /// no tone curve).
    pub fn finished(width: u32, height: u32) -> RenderOptions {
        RenderOptions {
            width,
            height,
            msaa: 4,
            tone_mapping: ToneMapping {
                curve: crate::render::kit::tone_curves::ToneMap::PbrNeutral,
                exposure_ev: 0.0,
            },
            environment: EnvironmentSource::Sky,
            background: Background::Environment,
            ..RenderOptions::default()
        }
    }
}

/// A map the frame built: the pyramid and the conservative cone map on the GPU, the other
/// precomputed maps on the CPU.
#[derive(Debug, Clone, Serialize)]
pub struct BuiltMap {
    /// What was built, as `--explain` names it (a map kind's name, "layer stack", "blended
    /// pyramid", ...).
    pub kind: &'static str,
    /// The height map it belongs to.
    pub source: String,
    /// Width and height of the map's finest level, in texels.
    pub size: [u32; 2],
    /// GPU ms for maps built on the GPU, CPU wall ms for those built on the CPU.
    pub ms: f64,
    /// "gpu" or "cpu".
    pub on: &'static str,
}

/// A rendered image (sRGB RGBA8, rows top to bottom), how long each pass took, and the plan it
/// followed.
#[derive(Debug, Clone)]
pub struct Frame {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// `width * height * 4` bytes: sRGB RGBA8, rows top to bottom, no padding.
    pub rgba: Vec<u8>,
    /// With a shadow probe, the depth of every pixel (1 where nothing was drawn), rows top to
    /// bottom; empty otherwise.
    pub depth: Vec<f32>,
    /// With `RenderOptions::keep_radiance`, every pixel's linear radiance before exposure and
    /// tone mapping, RGBA, rows top to bottom; empty otherwise.
    pub radiance: Vec<[f32; 4]>,
    /// With `RenderOptions::gbuffer`, the surface pass's G-buffer.
    pub gbuffer: Option<super::gbuffer::GBufferChannels>,
    /// GPU time of each pass recorded in this frame.
    pub timings: Vec<PassTiming>,
    /// CPU wall time of uploading height maps and precomputed maps, in ms.
    pub upload_ms: f64,
    /// The plan the frame followed: what it built and what it skipped.
    pub plan: Plan,
    /// The pyramids and precomputed maps built for it, with their cost.
    pub maps: Vec<BuiltMap>,
    /// The cell complexes built.
    pub cells: Vec<BuiltComplex>,
}

/// The heights of one planned height map, as stored on the GPU. The frame's own map is borrowed
/// when it is stored as it is (R32F), not copied.
pub(in crate::render) fn planned_heights<'a>(
    ctx: &Arc<Context>,
    scene: &Scene,
    plan: &HeightPlan,
    frame_heights: Option<&'a Heightfield>,
    format: HeightFormat,
) -> Result<Cow<'a, Heightfield>, RenderError> {
    let hf = match plan.key {
        HeightKey::Layers { .. } => {
            return Err(VkError::Invalid("layered heights are blended on the GPU".into()).into())
        }
        HeightKey::Frame => Cow::Borrowed(
            frame_heights
                .ok_or_else(|| VkError::Invalid("the plan reads a frame height map".into()))?,
        ),
        HeightKey::Image {
            image,
            channel,
            invert,
            ..
        } => {
            let opts = LoadOptions { channel, invert };
            Cow::Owned(Heightfield::from_dynamic_image(
                &scene.images[image].pixels,
                &opts,
                &plan.source,
            )?)
        }
    };
    hf.check_max_dimension(ctx.info().max_image_dimension_2d, &plan.source)?;
    Ok(match format {
        HeightFormat::R16Unorm => Cow::Owned(hf.quantized_unorm16()),
        HeightFormat::R32Float => hf,
    })
}

/// Renders one frame of `scene` with a renderer made for it, and reads it back. Relief materials
/// without a height texture of their own read `frame_heights`. For more frames, keep a
/// [`Renderer`].
pub fn render(
    ctx: &Arc<Context>,
    scene: &Scene,
    frame_heights: Option<&Heightfield>,
    opts: &RenderOptions,
) -> Result<Frame, RenderError> {
    let mut renderer = Renderer::new(ctx, scene, frame_heights, opts)?;
    let request = FrameRequest {
        camera: renderer.default_camera(),
        read_back: true,
    };
    let out = renderer.draw(&request)?;
    let rgba = out
        .rgba
        .ok_or_else(|| VkError::Invalid("the frame was not read back".into()))?;
    Ok(Frame {
        width: out.width,
        height: out.height,
        rgba,
        depth: out.depth.unwrap_or_default(),
        radiance: out.radiance.unwrap_or_default(),
        gbuffer: out.gbuffer,
        timings: out.timings,
        upload_ms: renderer.upload_ms(),
        plan: renderer.plan().clone(),
        maps: renderer.maps().to_vec(),
        cells: renderer.cells().to_vec(),
    })
}

/// The supersampling factor a frame draws with: `opts.supersample`, checked; 1 for the shadow
/// probe (which reads one depth per pixel).
pub(super) fn choose_supersample(
    opts: &RenderOptions,
    max_side: u32,
    probe: bool,
) -> Result<u32, VkError> {
    let k = opts.supersample;
    if !(1..=MAX_SUPERSAMPLE).contains(&k) {
        return Err(VkError::Invalid(format!(
            "--supersample must be 1 to {MAX_SUPERSAMPLE} (samples per pixel along each axis), got {k}"
        )));
    }
    let side = opts.width.max(opts.height).saturating_mul(k);
    if side > max_side {
        return Err(VkError::Invalid(format!(
            "--supersample {k} draws a {}x{} image, larger than this device's {max_side}",
            opts.width.saturating_mul(k),
            opts.height.saturating_mul(k)
        )));
    }
    Ok(if probe { 1 } else { k })
}

/// The largest supersampling factor: 4 x 4 samples per pixel.
pub const MAX_SUPERSAMPLE: u32 = 4;
