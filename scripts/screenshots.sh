#!/usr/bin/env bash
# Screenshots of snell watch's page for docs/editing.md, taken in Debian's headless
# chromium (scripts/setup.sh test installs it) through the same DevTools helper as
# the watch tests (tests/watch/cdp.py):
#   docs/images/watch_page.png    the showcase, every pass done, the cursor's pixel read out
#   docs/images/watch_error.png   the same page after a typo is saved: the diagnostic, the
#                                 last good image greyed
# Usage: bash scripts/screenshots.sh [SNELL]   (default build/release/cli/snell)
# Runs on a copy of examples/ in a temporary folder; snell watch and chromium are
# stopped by PID when it ends, however it ends.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
snell="$(realpath "${1:-$here/build/release/cli/snell}")"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cp -r "$here/examples/." "$work/"
export OCIO="${OCIO:-$here/stdlib/ocio/config.ocio}"

SNELL="$snell" WORK="$work" OUT="$here/docs/images" \
  PYTHONPATH="$here/tests/watch" python3 - <<'PY'
import os
import re

from cdp import PAGE_STATE, Chromium
from watch_process import SnellWatch, save_like_an_editor

os.chdir(os.environ["WORK"])  # the page names the scene as given: showcase.scn
scene = "showcase.scn"
out = os.environ["OUT"]
watch = browser = None
try:
    watch = SnellWatch(os.environ["SNELL"], scene, "--stats")
    browser = Chromium(width=1600, height=640)
    browser.open(watch.url)
    state = "JSON.parse(%s)" % PAGE_STATE
    watch.wait_state(lambda s: s["status"].startswith("done"), timeout=300, what="every pass")
    browser.wait_for(f"{state}.status.startsWith('done')", what="the page's last pass")
    # The cursor over the glass sphere: the readout is that pixel's linear value.
    browser.send("Input.dispatchMouseEvent", {"type": "mouseMoved", "x": 480, "y": 300})
    browser.wait_for(f"{state}.pixel.includes('pixel') && !{state}.pixel.includes('centre')",
                     what="the cursor's pixel")
    browser.screenshot(os.path.join(out, "watch_page.png"))

    # A typo saved: the diagnostic beside the last good image.
    with open(scene) as f:
        text = f.read()
    save_like_an_editor(scene, re.sub(r"\bradius 1 ", "radus 1 ", text, count=1))
    browser.wait_for(f"{state}.diagnostics.includes('error')", what="the diagnostic")
    browser.send("Input.dispatchMouseEvent", {"type": "mouseMoved", "x": 1590, "y": 630})
    browser.screenshot(os.path.join(out, "watch_error.png"))
    print("wrote", os.path.join(out, "watch_page.png"), "and watch_error.png")
finally:
    if browser:
        browser.close()
    if watch:
        watch.stop()
PY
