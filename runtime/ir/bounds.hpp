// The one per-kind extent of a shape: the world points whose convex hull holds it.
// Validation (the float runtime's range) and the ray-offset scale both use it, and
// so does anything that needs an object's box.
#pragma once

#include <cmath>
#include <type_traits>
#include <variant>

#include "runtime/ir/ir.hpp"

namespace snell::ir {

// Object-space hull points per kind: f(object-space point).
// A sphere's and a box's: the 8 corners of their object-space box.
template <class F>
void hull_points(const Sphere& s, const Scene&, F&& f) {
  Vec3 lo = s.center - Vec3(s.radius), hi = s.center + Vec3(s.radius);
  for (int i = 0; i < 8; ++i)
    f(Vec3{i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z});
}
template <class F>
void hull_points(const Box& b, const Scene&, F&& f) {
  for (int i = 0; i < 8; ++i)
    f(Vec3{i & 1 ? b.max.x : b.min.x, i & 2 ? b.max.y : b.min.y, i & 4 ? b.max.z : b.min.z});
}
template <class F>
void hull_points(const Triangle& t, const Scene&, F&& f) {
  f(t.a), f(t.b), f(t.c);
}
template <class F>
void hull_points(const Mesh& m, const Scene& scene, F&& f) {
  if (m.mesh < scene.meshes.size())
    for (const Vec3& p : scene.meshes[m.mesh].positions) f(p);
}
// The axial shapes: the corners of the squares around each end disc in the frame
// of the axis (the convex hull of two discs holds the truncated cone between them).
template <class F>
void end_squares(Vec3 a, double ra, Vec3 b, double rb, Vec3 axis, F&& f) {
  Transform frame = axis_frame(a, normalize(axis));
  double h = dot(b - a, normalize(axis));
  for (int i = 0; i < 4; ++i) {
    double su = i & 1 ? 1 : -1, sv = i & 2 ? 1 : -1;
    f(frame.point({su * ra, sv * ra, 0}));
    f(frame.point({su * rb, sv * rb, h}));
  }
}
template <class F>
void hull_points(const Cylinder& c, const Scene&, F&& f) {
  end_squares(c.base, c.radius, c.cap, c.radius, c.cap - c.base, f);
}
template <class F>
void hull_points(const Cone& c, const Scene&, F&& f) {
  end_squares(c.base, c.base_radius, c.cap, c.cap_radius, c.cap - c.base, f);
}
template <class F>
void hull_points(const Disc& d, const Scene&, F&& f) {
  end_squares(d.center, d.radius, d.center, d.radius, d.normal, f);
}
// A torus: the corners of its box, |x|, |z| <= major + minor, |y| <= minor.
template <class F>
void hull_points(const Torus& t, const Scene&, F&& f) {
  double a = t.major + t.minor, b = t.minor;
  for (int i = 0; i < 8; ++i) f(Vec3{i & 1 ? a : -a, i & 2 ? b : -b, i & 4 ? a : -a});
}
// Planes are unbounded: no hull.
template <class F>
void hull_points(const Plane&, const Scene&, F&&) {}

// True for kinds with no finite extent (they stay out of bounding volumes).
template <class T>
inline constexpr bool kUnbounded = std::is_same_v<T, Plane>;
inline bool unbounded(const Shape& s) {
  return std::visit([](const auto& g) { return kUnbounded<std::decay_t<decltype(g)>>; }, s.geom);
}

// f(world point) for each hull point of `s`, placed by its world_from_object.
template <class F>
void world_hull_points(const Shape& s, const Scene& scene, F&& f) {
  std::visit(
      [&](const auto& g) {
        hull_points(g, scene, [&](Vec3 p) { f(s.world_from_object.point(p)); });
      },
      s.geom);
}

// The largest |coordinate| of `p - origin`.
inline double reach(Vec3 p, Vec3 origin) {
  Vec3 d = p - origin;
  return std::fmax(std::fabs(d.x), std::fmax(std::fabs(d.y), std::fabs(d.z)));
}

// How far the object reaches from `origin` (largest |coordinate| over its hull);
// an unbounded shape: the distance of its nearest point (a plane's foot).
double object_reach(const Shape& s, const Scene& scene, Vec3 origin);

}  // namespace snell::ir
