// The one per-kind extent of a shape: the world points whose convex hull holds it.
// Validation (the float runtime's range) and the ray-offset scale both use it, and
// so does anything that needs an object's box.
#pragma once

#include <cmath>
#include <type_traits>
#include <variant>

#include "runtime/ir/ir.hpp"

namespace snell::ir {

// Object-space hull points of a kind: its own hull() (shapes.hpp); a kind may
// instead give an overload here.
template <class K, class F>
void hull_points(const K& kind, const Scene& scene, F&& f) {
  kind.hull(scene, f);
}

// True for kinds with no finite extent (they stay out of bounding volumes).
template <class T>
concept UnboundedKind = requires {
  T::kUnbounded;
};
template <class T>
inline constexpr bool kUnbounded = UnboundedKind<T>;
inline bool unbounded(const Shape& s) {
  return std::visit([](const auto& g) { return kUnbounded<std::decay_t<decltype(g)>>; }, s.geom);
}

// f(world point) for each hull point of `s`, placed by its world_from_object.
template <class F>
void world_hull_points(const Shape& s, const Scene& scene, F&& f) {
  std::visit(
      [&](const auto& g) {
        hull_points(g, scene, [&](Vec3 p) { f(s.world_from_object().point(p)); });
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
