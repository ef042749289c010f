#!/usr/bin/env bash
# Renders the built-in default scene to frame.png (or the file given as $1) in the folder it is
# run from, installing what relief needs first. Extra arguments go to `relief render`.
set -euo pipefail
out=${1:-frame.png}
shift || true
# The path is the caller's: made absolute before the script moves to the checkout to build.
[[ $out == /* ]] || out="$PWD/$out"
cd "$(dirname "$0")/.."
scripts/setup.sh
cargo run --release --quiet -- render --out "$out" "$@"
