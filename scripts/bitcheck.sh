#!/usr/bin/env bash
# Renders every example and conformance scene (small, few samples) and dumps
# their IR, into OUT_DIR, so two builds can be compared bit for bit:
#   bash scripts/bitcheck.sh SNELL OUT_DIR        (then: cmp -r, or diff -r)
# Used to prove a refactoring changes no picture (docs/architecture.md).
set -euo pipefail
snell=$1 out=$2
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
mkdir -p "$out"
scenes=("$here"/examples/*.scn)
for d in "$here"/tests/conformance/*/; do [ -f "$d/scene.scn" ] && scenes+=("$d/scene.scn"); done
for s in "${scenes[@]}"; do
  name=$(basename "$(dirname "$s")")-$(basename "$s" .scn)
  "$snell" render "$s" --res 48x36 --dump-ir > "$out/$name.ir" 2>&1 || true
  for mode in auto all; do
    "$snell" render "$s" --res 48x36 --spp 4 --threads 2 --features "$mode" --quiet \
      -o "$out/$name-$mode.exr" > "$out/$name-$mode.err" 2>&1 || true
  done
done
echo "bitcheck: $(ls "$out"/*.exr | wc -l) images in $out"
