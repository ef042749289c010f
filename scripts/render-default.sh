#!/usr/bin/env bash
# Renders the built-in default scene to frame.png (or the file given as $1), installing what
# relief needs first. Extra arguments go to `relief render`.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
out=${1:-frame.png}
shift || true
cargo run --release --quiet -- render --out "$out" "$@"
