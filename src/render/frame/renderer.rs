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

use std::sync::Arc;
use std::time::Instant;

use super::frame_environment::{environment_passes, note_environment};
use super::frame_graph::{frame_graph, FrameParts};
pub use super::frame_request::{FrameOutput, FrameRequest};
use super::frame_setup::plan_frame;
use super::frame_slot::FrameSlot;
use super::height_upload::upload_heights;
use super::occluders::OccluderTargets;
use super::record_graph::{FrameWork, RecordingParts};
use super::scene_ao::SceneAo;
use super::single_frame::{BuiltMap, RenderOptions};
use super::surface_pass::SurfacePass;
use super::targets::{FrameReadbacks, TargetOptions, Targets};
use super::tonemap::ToneMapPass;
use crate::heightfield::Heightfield;
use crate::method::MapKind;
use crate::render::cells::cells_pass::{BuiltComplex, CellsPass};
use crate::render::environment::{BackgroundPass, EnvironmentLight};
use crate::render::heights::height_resources::HeightResources;
use crate::render::kit::formats::COLOR_FORMAT;
use crate::render::kit::frame_timeline::{HostSpan, HostWork, SubmittedTimeline};
use crate::render::kit::frame_uniforms::{frame_camera, FrameUniforms};
use crate::render::kit::graph::FrameGraph;
use crate::render::kit::pass::Pass;
use crate::render::kit::pass_timer::{per_pass, TimedScope};
use crate::render::kit::render_error::RenderError;
use crate::render::lighting::{
    lighting_pass_for, FrameTracedShadows, LightingPass, TracedShadows, TRACED_SAMPLES_PER_SIDE,
};
use crate::render::plan::frame_plan::{HeightKey, Plan};
use crate::render::shadows::light_views::LightView;
use crate::render::shadows::shadow_pass::ShadowMaps;
use crate::render::shells::shell_upload::BuiltShell;
use crate::render::terrain::layer_paint::LayerPainter;
use crate::scene::{Camera, Light, Mesh, Scene};
use crate::vk::{Buffer, Context, Image, Readback, SubmitSync, VkError, VkResult};

/// How many frames may be recorded or running at once.
pub const FRAMES_IN_FLIGHT: usize = 2;

/// Everything a scene needs on the device, kept across frames.
pub struct Renderer {
    pub(in crate::render) ctx: Arc<Context>,
    pub(in crate::render) plan: Plan,
    maps: Vec<BuiltMap>,
    upload_ms: f64,
    pub(in crate::render) heights: Vec<HeightResources>,
    /// By `Plan::heights` index: the painter of a layered map (`RenderOptions::paintable_layers`).
    pub(in crate::render) painters: Vec<Option<LayerPainter>>,
    pub(in crate::render) ao: SceneAo,
    pub(in crate::render) surface: SurfacePass,
    shadows: ShadowMaps,
    /// The light whose visibility frames write instead of colours.
    shadow_probe: Option<usize>,
    /// Read-back frames also return their radiance.
    keep_radiance: bool,
    cells: CellsPass,
    /// The environment's maps, when the ambient light comes from one.
    environment: Option<EnvironmentLight>,
    /// The environment drawn behind the scene (`RenderOptions::background`).
    background: Option<BackgroundPass>,
    tone_map: ToneMapPass,
    targets: Targets,
    /// The deferred frame's lighting pass (`RenderOptions::lighting`).
    lighting: Option<LightingPass>,
    /// The structures its shadow rays go through (`RenderOptions::traced_shadows`).
    _traced_shadows: Option<FrameTracedShadows>,
    /// The occluder pass's bounds, when some relief surface reads them.
    occluders: Option<OccluderTargets>,
    slots: Vec<FrameSlot>,
    lights: Vec<Light>,
    default_camera: Camera,
    width: u32,
    height: u32,
    submitted: u64,
    pub(in crate::render) pyramids_built: bool,
    /// Test-only: a frame-sized buffer made and kept at every retired frame (a leak a soak must
    /// catch); `None` in every real renderer.
    kept_for_leak_test: Option<Vec<Buffer>>,
    /// The camera the next frame's motion is measured from: the last frame's, or the one
    /// [`Renderer::set_motion_origin`] gave; none before the first frame (no motion).
    motion_origin: Option<Camera>,
    /// The frame's passes in recording order, and those left out.
    graph: FrameGraph,
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
        let (mut plan, traced) = plan_frame(ctx, scene, frame_heights, opts)?;
        let probe = opts.shadow_probe.is_some();
        let default_camera = frame_camera(scene);
        let aspect = opts.width as f32 / opts.height as f32;
        let uniforms = FrameUniforms::new(&default_camera, &plan.lights, aspect);
        let started = Instant::now();
        let (heights, maps, painters) =
            upload_heights(ctx, scene, &plan, frame_heights, opts, uniforms)?;
        let upload_ms = started.elapsed().as_secs_f64() * 1e3;
        let ao = SceneAo::new(ctx, &plan, &heights)?;
        let shadows = ShadowMaps::new(ctx, scene, &plan)?;
        let (environment, background) = environment_passes(ctx, opts, &mut plan, probe)?;
        let mut maps = maps;
        note_environment(&mut plan, &mut maps, environment.as_ref());
        let surface = SurfacePass::new(
            ctx,
            scene,
            &plan,
            &heights,
            &ao,
            shadows.atlas(),
            environment.as_ref(),
            &uniforms,
            FRAMES_IN_FLIGHT,
        )?;
        let cells = CellsPass::new(ctx, scene, &plan, opts.cells.as_ref())?;
        let tone_map = ToneMapPass::new(ctx, COLOR_FORMAT, plan.msaa.samples)?;
        let targets = Targets::new(
            ctx,
            opts.width,
            opts.height,
            TargetOptions::of(&plan, probe, opts.keep_radiance),
            &tone_map,
        )?;
        let lighting = traced_lighting(ctx, &plan, &targets, traced.as_ref())?;
        // The counters live beside the bounds, so a counting frame has the bounds' targets even
        // where nothing occludes (then they are cleared and never read).
        let occluders = (plan.occluders || plan.count_work)
            .then(|| occluder_targets(ctx, &surface, &targets, plan.count_work))
            .transpose()?;
        let slots = frame_slots(ctx, &plan, &ao)?;
        let graph = frame_graph(FrameParts {
            pyramids: heights.iter().any(HeightResources::builds_pyramid),
            ao_maps: ao.len() > 0,
            shadow_maps: !plan.shadow_maps.is_empty(),
            occluders: occluders.is_some(),
            cells: !cells.is_empty(),
            background: background.is_some(),
            gbuffer: plan.gbuffer,
            depth: probe,
            deferred: plan.deferred,
        })?;
        Ok(Renderer {
            ctx: ctx.clone(),
            graph,
            lights: plan.lights.clone(),
            plan,
            maps,
            upload_ms,
            heights,
            painters,
            ao,
            surface,
            shadows,
            shadow_probe: opts.shadow_probe,
            keep_radiance: opts.keep_radiance,
            cells,
            environment,
            background,
            tone_map,
            targets,
            lighting,
            _traced_shadows: traced,
            occluders,
            slots,
            default_camera,
            width: opts.width,
            height: opts.height,
            submitted: 0,
            pyramids_built: false,
            kept_for_leak_test: None,
            motion_origin: None,
        })
    }

    /// World size of a shadow-map texel of light `light` at each of `points` in a frame seen by
    /// `camera`: how finely its map places a shadow edge there (0 where no map covers a point).
    pub fn shadow_texel_world(
        &self,
        camera: &Camera,
        light: usize,
        points: &[Option<glam::Vec3>],
    ) -> Vec<f32> {
        let aspect = self.width as f32 / self.height as f32;
        self.shadows
            .texel_world(&self.plan, camera, aspect, light, points)
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

    /// The meshes drawn as prism shells (`Silhouettes::Shells`), with their prisms and bytes.
    pub fn shells(&self) -> &[BuiltShell] {
        self.surface.shells()
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
        let options =
            TargetOptions::of(&self.plan, self.shadow_probe.is_some(), self.keep_radiance);
        self.targets = Targets::new(&self.ctx, width, height, options, &self.tone_map)?;
        if self.occluders.is_some() {
            let counting = self.plan.count_work;
            self.occluders = Some(occluder_targets(
                &self.ctx,
                &self.surface,
                &self.targets,
                counting,
            )?);
        }
        self.slots.iter_mut().for_each(FrameSlot::forget_readbacks);
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
        self.invalidate_shadow_maps();
        Ok(retired)
    }

    /// Makes the next frame render every shadow map again, as it does after the casters changed
    /// (meshes replaced, a terrain edited or painted; views that move are noticed without it):
    /// for timing the shadow pass, or after a change the renderer cannot see.
    pub fn invalidate_shadow_maps(&mut self) {
        self.shadows.invalidate();
    }

    /// The frame's passes, in the order they are recorded, with what each reads and writes and
    /// how often it runs, and the passes left out.
    pub fn graph(&self) -> &FrameGraph {
        &self.graph
    }

    /// Measures the next frame's motion (the G-buffer's) from `camera` instead of the last
    /// frame's camera: for a sequence drawn out of order or in part, the camera of the frame
    /// before it in the sequence.
    pub fn set_motion_origin(&mut self, camera: Camera) {
        self.motion_origin = Some(camera);
    }

    /// Records and submits one frame. If the slot it takes still held an older frame, that frame
    /// is retired first and returned.
    pub fn submit(&mut self, request: &FrameRequest) -> Result<Option<FrameOutput>, RenderError> {
        self.submit_synced(request, SubmitSync::default())
    }

    /// As [`Renderer::submit`], with the frame's submission ordered by `sync`: it waits for
    /// `sync.wait` before its commands reach the stage named there, and signals `sync.signal`
    /// when it finishes. An engine hands its own semaphores over with
    /// [`crate::vk::Semaphore::borrowed`]: its submission that waits on the signalled one may then
    /// read [`Renderer::color_target`] (in `COLOR_ATTACHMENT_OPTIMAL`, written at colour
    /// attachment output) on any queue, as long as it finishes before this renderer's next
    /// submission draws into the target again.
    pub fn submit_synced(
        &mut self,
        request: &FrameRequest,
        sync: SubmitSync<'_>,
    ) -> Result<Option<FrameOutput>, RenderError> {
        let k = (self.submitted % FRAMES_IN_FLIGHT as u64) as usize;
        let retired = self.retire(k)?;
        let started = Instant::now();
        let aspect = self.width as f32 / self.height as f32;
        let mut uniforms = self.frame_uniforms(&request.camera, aspect);
        let views = self
            .shadows
            .write_views(&mut uniforms, &self.plan, &request.camera, aspect);
        self.write_slot_uniforms(k, uniforms)?;
        if request.read_back && self.slots[k].readback.is_none() {
            self.make_readbacks()?;
        }
        if let (Some(o), true) = (&self.occluders, self.plan.count_work) {
            // Every slot's at once, as the other read-backs, so later frames create nothing.
            for (j, slot) in self.slots.iter_mut().enumerate() {
                if slot.work_readback.is_none() {
                    let name = format!("frame slot {j} work counters readback");
                    slot.work_readback = Some(o.counters().readback(&self.ctx, &name)?);
                }
            }
        }
        let render_maps = self.shadows.needs_render(&views);
        let frame = self.record_frame(k, request, (&views, render_maps), sync)?;
        let timeline = self.submitted_timeline(started, &frame);
        let slot = &mut self.slots[k];
        slot.timeline = Some(timeline);
        slot.pending = Some((self.submitted, request.read_back, frame.culled));
        self.pyramids_built = true;
        if render_maps {
            self.shadows.mark_rendered(&views);
        }
        self.submitted += 1;
        Ok(retired)
    }

    /// The uniforms of a frame seen by `camera`, its motion measured from the motion origin
    /// (which `camera` becomes for the next frame).
    fn frame_uniforms(&mut self, camera: &Camera, aspect: f32) -> FrameUniforms {
        let mut uniforms = FrameUniforms::new(camera, &self.lights, aspect);
        let origin = self.motion_origin.replace(*camera);
        uniforms.previous_view_proj = origin
            .unwrap_or(*camera)
            .view_projection(aspect)
            .to_cols_array_2d();
        uniforms.viewport = [self.width as f32, self.height as f32, 0.0, 0.0];
        uniforms.counts[1] = self.shadow_probe.map_or(0, |k| k as i32 + 1);
        if let Some(e) = &self.environment {
            uniforms.counts[2] = 1;
            uniforms.ambient[3] = e.last_specular_level();
        }
        uniforms
    }

    /// Writes `uniforms` into slot `k`'s buffers (the height maps' and the plain set's), once
    /// the slot's last submission has finished.
    fn write_slot_uniforms(&mut self, k: usize, uniforms: FrameUniforms) -> VkResult<()> {
        // The slot's last submission is the only one binding its uniforms; retiring it waited
        // for it, and an idle slot's wait returns at once.
        self.slots[k].commands.wait()?;
        for h in &mut self.heights {
            // SAFETY: slot k's submissions have finished (waited for above).
            unsafe { h.write_uniforms(k, uniforms)? };
        }
        // SAFETY: as above.
        unsafe { self.surface.write_uniforms(k, &uniforms) }
    }

    /// Makes every slot's read-backs at once, so frames after the first create nothing.
    fn make_readbacks(&mut self) -> VkResult<()> {
        let asked = (self.shadow_probe.is_some(), self.keep_radiance);
        for (j, slot) in self.slots.iter_mut().enumerate() {
            slot.make_readbacks(&self.ctx, j, &self.targets, asked)?;
        }
        Ok(())
    }

    /// Records the frame `request` asks for into slot `k` and submits it; `views` are the
    /// shadow maps' views, rendered when `render_maps`. Returns what the frame culled and when
    /// it was recorded and submitted.
    fn record_frame(
        &mut self,
        k: usize,
        request: &FrameRequest,
        (views, render_maps): (&[LightView], bool),
        sync: SubmitSync<'_>,
    ) -> VkResult<RecordedFrame> {
        let aspect = self.width as f32 / self.height as f32;
        let build_pyramids = !self.pyramids_built;
        let parts = RecordingParts {
            graph: &self.graph,
            plan: &self.plan,
            heights: &self.heights,
            ao: &self.ao,
            shadows: &self.shadows,
            occluders: self.occluders.as_ref(),
            cells: &self.cells,
            surface: &self.surface,
            background: self.background.as_ref(),
            targets: &self.targets,
            tone_map: (&self.tone_map, self.plan.tone_mapping),
            lighting: self.lighting.as_ref(),
        };
        let slot = &mut self.slots[k];
        fn kept(buffer: &Option<Readback>, read: bool) -> Option<&Readback> {
            buffer.as_ref().filter(|_| read)
        }
        let read = request.read_back;
        let work = FrameWork {
            slot: k,
            eye: request.camera.eye(),
            view_proj: request.camera.view_projection(aspect),
            views,
            build_maps: build_pyramids,
            render_shadow_maps: render_maps,
            work: slot.work_readback.as_ref(),
            into: FrameReadbacks {
                color: kept(&slot.readback, read),
                depth: kept(&slot.depth_readback, read),
                radiance: kept(&slot.radiance_readback, read),
                gbuffer: slot.gbuffer_readback.as_deref().filter(|_| read),
            },
        };
        let timer = &mut slot.timer;
        let mut recorded = None;
        let culled = slot.commands.submit_synced(sync, |rec| {
            let start = Instant::now();
            let culled = parts.record(rec, timer, work);
            recorded = Some((start, Instant::now()));
            culled
        })?;
        Ok(RecordedFrame {
            culled,
            recorded,
            submitted: Instant::now(),
        })
    }

    /// The host's part of a frame whose submission began at `started`: the submission, and
    /// the recording within it.
    fn submitted_timeline(&self, started: Instant, frame: &RecordedFrame) -> SubmittedTimeline {
        let mut host = vec![HostSpan {
            work: HostWork::Submit,
            start: started,
            end: frame.submitted,
        }];
        if let Some((start, end)) = frame.recorded {
            host.push(HostSpan {
                work: HostWork::Record,
                start,
                end,
            });
        }
        SubmittedTimeline {
            host,
            calibration: self.ctx.calibrate(),
            submitted: frame.submitted,
        }
    }

    /// Test-only, never for real use: from now on the renderer makes a frame-sized buffer at
    /// every retired frame and keeps it until it is dropped, a leak of device objects and host
    /// memory that relief's soak test must catch.
    #[doc(hidden)]
    pub fn leak_a_buffer_every_frame_for_tests(&mut self) {
        self.kept_for_leak_test.get_or_insert_with(Vec::new);
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
        let retire_start = Instant::now();
        slot.commands.wait()?;
        let scopes = slot.timer.read()?;
        // SAFETY: the slot's only submission, the one that wrote its timer, was waited for above.
        unsafe { slot.timer.reset() };
        let pixels = slot.read_pixels(&self.targets, (self.width, self.height), read_back)?;
        if index == 0 {
            self.note_pyramids(&scopes);
            self.note_ao_maps(&scopes);
        }
        if let Some(kept) = &mut self.kept_for_leak_test {
            // Filled, so its pages count in the process's resident memory as a real leak's would.
            let bytes = vec![0x5a; self.targets.readback_bytes() as usize];
            let name = format!("frame {index} buffer kept for the leak test");
            let usage = ash::vk::BufferUsageFlags::TRANSFER_DST;
            kept.push(Buffer::with_data(&self.ctx, &bytes, usage, &name)?);
        }
        let work = match (&self.slots[k].work_readback, &self.occluders) {
            (Some(buffer), Some(o)) => Some(o.counters().decode(buffer.bytes()?)),
            _ => None,
        };
        let slot = &mut self.slots[k];
        let retire = HostSpan {
            work: HostWork::Retire,
            start: retire_start,
            end: Instant::now(),
        };
        let timeline = match slot.timeline.take() {
            Some(submitted) => submitted.finish(&slot.timer, &scopes, retire),
            None => SubmittedTimeline {
                host: Vec::new(),
                calibration: None,
                submitted: retire_start,
            }
            .finish(&slot.timer, &scopes, retire),
        };
        Ok(Some(FrameOutput {
            index,
            timeline,
            work,
            timings: per_pass(&scopes),
            rgba: pixels.rgba,
            width: self.width,
            height: self.height,
            culled_draws,
            depth: pixels.depth,
            radiance: pixels.radiance,
            gbuffer: pixels.gbuffer,
        }))
    }

    /// Lists the AO maps the first frame built, with their GPU time.
    fn note_ao_maps(&mut self, scopes: &[TimedScope]) {
        for TimedScope {
            scope, gpu_ms: ms, ..
        } in scopes
            .iter()
            .filter(|s| s.scope.pass == Pass::AmbientOcclusion)
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
    fn note_pyramids(&mut self, scopes: &[TimedScope]) {
        for TimedScope {
            scope, gpu_ms: ms, ..
        } in scopes.iter().filter(|s| s.scope.pass == Pass::Pyramid)
        {
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

/// A frame just submitted: the draws it culled, when it was recorded and when submitted.
struct RecordedFrame {
    culled: usize,
    recorded: Option<(Instant, Instant)>,
    submitted: Instant,
}

/// One frame slot per frame in flight, each with timer scopes for a pyramid build per height
/// map, an AO map, each shadow map, and the occluder, cells and surface passes.
fn frame_slots(ctx: &Arc<Context>, plan: &Plan, ao: &SceneAo) -> VkResult<Vec<FrameSlot>> {
    let scopes = (plan.heights.len() + ao.len()) as u32 + ShadowMaps::scopes(plan) + 3;
    (0..FRAMES_IN_FLIGHT)
        .map(|k| FrameSlot::new(ctx, k, scopes))
        .collect()
}

/// The lighting pass `plan` asks for, over `targets`' lit images, its shadows traced through
/// `traced` when the frame traces them.
fn traced_lighting(
    ctx: &Arc<Context>,
    plan: &Plan,
    targets: &Targets,
    traced: Option<&FrameTracedShadows>,
) -> VkResult<Option<LightingPass>> {
    lighting_pass_for(
        ctx,
        plan,
        targets.lit_images(),
        traced.map(|t| TracedShadows {
            scene: &t.scene,
            offset: t.offset,
            samples_per_side: TRACED_SAMPLES_PER_SIDE,
        }),
    )
}

/// The occluder bounds at the size the scene is drawn at (`targets`' depth, supersampling
/// included), bound through `surface`'s set 3.
fn occluder_targets(
    ctx: &Arc<Context>,
    surface: &SurfacePass,
    targets: &Targets,
    counting: bool,
) -> VkResult<OccluderTargets> {
    let desc = targets.depth.desc();
    let size = (desc.width, desc.height);
    OccluderTargets::new(ctx, surface.occluder_layout(), size, counting)
}
