"""Render one of the bench/peers scenes with Mitsuba 3 in this process and write a
linear EXR. Run by run.py in a fresh Python (the venv of setup.sh) so that its wall
time is a whole process: interpreter start, import, scene load, JIT, render, write.

  python mitsuba_render.py SCENE OUT.exr --spp N [--sampler S] [--slices K] [--seed N] [--emitter-samples E]

SCENE is thinlens or motion. Mitsuba 3.9.1 has no moving shapes, so `motion`
renders K time slices (stratified: slice k at t = (k + u_k) / K, u_k uniform, so
the mean is an unbiased estimate of the shutter average) with N / K samples per
pixel each, moving the sphere between them (mi.traverse + update), and averages
them. Prints one JSON line: {"render_seconds": ..., "load_seconds": ...}.
"""

import argparse
import json
import os
import sys
import time

t_start = time.perf_counter()
import drjit as dr  # noqa: E402
import mitsuba as mi  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mitsuba_scenes as S  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("scene", choices=["thinlens", "motion"])
    ap.add_argument("out")
    ap.add_argument("--spp", type=int, required=True)
    ap.add_argument("--sampler", default="independent")
    ap.add_argument("--slices", type=int, default=16, help="time slices (motion only)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--variant", default="llvm_ad_rgb")
    ap.add_argument("--emitter-samples", type=int, default=1, help="the direct integrator's")
    a = ap.parse_args()

    mi.set_variant(a.variant)
    dr.set_thread_count(a.threads)
    t0 = time.perf_counter()
    if a.scene == "thinlens":
        scene = mi.load_dict(S.thinlens(mi, a.sampler, a.spp, a.emitter_samples))
        t1 = time.perf_counter()
        img = mi.render(scene, spp=a.spp, seed=a.seed)
    else:
        k = a.slices
        if a.spp % k:
            sys.exit(f"--spp {a.spp} is not a multiple of --slices {k}")
        per = a.spp // k
        scene = mi.load_dict(S.motion(mi, a.sampler, per, a.emitter_samples))
        params = mi.traverse(scene)
        key = S.moving_sphere_key() + ".to_world"
        r = S.SPHERES[0][1]
        import numpy as np
        u = np.random.default_rng(1000003 * a.seed + 17).random(k)
        t1 = time.perf_counter()
        img = None
        for i in range(k):
            t = (i + u[i]) / k
            params[key] = mi.ScalarTransform4f().translate(S.sphere_center_at(t)).scale(r)
            params.update()
            part = mi.render(scene, params, spp=per, seed=a.seed * k + i)
            img = part if img is None else img + part
        img = img / k
    dr.eval(img)
    dr.sync_thread()  # kernels launch asynchronously: wait for them
    t2 = time.perf_counter()
    mi.Bitmap(img).write(a.out)
    t3 = time.perf_counter()
    print(json.dumps({"import_seconds": t0 - t_start, "load_seconds": t1 - t0,
                      "render_seconds": t2 - t1, "write_seconds": t3 - t2}))


if __name__ == "__main__":
    main()
