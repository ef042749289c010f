//! Failures below `relief::vk` end in errors that say what happened: a GPU that does not finish
//! in time, memory that cannot be had (with the allocator's own reason and the buffer's name).
#![deny(clippy::undocumented_unsafe_blocks)]

mod common;

use std::time::Duration;

use relief::vk::{raw as vk, Buffer, ContextOptions, MemoryLocation, VkError};

#[test]
fn fence_wait_past_the_timeout_is_a_hang_error() {
    let options = ContextOptions::default().with_gpu_timeout(Some(Duration::from_millis(20)));
    let Some(ctx) = common::device_with("fence_wait_past_the_timeout_is_a_hang_error", &options)
    else {
        return;
    };
    assert_eq!(ctx.gpu_timeout(), Duration::from_millis(20));
    // SAFETY: a plain unsignalled fence on this device, destroyed below; it is never submitted.
    let fence = unsafe {
        ctx.device()
            .create_fence(&vk::FenceCreateInfo::default(), None)
    }
    .expect("fence");
    // SAFETY: the fence was created above on this context's device and is destroyed below.
    let e = unsafe { ctx.wait_fence(fence, "the never-signalled test fence") }
        .expect_err("the fence is never signalled");
    assert!(matches!(e, VkError::Hang { .. }), "{e:?}");
    let text = e.to_string();
    assert!(
        text.starts_with("the GPU did not finish the never-signalled test fence within 0.02 s"),
        "{text}"
    );
    // SAFETY: as above.
    let e = unsafe { ctx.wait_fence_within(fence, "again", Duration::from_millis(1)) }
        .expect_err("still unsignalled");
    assert!(e.to_string().contains("within 0.001 s"), "{e}");
    // SAFETY: the fence was never submitted, so nothing uses it.
    unsafe { ctx.device().destroy_fence(fence, None) };
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn absurd_buffer_fails_with_the_allocators_reason_and_its_name() {
    let Some(ctx) = common::device("absurd_buffer_fails_with_the_allocators_reason_and_its_name")
    else {
        return;
    };
    let result = Buffer::new(
        &ctx,
        1 << 50,
        vk::BufferUsageFlags::STORAGE_BUFFER,
        MemoryLocation::GpuOnly,
        "absurd test buffer",
    );
    let e = result.err().expect("a petabyte buffer cannot be allocated");
    let text = e.to_string();
    assert!(
        text.contains("absurd test buffer"),
        "names the buffer: {text}"
    );
    // The driver may refuse the buffer itself (lavapipe does) or the allocator its memory.
    let reason = match &e {
        VkError::Allocation { reason, .. } => reason.to_string(),
        VkError::Object { reason, .. } => {
            assert!(
                matches!(**reason, VkError::OutOfMemory { .. }),
                "{reason:?}"
            );
            reason.to_string()
        }
        other => panic!("expected an allocation error, got {other:?}"),
    };
    assert!(text.contains(&reason), "keeps the reason: {text}");
    common::assert_no_validation_errors(&ctx);
}
