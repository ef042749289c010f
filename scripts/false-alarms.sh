#!/usr/bin/env bash
# How often `relief bench compare` calls a difference where there is none: runs the same small
# sweep RUNS times with one build and compares every pair (both orders), counting the verdicts.
#
#   scripts/false-alarms.sh OUT [RUNS] [-- extra relief bench flags]
#
# RELIEF_BIN names the binary (default target/release/relief, built if missing). The sweep is the
# quick one's runs alone (the other sections are not compared). Validation is off: these are
# timings. Runs already in OUT are kept, so the comparisons can be repeated with another relief.
# Prints one summary line per pair and the totals.
set -euo pipefail
cd "$(dirname "$0")/.."

out=${1:?usage: scripts/false-alarms.sh OUT [RUNS] [-- relief bench flags]}
shift
runs=5
if [[ $# -gt 0 && $1 != -- ]]; then
    runs=$1
    shift
fi
[[ ${1:-} == -- ]] && shift
bin=${RELIEF_BIN:-target/release/relief}
[[ -x $bin ]] || cargo build --release
export RELIEF_VALIDATION=0

mkdir -p "$out"
for k in $(seq 1 "$runs"); do
    [[ -f $out/run$k/results.json ]] && continue
    "$bin" bench --quick --no-stability --no-shading --no-lod --no-edits --no-blending \
        --no-scene-shadows "$@" --out "$out/run$k" 2>/dev/null
done
cells=0 comparisons=0 alarms=0
for a in $(seq 1 "$runs"); do
    for b in $(seq 1 "$runs"); do
        [[ $a == "$b" ]] && continue
        line=$("$bin" bench compare "$out/run$a" "$out/run$b" | tail -n 1)
        echo "run$a -> run$b: $line"
        n=${line%% cells:*}
        slower=$(sed -E 's/.*: ([0-9]+) slower.*/\1/' <<<"$line")
        faster=$(sed -E 's/.* ([0-9]+) faster.*/\1/' <<<"$line")
        cells=$((cells + n))
        comparisons=$((comparisons + 1))
        alarms=$((alarms + slower + faster))
    done
done
echo "false alarms: $alarms of $cells cell comparisons in $comparisons file comparisons ($runs runs)"
