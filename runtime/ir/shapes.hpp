// Shapes: one plain struct per kind (kinds.def) in the object's own space, each
// naming its fields once (fields.hpp), and the Shape that places one in the
// world with a material, transforms and motion. Member initialisers are the
// kinds' defaults (compiler/properties.def takes its defaults from them).
#pragma once

#include <cstdint>
#include <string>
#include <tuple>
#include <variant>
#include <vector>

#include "runtime/ir/enums.hpp"
#include "runtime/ir/fields.hpp"
#include "runtime/ir/materials.hpp"
#include "runtime/ir/math.hpp"
#include "runtime/ir/source_ref.hpp"

namespace snell::ir {

// Each kind names its fields and, in `hull(scene, f)`, the object-space points
// whose convex hull holds it (ir/bounds.hpp: validation's range and the ray-offset
// scale). A kind with no finite extent says `static constexpr bool kUnbounded`.
struct Sphere {
  Vec3 center{0, 0, 0};
  double radius = 1;
  // The 8 corners of its object-space box.
  template <class Scene, class F>
  void hull(const Scene&, F&& f) const {
    Vec3 lo = center - Vec3(radius), hi = center + Vec3(radius);
    for (int i = 0; i < 8; ++i)
      f(Vec3{i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z});
  }
  static constexpr auto fields() {
    return std::tuple{field("center", &Sphere::center), field("radius", &Sphere::radius)};
  }
};
// Points p with dot(p, normal) = distance; normal unit length (lowering normalises).
struct Plane {
  Vec3 normal{0, 1, 0};
  double distance = 0;
  static constexpr bool kUnbounded = true;
  template <class Scene, class F>
  void hull(const Scene&, F&&) const {}
  static constexpr auto fields() {
    return std::tuple{field("normal", &Plane::normal), field("distance", &Plane::distance)};
  }
};
struct Box {
  Vec3 min{0, 0, 0}, max{0, 0, 0};
  template <class Scene, class F>
  void hull(const Scene&, F&& f) const {
    for (int i = 0; i < 8; ++i)
      f(Vec3{i & 1 ? max.x : min.x, i & 2 ? max.y : min.y, i & 4 ? max.z : min.z});
  }
  static constexpr auto fields() {
    return std::tuple{field("min", &Box::min), field("max", &Box::max)};
  }
};
struct Triangle {
  Vec3 a, b, c;
  template <class Scene, class F>
  void hull(const Scene&, F&& f) const {
    f(a), f(b), f(c);
  }
  static constexpr auto fields() {
    return std::tuple{field("a", &Triangle::a), field("b", &Triangle::b), field("c", &Triangle::c)};
  }
};
// A mesh object: an index into Scene::meshes (the triangles, shared by every
// object that names the same file).
struct Mesh {
  std::uint32_t mesh = 0;
  template <class Scene, class F>
  void hull(const Scene& scene, F&& f) const {
    if (mesh < scene.meshes.size())
      for (const Vec3& p : scene.meshes[mesh].positions) f(p);
  }
  static constexpr auto fields() { return std::tuple{field("mesh", &Mesh::mesh)}; }
};

#define SNELL_SHAPE(name, Type) Type,
using ShapeGeom = variant_of<
#include "runtime/ir/kinds.def"
    ListEnd>;

#define SNELL_SHAPE SNELL_KIND_NAME
#include "runtime/ir/kinds.def"

// One transform step of a `motion { }` block (§8).
struct TransformOp {
  enum class Kind : std::uint8_t { Translate, Rotate, Scale };
  Kind kind = Kind::Translate;
  Vec3 value;
};

// How an object moves during the shutter interval. At time fraction u in [0, 1]
// (0 = shutter open, 1 = shutter close) each op is applied partially: translate
// u·V, rotate u·R (degrees, x then y then z), scale (1-u) + u·S. The object's
// transform at u is motion_at(u) * world_from_object.
struct Motion {
  std::vector<TransformOp> ops;
  bool moves() const;
  Transform at(double u) const;
};

struct Shape {
  ShapeGeom geom;               // the object-space definition, as written in the block
  std::uint32_t material = 0;   // index into Scene::materials
  Transform world_from_object;  // the object's transforms, in the order written
  Motion motion;
  SourceRef src;
  ShapeKind kind() const { return ShapeKind(geom.index()); }
  template <class T>
  const T* as() const {
    return std::get_if<T>(&geom);
  }
};

// The triangles of mesh files, in object space.
struct MeshData {
  std::string path;                    // as resolved on disk
  std::vector<Vec3> positions;         // object space
  std::vector<std::uint32_t> indices;  // three per triangle
};

}  // namespace snell::ir
