#!/usr/bin/env python3
"""Snell against Mitsuba 3: time to equal error, measured in one run (bench/peers/README.md).

  bench/peers/setup.sh                      # once: libllvm19 + the venv
  bench/peers/run.py [--snell PATH] [--repeats 3] [--scenes thinlens motion]

For each scene: a converged Mitsuba reference (rendered once, cached in build/peers/);
Mitsuba llvm_ad_rgb at --mitsuba-spp in a fresh Python process (whole-process wall
time, and its in-process render time) and its RMSE against the reference; Snell
(`snell render`, --threads 2, whole-process wall time) at 4, 8, 16, ... spp until its
RMSE is at most Mitsuba's. The time Snell needs for Mitsuba's error is interpolated
between the two bracketing spp counts (RMSE ~ c·spp^-p through both points, wall time
linear in spp). Then --repeats - 1 more rounds time Mitsuba and the two bracketing Snell
renders again, interleaved; every wall time reported is the minimum over the rounds.
"""

import argparse
import json
import math
import os
import re
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
DEFAULT_VENV = Path(os.environ.get("SNELL_PEERS_VENV", Path.home() / ".cache" / "snell-peers-venv"))
LLVM19 = "/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1"


def ensure_venv(venv):
    """Re-run this script under the venv's Python when mitsuba is not importable here."""
    try:
        import mitsuba  # noqa: F401
        return
    except ImportError:
        pass
    py = venv / "bin" / "python"
    if not py.exists() or os.environ.get("SNELL_PEERS_REEXEC"):
        sys.exit(f"run.py: no mitsuba here and no venv at {venv}: run bench/peers/setup.sh first")
    env = dict(os.environ, SNELL_PEERS_REEXEC="1")
    os.execve(str(py), [str(py), __file__] + sys.argv[1:], env)


def mitsuba_env():
    env = dict(os.environ)
    if "DRJIT_LIBLLVM_PATH" not in env and os.path.exists(LLVM19):
        env["DRJIT_LIBLLVM_PATH"] = LLVM19
    return env


def run_mitsuba(a, scene, out, spp, seed, slices, sampler, emitter_samples=None):
    """emitter_samples: --mitsuba-emitter-samples unless given (the reference gives 1)."""
    cmd = [sys.executable, str(HERE / "mitsuba_render.py"), scene, str(out), "--spp", str(spp),
           "--sampler", sampler, "--seed", str(seed), "--threads", str(a.threads),
           "--emitter-samples", str(emitter_samples or a.mitsuba_emitter_samples)]
    if scene == "motion":
        cmd += ["--slices", str(slices)]
    t0 = time.perf_counter()
    p = subprocess.run(cmd, env=mitsuba_env(), capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if p.returncode != 0:
        sys.exit(f"run.py: mitsuba failed ({' '.join(cmd)}):\n{p.stderr}")
    info = json.loads(p.stdout.strip().splitlines()[-1])
    return wall, info["render_seconds"]


def run_snell(a, scene, out, spp, seed=0):
    cmd = [str(a.snell), "render", str(snell_scene(a, scene)), "-o", str(out), "--spp", str(spp),
           "--threads", str(a.threads), "--seed", str(seed), "--quiet"]
    t0 = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if p.returncode != 0:
        sys.exit(f"run.py: snell failed ({' '.join(cmd)}):\n{p.stderr}")
    import mitsuba as mi
    render = float(mi.Bitmap(str(out)).metadata()["snell:render_seconds"])
    return wall, render


def snell_scene(a, scene):
    """The Snell scene as shipped (its area light takes a 2 x 2 jittered grid of shadow
    rays per camera sample), or with --light-grid N a copy in --out whose area light
    takes N x N (the same image in the limit: a sampling choice of the scene, stated
    beside the ratios it gives)."""
    src = HERE / f"{scene}.scn"
    if a.light_grid is None:
        return src
    text, n = re.subn(r"(area_light \{[^}]*?)samples <\d+, \d+>",
                      rf"\g<1>samples <{a.light_grid}, {a.light_grid}>", src.read_text())
    if n != 1:
        sys.exit(f"run.py: {src} has {n} area lights with samples, --light-grid expects one")
    dst = a.out / f"{scene}-light{a.light_grid}.scn"
    dst.write_text(text)
    return dst


def reference(a, scene):
    """The converged reference: Mitsuba with --ref-sampler at --ref-spp (motion: in
    --ref-slices time slices), a seed no measured render uses. Cached by scene and those."""
    tag = f"{scene}-mitsuba-{a.ref_sampler}-{a.ref_spp}" + (
        f"-{a.ref_slices}slices" if scene == "motion" else "")
    path = a.out / f"ref-{tag}.exr"
    if not path.exists():
        print(f"[{scene}] rendering the reference ({tag}); once, then cached as {path}", flush=True)
        tmp = path.with_name("tmp-" + path.name)
        wall, _ = run_mitsuba(a, scene, tmp, a.ref_spp, 1000, a.ref_slices, a.ref_sampler,
                              emitter_samples=1)
        tmp.rename(path)
        print(f"[{scene}] reference done in {wall:.0f} s", flush=True)
    import imgs
    return imgs.read_exr(path), path


def interpolate(lo, hi, target):
    """(spp, rmse, wall) bracketing the target RMSE -> (spp, wall) where RMSE = target,
    with RMSE = c·spp^-p through both points and wall time linear in spp."""
    (s0, e0, w0), (s1, e1, w1) = lo, hi
    p = math.log(e0 / e1) / math.log(s1 / s0) if e0 > e1 else 0.5
    s = s0 * (e0 / target) ** (1 / p)
    w = w0 + (w1 - w0) * (s - s0) / (s1 - s0)
    return s, w, p


def bench_scene(a, scene, sampler):
    import imgs
    ref, ref_path = reference(a, scene)
    m_out = a.out / f"mitsuba-{scene}.exr"
    s_out = a.out / f"snell-{scene}.exr"

    # Warm-ups, untimed: Dr.Jit's kernel cache (~/.drjit), the page cache for both binaries.
    run_mitsuba(a, scene, m_out, a.mitsuba_spp, 1, a.slices, sampler)
    run_snell(a, scene, s_out, 4)

    # Round 1: Mitsuba, then Snell at doubling spp until it reaches Mitsuba's error.
    m_wall, m_render = run_mitsuba(a, scene, m_out, a.mitsuba_spp, 1, a.slices, sampler)
    m_rmse = imgs.rmse(imgs.read_exr(m_out), ref)
    print(f"[{scene}] mitsuba {sampler} {a.mitsuba_spp} spp: RMSE {m_rmse:.5f}, wall {m_wall:.2f} s "
          f"(render {m_render:.2f} s)", flush=True)
    steps = []  # (spp, rmse, wall, render)
    spp = a.snell_start_spp
    while True:
        wall, render = run_snell(a, scene, s_out, spp)
        e = imgs.rmse(imgs.read_exr(s_out), ref)
        print(f"[{scene}] snell {spp} spp: RMSE {e:.5f}, wall {wall:.2f} s (render {render:.2f} s)",
              flush=True)
        steps.append([spp, e, wall, render])
        if e <= m_rmse or spp >= a.snell_max_spp:
            break
        spp *= 2
    hi = steps[-1]
    lo = steps[-2] if len(steps) > 1 else None
    if hi[1] > m_rmse:
        print(f"[{scene}] snell did not reach Mitsuba's RMSE by {hi[0]} spp", flush=True)

    # Rounds 2..R: the same renders again, interleaved; keep the minimum wall times.
    m_walls, m_renders = [m_wall], [m_render]
    for r in range(1, a.repeats):
        w, rr = run_mitsuba(a, scene, m_out, a.mitsuba_spp, 1, a.slices, sampler)
        m_walls.append(w)
        m_renders.append(rr)
        for st in ([lo, hi] if lo else [hi]):
            w, rr = run_snell(a, scene, s_out, st[0])
            st[2], st[3] = min(st[2], w), min(st[3], rr)
        print(f"[{scene}] round {r + 1}: mitsuba wall {m_walls[-1]:.2f} s", flush=True)
    m_wall, m_render = min(m_walls), min(m_renders)

    res = dict(scene=scene, sampler=sampler, m_spp=a.mitsuba_spp, m_rmse=m_rmse, m_wall=m_wall, m_render=m_render,
               s_first=dict(spp=hi[0], rmse=hi[1], wall=hi[2], render=hi[3]), steps=steps,
               reference=str(ref_path))
    if lo and hi[1] <= m_rmse:
        s, w, p = interpolate(lo[:3], hi[:3], m_rmse)
        _, wr, _ = interpolate((lo[0], lo[1], lo[3]), (hi[0], hi[1], hi[3]), m_rmse)
        res["s_equal"] = dict(spp=s, wall=w, render=wr, slope=p)
    return res


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--snell", type=Path, default=ROOT / "build" / "release" / "cli" / "snell")
    ap.add_argument("--scenes", nargs="+", default=["thinlens", "motion"], choices=["thinlens", "motion"])
    ap.add_argument("--out", type=Path, default=ROOT / "build" / "peers", help="renders and the cached references")
    ap.add_argument("--venv", type=Path, default=DEFAULT_VENV)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--repeats", type=int, default=3, help="timing rounds; the minimum wall time counts")
    ap.add_argument("--mitsuba-spp", type=int, default=256)
    ap.add_argument("--mitsuba-samplers", nargs="+", default=["independent", "stratified"],
                    help="one table row per scene and sampler (stratified needs a square spp)")
    ap.add_argument("--slices", type=int, default=16, help="Mitsuba's time slices for motion blur")
    ap.add_argument("--ref-spp", type=int, default=16384)
    ap.add_argument("--ref-slices", type=int, default=256)
    ap.add_argument("--ref-sampler", default="stratified")
    ap.add_argument("--snell-start-spp", type=int, default=4)
    ap.add_argument("--snell-max-spp", type=int, default=16384)
    ap.add_argument("--light-grid", type=int, default=None,
                    help="Snell's area light sampled as an N x N grid per camera sample (default: as shipped, 2)")
    ap.add_argument("--mitsuba-emitter-samples", type=int, default=1,
                    help="light samples per camera sample in Mitsuba's direct integrator (default: its own, 1)")
    ap.add_argument("--json", type=Path, help="also write the results here")
    a = ap.parse_args()
    ensure_venv(a.venv)
    sys.path.insert(0, str(HERE))
    a.snell = a.snell.resolve()
    if not a.snell.exists():
        sys.exit(f"run.py: no snell binary at {a.snell} (build it, or pass --snell PATH)")
    a.out.mkdir(parents=True, exist_ok=True)

    results = [bench_scene(a, s, m) for s in a.scenes for m in a.mitsuba_samplers]

    print()
    for scene in a.scenes:
        m = re.search(r"area_light \{[^}]*?samples <(\d+), (\d+)>", snell_scene(a, scene).read_text())
        grid = f"<{m[1]}, {m[2]}>" if m else "<1, 1>"
        print(f"{scene}: snell's area light samples {grid} per camera sample; "
              f"Mitsuba's direct integrator: emitter_samples {a.mitsuba_emitter_samples}")
    print(f"time to equal error, {a.threads} threads, whole-process wall times "
          f"(minimum of {a.repeats} rounds); RMSE against the converged Mitsuba reference")
    hdr = (f"{'scene':9} | {'mitsuba sampler':>15} {'spp':>5} {'RMSE':>8} {'wall s':>7} {'render s':>8} | "
           f"{'snell spp':>9} {'RMSE':>8} {'wall s':>7} {'render s':>8} | {'ratio':>6} | "
           f"{'equal-error spp':>15} {'wall s':>7} {'ratio':>6}")
    print(hdr)
    print("-" * len(hdr))
    for r in results:
        f = r["s_first"]
        line = (f"{r['scene']:9} | {r['sampler']:>15} {r['m_spp']:>5} {r['m_rmse']:8.5f} {r['m_wall']:7.2f} "
                f"{r['m_render']:8.2f} | {f['spp']:>9} {f['rmse']:8.5f} {f['wall']:7.2f} "
                f"{f['render']:8.2f} | {f['wall'] / r['m_wall']:6.2f} | ")
        if "s_equal" in r:
            q = r["s_equal"]
            line += f"{q['spp']:15.0f} {q['wall']:7.2f} {q['wall'] / r['m_wall']:6.2f}"
        print(line)
    print("ratio = Snell wall / Mitsuba wall: first at the first power-of-two spp that reaches "
          "Mitsuba's RMSE, then at the interpolated spp of equal RMSE")
    if a.json:
        a.json.write_text(json.dumps(results, indent=1))


if __name__ == "__main__":
    main()
