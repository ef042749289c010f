//! Why a frame could not be rendered: the one error type every pass folder returns.

use crate::environment::EnvironmentError;
use crate::heightfield::HeightfieldError;
use crate::render::kit::graph::GraphError;
use crate::render::plan::frame_plan::PlanError;
use crate::vk::VkError;

/// Why a frame could not be rendered.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// The scene cannot be planned.
    #[error(transparent)]
    Plan(#[from] PlanError),
    /// The frame's passes do not form a graph that can be recorded.
    #[error("the frame's passes: {0}")]
    Graph(#[from] GraphError),
    /// A height map cannot be read, or exceeds the device's largest image.
    #[error(transparent)]
    Height(#[from] HeightfieldError),
    /// The environment image cannot be read or used.
    #[error(transparent)]
    Environment(#[from] EnvironmentError),
    /// A Vulkan call failed, or the device lacks something the frame needs.
    #[error(transparent)]
    Vulkan(#[from] VkError),
    /// The ray-traced path was asked for on a device without ray queries.
    #[error("{device} has no ray queries (VK_KHR_ray_query and VK_KHR_acceleration_structure); the traced path needs them")]
    NoRayQueries {
        /// The device's name.
        device: String,
    },
    /// The ray-traced path cannot take this scene as it is; the message says why.
    #[error("ray-traced path: {0}")]
    Traced(String),
    /// A mesh selected by `--cells` cannot be turned into a cell complex.
    #[error(transparent)]
    Cells(#[from] crate::cells::MeshError),
    /// A layered material's textures cannot be blended or painted; the message says why.
    #[error("layered material: {0}")]
    Layers(String),
    /// A paint stroke is invalid.
    #[error("paint: {0}")]
    Stroke(#[from] crate::terrain::StrokeError),
    #[error("--cells {name:?}: its maps take {mib} MiB in one storage buffer, more than this device's {limit_mib} MiB; lower --cells-resolution or --cells-max-grid")]
    /// A cell complex's maps or attributes exceed the device's storage buffer range
    /// (`maxStorageBufferRange`).
    CellsBufferTooLarge {
        /// The `--cells` mesh name.
        name: String,
        /// Size of its largest buffer, in MiB.
        mib: u64,
        /// The device's limit, in MiB.
        limit_mib: u64,
    },
    #[error("--cells {name:?}: {source}; lower --cells-grid or --cells-resolution")]
    /// A cell complex's fixed grid would take more memory than the cells module allows.
    CellsTooLarge {
        /// The `--cells` mesh name.
        name: String,
        /// Which limit the grid exceeds.
        source: crate::cells::GridTooLarge,
    },
}
