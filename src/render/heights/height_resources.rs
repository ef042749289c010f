//! What every pass that traces rays binds: the height image with its pyramid (built on the GPU),
//! the frame uniforms with this map's height info, and the method's precomputed map when it has
//! one. Bindings 0..=3 of `shaders/include/bindings.glsl`, plus binding 4 (the averaged pyramid,
//! `shaders/include/lod.glsl`) for the LOD variants of pyramid methods. The uniforms come in one host-visible
//! copy per frame in flight, so a frame can rewrite its copy while the GPU still reads another.

use std::borrow::Cow;
use std::sync::Arc;

use ash::vk;

use super::method_map::GpuMethodMap;
use crate::heightfield::{Address, Heightfield, MapData, MaxPyramid};
use crate::render::kit::frame_uniforms::FrameUniforms;
use crate::render::kit::gpu_heightfield::{GpuHeightfield, HeightFormat};
use crate::render::maps::mean_pyramid_pass::MeanPyramid;
use crate::render::maps::pyramid_pass::{PyramidJob, PyramidPass};
use crate::render::shader_interface::{
    BINDING_FRAME, BINDING_HEIGHT_LINEAR, BINDING_HEIGHT_MEAN, BINDING_HEIGHT_POINT,
    BINDING_METHOD_MAP,
};
use crate::vk::{Bind, Buffer, Context, Recording, VkError, VkResult};

/// Uploaded heights, their pyramid pass (when a method reads it), uniforms and the optional
/// method map.
pub struct HeightResources {
    /// The heights and, in their mip chain, the max pyramid (bindings 1 and 2).
    pub heights: GpuHeightfield,
    pyramid: Option<(PyramidPass, PyramidJob)>,
    /// The pyramid came built with the heights (`with_pyramid`).
    prebuilt: bool,
    uniforms: Vec<Buffer>,
    map: Option<GpuMethodMap>,
    mean: MeanBinding,
}

/// What binding 4 holds.
enum MeanBinding {
    /// No binding 4 (non-LOD or non-pyramid variants).
    None,
    /// The max pyramid stands in: the variants bind 4 but their materials never read it.
    StandIn,
    /// The averaged pyramid, built with the max one.
    Built(Box<MeanPyramid>),
}

impl MeanBinding {
    /// What `upload` asks for; `level0` gives the heights to average, only when it is built.
    fn new<'h>(
        ctx: &Arc<Context>,
        upload: &HeightUpload,
        level0: impl FnOnce() -> VkResult<Cow<'h, Heightfield>>,
    ) -> VkResult<MeanBinding> {
        Ok(match (upload.mean_binding, upload.mean_pyramid) {
            (false, _) => MeanBinding::None,
            (true, false) => MeanBinding::StandIn,
            (true, true) => MeanBinding::Built(Box::new(MeanPyramid::new(
                ctx,
                level0()?.as_ref(),
                upload.format,
            )?)),
        })
    }
}

/// How a height map is stored and what comes with it.
#[derive(Debug, Clone, Copy)]
pub struct HeightUpload<'a> {
    /// How the heights are stored on the GPU.
    pub format: HeightFormat,
    /// What lies outside the map; the height samplers and the method map's use it.
    pub address: Address,
    /// The method's precomputed map (binding 3), if it reads one.
    pub map: Option<&'a MapData>,
    /// Whether to build the max pyramid in the image's mip chain (methods that read no pyramid
    /// get a single-level image and no pyramid pass).
    pub pyramid: bool,
    /// Copies of the uniforms, one per frame in flight.
    pub slots: usize,
    /// Whether draws bind binding 4 (LOD variants of pyramid methods).
    pub mean_binding: bool,
    /// Whether binding 4 is the averaged pyramid, built here (else the max pyramid stands in).
    pub mean_pyramid: bool,
}

impl<'a> HeightUpload<'a> {
    /// One frame slot's worth, with the max pyramid and no averaged one (traces and benches).
    pub fn single(format: HeightFormat, address: Address, map: Option<&'a MapData>) -> Self {
        HeightUpload {
            format,
            address,
            map,
            pyramid: true,
            slots: 1,
            mean_binding: false,
            mean_pyramid: false,
        }
    }
}

impl HeightResources {
    /// Uploads `hf` (and `map`), prepares the pyramid build and one copy of the uniforms in
    /// `frame`, whose `height_info` is filled in here.
    pub fn new(
        ctx: &Arc<Context>,
        hf: &Heightfield,
        format: HeightFormat,
        address: Address,
        map: Option<&MapData>,
        frame: FrameUniforms,
    ) -> VkResult<HeightResources> {
        let upload = HeightUpload::single(format, address, map);
        Self::upload(ctx, hf, &upload, frame)
    }

    /// Like [`HeightResources::new`], with `pyramid` (level 0 the heights) uploaded as the height
    /// image's mip chain instead of a pyramid built from the heights on the GPU.
    pub fn with_pyramid(
        ctx: &Arc<Context>,
        pyramid: &MaxPyramid,
        format: HeightFormat,
        address: Address,
        map: Option<&MapData>,
        frame: FrameUniforms,
    ) -> VkResult<HeightResources> {
        let upload = HeightUpload::single(format, address, map);
        Self::upload_prebuilt(ctx, pyramid, &upload, frame)
    }

    /// [`HeightResources::with_pyramid`] as `upload` says (its `pyramid` is ignored: the pyramid
    /// is given); an averaged pyramid, when asked for, is built from `pyramid`'s level 0 by the
    /// first frame.
    pub fn upload_prebuilt(
        ctx: &Arc<Context>,
        pyramid: &MaxPyramid,
        upload: &HeightUpload,
        mut frame: FrameUniforms,
    ) -> VkResult<HeightResources> {
        let HeightUpload {
            format,
            address,
            map,
            slots,
            ..
        } = *upload;
        let heights = GpuHeightfield::upload_prebuilt(ctx, pyramid, format, address)?;
        frame.height_info = heights.shader_info();
        let (uniforms, map) = uniforms_and_map(ctx, &frame, slots, map, address)?;
        let mean = MeanBinding::new(ctx, upload, || {
            let base = pyramid.level(0);
            Heightfield::new(base.width, base.height, base.data.clone())
                .map(Cow::Owned)
                .map_err(|e| VkError::Invalid(e.to_string()))
        })?;
        Ok(HeightResources {
            heights,
            pyramid: None,
            prebuilt: true,
            uniforms,
            map,
            mean,
        })
    }

    /// Uploads `hf` as `upload` says, with `frame` in every copy of the uniforms.
    pub fn upload(
        ctx: &Arc<Context>,
        hf: &Heightfield,
        upload: &HeightUpload,
        mut frame: FrameUniforms,
    ) -> VkResult<HeightResources> {
        let HeightUpload {
            format,
            address,
            map,
            pyramid,
            slots,
            ..
        } = *upload;
        let (heights, pyramid) = if pyramid {
            let heights = GpuHeightfield::upload(ctx, hf, format, address)?;
            let pass = PyramidPass::new(ctx, format.shader_suffix())?;
            let job = pass.prepare(&heights)?;
            (heights, Some((pass, job)))
        } else {
            let heights = GpuHeightfield::upload_without_pyramid(ctx, hf, format, address)?;
            (heights, None)
        };
        frame.height_info = heights.shader_info();
        let (uniforms, map) = uniforms_and_map(ctx, &frame, slots, map, address)?;
        let mean = MeanBinding::new(ctx, upload, || Ok(Cow::Borrowed(hf)))?;
        Ok(HeightResources {
            heights,
            pyramid,
            prebuilt: false,
            uniforms,
            map,
            mean,
        })
    }

    /// The descriptor types of bindings 0..=3 (3 only with a map).
    pub fn layout_bindings(&self) -> Vec<(u32, vk::DescriptorType)> {
        let sampled = vk::DescriptorType::COMBINED_IMAGE_SAMPLER;
        let mut list = vec![
            (BINDING_FRAME, vk::DescriptorType::UNIFORM_BUFFER),
            (BINDING_HEIGHT_POINT, sampled),
            (BINDING_HEIGHT_LINEAR, sampled),
        ];
        if self.map.is_some() {
            list.push((BINDING_METHOD_MAP, sampled));
        }
        if self.has_mean_binding() {
            list.push((BINDING_HEIGHT_MEAN, sampled));
        }
        list
    }

    /// The resources for bindings 0..=3, with the uniforms of frame slot 0.
    pub fn binds(&self) -> Vec<Bind<'_>> {
        self.slot_binds(0)
    }

    /// The resources for bindings 0..=3, with the uniforms of frame slot `slot`.
    pub fn slot_binds(&self, slot: usize) -> Vec<Bind<'_>> {
        let view = self.heights.image.view();
        let uniforms = &self.uniforms[slot.min(self.uniforms.len() - 1)];
        let mut list = vec![
            Bind::Uniform(BINDING_FRAME, uniforms),
            Bind::Texture(BINDING_HEIGHT_POINT, view, &self.heights.point),
            Bind::Texture(BINDING_HEIGHT_LINEAR, view, &self.heights.linear),
        ];
        if let Some(map) = &self.map {
            list.push(Bind::Texture(
                BINDING_METHOD_MAP,
                map.image.view(),
                &map.sampler,
            ));
        }
        let point = &self.heights.point;
        match &self.mean {
            MeanBinding::None => {}
            MeanBinding::StandIn => list.push(Bind::Texture(BINDING_HEIGHT_MEAN, view, point)),
            MeanBinding::Built(mean) => {
                list.push(Bind::Texture(BINDING_HEIGHT_MEAN, mean.view(), point))
            }
        }
        list
    }

    /// Records the pyramid build (if there is one); afterwards the height image is ready for
    /// sampling.
    pub fn record_pyramid(&self, rec: &Recording) -> VkResult<()> {
        if let MeanBinding::Built(mean) = &self.mean {
            mean.record(rec)?;
        }
        match &self.pyramid {
            Some((pass, job)) => pass.record(rec, &self.heights, job),
            None => Ok(()),
        }
    }

    /// Writes `frame`, with this map's height info, into slot `slot`'s uniforms.
    ///
    /// # Safety
    /// The slot's previous frame has finished on the GPU (its fence was waited for): the
    /// uniforms are host memory its draws read.
    pub unsafe fn write_uniforms(&mut self, slot: usize, mut frame: FrameUniforms) -> VkResult<()> {
        frame.height_info = self.heights.shader_info();
        let count = self.uniforms.len();
        let buffer = self
            .uniforms
            .get_mut(slot)
            .ok_or_else(|| VkError::Invalid(format!("uniform slot {slot} of {count}")))?;
        // SAFETY: only the slot's frames bind its buffer, and the caller waited for them.
        unsafe { buffer.write(0, bytemuck::bytes_of(&frame)) }
    }

    /// The shaders' `height_info` of this map: width, height, mip levels, 1 for repeat.
    pub fn shader_info(&self) -> [f32; 4] {
        self.heights.shader_info()
    }

    /// How many frame slots have uniforms.
    pub fn slots(&self) -> usize {
        self.uniforms.len()
    }

    /// Whether a method map is bound (binding 3).
    pub fn has_map(&self) -> bool {
        self.map.is_some()
    }

    /// Whether binding 4 is bound (LOD variants of pyramid methods).
    pub fn has_mean_binding(&self) -> bool {
        !matches!(self.mean, MeanBinding::None)
    }

    /// Whether the averaged pyramid is built here.
    pub fn has_mean_pyramid(&self) -> bool {
        matches!(self.mean, MeanBinding::Built(_))
    }

    /// Whether the height image carries a max pyramid (built by the first frame, or uploaded).
    pub fn has_pyramid(&self) -> bool {
        self.pyramid.is_some() || self.prebuilt
    }

    /// Whether the first frame builds a pyramid (`record_pyramid`): the max pyramid, or the
    /// averaged one beside an uploaded max pyramid.
    pub fn builds_pyramid(&self) -> bool {
        self.pyramid.is_some() || matches!(self.mean, MeanBinding::Built(_))
    }
}

/// One copy of `frame` per frame slot, and the method map uploaded (if any).
fn uniforms_and_map(
    ctx: &Arc<Context>,
    frame: &FrameUniforms,
    slots: usize,
    map: Option<&MapData>,
    address: Address,
) -> VkResult<(Vec<Buffer>, Option<GpuMethodMap>)> {
    let uniforms = (0..slots.max(1))
        .map(|slot| {
            Buffer::with_data(
                ctx,
                bytemuck::bytes_of(frame),
                vk::BufferUsageFlags::UNIFORM_BUFFER,
                &format!("frame uniforms {slot}"),
            )
        })
        .collect::<VkResult<Vec<_>>>()?;
    let map = map
        .map(|m| GpuMethodMap::upload(ctx, m, address, "method map"))
        .transpose()?;
    Ok((uniforms, map))
}
