"""The watch page in headless Chromium (ctest -L watch): snell watch on a scene in a
temporary folder; the page shows an image; saving a new background colour shows a new
image whose centre pixel reads the new colour; `snell check`'s warnings about the scene
show; an error shows its file:line:col on the
page and greys the old image; fixing it brings an image back; an edit of an imported
file is a new image too, and so is a missing import's file once it is saved.
Usage: test_page.py SNELL"""

import os
import re
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cdp import PAGE_STATE, Chromium  # noqa: E402
from watch_process import SnellWatch, save_like_an_editor  # noqa: E402

SCENE = """settings {{ resolution <48, 32> samples 4 }}
camera {{ location <0, 0, -5> look_at <0, 0, 0> fov 40 }}
background {bg}
"""


def main():
    snell = sys.argv[1]
    folder = tempfile.mkdtemp(prefix="snell-watch-test-")
    scene = os.path.join(folder, "scene.scn")
    with open(scene, "w") as f:
        f.write(SCENE.format(bg="<0.25, 0.5, 0.75>"))
    watch = browser = None
    try:
        watch = SnellWatch(snell, scene, "--stats")
        browser = Chromium()
        browser.open(watch.url)
        state = "JSON.parse(%s)" % PAGE_STATE

        # 1. An image appears, at the scene's size, and the readout is its linear value.
        browser.wait_for(f"{state}.loaded.endsWith(' 48x32')", what="the first image")
        browser.wait_for(f"{state}.pixel.includes('0.25000 0.50000 0.75000')",
                         what="the centre pixel's value")
        first = browser.eval(f"{state}.loaded")
        stats = browser.eval(f"{state}.stats")
        assert "48x32" in stats and "camera" in stats, stats
        # `snell check`'s warnings about the scene as a whole are shown too (this
        # one has only a background).
        browser.wait_for(f"{state}.diagnostics.includes('warning: the scene has no object')",
                         what="the scene's warning")

        # 2. A new colour saved: a new image, and the readout follows it.
        save_like_an_editor(scene, SCENE.format(bg="<0.75, 0.5, 0.125>"))
        browser.wait_for(f"{state}.pixel.includes('0.75000 0.50000 0.12500')",
                         what="the edited colour")
        assert browser.eval(f"{state}.loaded") != first

        # 3. An error: its place on the page, the old image greyed.
        save_like_an_editor(scene, SCENE.format(bg="<0.75, 0.5, nosuch>"))
        browser.wait_for(f"{state}.diagnostics.includes('error')", what="the diagnostic")
        diag = browser.eval(f"{state}.diagnostics")
        assert re.search(r"scene\.scn:3:\d+: error", diag), diag
        assert "nosuch" in diag, diag
        # As `snell check` prints them, closing line included.
        assert re.search(r"1 error in .*scene\.scn", diag), diag
        assert browser.eval(f"{state}.stale") is True
        assert "error" in browser.eval(f"{state}.status")
        assert watch.proc.poll() is None, "snell watch ended on a scene error"

        # 4. Fixed: the diagnostic goes and an image comes back, not stale.
        save_like_an_editor(scene, SCENE.format(bg="<0.125, 1, 0.5>"))
        browser.wait_for(f"{state}.pixel.includes('0.12500 1.0000 0.50000')",
                         what="the fixed scene's image")
        browser.wait_for(f"!{state}.diagnostics.includes('error') && !{state}.stale",
                         what="the errors cleared")

        # 5. An imported file is watched too: a new colour there is a new image.
        lib = os.path.join(folder, "colours.scn")
        with open(lib, "w") as f:
            f.write("let sky = <0.5, 0.25, 1>;\n")
        save_like_an_editor(scene, 'import "colours.scn";\n' + SCENE.format(bg="sky"))
        browser.wait_for(f"{state}.pixel.includes('0.50000 0.25000 1.0000')",
                         what="the imported colour")
        with open(lib, "w") as f:  # written in place this time
            f.write("let sky = <1, 0.25, 0.5>;\n")
        browser.wait_for(f"{state}.pixel.includes('1.0000 0.25000 0.50000')",
                         what="the imported file's edit")

        # 6. A missing import is an error until the file appears beside the scene.
        save_like_an_editor(scene, 'import "later.scn";\n' + SCENE.format(bg="late"))
        browser.wait_for(f"{state}.diagnostics.includes('later.scn')", what="the missing import")
        assert browser.eval(f"{state}.stale") is True
        with open(os.path.join(folder, "later.scn"), "w") as f:
            f.write("let late = <0.375, 0.75, 0.25>;\n")
        browser.wait_for(f"{state}.pixel.includes('0.37500 0.75000 0.25000')",
                         what="the image once the import exists")
        print("watch page: image, edit, error, fix, an import's edit and a late import shown")
    finally:
        if browser:
            browser.close()
        if watch:
            code = watch.stop()
            assert code == 0, f"snell watch exited {code} on SIGTERM"
        for name in os.listdir(folder):
            os.unlink(os.path.join(folder, name))
        os.rmdir(folder)


if __name__ == "__main__":
    main()
