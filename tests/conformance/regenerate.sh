#!/usr/bin/env bash
# Deliberately regenerates conformance references (never run by the tests).
#   bash tests/conformance/regenerate.sh CASE...     # named cases
#   bash tests/conformance/regenerate.sh --all       # every case
# Renders each scene at the case's resolution with ref_spp samples (default
# 4096) and a seed of its own, so the reference's noise is independent of the
# test render's. Look at every reference (a PNG is written beside it, not
# committed) before committing it.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
snell="${SNELL:-$here/../../build/release/cli/snell}"
cases=("$@")
if [ "${1:-}" = --all ]; then cases=(); for d in "$here"/*/; do [ -f "$d/case.txt" ] && cases+=("$(basename "$d")"); done; fi
[ ${#cases[@]} -gt 0 ] || { echo "usage: regenerate.sh CASE... | --all" >&2; exit 2; }
for c in "${cases[@]}"; do
  d="$here/$c"
  field() { sed -n "s/^$1:[[:space:]]*//p" "$d/case.txt" | head -n1; }
  res=$(field res); ref=$(field ref_spp)
  echo "== $c (${res:-64x48}, ${ref:-4096} spp)"
  "$snell" render "$d/scene.scn" --res "${res:-64x48}" --spp "${ref:-4096}" --seed 977 --quiet \
    -o "$d/reference.exr" -o "$d/reference.png"
done
