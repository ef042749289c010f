#!/usr/bin/env bash
# Runs the whole test suite on whatever Vulkan device is present (lavapipe without a GPU),
# installing what relief needs first. With CI=true a missing device fails the tests.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
cargo fmt --all -- --check
cargo clippy --all-targets --quiet -- -D warnings

# The library without its default features is what an engine depends on: it must not pull in the
# command line or the window system, even through another crate.
lean_tree=$(cargo tree --no-default-features -e normal --prefix none)
heavy=$(grep -E '^(clap|indicatif|winit|exr) ' <<<"$lean_tree" | sort -u || true)
if [[ -n $heavy ]]; then
    echo "relief test: the library without default features depends on:" >&2
    echo "$heavy" >&2
    echo "clap, indicatif and exr belong behind the cli feature, winit behind window (see Cargo.toml)" >&2
    exit 1
fi

# tests/examples.rs runs the examples' own binaries, which `cargo test` builds only as test harnesses.
cargo build --examples --quiet
cargo test --all-targets "$@"
if (($# == 0)); then
    # --all-targets leaves out doctests; they hold the compile_fail checks that safe code cannot
    # record into a command buffer outside a submission nor hand relief::vk a raw Vulkan handle,
    # and the guide's frame render.
    cargo test --doc
    RUSTDOCFLAGS="-D warnings" cargo doc --no-deps --lib
    # The SPIR-V the package ships, written by this build (glslang compiles it).
    RELIEF_WRITE_PREBUILT_SPIRV="$PWD/prebuilt-spirv" cargo build --lib --quiet
    # A dependent with default-features = false must not build glslang, even indirectly.
    if cargo tree --no-default-features -e normal,build --prefix none | grep -q '^glslang'; then
        echo "relief test: the library without default features still builds glslang" >&2
        exit 1
    fi
    # The crate as it would be published: packaged, then built from the package alone as that
    # dependent builds it, without glslang, from the prebuilt SPIR-V (whose fingerprint the build
    # checks against the packaged shader sources). --allow-dirty lets a working tree with
    # uncommitted edits run it.
    cargo package --allow-dirty --quiet --no-default-features
    if ! cargo package --list --allow-dirty | grep -qx 'prebuilt-spirv/manifest.txt'; then
        echo "relief test: the package does not carry prebuilt-spirv/" >&2
        exit 1
    fi
    # The package's build shares this target folder and relief's artifact names, and leaves its
    # fingerprints behind: without this, the next `cargo build` here would take the package's
    # binary for an up-to-date build of the working tree.
    cargo clean --package relief --quiet
    rm -rf prebuilt-spirv
fi
