//! A command buffer while it records. Only this layer makes one, inside a submission (a one-shot
//! submit or a frame slot), and lends it to the caller by reference for the length of the
//! recording: safe code can record only into a buffer that is recording now, never into a null,
//! foreign or finished one. Every command relief records goes through it.

use std::cell::RefCell;
use std::marker::PhantomData;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

use ash::vk;

use super::buffer::Buffer;
use super::error::{VkError, VkResult};
use super::image::{Image, WholeImage};

/// A readback's mark while the recording that fills it is not yet submitted (timeline values
/// count up from 1; 0 is "never filled").
pub(crate) const UNSUBMITTED: u64 = u64::MAX;

/// One colour attachment of a dynamic rendering: the image drawn into, where (and how) its
/// samples are resolved when rendering ends, and the value it is cleared to.
#[derive(Clone, Copy)]
pub struct ColorTarget<'a> {
    /// The attachment, in the colour attachment layout.
    pub image: &'a Image,
    /// A single-sample image (in the colour attachment layout) its samples resolve into, and
    /// how: averaged for float formats, sample 0 for integer ones.
    pub resolve: Option<(&'a Image, vk::ResolveModeFlags)>,
    /// What it is cleared to.
    pub clear: vk::ClearColorValue,
}

/// A command buffer in the recording state, borrowed for one recording.
///
/// Safe code cannot make a recording of its own, so it cannot record into a null or foreign
/// command buffer:
///
/// ```compile_fail
/// use relief::vk::{raw, Context, Recording};
/// fn forge(ctx: &Context) {
///     let rec = Recording::new(ctx.device(), raw::CommandBuffer::null());
///     rec.dispatch([1, 1, 1]);
/// }
/// ```
///
/// nor keep one past its submission, so it cannot record into a finished buffer:
///
/// ```compile_fail
/// fn keep(ctx: &relief::vk::Context) {
///     let mut kept = None;
///     ctx.one_shot(|rec| {
///         kept = Some(rec);
///         Ok(())
///     })
///     .unwrap();
///     drop(kept);
/// }
/// ```
///
/// while recording inside a submission compiles:
///
/// ```no_run
/// fn record(ctx: &relief::vk::Context) -> relief::vk::VkResult<()> {
///     ctx.one_shot(|rec| {
///         rec.dispatch([1, 1, 1]);
///         Ok(())
///     })
/// }
/// ```
pub struct Recording<'a> {
    device: &'a ash::Device,
    cmd: vk::CommandBuffer,
    /// The submission marks of the readbacks this recording copies into: told the
    /// submission's timeline value when it is submitted.
    fills: RefCell<Vec<Arc<AtomicU64>>>,
    // Not Send or Sync: a command buffer is recorded by one thread (its pool is externally
    // synchronised).
    _single_thread: PhantomData<*const ()>,
}

impl<'a> Recording<'a> {
    /// Wraps `cmd`, which must be in the recording state until this value is dropped.
    pub(crate) fn new(device: &'a ash::Device, cmd: vk::CommandBuffer) -> Recording<'a> {
        Recording {
            device,
            cmd,
            fills: RefCell::new(Vec::new()),
            _single_thread: PhantomData,
        }
    }

    /// Marks `fill` (a readback's) as filled by this recording: unsubmitted until
    /// [`Recording::submitted`] tells it the submission's timeline value.
    pub(crate) fn note_fill(&self, fill: &Arc<AtomicU64>) {
        fill.store(UNSUBMITTED, Ordering::Release);
        self.fills.borrow_mut().push(fill.clone());
    }

    /// Tells every readback filled by this recording that it went out as timeline `value`.
    pub(crate) fn submitted(&self, value: u64) {
        for fill in self.fills.borrow().iter() {
            fill.store(value, Ordering::Release);
        }
    }

    /// The raw command buffer, for the vk layer's own recording functions and an engine's
    /// commands between them (the shader-library example draws with its own pipeline here).
    pub fn raw(&self) -> vk::CommandBuffer {
        self.cmd
    }

    pub(crate) fn device(&self) -> &ash::Device {
        self.device
    }

    /// Dispatches `groups` workgroups of the bound compute pipeline.
    pub fn dispatch(&self, groups: [u32; 3]) {
        // SAFETY: the buffer is recording (the type's invariant); a compute pipeline whose sets
        // are bound is the caller's contract with the shader, checked by the validation layer.
        unsafe {
            self.device
                .cmd_dispatch(self.cmd, groups[0], groups[1], groups[2])
        };
    }

    /// Binds `vertices` at binding 0 and `indices` as 32-bit indices.
    pub fn bind_mesh(&self, vertices: &Buffer, indices: &Buffer) {
        // SAFETY: the buffer is recording; both buffers are alive and owned by relief.
        unsafe {
            self.device
                .cmd_bind_vertex_buffers(self.cmd, 0, &[vertices.raw()], &[0]);
            self.device
                .cmd_bind_index_buffer(self.cmd, indices.raw(), 0, vk::IndexType::UINT32);
        }
    }

    /// Draws `vertex_count` vertices without vertex buffers (the vertex shader makes them from
    /// their index), one instance.
    pub fn draw(&self, vertex_count: u32) {
        // SAFETY: the buffer is recording inside dynamic rendering (the caller's
        // `begin_rendering`); the validation layer checks the bound state.
        unsafe { self.device.cmd_draw(self.cmd, vertex_count, 1, 0, 0) };
    }

    /// Draws `index_count` indices of the bound mesh, one instance.
    pub fn draw_indexed(&self, index_count: u32) {
        // SAFETY: the buffer is recording inside dynamic rendering (the caller's
        // `begin_rendering`); the validation layer checks the bound state.
        unsafe {
            self.device
                .cmd_draw_indexed(self.cmd, index_count, 1, 0, 0, 0)
        };
    }

    /// Draws `index_count` indices of the bound index buffer from `first_index` on, once.
    pub fn draw_indexed_range(&self, index_count: u32, first_index: u32) {
        // SAFETY: as `draw_indexed`; the validation layer checks the range against the buffer.
        unsafe {
            self.device
                .cmd_draw_indexed(self.cmd, index_count, 1, first_index, 0, 0)
        };
    }

    /// Copies the whole of `src` to the start of `dst`.
    pub fn copy_buffer(&self, src: &Buffer, dst: &Buffer) {
        let size = src.size().min(dst.size());
        let region = [vk::BufferCopy {
            src_offset: 0,
            dst_offset: 0,
            size,
        }];
        // SAFETY: the buffer is recording; the region lies inside both buffers.
        unsafe {
            self.device
                .cmd_copy_buffer(self.cmd, src.raw(), dst.raw(), &region)
        };
    }

    /// Fills `size` bytes of `buffer` from `offset` with the 32-bit `word`. Both must be
    /// multiples of 4 and the range inside the buffer; otherwise nothing is recorded and the
    /// error says why (an engine recovers from an error, not from a panic).
    pub fn fill_buffer(&self, buffer: &Buffer, offset: u64, size: u64, word: u32) -> VkResult<()> {
        if offset % 4 != 0 || size % 4 != 0 {
            return Err(VkError::Invalid(format!(
                "fill of {size} bytes at {offset} in buffer {:?}: both must be multiples of 4",
                buffer.name()
            )));
        }
        buffer.check_range(offset, size, "fill")?;
        // SAFETY: the buffer is recording; the range is aligned and inside the buffer (checked
        // above).
        unsafe {
            self.device
                .cmd_fill_buffer(self.cmd, buffer.raw(), offset, size, word)
        };
        Ok(())
    }

    /// Begins dynamic rendering into `color` (cleared to `clear`) and, if given, `depth`
    /// (cleared to 1), both already in attachment layouts, with a full-target viewport.
    /// `store_depth` keeps the depth for later reads (a copy); otherwise it is discarded.
    pub fn begin_rendering(
        &self,
        color: &Image,
        depth: Option<&Image>,
        clear: [f32; 4],
        store_depth: bool,
    ) {
        self.begin_rendering_resolved(color, None, depth, clear, store_depth);
    }

    /// [`Recording::begin_rendering`] into a multisampled `color`, averaged into the
    /// single-sample `resolve` (also in the colour attachment layout) when rendering ends. The
    /// samples themselves are stored too (for a pass that reads them).
    pub fn begin_rendering_resolved(
        &self,
        color: &Image,
        resolve: Option<&Image>,
        depth: Option<&Image>,
        clear: [f32; 4],
        store_depth: bool,
    ) {
        let target = ColorTarget {
            image: color,
            resolve: resolve.map(|r| (r, vk::ResolveModeFlags::AVERAGE)),
            clear: vk::ClearColorValue { float32: clear },
        };
        self.begin_rendering_targets(&[target], depth, store_depth);
    }

    /// Begins dynamic rendering into `colors` (each cleared, stored, and resolved into its
    /// single-sample image as rendering ends when it names one) and, if given, `depth` (cleared
    /// to 1), all already in attachment layouts, with a viewport over the first colour target.
    /// `store_depth` keeps the depth for later reads (a copy); otherwise it is discarded.
    pub fn begin_rendering_targets(
        &self,
        colors: &[ColorTarget],
        depth: Option<&Image>,
        store_depth: bool,
    ) {
        let Some(first) = colors.first() else {
            return;
        };
        let (width, height) = (first.image.desc().width, first.image.desc().height);
        let color_attachment: Vec<vk::RenderingAttachmentInfo> = colors
            .iter()
            .map(|c| {
                let attachment = vk::RenderingAttachmentInfo::default()
                    .image_view(c.image.view().raw())
                    .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
                    .load_op(vk::AttachmentLoadOp::CLEAR)
                    .store_op(vk::AttachmentStoreOp::STORE)
                    .clear_value(vk::ClearValue { color: c.clear });
                match c.resolve {
                    Some((target, mode)) => attachment
                        .resolve_mode(mode)
                        .resolve_image_view(target.view().raw())
                        .resolve_image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL),
                    None => attachment,
                }
            })
            .collect();
        let depth_attachment = depth.map(|d| {
            vk::RenderingAttachmentInfo::default()
                .image_view(d.view().raw())
                .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
                .load_op(vk::AttachmentLoadOp::CLEAR)
                .store_op(if store_depth {
                    vk::AttachmentStoreOp::STORE
                } else {
                    vk::AttachmentStoreOp::DONT_CARE
                })
                .clear_value(vk::ClearValue {
                    depth_stencil: vk::ClearDepthStencilValue {
                        depth: 1.0,
                        stencil: 0,
                    },
                })
        });
        let area = vk::Rect2D {
            offset: vk::Offset2D::default(),
            extent: vk::Extent2D { width, height },
        };
        let mut info = vk::RenderingInfo::default()
            .render_area(area)
            .layer_count(1)
            .color_attachments(&color_attachment);
        if let Some(depth) = &depth_attachment {
            info = info.depth_attachment(depth);
        }
        let viewport = vk::Viewport {
            x: 0.0,
            y: 0.0,
            width: width as f32,
            height: height as f32,
            min_depth: 0.0,
            max_depth: 1.0,
        };
        // SAFETY: the buffer is recording; the attachments are alive and in the layouts named.
        unsafe {
            self.device.cmd_begin_rendering(self.cmd, &info);
            self.device.cmd_set_viewport(self.cmd, 0, &[viewport]);
            self.device.cmd_set_scissor(self.cmd, 0, &[area]);
        }
    }

    /// Draws into the `width` x `height` rectangle at (`x`, `y`) from now on: viewport and
    /// scissor alike, depth 0 to 1.
    pub fn set_viewport(&self, x: u32, y: u32, width: u32, height: u32) {
        let viewport = vk::Viewport {
            x: x as f32,
            y: y as f32,
            width: width as f32,
            height: height as f32,
            min_depth: 0.0,
            max_depth: 1.0,
        };
        let scissor = vk::Rect2D {
            offset: vk::Offset2D {
                x: x as i32,
                y: y as i32,
            },
            extent: vk::Extent2D { width, height },
        };
        // SAFETY: the buffer is recording; both states are dynamic in every graphics pipeline.
        unsafe {
            self.device.cmd_set_viewport(self.cmd, 0, &[viewport]);
            self.device.cmd_set_scissor(self.cmd, 0, &[scissor]);
        }
    }

    /// Ends the dynamic rendering begun by [`Recording::begin_rendering`].
    pub fn end_rendering(&self) {
        // SAFETY: the buffer is recording inside dynamic rendering.
        unsafe { self.device.cmd_end_rendering(self.cmd) };
    }

    /// Blits the whole colour image `src` (in `TRANSFER_SRC_OPTIMAL`) onto the whole of `dst`
    /// (in `TRANSFER_DST_OPTIMAL`), filtering linearly where the sizes differ and converting
    /// formats (sRGB decoded, then encoded). Both are images of this layer (an [`Image`] or a
    /// [`SwapchainImage`](super::SwapchainImage)), never raw handles:
    ///
    /// ```compile_fail,E0277
    /// use relief::vk::{raw, Image, Recording};
    /// fn forge(rec: &Recording, image: &Image) {
    ///     rec.blit_whole(image, &raw::Image::null());
    /// }
    /// ```
    ///
    /// ```no_run
    /// use relief::vk::{Image, Recording};
    /// fn blit(rec: &Recording, src: &Image, dst: &Image) {
    ///     rec.blit_whole(src, dst);
    /// }
    /// ```
    pub fn blit_whole(&self, src: &impl WholeImage, dst: &impl WholeImage) {
        let corner = |e: vk::Extent2D| vk::Offset3D {
            x: e.width as i32,
            y: e.height as i32,
            z: 1,
        };
        let layers = vk::ImageSubresourceLayers::default()
            .aspect_mask(vk::ImageAspectFlags::COLOR)
            .layer_count(1);
        let region = vk::ImageBlit::default()
            .src_subresource(layers)
            .src_offsets([vk::Offset3D::default(), corner(src.whole_extent())])
            .dst_subresource(layers)
            .dst_offsets([vk::Offset3D::default(), corner(dst.whole_extent())]);
        // SAFETY: the buffer is recording; both images are alive (borrowed, and kept to the end
        // of the submission by deferred destruction or the swapchain's idle wait); their
        // layouts are the caller's contract, checked by the validation layer.
        unsafe {
            self.device.cmd_blit_image(
                self.cmd,
                src.whole_raw(),
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                dst.whole_raw(),
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &[region],
                vk::Filter::LINEAR,
            )
        };
    }
}
