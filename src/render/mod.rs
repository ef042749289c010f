//! The frame: joins height fields and scenes with the Vulkan layer. Uploads, the pyramid pass,
//! the surface pass, timestamps around each, and readback to an image.

mod bench_pass;
mod frame;
mod gpu_heightfield;
mod height_resources;
mod method_map;
mod pyramid_pass;
mod surface_pass;
mod trace_pass;

pub use bench_pass::{time_method, BenchRequest, BenchTiming};
pub use frame::{render, Frame, PassTiming, RenderOptions};
pub use gpu_heightfield::{Addressing, GpuHeightfield, HeightFormat};
pub use height_resources::HeightResources;
pub use method_map::{GpuMethodMap, MapData};
pub use pyramid_pass::{build_pyramid_on_gpu, PyramidJob, PyramidPass};
pub use surface_pass::{FrameUniforms, COLOR_FORMAT, DEPTH_FORMAT};
pub use trace_pass::{trace_on_gpu, TraceOutput, TraceRequest};
