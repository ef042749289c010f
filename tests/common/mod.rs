//! Shared test plumbing: a device per test (skipped loudly without one, failing under CI), a
//! validation check at teardown, and image comparison with written evidence.
#![allow(dead_code)]

pub mod base64;
#[cfg(feature = "cli")]
pub mod cli;
pub mod corpus;
pub mod displaced;
pub mod golden;
pub mod mesh_gltf;
pub mod npy;
pub mod plane_gltf;
pub mod rays;
pub mod soak;
pub mod srgb;
pub mod terrain;
pub mod xvfb;

use std::path::PathBuf;
use std::sync::Arc;

use relief::vk::{Context, ContextOptions, VkError};

/// Whether a missing device must fail the test (`CI=true` or `RELIEF_REQUIRE_GPU=1`).
pub fn device_required() -> bool {
    under_ci() || std::env::var("RELIEF_REQUIRE_GPU").is_ok_and(|v| v == "1")
}

/// Whether the tests run under CI (`CI=true` or `CI=1`), where checks must not pass vacuously.
pub fn under_ci() -> bool {
    std::env::var("CI").is_ok_and(|v| v == "true" || v == "1")
}

/// Whether a "zero validation errors" check means anything: under CI it must, so a missing
/// validation layer is an error there; elsewhere the check is skipped (the layer is optional).
pub fn validation_check(ci: bool, validation_enabled: bool) -> Result<(), String> {
    if ci && !validation_enabled {
        return Err("the Khronos validation layer is not loaded, so validation checks would pass \
                    vacuously under CI; install it with: sudo apt-get install vulkan-validationlayers \
                    (and do not set RELIEF_VALIDATION=0 or test a release build)"
            .into());
    }
    Ok(())
}

/// Panics when [`validation_check`] says this context's validation checks would be vacuous.
pub fn require_validation(ctx: &Context) {
    if let Err(why) = validation_check(under_ci(), ctx.validation_enabled()) {
        panic!("{why}");
    }
}

/// A fresh device context, or `None` (after printing SKIPPED) when none exists and none is required.
/// Under CI the context must have the validation layer loaded.
pub fn device(test: &str) -> Option<Arc<Context>> {
    device_with(test, &ContextOptions::default())
}

/// [`device`] with ray queries, or `None` (the test says it skipped) on a device without them;
/// under CI, whose lavapipe has them, their absence fails the test.
pub fn ray_query_device(test: &str) -> Option<Arc<Context>> {
    let ctx = device(test)?;
    if !ctx.info().ray_query {
        assert!(
            !under_ci(),
            "{test}: CI's lavapipe has ray queries; {} has none",
            ctx.info().name
        );
        eprintln!("SKIPPED: {} has no ray queries ({test})", ctx.info().name);
        return None;
    }
    Some(ctx)
}

/// [`device`] with explicit options.
pub fn device_with(test: &str, options: &ContextOptions) -> Option<Arc<Context>> {
    match Context::new(options) {
        Ok(ctx) => {
            require_validation(&ctx);
            Some(ctx)
        }
        Err(e @ (VkError::NoDevice | VkError::Loader(_))) if !device_required() => {
            eprintln!("SKIPPED: no Vulkan device ({test}): {e}");
            None
        }
        Err(e) => panic!("{test}: cannot create a Vulkan device: {e}"),
    }
}

/// Asserts the validation layer reported no errors during the test (and, under CI, that it was
/// loaded at all).
pub fn assert_no_validation_errors(ctx: &Context) {
    require_validation(ctx);
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
