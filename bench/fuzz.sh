#!/usr/bin/env bash
# Runs the libFuzzer target tests/fuzz/fuzz_compile (lex + parse + evaluate + lower)
# for SECONDS (default 60), on both cores unless FUZZ_JOBS says otherwise.
#   bash bench/fuzz.sh [SECONDS]
# Builds the `fuzz` preset (clang, ASan + UBSan) into build/fuzz first. The working
# corpus is build/fuzz/corpus (kept between runs, so each run starts where the last
# stopped); it is seeded from tests/lang/**/*.scn, examples/*.scn and stdlib/*.scn.
# Findings land in build/fuzz/findings/ (crash-*, timeout-*, oom-*); the script exits
# non-zero when libFuzzer reports one. Reproduce a finding with
#   build/fuzz/tests/fuzz/fuzz_compile build/fuzz/findings/crash-…
# Limits per input: 10 s (a hang), 2048 MB resident (runaway memory), 64 KiB input.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$here"
seconds="${1:-60}"
jobs="${FUZZ_JOBS:-$(nproc)}"
# The evaluator's known closure/scope cycle leaks (tests/fuzz/lsan.supp); without
# the suppression every input defining a `fn` would be reported as a leak.
export LSAN_OPTIONS="suppressions=$here/tests/fuzz/lsan.supp:print_suppressions=0${LSAN_OPTIONS:+:$LSAN_OPTIONS}"

cmake --preset fuzz >/dev/null
cmake --build --preset fuzz

exe=build/fuzz/tests/fuzz/fuzz_compile
corpus=build/fuzz/corpus
findings=build/fuzz/findings
mkdir -p "$corpus" "$findings"
# Seeds: copied under content-derived names, so re-running adds nothing twice.
shopt -s globstar nullglob
for f in tests/lang/**/*.scn examples/*.scn stdlib/*.scn; do
  cp "$f" "$corpus/seed-$(sha1sum "$f" | cut -c1-16)"
done

log=build/fuzz/fuzz.log
echo "fuzz: ${seconds} s on ${jobs} job(s), corpus $(ls "$corpus" | wc -l) files, log $log"
# -fork runs inputs in child processes: a crash, hang or OOM is recorded and the run
# goes on (-ignore_crashes etc.), so one run lists every distinct finding.
marker="$findings/.run-start"
touch "$marker"
status=0
"$exe" "$corpus" \
  -dict=tests/fuzz/scn.dict \
  -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=65536 \
  -fork="$jobs" -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1 \
  -artifact_prefix="$findings/" -print_final_stats=1 >"$log" 2>&1 || status=$?

grep -E '^#[0-9]+: cov|DONE|INFO: fuzzed for|stat::' "$log" | tail -n 4 || true
n=$(find "$findings" -type f \( -name 'crash-*' -o -name 'timeout-*' -o -name 'oom-*' -o -name 'leak-*' \) -newer "$marker" | wc -l)
if [ "$status" -ne 0 ] || [ "$n" -gt 0 ]; then
  echo "fuzz: FAILED (exit $status, $n new finding(s) in $findings); see $log" >&2
  exit 1
fi
echo "fuzz: no findings"
