// Shape intersection in double precision, shared by the static and the moving
// geometry of the Embree scene (embree_scene.cpp); no Embree types here.
#pragma once

#include <cmath>
#include <cstdint>
#include <utility>

#include "runtime/ir/ir.hpp"
#include "runtime/vec.hpp"

namespace snell::rt::shapes {

using ir::Vec3;

// A sphere prepared for object-space intersection from camera-relative rays.
struct SphereData {
  ir::Mat4 object_from_rel;  // camera-relative world -> object space
  Vec3 center;
  double radius = 1;
  // A similarity transform (rotation, uniform scale, translation) keeps a sphere a
  // sphere: then it is intersected directly in camera-relative space, skipping the
  // per-ray matrix products (most scenes' spheres).
  bool similarity = false;
  Vec3 rel_center;
  double rel_radius = 1;
  std::uint32_t shape = 0;
};

struct PlaneData {
  Vec3 n;        // unit world normal
  double d = 0;  // dot(n, x) = d for camera-relative x
  std::uint32_t shape = 0;
  // A moving plane (motion on, shutter open) is placed at each ray's time instead.
  const ir::Shape* moving = nullptr;
};

inline Vec3 xform_point(const ir::Mat4& m, Vec3 p) {
  return {m(0, 0) * p.x + m(0, 1) * p.y + m(0, 2) * p.z + m(0, 3),
          m(1, 0) * p.x + m(1, 1) * p.y + m(1, 2) * p.z + m(1, 3),
          m(2, 0) * p.x + m(2, 1) * p.y + m(2, 2) * p.z + m(2, 3)};
}
inline Vec3 xform_vector(const ir::Mat4& m, Vec3 v) {
  return {m(0, 0) * v.x + m(0, 1) * v.y + m(0, 2) * v.z,
          m(1, 0) * v.x + m(1, 1) * v.y + m(1, 2) * v.z,
          m(2, 0) * v.x + m(2, 1) * v.y + m(2, 2) * v.z};
}
// Normal to world: inverse transpose of world_from_object = transpose of object_from_world.
inline Vec3 xform_normal_by_inverse(const ir::Mat4& inv, Vec3 n) {
  return {inv(0, 0) * n.x + inv(1, 0) * n.y + inv(2, 0) * n.z,
          inv(0, 1) * n.x + inv(1, 1) * n.y + inv(2, 1) * n.z,
          inv(0, 2) * n.x + inv(1, 2) * n.y + inv(2, 2) * n.z};
}
inline double det3(const ir::Mat4& m) {
  return m(0, 0) * (m(1, 1) * m(2, 2) - m(1, 2) * m(2, 1)) -
         m(0, 1) * (m(1, 0) * m(2, 2) - m(1, 2) * m(2, 0)) +
         m(0, 2) * (m(1, 0) * m(2, 1) - m(1, 1) * m(2, 0));
}

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

// Intersects sphere `s` with a camera-relative float ray; returns the nearest t in
// (tnear, tfar) and the outward unit world normal.
inline bool hit_sphere(const SphereData& s, float ox, float oy, float oz, float dx, float dy,
                       float dz, float tnear, float tfar, float& t_out, Vec3f& n_out) {
  double t0, t1;
  if (s.similarity) {
    Vec3 o(ox, oy, oz), d(dx, dy, dz);
    if (!sphere_roots(o, d, s.rel_center, s.rel_radius, t0, t1)) return false;
    double t = t0 > tnear ? t0 : t1;
    if (!(t > tnear) || !(t < tfar)) return false;
    t_out = static_cast<float>(t);
    if (!(t_out > tnear && t_out < tfar)) return false;
    Vec3 n = (o + d * t - s.rel_center) / s.rel_radius;
    n = ir::normalize(n);
    n_out = to_float(n.x, n.y, n.z);
    return true;
  }
  Vec3 o = xform_point(s.object_from_rel, Vec3(ox, oy, oz));
  Vec3 d = xform_vector(s.object_from_rel, Vec3(dx, dy, dz));
  if (!sphere_roots(o, d, s.center, s.radius, t0, t1)) return false;
  double t = t0 > tnear ? t0 : t1;
  if (!(t > tnear) || !(t < tfar)) return false;
  Vec3 no = (o + d * t - s.center) / s.radius;
  Vec3 nw = ir::normalize(xform_normal_by_inverse(s.object_from_rel, no));
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
    for (int k = 0; k < 3; ++k) lo[k] = std::fmin(lo[k], w[k]), hi[k] = std::fmax(hi[k], w[k]);
  }
}

}  // namespace snell::rt::shapes
