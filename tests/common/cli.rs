//! Running the `relief` binary, and what every failing command line must look like.

use std::process::{Command, Output};

/// Runs the `relief` binary built with the tests with `args`, to completion.
pub fn relief(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_relief"))
        .args(args)
        .output()
        .expect("binary runs")
}

/// Asserts that the command failed cleanly: exit code 1, no panic, and exactly one
/// `relief: error:` line, which names every one of `needles`.
pub fn assert_clean_failure(out: &Output, needles: &[&str]) {
    assert_failure_with(out, 1, needles);
}

/// Asserts that the command was refused as bad usage found after parsing (a bad value or a bad
/// combination of flags): exit code 2, no panic, and exactly one `relief: error:` line naming
/// every one of `needles`.
pub fn assert_usage_failure(out: &Output, needles: &[&str]) {
    assert_failure_with(out, 2, needles);
}

fn assert_failure_with(out: &Output, code: i32, needles: &[&str]) {
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(
        out.status.code(),
        Some(code),
        "exit code {code} expected; stderr:\n{err}"
    );
    assert!(!err.contains("panicked"), "must not panic:\n{err}");
    let lines: Vec<&str> = err
        .lines()
        .filter(|l| l.starts_with("relief: error:"))
        .collect();
    assert_eq!(lines.len(), 1, "exactly one error line expected:\n{err}");
    for needle in needles {
        assert!(
            lines[0].contains(needle),
            "the error names {needle:?}: {}",
            lines[0]
        );
    }
}

/// Runs `relief args` for a test that needs a Vulkan device with ray queries: `None` (the test
/// says it skipped) without a device, or without ray queries outside CI; CI's lavapipe has them.
pub fn relief_with_ray_queries(args: &[&str]) -> Option<Output> {
    let out = relief(args);
    let stderr = String::from_utf8_lossy(&out.stderr);
    if out.status.code() == Some(77) {
        eprintln!("SKIPPED: no Vulkan device: {stderr}");
        return None;
    }
    if stderr.contains("has no ray queries") {
        assert!(
            !super::under_ci(),
            "CI's lavapipe has ray queries: {stderr}"
        );
        eprintln!("SKIPPED: no ray queries: {stderr}");
        return None;
    }
    Some(out)
}
