#!/usr/bin/env bash
# Counts relief's public API as rustdoc documents it (no nightly toolchain needed): the items
# reachable from the crate root (rustdoc's all.html, less ash's types re-exported as
# `relief::vk::raw`), and on their pages the public fields, enum variants, inherent methods and
# associated constants, and trait methods. Usage: scripts/public-api.sh [cargo doc options], for
# example `--no-default-features --features compile-shaders` for what an engine sees (the
# feature compiles the shaders in a checkout, which has no prebuilt SPIR-V; it adds no API).
set -euo pipefail
cd "$(dirname "$0")/.."
# Without the default features some of the guide's links have no target; those warnings are
# not what this counts, so cargo's output is kept for a failure only.
log=$(mktemp)
trap 'rm -f "$log"' EXIT
if ! cargo doc --no-deps --lib --quiet "$@" >"$log" 2>&1; then
    cat "$log" >&2
    exit 1
fi
doc=${CARGO_TARGET_DIR:-target}/doc/relief
items=$(grep -o '<li><a href="[^"]*"' "$doc/all.html" | sed 's/.*href="//; s/"$//' |
    grep -v '^#' | grep -v '^vk/raw/' | sort -u)
count() { grep -c . <<<"$1" || true; }
echo "items: $(count "$items")"
for kind in struct enum fn trait constant type macro union; do
    n=$(grep -c "/$kind\.\|^$kind\." <<<"$items" || true)
    ((n > 0)) && echo "  $kind: $n"
done
# Ids come in document order: inherent methods lie between "implementations-list" and the first
# trait, synthetic or blanket implementation list.
members=$(while read -r page; do
    grep -o 'id="[^"]*"' "$doc/$page" | sed 's/^id="//; s/"$//'
done <<<"$items" | awk '
    /^implementations-list$/ { inherent = 1; next }
    /^(trait|synthetic|blanket)-implementations/ { inherent = 0 }
    /^structfield\./ { fields++ }
    /^variant\./ { variants++ }
    /^tymethod\./ { trait_methods++ }
    inherent && /^method\./ { methods++ }
    inherent && /^associatedconstant\./ { consts++ }
    END { printf "fields %d\nvariants %d\nmethods %d\nassociated_constants %d\ntrait_methods %d\n",
          fields, variants, methods, consts, trait_methods }')
echo "$members" | sed 's/^/  /'
total=$(( $(count "$items") + $(awk '{s += $2} END {print s}' <<<"$members") ))
echo "total: $total"
