//! Shared test plumbing: a device per test (skipped loudly without one, failing under CI), a
//! validation check at teardown, and image comparison with written evidence.
#![allow(dead_code)]

pub mod base64;
pub mod corpus;
pub mod golden;

use std::path::PathBuf;
use std::sync::Arc;

use relief::vk::{Context, ContextOptions, VkError};

/// Whether a missing device must fail the test (`CI=true` or `RELIEF_REQUIRE_GPU=1`).
pub fn device_required() -> bool {
    std::env::var("CI").is_ok_and(|v| v == "true" || v == "1")
        || std::env::var("RELIEF_REQUIRE_GPU").is_ok_and(|v| v == "1")
}

/// A fresh device context, or `None` (after printing SKIPPED) when none exists and none is required.
pub fn device(test: &str) -> Option<Arc<Context>> {
    match Context::new(&ContextOptions::default()) {
        Ok(ctx) => Some(ctx),
        Err(e @ (VkError::NoDevice | VkError::Loader(_))) if !device_required() => {
            eprintln!("SKIPPED: no Vulkan device ({test}): {e}");
            None
        }
        Err(e) => panic!("{test}: cannot create a Vulkan device: {e}"),
    }
}

/// Asserts the validation layer reported no errors during the test.
pub fn assert_no_validation_errors(ctx: &Context) {
    let messages = ctx.messages();
    assert_eq!(
        messages.errors(),
        0,
        "validation errors were reported:\n{}",
        messages.kept_messages().join("\n")
    );
}

/// A folder under `target/` for evidence a failing test leaves behind.
pub fn evidence_dir(kind: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("target")
        .join("test-output")
        .join(kind);
    std::fs::create_dir_all(&dir).expect("target/ is writable");
    dir
}

/// A fresh scratch folder for one test.
pub fn scratch_dir(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("relief-test-{}-{test}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir is writable");
    dir
}
