//! Typed errors for the Vulkan layer: every failing call is named, so a user sees which step broke.

use ash::vk;

/// Everything that can go wrong below `relief::vk`.
#[derive(Debug, thiserror::Error)]
pub enum VkError {
    /// The Vulkan loader library (`libvulkan.so.1`) could not be opened.
    #[error(
        "the Vulkan loader could not be loaded ({0}); install it with: \
         sudo apt-get install libvulkan1 mesa-vulkan-drivers"
    )]
    Loader(String),
    /// The loader works but no physical device is present (no driver, not even lavapipe).
    #[error(
        "no Vulkan device found; for a software device install lavapipe with: \
         sudo apt-get install mesa-vulkan-drivers"
    )]
    NoDevice,
    /// `--device SUBSTRING` matched nothing.
    #[error("no Vulkan device matches {wanted:?}; available: {available}")]
    NoMatchingDevice { wanted: String, available: String },
    /// A Vulkan call returned an error code.
    #[error("{call} failed: {result}")]
    Call {
        call: &'static str,
        result: vk::Result,
    },
    /// gpu-allocator could not place an allocation.
    #[error("GPU memory allocation for {name:?} failed: {source}")]
    Allocation {
        name: String,
        source: gpu_allocator::AllocationError,
    },
    /// The device lacks something relief needs (a format feature, timestamps, ...).
    #[error("the device does not support {0}")]
    Unsupported(String),
    /// A request the caller should not have made (sizes, ranges).
    #[error("invalid request: {0}")]
    Invalid(String),
}

/// Result alias for the Vulkan layer.
pub type VkResult<T> = Result<T, VkError>;

/// Attaches the name of the Vulkan call to a raw `vk::Result`.
pub(crate) trait Named<T> {
    fn named(self, call: &'static str) -> VkResult<T>;
}

impl<T> Named<T> for Result<T, vk::Result> {
    fn named(self, call: &'static str) -> VkResult<T> {
        self.map_err(|result| VkError::Call { call, result })
    }
}
