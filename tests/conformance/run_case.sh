#!/usr/bin/env bash
# Renders one conformance case and compares it with its reference.
#   run_case.sh SNELL IDIFF CASE_DIR auto|all OUT_DIR
# On failure OUT_DIR keeps out.exr (the render), reference.exr (a copy) and
# diff.exr (|out - reference| x 20), and the idiff report is printed.
set -euo pipefail
snell=$1 idiff=$2 dir=$3 mode=$4 out=$5
field() { sed -n "s/^$1:[[:space:]]*//p" "$dir/case.txt" | head -n1; }
res=$(field res); spp=$(field spp)
fail=$(field fail); failrelative=$(field failrelative); failpercent=$(field failpercent)
hardfail=$(field hardfail)
rm -rf "$out"; mkdir -p "$out"
"$snell" render "$dir/scene.scn" --res "${res:-64x48}" --spp "${spp:-64}" --features "$mode" \
  --quiet --stats -o "$out/out.exr" 2> "$out/stats.txt" || { cat "$out/stats.txt"; exit 1; }
if grep -q "non-finite sample" "$out/stats.txt" && ! grep -q "non-finite samples dropped: 0" "$out/stats.txt"; then
  echo "non-finite samples were dropped:"; cat "$out/stats.txt"; exit 1
fi
set +e
"$idiff" -fail "${fail:-0.02}" -failrelative "${failrelative:-0.05}" -failpercent "${failpercent:-2}" \
  -hardfail "${hardfail:-0.5}" \
  -abs -scale 20 -o "$out/diff.exr" "$out/out.exr" "$dir/reference.exr" > "$out/idiff.txt" 2>&1
status=$?
set -e
cat "$out/idiff.txt"
if [ $status -ge 2 ]; then   # idiff: 0 pass, 1 warning, 2 failure, 3 size mismatch, 4 file error
  cp "$dir/reference.exr" "$out/reference.exr"
  echo "FAILED: render, reference and difference image in $out"
  exit 1
fi
rm -f "$out/diff.exr"
