#!/usr/bin/env bash
# CTest's checks of tests/conformance/run itself (the suite as a product):
#   test_run.sh junit SNELL IDIFF OUT   two cases in both modes pass: exit 0, and
#                                       the JUnit XML is well-formed, names the
#                                       four runs and has no <failure>;
#   test_run.sh fails SNELL IDIFF OUT   a case with a wrong reference and one with
#                                       a threshold no render meets fail beside one
#                                       that passes: exit 1, and the XML has a
#                                       <failure> for exactly those two.
# Exit 77 (skipped) without python3, which reads the XML.
set -euo pipefail
what=$1 snell=$2 idiff=$3 out=$4
here="$(cd "$(dirname "$0")" && pwd)"
command -v python3 >/dev/null || { echo "python3 not found: skipped"; exit 77; }
rm -rf "$out"
mkdir -p "$out"

# check_xml FILE EXPECTED_FAILURES NAME... : the report names exactly these runs,
# and those given as NAME! have a <failure>.
check_xml() {
  python3 - "$@" <<'PY'
import sys, xml.etree.ElementTree as ET
path, want_failures, names = sys.argv[1], int(sys.argv[2]), sys.argv[3:]
suite = ET.parse(path).getroot().find("testsuite")
assert suite is not None, "no <testsuite>"
cases = {c.get("name"): c for c in suite.findall("testcase")}
want = {n.rstrip("!"): n.endswith("!") for n in names}
assert set(cases) == set(want), f"runs {sorted(cases)} != {sorted(want)}"
for name, should_fail in want.items():
    failure = cases[name].find("failure")
    assert (failure is not None) == should_fail, f"{name}: failure {failure is not None}"
    if should_fail:
        assert failure.get("message", "").startswith("FAIL"), failure.get("message")
assert int(suite.get("tests")) == len(want), suite.get("tests")
assert int(suite.get("failures")) == want_failures, suite.get("failures")
print(f"{path}: {len(cases)} runs, {want_failures} failure(s), as expected")
PY
}

case "$what" in
  junit)
    bash "$here/run" --snell "$snell" --idiff "$idiff" --filter '^(mesh|diffuse):' \
      --junit "$out/report.xml" --out "$out/runs"
    check_xml "$out/report.xml" 0 mesh:auto mesh:all diffuse:auto diffuse:all
    ;;
  fails)
    mkdir -p "$out/cases"
    cp -r "$here/mesh" "$out/cases/passes"
    cp -r "$here/diffuse" "$out/cases/wrong-reference"
    cp "$here/background/reference.exr" "$out/cases/wrong-reference/reference.exr"
    cp -r "$here/diffuse" "$out/cases/wrong-threshold"
    sed -i -e 's/^fail:.*/fail: 0.0001/' -e 's/^failrelative:.*/failrelative: 0/' \
      -e 's/^failpercent:.*/failpercent: 0/' -e 's/^hardfail:.*/hardfail: 0.001/' \
      "$out/cases/wrong-threshold/case.txt"
    rc=0
    bash "$here/run" --snell "$snell" --idiff "$idiff" --cases "$out/cases" --modes auto \
      --junit "$out/report.xml" --out "$out/runs" || rc=$?
    [ "$rc" -eq 1 ] || { echo "run exited $rc, expected 1"; exit 1; }
    check_xml "$out/report.xml" 2 passes:auto wrong-reference:auto! wrong-threshold:auto!
    ;;
  *) echo "usage: test_run.sh junit|fails SNELL IDIFF OUT" >&2; exit 2 ;;
esac
