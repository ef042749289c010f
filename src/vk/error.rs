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
    NoMatchingDevice {
        /// The substring asked for.
        wanted: String,
        /// The devices there are, for the message.
        available: String,
    },
    /// The device was lost (driver crash, GPU reset, hardware removed); nothing on it can be used
    /// any more.
    #[error(
        "{call} failed: the GPU device was lost (driver crash, GPU reset or removal); \
         nothing more can run on it"
    )]
    DeviceLost {
        /// The Vulkan call that reported it.
        call: &'static str,
    },
    /// The driver ran out of device or host memory.
    #[error("{call} failed: out of {memory} memory ({result}); try smaller maps or images")]
    OutOfMemory {
        /// The Vulkan call that failed.
        call: &'static str,
        /// "device" (GPU) or "host" (CPU).
        memory: &'static str,
        /// The driver's result code.
        result: vk::Result,
    },
    /// Submitted work did not finish within the GPU timeout (`RELIEF_GPU_TIMEOUT_S`).
    #[error(
        "the GPU did not finish {what} within {seconds} s \
         (a hang, or slow work: raise RELIEF_GPU_TIMEOUT_S)"
    )]
    Hang {
        /// What the GPU was doing.
        what: String,
        /// The limit that passed.
        seconds: f64,
    },
    /// A Vulkan call returned an error code.
    #[error("{call} failed: {result}")]
    Call {
        /// The Vulkan call.
        call: &'static str,
        /// Its result code.
        result: vk::Result,
    },
    /// gpu-allocator could not place an allocation. (`reason` is not a `source`: the message
    /// already holds it, and `{:#}` would print it twice.)
    #[error("GPU memory allocation for {name:?} failed: {reason}")]
    Allocation {
        /// The debug name of the buffer or image.
        name: String,
        /// gpu-allocator's reason.
        reason: gpu_allocator::AllocationError,
    },
    /// Creating a named object failed; `reason` says how (e.g. the driver's out of memory).
    #[error("{kind} {name:?}: {reason}")]
    Object {
        /// What kind of object ("buffer", "image").
        kind: &'static str,
        /// Its debug name.
        name: String,
        /// Why creating it failed.
        reason: Box<VkError>,
    },
    /// gpu-allocator could not be set up for the device (its own reason is kept).
    #[error("creating the GPU memory allocator failed: {reason}")]
    AllocatorSetup {
        /// gpu-allocator's reason.
        reason: gpu_allocator::AllocationError,
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
        self.map_err(|result| VkError::from_call(call, result))
    }
}

impl VkError {
    /// This error, saying which object (`kind` and debug name) was being created.
    pub fn for_object(self, kind: &'static str, name: &str) -> VkError {
        VkError::Object {
            kind,
            name: name.to_owned(),
            reason: Box::new(self),
        }
    }

    /// The error for `call` returning `result`: device loss and exhausted memory get their own
    /// variants (they need different advice), every other code stays a plain [`VkError::Call`].
    pub fn from_call(call: &'static str, result: vk::Result) -> VkError {
        match result {
            vk::Result::ERROR_DEVICE_LOST => VkError::DeviceLost { call },
            vk::Result::ERROR_OUT_OF_DEVICE_MEMORY => VkError::OutOfMemory {
                call,
                memory: "device",
                result,
            },
            vk::Result::ERROR_OUT_OF_HOST_MEMORY => VkError::OutOfMemory {
                call,
                memory: "host",
                result,
            },
            _ => VkError::Call { call, result },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn device_lost_has_its_own_variant_and_message() {
        let e = VkError::from_call("vkQueueSubmit", vk::Result::ERROR_DEVICE_LOST);
        assert!(matches!(
            e,
            VkError::DeviceLost {
                call: "vkQueueSubmit"
            }
        ));
        let text = e.to_string();
        assert!(
            text.contains("vkQueueSubmit") && text.contains("device was lost"),
            "{text}"
        );
    }

    #[test]
    fn out_of_memory_says_which_memory() {
        let device = VkError::from_call("vkAllocateMemory", vk::Result::ERROR_OUT_OF_DEVICE_MEMORY);
        assert!(matches!(
            device,
            VkError::OutOfMemory {
                memory: "device",
                ..
            }
        ));
        assert!(
            device.to_string().contains("out of device memory"),
            "{device}"
        );
        let host = VkError::from_call("vkCreateFence", vk::Result::ERROR_OUT_OF_HOST_MEMORY);
        assert!(matches!(host, VkError::OutOfMemory { memory: "host", .. }));
        assert!(
            host.to_string()
                .contains("vkCreateFence failed: out of host memory"),
            "{host}"
        );
    }

    #[test]
    fn other_codes_stay_plain_calls() {
        let e = Err::<(), _>(vk::Result::ERROR_INITIALIZATION_FAILED).named("vkCreateDevice");
        assert!(matches!(
            e,
            Err(VkError::Call {
                call: "vkCreateDevice",
                result: vk::Result::ERROR_INITIALIZATION_FAILED
            })
        ));
    }

    #[test]
    fn object_errors_name_the_object_and_keep_the_reason() {
        let e = VkError::from_call("vkCreateBuffer", vk::Result::ERROR_OUT_OF_DEVICE_MEMORY)
            .for_object("buffer", "trace hits");
        let text = e.to_string();
        assert!(
            text.starts_with("buffer \"trace hits\": vkCreateBuffer failed: out of device memory"),
            "{text}"
        );
    }

    #[test]
    fn hang_names_the_work_and_the_limit() {
        let e = VkError::Hang {
            what: "the cone map".into(),
            seconds: 600.0,
        };
        assert!(
            e.to_string()
                .starts_with("the GPU did not finish the cone map within 600 s"),
            "{e}"
        );
    }
}
