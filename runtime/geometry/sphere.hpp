// Spheres (§5): intersected in object space in double precision, so any affine
// transform (non-uniform scale, rotation) is exact; robust discriminant (Haines et
// al., RTG ch. 7). Static spheres and spheres that move while the shutter is open
// are two primitive sets of the user-geometry class (traits.hpp). No Embree types.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "runtime/geometry/motion.hpp"
#include "runtime/geometry/ray.hpp"
#include "runtime/geometry/xform.hpp"
#include "runtime/ir/ir.hpp"
#include "runtime/vec.hpp"

namespace snell::rt::geom {

// How many ulps of a hit point's largest coordinate a ray leaving a sphere or a
// plane starts off it (sphere.cpp: why 8).
inline constexpr double kSurfaceOffsetUlps = 8;

// A moving sphere placed at a ray's time, for object-space intersection from
// camera-relative rays.
struct SphereData {
  ir::Mat4 object_from_rel;  // camera-relative world -> object space
  Vec3 center;
  double radius = 1;
};

// Smallest and largest roots of |o + t d - c|² = r² in double, with the
// discriminant in the cancellation-free form of Haines et al. (RTG ch. 7).
inline bool sphere_roots(Vec3 o, Vec3 d, Vec3 c, double r, double& t0, double& t1) {
  Vec3 f = o - c;
  double a = ir::dot(d, d);
  double b = ir::dot(f, d);  // half of the usual b
  Vec3 v = f - d * (b / a);
  double lv = ir::length(v);
  double disc = (r + lv) * (r - lv);  // r² - |v|², i.e. the discriminant / (4a)
  if (!(disc >= 0)) return false;
  double cc = ir::dot(f, f) - r * r;
  double q = -b - std::copysign(std::sqrt(a * disc), b);
  if (q == 0) {  // ray through the centre aimed... degenerate only for a = 0 or o = c
    double s = std::sqrt(disc / a);
    t0 = -s, t1 = s;
    return a > 0;
  }
  t0 = cc / q;
  t1 = q / a;
  if (t0 > t1) std::swap(t0, t1);
  return true;
}

// 2^-e for a radius r in [2^e, 2^(e+1)): multiplying by it is exact, and takes a
// vector r long to one between 1 and 2 long, in float's range whatever r is.
inline double normal_scale(double r) {
  const std::uint64_t bits = std::bit_cast<std::uint64_t>(r);
  const int e = int((bits >> 52) & 0x7ff);                          // r > 0: the biased exponent
  if (e == 0 || e >= 2046) return std::ldexp(1.0, -std::ilogb(r));  // subnormal or near max
  return std::bit_cast<double>(std::uint64_t(2046 - e) << 52);
}

// Intersects the camera-relative sphere (rel_center, rel_radius) with a
// camera-relative float ray; returns the nearest t in (tnear, tfar) and the outward
// world normal, not unit: (o + t·d − c) in double, scaled exactly by
// normal_scale(r), then rounded to float. The hit's user normalises it in float
// (finish_hit, for the one hit that is kept): the cancellation of o + t·d − c is
// done in double, so the float normal is within a few float ulps of the exact one.
// A packet's candidate hits (sphere_lanes) skip the double normalisation's three
// divisions and square root, most of them for hits a nearer one replaces.
inline bool hit_similar_sphere(Vec3 rel_center, double rel_radius, float ox, float oy, float oz,
                               float dx, float dy, float dz, float tnear, float tfar, float& t_out,
                               Vec3f& n_out) {
  double t0, t1;
  Vec3 o(ox, oy, oz), d(dx, dy, dz);
  if (!sphere_roots(o, d, rel_center, rel_radius, t0, t1)) return false;
  double t = t0 > tnear ? t0 : t1;
  if (!(t > tnear) || !(t < tfar)) return false;
  t_out = static_cast<float>(t);
  if (!(t_out > tnear && t_out < tfar)) return false;
  Vec3 n = (o + d * t - rel_center) * normal_scale(rel_radius);
  n_out = to_float(n.x, n.y, n.z);
  return true;
}

// The same for the object-space sphere (center, radius) under any affine
// `object_from_rel`: the ray is taken to object space and intersected there.
inline bool hit_general_sphere(const ir::Mat4& object_from_rel, Vec3 center, double radius,
                               float ox, float oy, float oz, float dx, float dy, float dz,
                               float tnear, float tfar, float& t_out, Vec3f& n_out) {
  double t0, t1;
  Vec3 o = xform_point(object_from_rel, Vec3(ox, oy, oz));
  Vec3 d = xform_vector(object_from_rel, Vec3(dx, dy, dz));
  if (!sphere_roots(o, d, center, radius, t0, t1)) return false;
  double t = t0 > tnear ? t0 : t1;
  if (!(t > tnear) || !(t < tfar)) return false;
  Vec3 no = (o + d * t - center) / radius;
  Vec3 nw = ir::normalize(xform_normal_by_inverse(object_from_rel, no));
  t_out = static_cast<float>(t);
  if (!(t_out > tnear && t_out < tfar)) return false;
  n_out = to_float(nw.x, nw.y, nw.z);
  return true;
}

// Camera-relative bounds of the object-space box around sphere (c, r) under the
// affine `rel_from_object`, accumulated into lo/hi.
inline void sphere_box(const ir::Mat4& rel_from_object, Vec3 c, double r, double lo[3],
                       double hi[3]) {
  for (int i = 0; i < 8; ++i) {
    Vec3 q = c + Vec3(i & 1 ? r : -r, i & 2 ? r : -r, i & 4 ? r : -r);
    Vec3 w = xform_point(rel_from_object, q);
    for (int k = 0; k < 3; ++k) lo[k] = ir::min_num(lo[k], w[k]), hi[k] = ir::max_num(hi[k], w[k]);
  }
}

// The static spheres: one user primitive each (the interface of traits.hpp).
// The static spheres: 48 bytes each when the transform is a similarity (most
// scenes' spheres), plus 288 for the matrices of any other (#18: 10 M spheres).
// The bounds are recomputed from the IR shape as the BVH builds, as the general
// case's matrices were made, so the BVH and every image are what they were when
// each sphere held both matrices. The IR scene outlives the set (as for
// MovingSphereSet).
class SphereSet {
 public:
  void reserve(std::size_t n) { spheres_.reserve(n); }
  void add(const ir::Shape& s, const ir::Sphere& g, std::uint32_t index, Vec3 origin);
  std::size_t size() const { return spheres_.size(); }
  std::uint32_t shape(unsigned prim) const { return spheres_[prim].shape; }
  void bounds(unsigned prim, Box3& box) const;
  bool hit(unsigned prim, float, Vec3f o, Vec3f d, float tnear, float tfar, float& t,
           Vec3f& n) const {
    const Static& s = spheres_[prim];
    if (s.general == kSimilar)
      return hit_similar_sphere(s.rel_center, s.rel_radius, o.x, o.y, o.z, d.x, d.y, d.z, tnear,
                                tfar, t, n);
    const General& g = general_[s.general];
    return hit_general_sphere(g.object_from_rel, g.center, g.radius, o.x, o.y, o.z, d.x, d.y, d.z,
                              tnear, tfar, t, n);
  }
  // The hit point projected onto the sphere in double, and its bounded offset.
  void refine(unsigned prim, const Ray& r, float t, Hit& hit) const;
  // A similarity's sphere, camera-relative (what hit() tests), for a packet's test
  // of all its lanes at once (sphere_lanes.hpp); false for any other transform.
  bool similar(unsigned prim, Vec3& centre, double& radius) const {
    const Static& s = spheres_[prim];
    centre = s.rel_center, radius = s.rel_radius;
    return s.general == kSimilar;
  }

 private:
  static constexpr std::uint32_t kSimilar = 0xffffffffu;
  struct Static {
    Vec3 rel_center;  // camera-relative; a similarity's sphere
    double rel_radius = 1;
    const ir::Shape* ir = nullptr;  // for the bounds
    std::uint32_t shape = 0;
    std::uint32_t general = kSimilar;  // into general_, or kSimilar
  };
  struct General {
    ir::Mat4 object_from_rel, rel_from_object;
    Vec3 center;  // object space
    double radius = 1;
  };
  std::vector<Static> spheres_;
  std::vector<General> general_;
  Vec3 origin_{0, 0, 0};  // of the layer: every add passes the same one
};

// Spheres that move during the open shutter: user geometry whose static bounds
// hold the whole sweep; the intersector places the sphere at the ray's time
// (Motion::at, exact rotation) and intersects it in object space in double.
class MovingSphereSet {
 public:
  void add(const ir::Shape& s, const ir::Sphere& g, std::uint32_t index, Vec3 origin);
  std::size_t size() const { return spheres_.size(); }
  std::uint32_t shape(unsigned prim) const { return spheres_[prim].index; }
  void bounds(unsigned prim, Box3& box) const;
  bool hit(unsigned prim, float time, Vec3f o, Vec3f d, float tnear, float tfar, float& t,
           Vec3f& n) const {
    return may_hit(spheres_[prim], time, o, d, tnear, tfar) &&
           hit_exact(prim, time, o, d, tnear, tfar, t, n);
  }
  // o + t·d with no bound of its own (unbounded_offset): the Wächter–Binder offset
  // covers its error.
  void refine(unsigned, const Ray& r, float t, Hit& hit) const {
    hit.p = r.org + r.dir * t, hit.offset = unbounded_offset(r, hit.p);
  }
  // hit() without its pre-test, and the pre-test alone (tests: the pre-test never
  // turns away a ray the exact test hits).
  bool hit_exact(unsigned prim, float time, Vec3f o, Vec3f d, float tnear, float tfar, float& t,
                 Vec3f& n) const {
    SphereData s = at(spheres_[prim], time);
    return hit_general_sphere(s.object_from_rel, s.center, s.radius, o.x, o.y, o.z, d.x, d.y, d.z,
                              tnear, tfar, t, n);
  }
  bool may_hit(unsigned prim, float time, Vec3f o, Vec3f d, float tnear, float tfar) const {
    return may_hit(spheres_[prim], time, o, d, tnear, tfar);
  }

 private:
  // The shutter in kSegments equal parts, each with the box of the sphere's sweep
  // over it (grown like bounds(), plus a margin for the slab test's rounding).
  // Embree's box holds the whole sweep; a ray that crosses it but not its own
  // part's box cannot hit the sphere at its time, and is turned away before the
  // placement (three 4x4 products in double) is computed.
  static constexpr unsigned kSegments = 8;
  struct Moving {
    const ir::Shape* shape = nullptr;
    ir::Sphere sphere;
    Vec3 origin;
    std::uint32_t index = 0;
    Box3 part[kSegments];
  };
  static SphereData at(const Moving& m, float time);
  // False only when the ray's segment (tnear, tfar) misses its part's box.
  static bool may_hit(const Moving& m, float time, Vec3f o, Vec3f d, float tnear, float tfar) {
    double u = shutter_fraction(time) * kSegments;
    const Box3& b = m.part[u < kSegments - 1 ? unsigned(u) : kSegments - 1];
    double t0 = tnear, t1 = tfar;
    const float os[3] = {o.x, o.y, o.z}, ds[3] = {d.x, d.y, d.z};
    for (int k = 0; k < 3; ++k) {
      if (ds[k] == 0) {
        if (!(os[k] >= b.lo[k] && os[k] <= b.hi[k])) return false;
        continue;
      }
      double inv = 1.0 / double(ds[k]);
      double ta = (b.lo[k] - os[k]) * inv, tb = (b.hi[k] - os[k]) * inv;
      if (ta > tb) std::swap(ta, tb);
      t0 = ir::max_num(t0, ta), t1 = ir::min_num(t1, tb);
      if (!(t0 <= t1)) return false;
    }
    return true;
  }
  std::vector<Moving> spheres_;
};

}  // namespace snell::rt::geom
