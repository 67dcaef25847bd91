#!/usr/bin/env bash
# Makes the images examples/textures/textured_room.scn reads (§17), with oiiotool: no
# downloaded files. Usage: bash scripts/make_textures.sh [OUT_DIR]
# (default examples/textures). Outputs:
#   floor.png  8-bit sRGB wooden-looking tiles (a two-tone checker, 8 tiles across)
#   wall.png   8-bit sRGB warm plaster: a vertical ramp with a little noise
#   sky.exr    float linear latlong sky, 2:1: blue zenith to bright horizon, a dark
#              ground below the horizon and a small sun (radiance 60) at u ≈ 0.69
set -euo pipefail
out=${1:-"$(dirname "$0")/../examples/textures"}
mkdir -p "$out"
command -v oiiotool >/dev/null || { echo "make_textures.sh: needs oiiotool (openimageio-tools)" >&2; exit 1; }
oiiotool --pattern checker:width=64:height=64:color1=0.55,0.35,0.2:color2=0.35,0.2,0.1 512x512 3 \
  -d uint8 -o "$out/floor.png"
oiiotool --pattern fill:top=0.85,0.82,0.75:bottom=0.6,0.55,0.5 256x256 3 \
  --pattern noise:type=gaussian:mean=0:stddev=0.03:seed=7 256x256 3 --add -d uint8 -o "$out/wall.png"
oiiotool --pattern fill:top=0.2,0.4,1.1:bottom=1.0,1.05,1.2 1024x512 3 \
  --fill:top=0.3,0.27,0.2:bottom=0.06,0.05,0.04 1024x256+0+256 \
  --fill:color=60,55,45 16x16+700+180 -d float -o "$out/sky.exr"
echo "wrote $out/floor.png $out/wall.png $out/sky.exr"
