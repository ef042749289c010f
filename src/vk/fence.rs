//! Waiting for the GPU with a limit: every fence wait in relief goes through [`Context::wait_fence`],
//! so a hung or lost device ends in an error that says what it was doing instead of a process that
//! waits forever.
//!
//! The limit is generous by default (lavapipe's longest single submission, a 4096^2 cone map chunk,
//! takes about a minute on two cores) and can be set with `RELIEF_GPU_TIMEOUT_S`.

use std::time::Duration;

use ash::vk;

use super::context::Context;
use super::error::{Named, VkError, VkResult};

/// The environment variable that overrides [`DEFAULT_GPU_TIMEOUT`], in (fractional) seconds.
pub const GPU_TIMEOUT_ENV: &str = "RELIEF_GPU_TIMEOUT_S";
/// How long one submission may take before relief calls it a hang.
pub const DEFAULT_GPU_TIMEOUT: Duration = Duration::from_secs(600);

/// The GPU timeout for a value of `RELIEF_GPU_TIMEOUT_S` (`None`: unset, the default).
pub fn gpu_timeout_from(value: Option<&str>) -> VkResult<Duration> {
    let Some(text) = value else {
        return Ok(DEFAULT_GPU_TIMEOUT);
    };
    match text.trim().parse::<f64>() {
        Ok(s) if s.is_finite() && s > 0.0 => Ok(Duration::from_secs_f64(s)),
        _ => Err(VkError::Invalid(format!(
            "{GPU_TIMEOUT_ENV}={text:?}: expected a positive number of seconds"
        ))),
    }
}

/// The GPU timeout from the environment (see [`gpu_timeout_from`]).
pub fn gpu_timeout_from_env() -> VkResult<Duration> {
    gpu_timeout_from(std::env::var(GPU_TIMEOUT_ENV).ok().as_deref())
}

impl Context {
    /// Waits until `fence` is signalled, at most the context's GPU timeout
    /// ([`Context::gpu_timeout`]). `what` names the work for the error, e.g. "the cone map".
    ///
    /// Returns [`VkError::Hang`] when the limit passes and [`VkError::DeviceLost`] when the device
    /// is lost. After a hang the fence and whatever its submission uses are still pending: the
    /// caller must not destroy them (the context stops tearing down the device, see `Drop`).
    ///
    /// # Safety
    /// `fence` is a live fence of this context's device (it takes a raw handle, which safe code
    /// could otherwise forge).
    pub unsafe fn wait_fence(&self, fence: vk::Fence, what: &str) -> VkResult<()> {
        // SAFETY: the caller's contract.
        unsafe { self.wait_fence_within(fence, what, self.gpu_timeout()) }
    }

    /// [`Context::wait_fence`] with an explicit limit.
    ///
    /// # Safety
    /// As [`Context::wait_fence`].
    pub unsafe fn wait_fence_within(
        &self,
        fence: vk::Fence,
        what: &str,
        timeout: Duration,
    ) -> VkResult<()> {
        let nanos = u64::try_from(timeout.as_nanos()).unwrap_or(u64::MAX);
        // SAFETY: a live fence of this device (the caller's contract); waiting needs no external
        // sync.
        match unsafe { self.device().wait_for_fences(&[fence], true, nanos) } {
            Err(vk::Result::TIMEOUT) => {
                self.mark_hung();
                Err(VkError::Hang {
                    what: what.to_owned(),
                    seconds: timeout.as_secs_f64(),
                })
            }
            other => other.named("vkWaitForFences"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unset_timeout_is_the_generous_default() {
        assert_eq!(gpu_timeout_from(None).unwrap(), Duration::from_secs(600));
    }

    #[test]
    fn timeout_reads_fractional_seconds() {
        assert_eq!(
            gpu_timeout_from(Some(" 2.5 ")).unwrap(),
            Duration::from_millis(2500)
        );
    }

    #[test]
    fn nonsense_timeouts_are_refused_with_the_variable_named() {
        for bad in ["", "soon", "0", "-3", "inf", "NaN"] {
            let e = gpu_timeout_from(Some(bad)).unwrap_err().to_string();
            assert!(e.contains(GPU_TIMEOUT_ENV), "{bad:?}: {e}");
        }
    }
}
