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
