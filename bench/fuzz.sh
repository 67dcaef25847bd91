#!/usr/bin/env bash
# Runs the libFuzzer targets, one after the other, for SECONDS in all (default 60),
# each on both cores unless FUZZ_JOBS says otherwise:
#   compile  tests/fuzz/fuzz_compile (lex + parse + evaluate + lower a .scn text),
#            3/4 of the time;
#   obj      tests/fuzz/fuzz_obj (the strict OBJ reader and the mesh built from
#            it), the other 1/4 (FUZZ_OBJ_PERCENT=25).
#   bash bench/fuzz.sh [SECONDS]           # CI: 60 (45 s + 15 s)
#   bash bench/fuzz.sh 36000               # ten hours, to pile up executions
#   FUZZ_TARGETS=obj bash bench/fuzz.sh 600
# Builds the `fuzz` preset (clang, ASan + UBSan) into build/fuzz first. Working
# corpora (kept between runs, so each run starts where the last stopped):
# build/fuzz/corpus (seeded from tests/lang/**/*.scn, examples/*.scn, stdlib/*.scn)
# and build/fuzz/corpus-obj (seeded from tests/fuzz/obj/*.obj and every *.obj in the
# repository). Findings land in build/fuzz/findings/ as TARGET-crash-*,
# TARGET-timeout-*, TARGET-oom-*; the script exits non-zero when a target reports
# one. Reproduce a finding with
#   build/fuzz/tests/fuzz/fuzz_obj build/fuzz/findings/obj-crash-…
# At the end it prints each target's executions (from libFuzzer's last status
# line) and their total. Limits per input: 10 s for a scene, 2 s for an OBJ file
# (a reader that is not linear shows as a timeout), 2048 MB resident, 64 KiB.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$here"
seconds="${1:-60}"
jobs="${FUZZ_JOBS:-$(nproc)}"
targets="${FUZZ_TARGETS:-compile obj}"
obj_percent="${FUZZ_OBJ_PERCENT:-25}"
# The evaluator's known closure/scope cycle leaks (tests/fuzz/lsan.supp); without
# the suppression every input defining a `fn` would be reported as a leak.
export LSAN_OPTIONS="suppressions=$here/tests/fuzz/lsan.supp:print_suppressions=0${LSAN_OPTIONS:+:$LSAN_OPTIONS}"

cmake --preset fuzz >/dev/null
cmake --build --preset fuzz

findings=build/fuzz/findings
mkdir -p "$findings"
shopt -s globstar nullglob
# Seeds: copied under content-derived names, so re-running adds nothing twice.
seed() {  # seed CORPUS FILE...
  local corpus=$1 f
  shift
  mkdir -p "$corpus"
  for f in "$@"; do cp "$f" "$corpus/seed-$(sha1sum "$f" | cut -c1-16)"; done
}

# The time each target gets: obj its percentage, compile the rest; a target run
# alone gets all of it.
share() {  # share TARGET
  case "$targets" in
    compile | obj) echo "$seconds" ;;
    *) if [ "$1" = obj ]; then
         echo $((seconds * obj_percent / 100 > 0 ? seconds * obj_percent / 100 : 1))
       else
         echo $((seconds - seconds * obj_percent / 100))
       fi ;;
  esac
}

marker="$findings/.run-start"
touch "$marker"
status=0
declare -A execs
for t in $targets; do
  case "$t" in
    compile)
      corpus=build/fuzz/corpus log=build/fuzz/fuzz.log dict=tests/fuzz/scn.dict timeout=10
      seed "$corpus" tests/lang/**/*.scn examples/*.scn stdlib/*.scn ;;
    obj)
      corpus=build/fuzz/corpus-obj log=build/fuzz/fuzz-obj.log dict=tests/fuzz/obj.dict timeout=2
      seed "$corpus" tests/fuzz/obj/*.obj $(git ls-files '*.obj' 2>/dev/null || true) ;;
    *) echo "fuzz: unknown target '$t' (compile, obj)" >&2; exit 2 ;;
  esac
  s=$(share "$t")
  echo "fuzz $t: ${s} s on ${jobs} job(s), corpus $(ls "$corpus" | wc -l) files, log $log"
  # -fork runs inputs in child processes: a crash, hang or OOM is recorded and the
  # run goes on (-ignore_crashes etc.), so one run lists every distinct finding.
  rc=0
  "build/fuzz/tests/fuzz/fuzz_$t" "$corpus" \
    -dict="$dict" \
    -max_total_time="$s" -timeout="$timeout" -rss_limit_mb=2048 -max_len=65536 \
    -fork="$jobs" -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1 \
    -artifact_prefix="$findings/$t-" -print_final_stats=1 >"$log" 2>&1 || rc=$?
  [ "$rc" -eq 0 ] || status=$rc
  grep -E '^#[0-9]+: cov|DONE|INFO: fuzzed for|stat::' "$log" | tail -n 3 || true
  # In fork mode each status line starts with the executions so far: "#N: cov: …".
  execs[$t]=$(grep -oE '^#[0-9]+' "$log" | tail -n 1 | tr -d '#' || true)
done

total=0
for t in $targets; do
  echo "fuzz $t: ${execs[$t]:-0} executions"
  total=$((total + ${execs[$t]:-0}))
done
echo "fuzz: $total executions in all"
n=$(find "$findings" -type f \( -name '*crash-*' -o -name '*timeout-*' -o -name '*oom-*' -o -name '*leak-*' \) -newer "$marker" | wc -l)
if [ "$status" -ne 0 ] || [ "$n" -gt 0 ]; then
  echo "fuzz: FAILED (exit $status, $n new finding(s) in $findings); see build/fuzz/fuzz*.log" >&2
  exit 1
fi
echo "fuzz: no findings"
