#!/usr/bin/env bash
# Renders the §15 pattern gallery (examples/pattern_gallery.scn) into
# docs/images/pattern_gallery.png, the picture docs/language.md shows.
# Usage: scripts/pattern_gallery.sh [path/to/snell]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
snell="${1:-$root/build/release/cli/snell}"
"$snell" render "$root/examples/pattern_gallery.scn" --res 1000x600 --spp 16 -q \
  -o "$root/docs/images/pattern_gallery.png"
echo "wrote docs/images/pattern_gallery.png"
