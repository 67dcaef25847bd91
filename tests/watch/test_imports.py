"""An import found through -I is watched where the search could find it first: a
file of that name saved beside the scene (the importing file's folder is searched
before -I, §9) takes over, and the preview follows it; it kept the -I file's image.
Usage: test_imports.py SNELL"""

import json
import os
import shutil
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from watch_process import SnellWatch, save_like_an_editor  # noqa: E402

SCENE = """import "colours.scn";
settings { resolution <16, 16> samples 1 }
camera { location <0, 0, -5> look_at <0, 0, 0> fov 40 }
background sky
"""


def centre(watch):
    return json.loads(watch.get("/pixel?x=8&y=8"))["rgb"]


def main():
    snell = sys.argv[1]
    root = tempfile.mkdtemp(prefix="snell-watch-imports-")
    scene_dir, lib_dir = os.path.join(root, "scene"), os.path.join(root, "lib")
    os.mkdir(scene_dir)
    os.mkdir(lib_dir)
    scene = os.path.join(scene_dir, "m.scn")
    with open(scene, "w") as f:
        f.write(SCENE)
    with open(os.path.join(lib_dir, "colours.scn"), "w") as f:
        f.write("let sky = <0.25, 0.25, 0.75>;\n")
    watch = None
    try:
        watch = SnellWatch(snell, scene, "--quiet", "-I", lib_dir)
        watch.wait_state(lambda s: s.get("spp", 0) > 0 and s.get("status", "").startswith("done"),
                         what="a first image")
        assert centre(watch) == [0.25, 0.25, 0.75], centre(watch)
        save_like_an_editor(os.path.join(scene_dir, "colours.scn"), "let sky = <0.5, 0.125, 0.125>;\n")
        watch.wait_state(lambda s: centre(watch) == [0.5, 0.125, 0.125],
                         what="the image of the import now found beside the scene")
        print("watch imports: a file that now wins the import search is followed")
    finally:
        if watch:
            code = watch.stop()
            assert code == 0, f"snell watch exited {code} on SIGTERM"
        shutil.rmtree(root)


if __name__ == "__main__":
    main()
