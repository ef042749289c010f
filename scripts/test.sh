#!/usr/bin/env bash
# Runs the whole test suite on whatever Vulkan device is present (lavapipe without a GPU),
# installing what relief needs first. With CI=true a missing device fails the tests.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
cargo fmt --all -- --check
cargo clippy --all-targets --quiet -- -D warnings
cargo test --all-targets "$@"
# --all-targets leaves out doctests; they hold the compile_fail checks that safe code cannot
# record into a command buffer outside a submission nor hand relief::vk a raw Vulkan handle.
if (($# == 0)); then
    cargo test --doc
fi
