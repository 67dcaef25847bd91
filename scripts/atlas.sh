#!/usr/bin/env bash
# Regenerates the accuracy-versus-time atlas: docs/accuracy.md and docs/accuracy/
# (plots, images, CSV/JSON). Every figure in it is measured by this run.
#   bash scripts/atlas.sh            # about 10-20 minutes on 2 cores
# Measurements are taken on whatever machine runs it: ratios within one run are
# meaningful, absolute times are that machine's.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh deps
cmake --preset release >/dev/null
cmake --build --preset release --target snell

S=build/release/cli/snell
OUT=docs/accuracy
RES="${ATLAS_RES:-192x108}"
REF="${ATLAS_REF_SPP:-1024}"
REPEATS="${ATLAS_REPEATS:-3}"
mkdir -p "$OUT"
rm -f "$OUT"/*.md "$OUT"/*.svg "$OUT"/*.csv "$OUT"/*.json "$OUT"/images/*.png

sweep() {  # scene name knob... -- extra args
  local scene=$1 name=$2
  shift 2
  echo "== $scene: $name" >&2
  "$S" sweep "examples/$scene.scn" --res "$RES" --reference-spp "$REF" --repeats "$REPEATS" \
    --out "$OUT" --name "$scene-$name" --markdown "$OUT/$scene-$name.md" --quiet "$@"
}

for scene in showcase glass material_gallery; do
  sweep "$scene" sampler   --vary samples=1,4,16,64 --series sampler=independent,stratified,sobol --no-images
  sweep "$scene" fresnel   --vary samples=1,4,16,64 --series fresnel=exact,schlick
  sweep "$scene" branching --vary samples=1,4,16,64 --series branching=split,stochastic
  # A cutoff of 0.05 prunes often enough to show the cutoff's bias against roulette.
  sweep "$scene" termination --vary samples=1,4,16,64 --series termination=cutoff,roulette --set min_weight=0.05
  sweep "$scene" kernel    --vary samples=1,4,16,64 --series kernel=specialised,general --no-images
  sweep "$scene" depth     --vary max_depth=1,2,3,4,6,8,12 --set samples=16 --no-images
  sweep "$scene" weight    --vary min_weight=0.3,0.1,0.03,0.01,0.001,0 --set samples=16 --no-images
  sweep "$scene" area      --vary area_samples=1,2,4,8 --set samples=4 --no-images
  sweep "$scene" lights    --vary samples=1,4,16,64 --series light_sampling=area,solid_angle,adaptive
  # Only scenes with glossy surfaces: elsewhere the knob changes nothing.
  if grep -q glossy "examples/$scene.scn"; then
    sweep "$scene" glossy  --vary samples=1,4,16,64 --series glossy_sampling=lobe,mis
  fi
done

{
  cat docs/accuracy-intro.md
  for scene in showcase glass material_gallery; do
    echo
    echo "## $scene"
    echo
    for part in sampler fresnel branching termination kernel depth weight area lights glossy; do
      [ -f "$OUT/$scene-$part.md" ] || continue
      sed "s#](#](accuracy/#g; s#(accuracy/http#(http#g" "$OUT/$scene-$part.md"
    done
  done
} > docs/accuracy.md
echo "wrote docs/accuracy.md" >&2
