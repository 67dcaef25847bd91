// Shading normals that differ from the geometric one (smooth meshes' interpolated
// `vn`; robustness.md hard case #20). The geometric normal stays the authority for
// which side a ray is on (entering, offsets, which side a branch leaves from); the
// shading normal only bends the lobes. Two things go wrong when it is used as is:
//  - the mirror direction about it can point below the real surface (near the
//    silhouette of a coarse smooth mesh), and the viewer can even be behind it:
//    reflections then start into the surface (black facets, light leaking through);
//  - a refracted direction about it can come out on the incident side.
// The repair, in two steps (the first after Cycles' ensure_valid_specular_reflection,
// derived and written here from its idea; three-gpu-pathtracer PR #792 ports it):
//  1. bend_shading_normal: when the mirror direction of wo about ns would leave
//     less than `t = min(0.9·cosθ_g, 0.01)` above the geometric surface, ns is
//     turned towards ng in the plane of (ns, ng), just far enough that it leaves at
//     exactly t. The result is continuous in wo and ns (no facet edges appear), is
//     ns itself wherever ns was fine, keeps dot(wo, ns') > 0 and is used for every
//     lobe of the hit (mirror, Fresnel, refraction, glossy, the diffuse cosine).
//  2. leave_side: a branch direction that still ends up on the wrong side of the
//     geometric surface (refraction about a strongly bent normal; rounding in step
//     1) is mirrored across the geometric plane: the same energy, continuous where
//     the violation begins (a direction in the plane maps to itself), and exactly
//     on the required side afterwards (a tangent result is lifted by 1e-3).
// Why not discard or resample: the Whitted tree has one ray per branch; discarding
// darkens exactly the rims where it happens, and this is what Cycles and pbrt's
// `ensure valid` ideas amount to for delta lobes.
// Direct light on a smooth face is taken over the shading normal's hemisphere, with
// shadow rays from the hit point lifted towards the smooth surface (Hanika 2021,
// "Hacking the shadow terminator"; geometry/triangles.hpp SmoothNormals::shade):
// without the lift, a light just below a facet's plane is blocked by the facet
// itself and the terminator of a coarse mesh is a staircase of black facets. The
// lift is zero on concave and flat parts, where the staircase cannot occur.
#pragma once

#include <cmath>

#include "runtime/vec.hpp"

namespace snell::rt {

// wo: unit, towards the viewer, dot(wo, ng) >= 0. ng: the unit geometric normal on
// the viewer's side. ns: the unit shading normal on the same side (dot(ns, ng) > 0).
// In double: the root below loses half its digits to cancellation in float.
inline Vec3f bend_shading_normal(Vec3f wo, Vec3f ng, Vec3f ns) {
  double g[3] = {ng.x, ng.y, ng.z}, s[3] = {ns.x, ns.y, ns.z}, w[3] = {wo.x, wo.y, wo.z};
  auto dot3 = [](const double* a, const double* b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  };
  double iz = dot3(w, g), ws = dot3(w, s), sg = dot3(s, g);
  double t = std::fmin(0.9 * iz, 0.01);
  // dot(reflect(wo, ns), ng) = 2·(wo·ns)(ns·ng) − wo·ng.
  if (2 * ws * sg - iz >= t) return ns;
  // The frame (X, ng) of the plane through ns and ng; wo's component across it does
  // not change the reflection's height above the surface.
  double x[3] = {s[0] - sg * g[0], s[1] - sg * g[1], s[2] - sg * g[2]};
  double xl = std::sqrt(dot3(x, x));
  if (!(xl > 0)) return ng;
  for (double& c : x) c /= xl;
  double ix = dot3(w, x);
  // N' = sqrt(1 - z)·X + sqrt(z)·ng with z = cos²α solving
  // 2(ix·sinα + iz·cosα)·cosα − iz = t, squared: 4a·z² − 2b·z + (iz + t)² = 0,
  // a = ix² + iz², b = 2(a + iz·t). The root whose sign agrees before squaring:
  // the larger one when ix < 0 (ns leans away from the viewer).
  double a = ix * ix + iz * iz;
  if (!(a > 0)) return ng;
  double b = 2 * (a + iz * t), c = (iz + t) * (iz + t);
  double disc = std::sqrt(std::fmax(0.0, b * b - 4 * a * c));
  double z = ix < 0 ? (b + disc) / (4 * a) : (b - disc) / (4 * a);
  z = std::fmin(1.0, std::fmax(0.0, z));
  double nx = std::sqrt(1 - z), nz = std::sqrt(z);
  Vec3f out = to_float(nx * x[0] + nz * g[0], nx * x[1] + nz * g[1], nx * x[2] + nz * g[2]);
  return normalize(out);
}

// `w` moved, if needed, to the side of the unit geometric normal `n` (dot(w, n) > 0
// afterwards): mirrored across the plane, then lifted off it when that leaves it
// tangent. `w` unit.
inline Vec3f leave_side(Vec3f w, Vec3f n) {
  float h = dot(w, n);
  if (h > 0) return w;
  w = w - n * (2 * h);
  if (dot(w, n) > 0) return w;
  w = normalize(w + n * 1e-3f);
  return dot(w, n) > 0 ? w : n;
}

// The normals of one hit as the ray tree uses them: `nf` geometric on the ray's side
// (entering, offsets, which side a branch leaves from), `ns` the lobes' normal on
// the same side (== nf unless the surface is smooth, then bent as above), and `nl`
// the normal direct light is taken about (the diffuse cosine, the §16 highlight).
// `nl` is `ns` except under a bump: §16 gives its shading normal as
// normalize(n − A·∇ₜP), changed only where it faces away from the viewer (then it
// is `ns`, which faces the viewer); the bend for mirror directions is about
// reflections and leaves the cosine alone. (A smooth mesh's `vn` keeps the bent
// normal for both: its direct light goes with the lifted shadow origin above.)
struct HitFrame {
  Vec3f nf, ns, nl;
  bool smooth = false;
  // wo: unit, towards the viewer; ns_outward: the surface's unit shading normal on
  // the side of its outward geometric normal; `bump`: it is a §16 bump's.
  static HitFrame make(Vec3f wo, Vec3f nf, bool entering, bool smooth, Vec3f ns_outward,
                       bool bump = false) {
    if (!smooth) return {nf, nf, nf, false};
    const Vec3f raw = entering ? ns_outward : -ns_outward;
    const Vec3f ns = bend_shading_normal(wo, nf, raw);
    return {nf, ns, bump && dot(wo, raw) > 0 ? raw : ns, true};
  }
  // A branch direction leaving on the ray's side (`outside`) or through the surface.
  Vec3f leave(Vec3f wi, bool outside) const {
    if (!smooth) return wi;
    return leave_side(wi, outside ? nf : -nf);
  }
};

}  // namespace snell::rt
