// The geometry seam: how each IR shape kind (runtime/ir/kinds.def) enters the
// scene query. A kind belongs to one class:
//   Triangles  object_triangles(kind, scene, flip, soup) gives its triangles; the
//              BVH holds them as triangle geometry (moving ones with time steps).
//   User       a primitive set (one per kind, and one for its moving objects) that
//              the BVH calls back; the set's interface:
//                void add(const ir::Shape&, const Kind&, uint32_t shape_index, Vec3 origin)
//                size_t size() const;  uint32_t shape(unsigned prim) const
//                void bounds(unsigned prim, Box3&) const      camera-relative, double
//                bool hit(unsigned prim, float time, Vec3f o, Vec3f d, float tnear,
//                         float tfar, float& t, Vec3f& n) const
//                void refine(unsigned prim, const Ray&, float t, Hit&) const
//                             the hit point and its bounded offset (Hit::offset)
//   Unbounded  a set tested analytically after the BVH query (planes):
//                add(shape, kind, index, origin, moving), intersect(ray, tmax&, tie, hit),
//                occluded(ray), occluded_lanes(shadow lanes, live mask)
// Solids also give their ray intervals [t_in, t_out]... (intervals.hpp), which CSG
// composes.
// The accelerator (embree_scene.cpp) builds per class, never per shape, and is the
// only code that knows Embree. Adding a kind: its file here, its Geometry<>
// specialisation, and — for a user kind — its sets in UserSets (a kind intersected
// in a local frame writes only a local surface; local_set.hpp makes its sets).
#pragma once

#include <tuple>

#include "runtime/geometry/cone.hpp"
#include "runtime/geometry/csg.hpp"
#include "runtime/geometry/disc.hpp"
#include "runtime/geometry/local_set.hpp"
#include "runtime/geometry/plane.hpp"
#include "runtime/geometry/sphere.hpp"
#include "runtime/geometry/torus.hpp"
#include "runtime/geometry/triangles.hpp"

namespace snell::rt::geom {

enum class GeometryClass { Triangles, User, Unbounded, Instance };

template <class Kind>
struct Geometry;

template <>
struct Geometry<ir::Sphere> {
  static constexpr GeometryClass kind = GeometryClass::User;
  using Static = SphereSet;
  using Moving = MovingSphereSet;
};
template <>
struct Geometry<ir::Plane> {
  static constexpr GeometryClass kind = GeometryClass::Unbounded;
  using Set = PlaneSet;
};
template <>
struct Geometry<ir::Box> {
  static constexpr GeometryClass kind = GeometryClass::Triangles;
};
template <>
struct Geometry<ir::Triangle> {
  static constexpr GeometryClass kind = GeometryClass::Triangles;
};
template <>
struct Geometry<ir::Mesh> {
  static constexpr GeometryClass kind = GeometryClass::Triangles;
};

// §11's shapes: a local surface each (local_set.hpp), so their sets are the two
// templates; cylinders and cones share one surface type and so one pair of sets.
template <>
struct Geometry<ir::Cylinder> {
  static constexpr GeometryClass kind = GeometryClass::User;
  using Static = LocalSet<TruncatedCone>;
  using Moving = MovingLocalSet<TruncatedCone>;
};
template <>
struct Geometry<ir::Cone> : Geometry<ir::Cylinder> {};
template <>
struct Geometry<ir::Disc> {
  static constexpr GeometryClass kind = GeometryClass::User;
  using Static = LocalSet<DiscSurface>;
  using Moving = MovingLocalSet<DiscSurface>;
};
template <>
struct Geometry<ir::Torus> {
  static constexpr GeometryClass kind = GeometryClass::User;
  using Static = LocalSet<TorusSurface>;
  using Moving = MovingLocalSet<TorusSurface>;
};

// §12: one user primitive per CSG object (csg.hpp); its set also takes the scene
// (`add(shape, kind, index, origin, scene)`: the tree) and reports the leaf hit.
template <>
struct Geometry<ir::Csg> {
  static constexpr GeometryClass kind = GeometryClass::User;
  using Static = CsgSet;
  using Moving = MovingCsgSet;
};
// §13: an instance of a prototype, which the accelerator builds once as a BVH of
// its own and instances (embree_scene.cpp).
template <>
struct Geometry<ir::Instance> {
  static constexpr GeometryClass kind = GeometryClass::Instance;
};

// Every user primitive set, in the order the BVH attaches them, and every
// unbounded set.
using UserSets =
    std::tuple<SphereSet, MovingSphereSet, LocalSet<TruncatedCone>, MovingLocalSet<TruncatedCone>,
               LocalSet<DiscSurface>, MovingLocalSet<DiscSurface>, LocalSet<TorusSurface>,
               MovingLocalSet<TorusSurface>, CsgSet, MovingCsgSet>;
using UnboundedSets = std::tuple<PlaneSet>;

}  // namespace snell::rt::geom
