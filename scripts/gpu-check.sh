#!/usr/bin/env bash
# The GPU check: what a machine with a real GPU runs once to put its figures beside lavapipe's.
# Prints the device, then measures with `relief bench`: how QDM and POM scale with map size (fbm,
# 256^2 to 4096^2, 30 degrees) and quadric tracing against cone stepping (15 and 30 degrees), and
# writes OUT/results.json (both sweeps' results under "scaling" and "quadric") and OUT/report.md.
#
#   scripts/gpu-check.sh OUT [--quick]
#
# RELIEF_BIN=path/to/relief uses a binary built elsewhere (a device machine without network cannot
# fetch crates); otherwise it builds one in release. --quick runs small sizes, for trying the
# script on lavapipe in a couple of minutes. Validation is off: the numbers are timings.
set -euo pipefail
cd "$(dirname "$0")/.."

out=${1:?usage: scripts/gpu-check.sh OUT [--quick]}
quick=${2:-}
if [[ -n $quick && $quick != --quick ]]; then
    echo "gpu-check: unknown option $quick (expected --quick)" >&2
    exit 2
fi

relief=${RELIEF_BIN:-}
if [[ -z $relief ]]; then
    cargo build --release --quiet
    relief=target/release/relief
fi
export RELIEF_VALIDATION=0

if [[ -n $quick ]]; then
    sizes=64,128,256 quadric_size=128 resolution=128x128 frames=3
else
    sizes=256,512,1024,2048,4096 quadric_size=1024 resolution=1024x1024 frames=10
fi

mkdir -p "$out"
started=$(date +%s)
"$relief" devices | tee "$out/devices.txt"

common=(--no-stability --no-shading --no-lod --resolution "$resolution" --frames "$frames" --depth-scales 0.1)
echo "gpu-check: scaling of qdm and pom over $sizes" >&2
"$relief" bench --methods qdm,pom --fields fbm --sizes "$sizes" --angles 30 "${common[@]}" \
    --out "$out/scaling"
echo "gpu-check: quadric against csm at $quadric_size^2" >&2
"$relief" bench --methods csm,quadric --fields fbm,bricks --sizes "$quadric_size" --angles 15,30 \
    "${common[@]}" --out "$out/quadric"

{
    printf '{"scaling": '
    cat "$out/scaling/results.json"
    printf ',\n"quadric": '
    cat "$out/quadric/results.json"
    printf '}\n'
} >"$out/results.json"
{
    echo "# relief GPU check"
    echo
    echo "Command: \`scripts/gpu-check.sh $out${quick:+ $quick}\`, $(($(date +%s) - started)) s."
    echo
    echo '```'
    cat "$out/devices.txt"
    echo '```'
    echo
    echo "# Scaling with map size (qdm, pom)"
    sed '1,/^## /{/^## /!d}' "$out/scaling/report.md"
    echo
    echo "# Quadric against cone stepping"
    sed '1,/^## /{/^## /!d}' "$out/quadric/report.md"
} >"$out/report.md"
echo "gpu-check: wrote $out/results.json and $out/report.md in $(($(date +%s) - started)) s" >&2
