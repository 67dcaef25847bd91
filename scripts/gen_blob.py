#!/usr/bin/env python3
"""Writes examples/meshes/blob.obj (with vertex normals, `f v//vn`) and
examples/meshes/blob_flat.obj (the same triangles, no normals): a lumpy ball,
rings x segments quads around the y axis, radius modulated by a few low-frequency
bumps. Vertex normals are the angle-weighted average of the adjacent face normals,
as modelling tools export them. The ball is closed (shared poles and seam), so
both files also load as closed meshes. Usage: python3 scripts/gen_blob.py [RINGS SEGMENTS]"""
import math, os, sys

rings = int(sys.argv[1]) if len(sys.argv) > 1 else 16
segs = int(sys.argv[2]) if len(sys.argv) > 2 else 32

def radius(th, ph):
    return 1 + 0.12 * math.sin(3 * ph) * math.sin(th) ** 2 + 0.08 * math.cos(4 * th) + 0.05 * math.sin(5 * ph + 2 * th)

def point(th, ph):
    r = radius(th, ph)
    return (r * math.sin(th) * math.cos(ph), r * math.cos(th), r * math.sin(th) * math.sin(ph))

pos = [point(0, 0)]
for i in range(1, rings):
    for j in range(segs):
        pos.append(point(math.pi * i / rings, 2 * math.pi * j / segs))
pos.append(point(math.pi, 0))
south = len(pos) - 1
ring = lambda i, j: 1 + (i - 1) * segs + (j % segs)
tris = []
for j in range(segs):
    tris.append((0, ring(1, j + 1), ring(1, j)))
for i in range(1, rings - 1):
    for j in range(segs):
        tris.append((ring(i, j), ring(i, j + 1), ring(i + 1, j + 1)))
        tris.append((ring(i, j), ring(i + 1, j + 1), ring(i + 1, j)))
for j in range(segs):
    tris.append((south, ring(rings - 1, j), ring(rings - 1, j + 1)))

def sub(a, b): return (a[0] - b[0], a[1] - b[1], a[2] - b[2])
def cross(a, b): return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])
def dot(a, b): return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
def norm(a):
    l = math.sqrt(dot(a, a))
    return (a[0] / l, a[1] / l, a[2] / l)

acc = [[0.0, 0.0, 0.0] for _ in pos]
for t in tris:
    n = norm(cross(sub(pos[t[1]], pos[t[0]]), sub(pos[t[2]], pos[t[0]])))
    for k in range(3):
        a, b, c = pos[t[k]], pos[t[(k + 1) % 3]], pos[t[(k + 2) % 3]]
        ang = math.acos(max(-1.0, min(1.0, dot(norm(sub(b, a)), norm(sub(c, a))))))
        for q in range(3):
            acc[t[k]][q] += ang * n[q]
nrm = [norm(a) for a in acc]

here = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "examples", "meshes")
os.makedirs(here, exist_ok=True)
for name, smooth in (("blob.obj", True), ("blob_flat.obj", False)):
    with open(os.path.join(here, name), "w") as f:
        f.write("# %s: a lumpy ball, %d x %d, written by scripts/gen_blob.py%s\n"
                % (name, rings, segs, " (with vertex normals)" if smooth else " (no normals)"))
        for p in pos:
            f.write("v %.6f %.6f %.6f\n" % p)
        if smooth:
            for n in nrm:
                f.write("vn %.6f %.6f %.6f\n" % n)
        for t in tris:
            if smooth:
                f.write("f %d//%d %d//%d %d//%d\n" % (t[0] + 1, t[0] + 1, t[1] + 1, t[1] + 1, t[2] + 1, t[2] + 1))
            else:
                f.write("f %d %d %d\n" % (t[0] + 1, t[1] + 1, t[2] + 1))
print("wrote", len(pos), "vertices", len(tris), "triangles")
