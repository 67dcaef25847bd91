#!/usr/bin/env bash
# Renders one conformance case and compares it with its reference.
#   run_case.sh SNELL IDIFF CASE_DIR auto|all OUT_DIR
# On failure OUT_DIR keeps out.exr (the render), reference.exr (a copy) and
# diff.exr (|out - reference| x 20), and the idiff report is printed.
# The comparison of the suite: CTest runs it per case and mode, and
# tests/conformance/run (the suite against any snell build) runs it for each case.
# Its last line is the verdict, for both to show and `run` to parse:
#   result: PASS|FAIL failing 0.033% (limit 2%) max 0.0319 (hardfail 0.5)
#   result: ERROR render failed | non-finite samples dropped
set -euo pipefail
snell=$1 idiff=$2 dir=$3 mode=$4 out=$5
field() { sed -n "s/^$1:[[:space:]]*//p" "$dir/case.txt" | head -n1; }
res=$(field res); spp=$(field spp)
fail=$(field fail); failrelative=$(field failrelative); failpercent=$(field failpercent)
hardfail=$(field hardfail)
rm -rf "$out"; mkdir -p "$out"
"$snell" render "$dir/scene.scn" --res "${res:-64x48}" --spp "${spp:-64}" --features "$mode" \
  --quiet --stats -o "$out/out.exr" 2> "$out/stats.txt" ||
  { cat "$out/stats.txt"; echo "result: ERROR render failed"; exit 1; }
if grep -q "non-finite sample" "$out/stats.txt" && ! grep -q "non-finite samples dropped: 0" "$out/stats.txt"; then
  echo "non-finite samples were dropped:"; cat "$out/stats.txt"
  echo "result: ERROR non-finite samples dropped"; exit 1
fi
set +e
"$idiff" -fail "${fail:-0.02}" -failrelative "${failrelative:-0.05}" -failpercent "${failpercent:-2}" \
  -hardfail "${hardfail:-0.5}" \
  -abs -scale 20 -o "$out/diff.exr" "$out/out.exr" "$dir/reference.exr" > "$out/idiff.txt" 2>&1
status=$?
set -e
cat "$out/idiff.txt"
# idiff's report: "Max error = E @ …" and "N pixels (P%) over T" for each threshold
# some pixel exceeds (none: 0 %).
max=$(sed -n 's/^ *Max error *= *\([^ ]*\).*/\1/p' "$out/idiff.txt" | head -n1)
pct=$(sed -n "s/^ *[0-9]* pixels (\([^)]*\)%) over ${fail:-0.02}\$/\1/p" "$out/idiff.txt" | head -n1)
metric="failing ${pct:-0}% (limit ${failpercent:-2}%) max ${max:-?} (hardfail ${hardfail:-0.5})"
if [ $status -ge 2 ]; then   # idiff: 0 pass, 1 warning, 2 failure, 3 size mismatch, 4 file error
  cp "$dir/reference.exr" "$out/reference.exr"
  echo "FAILED: render, reference and difference image in $out"
  if [ $status -ge 3 ]; then echo "result: ERROR idiff exit $status (size mismatch or unreadable file)"
  else echo "result: FAIL $metric"; fi
  exit 1
fi
rm -f "$out/diff.exr"
echo "result: PASS $metric"
