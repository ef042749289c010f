//! Faults a context feigns on request, so tests can drive relief's error paths on a healthy
//! device: the k-th memory allocation fails as out of device memory, the k-th queue submission
//! reports the device lost, or the k-th submission is silently not made, so its fence never
//! signals and the waiter meets the GPU timeout ([`VkError::Hang`]).
//!
//! Asked for with [`ContextOptions::faults`](super::ContextOptions::faults) or, for a child
//! process such as the `relief` binary, the environment variable [`FAULTS_ENV`]
//! (`alloc=K`, `lost=K`, `hang=K`, comma-separated; counts start at 1), read once when the
//! context is made. Without either, each hook costs one relaxed atomic add.

use std::sync::atomic::{AtomicU64, Ordering};

use super::error::{VkError, VkResult};

/// The environment variable holding the faults to feign (see the module docs).
pub const FAULTS_ENV: &str = "RELIEF_FAULTS";

/// Which operations fail; each count is 1-based over the context's lifetime.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Faults {
    /// This memory allocation (buffer or image) fails as out of device memory.
    pub fail_allocation: Option<u64>,
    /// This queue submission fails with `VK_ERROR_DEVICE_LOST`.
    pub lose_device_at_submission: Option<u64>,
    /// This queue submission is not made, so its fence never signals.
    pub hang_at_submission: Option<u64>,
}

impl Faults {
    /// Parses `alloc=K,lost=K,hang=K` (any subset, any order; empty: none).
    pub fn parse(text: &str) -> VkResult<Faults> {
        let mut faults = Faults::default();
        for item in text.split(',').map(str::trim).filter(|s| !s.is_empty()) {
            let bad = || {
                VkError::Invalid(format!(
                    "{FAULTS_ENV}={text:?}: {item:?} is not alloc=K, lost=K or hang=K with K >= 1"
                ))
            };
            let (key, value) = item.split_once('=').ok_or_else(bad)?;
            let k: u64 = value
                .trim()
                .parse()
                .ok()
                .filter(|&k| k >= 1)
                .ok_or_else(bad)?;
            let slot = match key.trim() {
                "alloc" => &mut faults.fail_allocation,
                "lost" => &mut faults.lose_device_at_submission,
                "hang" => &mut faults.hang_at_submission,
                _ => return Err(bad()),
            };
            *slot = Some(k);
        }
        Ok(faults)
    }

    /// The faults [`FAULTS_ENV`] asks for (none when unset).
    pub fn from_env() -> VkResult<Faults> {
        std::env::var(FAULTS_ENV).map_or(Ok(Faults::default()), |v| Faults::parse(&v))
    }
}

/// What a submission should do instead of being made.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum SubmitFault {
    LoseDevice,
    Hang,
}

/// The faults of one context and the operations counted so far.
#[derive(Debug, Default)]
pub(crate) struct FaultPlan {
    faults: Faults,
    allocations: AtomicU64,
    submissions: AtomicU64,
}

impl FaultPlan {
    pub(crate) fn new(faults: Faults) -> FaultPlan {
        FaultPlan {
            faults,
            ..FaultPlan::default()
        }
    }

    /// Counts an allocation; `Err` when this one is to fail.
    pub(crate) fn allocation(&self) -> VkResult<()> {
        let k = self.allocations.fetch_add(1, Ordering::Relaxed) + 1;
        if self.faults.fail_allocation == Some(k) {
            return Err(VkError::from_call(
                "vkAllocateMemory",
                ash::vk::Result::ERROR_OUT_OF_DEVICE_MEMORY,
            ));
        }
        Ok(())
    }

    /// Counts a submission; what it should do instead of being made, if anything.
    pub(crate) fn submission(&self) -> Option<SubmitFault> {
        let k = self.submissions.fetch_add(1, Ordering::Relaxed) + 1;
        if self.faults.lose_device_at_submission == Some(k) {
            Some(SubmitFault::LoseDevice)
        } else if self.faults.hang_at_submission == Some(k) {
            Some(SubmitFault::Hang)
        } else {
            None
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_each_fault_and_refuses_the_rest_by_name() {
        let f = Faults::parse("alloc=3, hang=2,lost=7").unwrap();
        assert_eq!(
            f,
            Faults {
                fail_allocation: Some(3),
                lose_device_at_submission: Some(7),
                hang_at_submission: Some(2),
            }
        );
        assert_eq!(Faults::parse("").unwrap(), Faults::default());
        for bad in ["alloc", "alloc=0", "lost=-1", "melt=2", "hang=x"] {
            let e = Faults::parse(bad).unwrap_err().to_string();
            assert!(e.contains(FAULTS_ENV) && e.contains(bad), "{e}");
        }
    }

    #[test]
    fn the_kth_operation_fails_and_only_it() {
        let plan = FaultPlan::new(Faults::parse("alloc=2,lost=3,hang=1").unwrap());
        assert!(plan.allocation().is_ok());
        assert!(matches!(
            plan.allocation(),
            Err(VkError::OutOfMemory { .. })
        ));
        assert!(plan.allocation().is_ok());
        assert_eq!(plan.submission(), Some(SubmitFault::Hang));
        assert_eq!(plan.submission(), None);
        assert_eq!(plan.submission(), Some(SubmitFault::LoseDevice));
        assert_eq!(plan.submission(), None);
    }
}
