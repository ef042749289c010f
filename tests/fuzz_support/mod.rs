//! What the parser fuzz tests share: an allocation counter, a bounded runner, mutations of
//! valid inputs and the seeds they start from.
#![allow(dead_code)]

pub mod alloc_cap;
pub mod bounded;
pub mod gltf_seed;
pub mod mutate;
pub mod png_seed;

use std::path::PathBuf;
use std::sync::atomic::{AtomicU32, Ordering};

use proptest::test_runner::{Config, FileFailurePersistence};

/// Cases a property runs: `PROPTEST_CASES` when set (long runs), else `default`, sized so the
/// whole file stays well under a minute in a debug build on two cores.
pub fn config(default: u32) -> Config {
    let cases = std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default);
    Config {
        cases,
        // Failures become named regression tests in the test file, not files beside it.
        failure_persistence: Some(Box::new(FileFailurePersistence::Off)),
        ..Config::default()
    }
}

/// A fresh path in a scratch folder for one case's input.
pub fn case_file(folder: &std::path::Path, ext: &str) -> PathBuf {
    static NEXT: AtomicU32 = AtomicU32::new(0);
    folder.join(format!(
        "case-{}.{ext}",
        NEXT.fetch_add(1, Ordering::Relaxed)
    ))
}
