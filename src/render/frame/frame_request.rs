//! What a frame is asked for and what comes back of it.

use super::gbuffer::GBufferChannels;
use super::work_counters::WorkCounts;
use crate::render::kit::frame_timeline::FrameTimeline;
use crate::render::kit::pass_timer::PassTiming;
use crate::scene::Camera;

/// What one frame draws: [`FrameRequest::new`] and the `with_*` setters.
#[derive(Debug, Clone)]
#[non_exhaustive]
pub struct FrameRequest {
    /// The view; the image's aspect ratio comes from the renderer's size.
    pub camera: Camera,
    /// Copy the colour image back to the host (for writing it out).
    pub read_back: bool,
}

impl FrameRequest {
    /// A frame seen through `camera`, read back.
    pub fn new(camera: Camera) -> FrameRequest {
        FrameRequest {
            camera,
            read_back: true,
        }
    }
}

with_setters!(FrameRequest {
    with_camera => camera: Camera,
    with_read_back => read_back: bool,
});

/// A finished frame: its GPU time per pass and, when asked for, its pixels.
#[derive(Debug, Clone)]
pub struct FrameOutput {
    /// 0 for the renderer's first frame.
    pub index: u64,
    /// GPU time of each pass the frame recorded.
    pub timings: Vec<PassTiming>,
    /// sRGB RGBA8, rows top to bottom.
    pub rgba: Option<Vec<u8>>,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Surface draws skipped because the view could not see their bounds.
    pub culled_draws: usize,
    /// With a shadow probe and a read-back, each pixel's depth (rows top to bottom).
    pub depth: Option<Vec<f32>>,
    /// With `RenderOptions::keep_radiance` and a read-back, each pixel's linear radiance before
    /// exposure and tone mapping, RGBA (rows top to bottom).
    pub radiance: Option<Vec<[f32; 4]>>,
    /// With `RenderOptions::gbuffer` and a read-back, the surface pass's G-buffer.
    pub gbuffer: Option<GBufferChannels>,
    /// What the host and the GPU did for the frame, on the host's clock.
    pub timeline: FrameTimeline,
    /// With `RenderOptions::count_work`, the relief fragments traced and their steps per pixel.
    pub work: Option<WorkCounts>,
}
