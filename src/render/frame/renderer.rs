//! The renderer: made once per (device, scene), it owns everything a frame reads (meshes,
//! textures, height maps with their pyramids and precomputed maps, descriptor sets, pipelines,
//! targets) and draws any number of frames from a camera. A frame only rewrites its slot's
//! uniforms and records commands; nothing is created per frame, and a static field's pyramid is
//! built by the first frame alone.
//!
//! Frames in flight: each of `FRAMES_IN_FLIGHT` slots has its command buffer, fence, uniforms,
//! timestamp scopes and read-back buffer. Submitting a frame first retires the slot's previous
//! frame (its fence has long signalled in a steady stream), so its timings and pixels are read
//! a frame later, without stalling the frame being recorded.

use std::borrow::Cow;
use std::sync::Arc;
use std::time::Instant;

use super::frame_uniforms::{frame_camera, FrameUniforms};
use super::height_resources::{HeightResources, HeightUpload};
use super::pass::Pass;
use super::pass_timer::{per_pass, PassTimer, PassTiming, Scope};
use super::plan::{HeightKey, Plan};
use super::scene_ao::SceneAo;
use super::single_frame::{planned_heights, BuiltMap, RenderError, RenderOptions};
use super::surface_pass::SurfacePass;
use super::targets::Targets;
use crate::heightfield::{Address, Heightfield};
use crate::method::MapKind;
use crate::render::cells::cells_pass::{BuiltComplex, CellsPass};
use crate::render::maps::map_builder::{build_method_map_with, MapBuilder};
use crate::render::terrain::blended_pyramid_pass::time_on_gpu;
use crate::render::terrain::layer_paint::{
    record_paint_copies, LayerPainter, PaintError, PaintReport, StagedPaint,
};
use crate::render::terrain::layered_heights::blended_heights;
use crate::scene::{Camera, Frustum, Light, Mesh, Scene};
use crate::terrain::{SplatMap, Stroke, TexelRect};
use crate::vk::{
    CommandSlot, Context, Image, Readback, RegionTexels, StagedRegions, VkError, VkResult,
};

/// How many frames may be recorded or running at once.
pub const FRAMES_IN_FLIGHT: usize = 2;

/// What one frame draws.
#[derive(Debug, Clone)]
pub struct FrameRequest {
    pub camera: Camera,
    /// Copy the colour image back to the host (for writing it out).
    pub read_back: bool,
}

/// A finished frame: its GPU time per pass and, when asked for, its pixels.
#[derive(Debug, Clone)]
pub struct FrameOutput {
    /// 0 for the renderer's first frame.
    pub index: u64,
    pub timings: Vec<PassTiming>,
    /// sRGB RGBA8, rows top to bottom.
    pub rgba: Option<Vec<u8>>,
    pub width: u32,
    pub height: u32,
    /// Surface draws skipped because the view could not see their bounds.
    pub culled_draws: usize,
}

struct FrameSlot {
    commands: CommandSlot,
    timer: PassTimer,
    readback: Option<Readback>,
    /// The frame submitted from this slot and not yet retired: (index, read back?, draws culled).
    pending: Option<(u64, bool, usize)>,
}

/// Everything a scene needs on the device, kept across frames.
pub struct Renderer {
    ctx: Arc<Context>,
    plan: Plan,
    maps: Vec<BuiltMap>,
    upload_ms: f64,
    heights: Vec<HeightResources>,
    /// By `Plan::heights` index: the painter of a layered map (`RenderOptions::paintable_layers`).
    painters: Vec<Option<LayerPainter>>,
    ao: SceneAo,
    surface: SurfacePass,
    cells: CellsPass,
    targets: Targets,
    slots: Vec<FrameSlot>,
    lights: Vec<Light>,
    default_camera: Camera,
    width: u32,
    height: u32,
    submitted: u64,
    pyramids_built: bool,
}

impl Renderer {
    /// Plans `scene`, uploads what the plan lists and builds its maps and pipelines. Relief
    /// materials without a height texture of their own read `frame_heights`.
    pub fn new(
        ctx: &Arc<Context>,
        scene: &Scene,
        frame_heights: Option<&Heightfield>,
        opts: &RenderOptions,
    ) -> Result<Renderer, RenderError> {
        let selection = opts.cells.as_ref().map(|c| &c.selection);
        let plan = Plan::derive_with_cells(scene, frame_heights, selection)?;
        let default_camera = frame_camera(scene);
        let aspect = opts.width as f32 / opts.height as f32;
        let uniforms = FrameUniforms::new(&default_camera, &plan.lights, aspect);
        let started = Instant::now();
        let (heights, maps, painters) =
            upload_heights(ctx, scene, &plan, frame_heights, opts, uniforms)?;
        let upload_ms = started.elapsed().as_secs_f64() * 1e3;
        let ao = SceneAo::new(ctx, &plan, &heights)?;
        let surface = SurfacePass::new(
            ctx,
            scene,
            &plan,
            &heights,
            &ao,
            &uniforms,
            FRAMES_IN_FLIGHT,
        )?;
        let cells = CellsPass::new(ctx, scene, &plan, opts.cells.as_ref())?;
        let targets = Targets::new(ctx, opts.width, opts.height)?;
        // One scope per pyramid build and per AO map, plus the cells and surface passes.
        let scopes = (plan.heights.len() + ao.len()) as u32 + 2;
        let slots = (0..FRAMES_IN_FLIGHT)
            .map(|k| {
                Ok(FrameSlot {
                    commands: CommandSlot::new(ctx, &format!("frame slot {k}"))?,
                    timer: PassTimer::new(ctx, scopes, &format!("frame slot {k} timestamps"))?,
                    readback: None,
                    pending: None,
                })
            })
            .collect::<VkResult<Vec<_>>>()?;
        Ok(Renderer {
            ctx: ctx.clone(),
            lights: plan.lights.clone(),
            plan,
            maps,
            upload_ms,
            heights,
            painters,
            ao,
            surface,
            cells,
            targets,
            slots,
            default_camera,
            width: opts.width,
            height: opts.height,
            submitted: 0,
            pyramids_built: false,
        })
    }

    /// The plan the renderer follows.
    pub fn plan(&self) -> &Plan {
        &self.plan
    }

    /// The maps built so far (pyramids appear once the first frame has finished).
    pub fn maps(&self) -> &[BuiltMap] {
        &self.maps
    }

    /// The cell complexes built (`--cells`), with their statistics.
    pub fn cells(&self) -> &[BuiltComplex] {
        self.cells.built()
    }

    /// CPU wall time of uploading height maps and building their precomputed maps, in ms.
    pub fn upload_ms(&self) -> f64 {
        self.upload_ms
    }

    /// The scene's camera, or one framing its bounds.
    pub fn default_camera(&self) -> Camera {
        self.default_camera
    }

    /// Target width and height.
    pub fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// The colour target frames are drawn into (sRGB RGBA8). After a submitted frame that was not
    /// read back it is in `COLOR_ATTACHMENT_OPTIMAL`; work submitted after the frame on the same
    /// queue (a presenter's blit) may read it once a barrier from colour attachment output makes
    /// it available. The next frame waits for transfers from it before clearing it.
    pub fn color_target(&self) -> &Image {
        &self.targets.color
    }

    /// Draws later frames at `width` x `height` (a resized window): waits for the frames in
    /// flight, which are returned, then replaces the targets and the read-back buffers. Nothing
    /// else depends on the size.
    pub fn resize(&mut self, width: u32, height: u32) -> Result<Vec<FrameOutput>, RenderError> {
        if (width, height) == (self.width, self.height) {
            return Ok(Vec::new());
        }
        if width == 0 || height == 0 {
            return Err(VkError::Invalid(format!("a {width}x{height} frame")).into());
        }
        let retired = self.finish()?;
        self.targets = Targets::new(&self.ctx, width, height)?;
        for slot in &mut self.slots {
            slot.readback = None;
        }
        (self.width, self.height) = (width, height);
        Ok(retired)
    }

    /// Replaces the vertices of scene meshes (edited terrain tiles, `(mesh index, new mesh)`,
    /// same triangles): waits for the frames in flight, which are returned, then uploads the
    /// new vertices; the maps and everything else stay.
    pub fn update_meshes(
        &mut self,
        meshes: &[(usize, &Mesh)],
    ) -> Result<Vec<FrameOutput>, RenderError> {
        if meshes.is_empty() {
            return Ok(Vec::new());
        }
        let retired = self.finish()?;
        for (index, mesh) in meshes {
            self.surface.replace_vertices(&self.ctx, *index, mesh)?;
        }
        Ok(retired)
    }

    /// The painted map of layered material `material`, checked for painting: its plan index.
    fn paintable(&self, material: usize) -> Result<usize, RenderError> {
        let refuse = |why: &str| Err(RenderError::Layers(format!("material {material}: {why}")));
        let Some(h) = self
            .plan
            .heights
            .iter()
            .position(|hp| hp.key == HeightKey::Layers { material })
        else {
            return refuse("not a drawn layered material; only layered weights are painted");
        };
        let hp = &self.plan.heights[h];
        if self.painters[h].is_none() {
            return refuse("the renderer was made without RenderOptions::paintable_layers");
        }
        if let Some(kind) = hp.map {
            return refuse(&format!(
                "its method reads a {} built once from the whole field; paint with a method without one (qdm, pdm, qrm, maxmip, relief, pom)",
                kind.name().replace('_', " ")
            ));
        }
        if hp.mean_pyramid {
            return refuse(
                "its level of detail reads an averaged pyramid built once; paint without --lod",
            );
        }
        Ok(h)
    }

    /// The splat map of layered material `material` as painted so far, if it can be painted:
    /// strokes for [`Renderer::paint_layers`] are in its texels.
    pub fn layer_splat(&self, material: usize) -> Result<&SplatMap, RenderError> {
        let h = self.paintable(material)?;
        Ok(self.painters[h]
            .as_ref()
            .map(LayerPainter::splat)
            .expect("paintable checked the painter"))
    }

    /// Checks `strokes` for [`Renderer::paint_layers`] without applying any.
    pub fn check_paint(&self, material: usize, strokes: &[Stroke]) -> Result<(), RenderError> {
        let h = self.paintable(material)?;
        if let Some(painter) = &self.painters[h] {
            painter.check(strokes)?;
        }
        Ok(())
    }

    /// Paints layered material `material`'s weights with `strokes` (`paint` strokes, centres and
    /// radii in its splat map's texels, all checked first): waits for the frames in flight, which
    /// are returned, then rebuilds on the GPU only what the strokes changed — the splat image
    /// shaded, the blended field and pyramid nodes above the repainted weights, and the AO near
    /// them.
    pub fn paint_layers(
        &mut self,
        material: usize,
        strokes: &[Stroke],
    ) -> Result<(Vec<FrameOutput>, PaintReport), RenderError> {
        let h = self.paintable(material)?;
        let painter = self.painters[h]
            .as_mut()
            .expect("paintable checked the painter");
        // Refused before waiting, so that a bad list loses no frame in flight.
        painter.check(strokes)?;
        let retired = self.finish()?;
        let painter = self.painters[h]
            .as_mut()
            .expect("paintable checked the painter");
        let staged = painter.paint(strokes).map_err(|e| match e {
            PaintError::Stroke(s) => RenderError::from(s),
            PaintError::Vulkan(v) => RenderError::from(v),
        })?;
        let report = self.rebuild_painted(h, material, &staged, strokes.len())?;
        Ok((retired, report))
    }

    /// Sets layered material `material`'s weights from `weights` (splat texel to weights) over
    /// splat texels `rect`, except where strokes painted by hand (`Renderer::paint_layers`):
    /// what rules derive from an edited elevation. Waits for the frames in flight, which are
    /// returned, and rebuilds what changed as painting does; `None` when nothing changed.
    pub fn reweigh_layers(
        &mut self,
        material: usize,
        rect: TexelRect,
        weights: impl Fn(u32, u32) -> [f32; 4],
    ) -> Result<(Vec<FrameOutput>, Option<PaintReport>), RenderError> {
        let h = self.paintable(material)?;
        let retired = self.finish()?;
        let painter = self.painters[h]
            .as_mut()
            .expect("paintable checked the painter");
        let Some(staged) = painter.reweigh(rect, weights)? else {
            return Ok((retired, None));
        };
        let report = self.rebuild_painted(h, material, &staged, 0)?;
        Ok((retired, Some(report)))
    }

    /// Rebuilds on the GPU what `staged` changed in layered height map `h` of `material`: the
    /// shading's splat texels, the blended pyramid's regions copied into the drawn height map,
    /// and the AO near them (once the first frame has built it).
    fn rebuild_painted(
        &self,
        h: usize,
        material: usize,
        staged: &StagedPaint,
        strokes: usize,
    ) -> Result<PaintReport, RenderError> {
        let painter = self.painters[h]
            .as_ref()
            .expect("paintable checked the painter");
        let splat_image = self.surface.layer_splat(material);
        let splat_staged = match splat_image {
            Some(image) => {
                let bytes: Vec<Vec<u8>> = staged
                    .splat_rects
                    .iter()
                    .map(|r| painter.splat_bytes(r))
                    .collect();
                let regions: Vec<RegionTexels> = staged
                    .splat_rects
                    .iter()
                    .zip(&bytes)
                    .map(|(r, b)| (0, [r.x0, r.y0, r.width(), r.height()], b.as_slice()))
                    .collect();
                Some(StagedRegions::new(&self.ctx, image, &regions)?)
            }
            None => None,
        };
        let target = &self.heights[h].heights.image;
        let ao_maps = if self.pyramids_built {
            self.ao.maps_of(h)
        } else {
            // The first frame builds the AO from the painted field.
            Vec::new()
        };
        let mut report = PaintReport {
            strokes,
            splat_texels: staged.splat_rects.iter().map(TexelRect::texels).sum(),
            ..PaintReport::default()
        };
        let ao = &self.ao;
        report.gpu_ms = time_on_gpu(&self.ctx, |rec| {
            let regions = painter.record(rec, staged)?;
            record_paint_copies(
                rec,
                painter,
                &regions,
                target,
                splat_image.zip(splat_staged.as_ref()),
            )?;
            report.blended_texels = regions
                .iter()
                .map(|level| {
                    level
                        .iter()
                        .map(|r| u64::from(r[2]) * u64::from(r[3]))
                        .sum()
                })
                .collect();
            for &k in &ao_maps {
                for rect in &regions[0] {
                    if let Some(done) = ao.record_region(rec, k, *rect)? {
                        report.ao_texels += u64::from(done[2]) * u64::from(done[3]);
                    }
                }
            }
            Ok(())
        })?;
        Ok(report)
    }

    /// Records and submits one frame. If the slot it takes still held an older frame, that frame
    /// is retired first and returned.
    pub fn submit(&mut self, request: &FrameRequest) -> Result<Option<FrameOutput>, RenderError> {
        let k = (self.submitted % FRAMES_IN_FLIGHT as u64) as usize;
        let retired = self.retire(k)?;
        let aspect = self.width as f32 / self.height as f32;
        let uniforms = FrameUniforms::new(&request.camera, &self.lights, aspect);
        for h in &mut self.heights {
            h.write_uniforms(k, uniforms)?;
        }
        self.surface.write_uniforms(k, &uniforms)?;
        if request.read_back && self.slots[k].readback.is_none() {
            // Every slot's at once, so frames after the first create nothing.
            for (j, slot) in self.slots.iter_mut().enumerate() {
                let name = format!("frame slot {j} readback");
                slot.readback = Some(self.targets.readback_buffer(&self.ctx, &name)?);
            }
        }
        let build_pyramids = !self.pyramids_built;
        let eye = request.camera.eye();
        let frustum = Frustum::from_view_projection(request.camera.view_projection(aspect));
        let slot = &mut self.slots[k];
        let readback = slot.readback.as_ref().filter(|_| request.read_back);
        let (heights, ao, surface, cells, targets) = (
            &self.heights,
            &self.ao,
            &self.surface,
            &self.cells,
            &self.targets,
        );
        let timer = &mut slot.timer;
        let culled = slot.commands.submit(|rec| {
            if build_pyramids {
                for (part, h) in heights
                    .iter()
                    .enumerate()
                    .filter(|(_, h)| h.builds_pyramid())
                {
                    let scope = Scope {
                        pass: Pass::Pyramid,
                        part: Some(part),
                    };
                    timer.scope(rec, scope, |rec| h.record_pyramid(rec))?;
                }
                for part in 0..ao.len() {
                    let scope = Scope {
                        pass: Pass::AmbientOcclusion,
                        part: Some(part),
                    };
                    timer.scope(rec, scope, |rec| ao.record(rec, part))?;
                }
            }
            let scope = |pass| Scope { pass, part: None };
            if cells.is_empty() {
                timer.scope(rec, scope(Pass::Surface), |rec| {
                    targets.begin(rec);
                    let culled = surface.record_draws(rec, k, eye, &frustum);
                    targets.end(rec, readback)?;
                    culled
                })
            } else {
                // The complexes first (opaque), then the surface pass's draws, blended ones last.
                timer.scope(rec, scope(Pass::Cells), |rec| {
                    targets.begin(rec);
                    let frame_set = surface
                        .plain_set(k)
                        .ok_or_else(|| VkError::Invalid("no plain frame set".into()))?;
                    cells.record(rec, frame_set, |m| surface.material_set(m))
                })?;
                timer.scope(rec, scope(Pass::Surface), |rec| {
                    let culled = surface.record_draws(rec, k, eye, &frustum);
                    targets.end(rec, readback)?;
                    culled
                })
            }
        })?;
        slot.pending = Some((self.submitted, request.read_back, culled));
        self.pyramids_built = true;
        self.submitted += 1;
        Ok(retired)
    }

    /// Waits for every frame still in flight and returns them, oldest first.
    pub fn finish(&mut self) -> Result<Vec<FrameOutput>, RenderError> {
        let mut out = Vec::new();
        for step in 0..FRAMES_IN_FLIGHT as u64 {
            let k = ((self.submitted + step) % FRAMES_IN_FLIGHT as u64) as usize;
            out.extend(self.retire(k)?);
        }
        Ok(out)
    }

    /// Draws one frame and waits for it (frames submitted earlier and still in flight are
    /// waited for too, and not returned).
    pub fn draw(&mut self, request: &FrameRequest) -> Result<FrameOutput, RenderError> {
        self.submit(request)?;
        self.finish()?
            .pop()
            .ok_or_else(|| RenderError::Vulkan(VkError::Invalid("no frame".into())))
    }

    /// Waits for slot `k`'s frame, if any, and reads its timings and pixels.
    fn retire(&mut self, k: usize) -> Result<Option<FrameOutput>, RenderError> {
        let slot = &mut self.slots[k];
        let Some((index, read_back, culled_draws)) = slot.pending.take() else {
            return Ok(None);
        };
        slot.commands.wait()?;
        let scopes = slot.timer.read()?;
        // SAFETY: the slot's only submission, the one that wrote its timer, was waited for above.
        unsafe { slot.timer.reset() };
        let rgba = match (&slot.readback, read_back) {
            (Some(buffer), true) => Some(buffer.bytes()?.to_vec()),
            _ => None,
        };
        if index == 0 {
            self.note_pyramids(&scopes);
            self.note_ao_maps(&scopes);
        }
        Ok(Some(FrameOutput {
            index,
            timings: per_pass(&scopes),
            rgba,
            width: self.width,
            height: self.height,
            culled_draws,
        }))
    }

    /// Lists the AO maps the first frame built, with their GPU time.
    fn note_ao_maps(&mut self, scopes: &[(Scope, f64)]) {
        for (scope, ms) in scopes
            .iter()
            .filter(|(s, _)| s.pass == Pass::AmbientOcclusion)
        {
            let Some(ao) = scope.part.and_then(|p| self.plan.ao_maps.get(p)) else {
                continue;
            };
            let hp = &self.plan.heights[ao.heights];
            self.maps.push(BuiltMap {
                kind: "ao",
                source: format!(
                    "{} ({}, depth scale {})",
                    hp.source, ao.mode, ao.depth_scale
                ),
                size: [hp.size.0, hp.size.1],
                ms: *ms,
                on: "gpu",
            });
        }
    }

    /// Lists the pyramids the first frame built, with their GPU time.
    fn note_pyramids(&mut self, scopes: &[(Scope, f64)]) {
        for (scope, ms) in scopes.iter().filter(|(s, _)| s.pass == Pass::Pyramid) {
            let Some(hp) = scope.part.and_then(|p| self.plan.heights.get(p)) else {
                continue;
            };
            // A layered map's max pyramid came blended; its first frame builds the averaged one.
            let kind = match hp.key {
                HeightKey::Layers { .. } => "averaged pyramid",
                _ => MapKind::MaxPyramid.name(),
            };
            self.maps.push(BuiltMap {
                kind,
                source: hp.source.clone(),
                size: [hp.size.0, hp.size.1],
                ms: *ms,
                on: "gpu",
            });
        }
    }
}

/// Uploads every planned height map with its precomputed map (built once, here).
fn upload_heights(
    ctx: &Arc<Context>,
    scene: &Scene,
    plan: &Plan,
    frame_heights: Option<&Heightfield>,
    opts: &RenderOptions,
    uniforms: FrameUniforms,
) -> Result<UploadedHeights, RenderError> {
    let mut heights = Vec::with_capacity(plan.heights.len());
    let mut painters = Vec::with_capacity(plan.heights.len());
    let mut maps = Vec::new();
    for hp in &plan.heights {
        let (stored, address, prebuilt) = match hp.key {
            HeightKey::Layers { material } => {
                let layers = scene.materials[material].layers.as_ref().ok_or_else(|| {
                    VkError::Invalid("the plan blends a material without layers".into())
                })?;
                let mut blended = blended_heights(
                    ctx,
                    scene,
                    layers,
                    opts.height_format,
                    opts.paintable_layers,
                )?;
                painters.push(blended.painter.take());
                maps.push(BuiltMap {
                    kind: "layer stack",
                    source: hp.source.clone(),
                    size: [hp.size.0, hp.size.1],
                    ms: blended.stack_ms,
                    on: "cpu",
                });
                maps.push(BuiltMap {
                    kind: "blended pyramid",
                    source: hp.source.clone(),
                    size: [hp.size.0, hp.size.1],
                    ms: blended.gpu_ms,
                    on: "gpu",
                });
                let level = blended.pyramid.level(0);
                let field = Heightfield::from_valid(level.width, level.height, level.data.clone());
                (Cow::Owned(field), Address::Clamp, Some(blended.pyramid))
            }
            HeightKey::Frame => {
                let stored = planned_heights(ctx, scene, hp, frame_heights, opts.height_format)?;
                painters.push(None);
                (stored, opts.address, None)
            }
            HeightKey::Image { address, .. } => {
                let stored = planned_heights(ctx, scene, hp, frame_heights, opts.height_format)?;
                painters.push(None);
                (stored, address, None)
            }
        };
        let map = match hp.map_method {
            Some(method) => build_method_map_with(method, &stored, address, MapBuilder::Gpu(ctx))?,
            None => None,
        };
        if let (Some(built), Some(kind)) = (&map, hp.map) {
            maps.push(BuiltMap {
                kind: kind.name(),
                source: hp.source.clone(),
                size: [built.data.width, built.data.height],
                ms: built.ms,
                on: built.on,
            });
        }
        let map_data = map.as_ref().map(|built| &built.data);
        let upload = HeightUpload {
            format: opts.height_format,
            address,
            map: map_data,
            pyramid: hp.pyramid,
            slots: FRAMES_IN_FLIGHT,
            mean_binding: hp.mean_binding,
            mean_pyramid: hp.mean_pyramid,
        };
        if let Some(pyramid) = &prebuilt {
            heights.push(HeightResources::upload_prebuilt(
                ctx, pyramid, &upload, uniforms,
            )?);
            continue;
        }
        heights.push(HeightResources::upload(ctx, &stored, &upload, uniforms)?);
    }
    Ok((heights, maps, painters))
}

/// Every planned height map uploaded, the maps built for them, and the painters of layered ones.
type UploadedHeights = (
    Vec<HeightResources>,
    Vec<BuiltMap>,
    Vec<Option<LayerPainter>>,
);
