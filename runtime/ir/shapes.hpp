// Shapes: one plain struct per kind (kinds.def) in the object's own space, each
// naming its fields once (fields.hpp), and the Shape that places one in the
// world with a material, transforms and motion. Member initialisers are the
// kinds' defaults (compiler/properties.def takes its defaults from them).
#pragma once

#include <algorithm>
#include <cstdint>
#include <functional>
#include <string>
#include <tuple>
#include <variant>
#include <vector>

#include "runtime/ir/enums.hpp"
#include "runtime/ir/fields.hpp"
#include "runtime/ir/materials.hpp"
#include "runtime/ir/math.hpp"
#include "runtime/ir/source_ref.hpp"
#include "runtime/ir/sparse.hpp"

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

// The axial shapes' hull: the corners of the squares around each end disc in the
// frame of the axis (the convex hull of two discs holds the truncated cone between
// them).
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

// §11. The points within `radius` of the segment base..cap's line, between the
// planes through base and cap perpendicular to it; `open`: the curved side only.
struct Cylinder {
  template <class Scene, class F>
  void hull(const Scene&, F&& f) const {
    end_squares(base, radius, cap, radius, cap - base, f);
  }
  Vec3 base{0, 0, 0}, cap{0, 1, 0};
  double radius = 1;
  bool open = false;
  static constexpr auto fields() {
    return std::tuple{field("base", &Cylinder::base), field("cap", &Cylinder::cap),
                      field("radius", &Cylinder::radius), field("open", &Cylinder::open)};
  }
};
// §11. A truncated cone: radius base_radius at base to cap_radius at cap, linearly
// (radii >= 0, not both 0).
struct Cone {
  template <class Scene, class F>
  void hull(const Scene&, F&& f) const {
    end_squares(base, base_radius, cap, cap_radius, cap - base, f);
  }
  Vec3 base{0, 0, 0};
  double base_radius = 1;
  Vec3 cap{0, 1, 0};
  double cap_radius = 0;
  bool open = false;
  static constexpr auto fields() {
    return std::tuple{field("base", &Cone::base), field("base_radius", &Cone::base_radius),
                      field("cap", &Cone::cap), field("cap_radius", &Cone::cap_radius),
                      field("open", &Cone::open)};
  }
};
// §11. The annulus hole <= |p - center| <= radius in the plane through center with
// `normal` (non-zero; lowering normalises it), which is its outward normal.
struct Disc {
  template <class Scene, class F>
  void hull(const Scene&, F&& f) const {
    end_squares(center, radius, center, radius, normal, f);
  }
  Vec3 center{0, 0, 0}, normal{0, 1, 0};
  double radius = 1, hole = 0;
  static constexpr auto fields() {
    return std::tuple{field("center", &Disc::center), field("normal", &Disc::normal),
                      field("radius", &Disc::radius), field("hole", &Disc::hole)};
  }
};
// §11. Centred at the origin around the y axis: the points at distance `minor` from
// the circle of radius `major` in the xz plane (major > minor > 0).
struct Torus {
  // The corners of its box, |x|, |z| <= major + minor, |y| <= minor.
  template <class Scene, class F>
  void hull(const Scene&, F&& f) const {
    double a = major + minor, b = minor;
    for (int i = 0; i < 8; ++i) f(Vec3{i & 1 ? a : -a, i & 2 ? b : -b, i & 4 ? a : -a});
  }
  double major = 1, minor = 0.25;
  static constexpr auto fields() {
    return std::tuple{field("major", &Torus::major), field("minor", &Torus::minor)};
  }
};

// §12. A CSG object: the tree rooted at Scene::csg_nodes[node], whose leaves are
// Scene::parts placed in the CSG object's space.
struct Csg {
  std::uint32_t node = 0;
  template <class Scene, class F>
  void hull(const Scene& scene, F&& f) const;  // below: the leaves' hulls
  static constexpr auto fields() { return std::tuple{field("node", &Csg::node)}; }
};
// §13. An instance: Scene::prototypes[prototype], shared by every instance of it,
// placed by the instance's transforms.
struct Instance {
  std::uint32_t prototype = 0;
  template <class Scene, class F>
  void hull(const Scene& scene, F&& f) const;  // below: the prototype's parts' hulls
  static constexpr auto fields() { return std::tuple{field("prototype", &Instance::prototype)}; }
};

#define SNELL_SHAPE(name, Type) Type,
#define SNELL_COMPOSITE(name, Type) Type,
using ShapeGeom = variant_of<
#include "runtime/ir/kinds.def"
    ListEnd>;

#define SNELL_SHAPE SNELL_KIND_NAME
#define SNELL_COMPOSITE SNELL_KIND_NAME
#include "runtime/ir/kinds.def"

// One transform step of a `motion { }` block (§8).
struct TransformOp {
  enum class Kind : std::uint8_t { Translate, Rotate, Scale };
  Kind kind = Kind::Translate;
  Vec3 value;
};

// The `motion { }` block of an object inside others (§12, §13). It acts where the
// object's own transforms leave it: in its parent's space, which the static
// transforms of the objects around it place in the world (or in a CSG object's
// space, for a leaf) by `world_from_frame`. Its pivot is a point of that space.
struct MotionBlock {
  Transform world_from_frame;
  std::vector<TransformOp> ops;
  bool has_pivot = false;
  Vec3 pivot{0, 0, 0};
};

// How an object moves during the shutter interval. At time fraction u in [0, 1]
// (0 = shutter open, 1 = shutter close) each op is applied partially: translate
// u·V, rotate u·R (degrees, x then y then z), scale (1-u) + u·S; with a pivot P
// (§19) a rotation or scale step is translate -P, the step, translate P. The
// object's transform at u is at(u) * world_from_object.
//
// `ops` and `pivot` are a block that acts in the world's own frame (a top-level
// object's motion, or that of an object whose enclosing objects have no
// transforms). The objects around a moving object may move too, and an object
// inside static ones moves in their space: `nested` holds those blocks, outermost
// first, each carried into the world by its frame, so
//   at(u) = block(u) · Π_k F_k · nested_k(u) · F_k⁻¹
// (§8's "motion after the object's transforms" and §13's "the instance's
// transforms after the value's own", composed). A motion of one world block is
// computed as it always was, to the bit.
struct Motion {
  std::vector<TransformOp> ops;
  bool has_pivot = false;  // false: about the origin (§8), no translations at all
  Vec3 pivot{0, 0, 0};
  std::vector<MotionBlock> nested{};
  bool moves() const;
  // No steps at all: at(u) is the identity (without computing it).
  bool empty() const { return ops.empty() && nested.empty(); }
  Transform at(double u) const;
  InverseTransform inverse_at(double u) const;  // at(u).inv, the same bits, half the work
};
// The same steps in the same frames (so the same at(u), to the bit).
bool same_motion(const Motion& a, const Motion& b);

// The motion of an object whose own motion is `own` (in its parent's space, placed
// in the world by `world_from_frame`) inside objects that move by `outer`.
Motion nest_motion(const Motion& outer, const Transform& world_from_frame, const Motion& own);

// §15 `space "object"`: the space of the top-level object a shape belongs to, where
// that is not the shape itself: a child of a top-level `union` (placed in the
// scene one by one) takes the union's space, and an instance placed by another
// instance's value the outer instance's. Patterns move with it.
struct ObjectSpace {
  Transform world_from_object;
  Motion motion;
};

// A shape's transform and motion are held out of line, and only when they are not
// the default (identity, still): most of a big scene's objects are spheres placed
// by `center`, and inline the two took 312 of a Shape's 416 bytes (#18: 10 M
// spheres). Read them through world_from_object() and motion(); set them whole.
struct Shape {
  ShapeGeom geom;              // the object-space definition, as written in the block
  std::uint32_t material = 0;  // index into Scene::materials
  SourceRef src;
  ShapeKind kind() const { return ShapeKind(geom.index()); }
  template <class T>
  const T* as() const {
    return std::get_if<T>(&geom);
  }
  // The object's transforms, in the order written.
  const Transform& world_from_object() const { return world_from_object_.get(); }
  const Motion& motion() const { return motion_.get(); }
  void set_world_from_object(const Transform& t) { world_from_object_.set(t, t.is_identity()); }
  void set_motion(Motion m) {
    bool still = m.ops.empty() && !m.has_pivot && m.nested.empty();
    motion_.set(std::move(m), still);
  }
  // The enclosing top-level object's space (ObjectSpace), when it has one.
  bool in_object() const { return object_space_.held(); }
  const ObjectSpace& object_space() const { return object_space_.get(); }
  void set_object_space(ObjectSpace o) { object_space_.set(std::move(o), false); }

 private:
  Sparse<Transform> world_from_object_;
  Sparse<Motion> motion_;
  Sparse<ObjectSpace> object_space_;
};

// A part (an element of Scene::parts: a CSG leaf or a prototype's shape) whose
// material is this takes the material of the instance that places it (§13: an
// instance's material applies to the children that have none).
inline constexpr std::uint32_t kInheritMaterial = 0xffffffffu;
inline constexpr std::uint32_t kNoPart = 0xffffffffu;

// A node of a CSG tree (§12): a leaf names a part (Scene::parts[part]: a solid,
// placed in the CSG object's space by its world_from_object), an operation its
// children (indices into Scene::csg_nodes). Inside another CSG a union is the
// solid union of its children, as merge is.
struct CsgNode {
  CsgOp op = CsgOp::Union;
  std::uint32_t part = kNoPart;
  std::vector<std::uint32_t> children;
  bool leaf() const { return part != kNoPart; }
};

// The shared geometry of the instances of one object value (§13): parts placed in
// the value's own space.
struct Prototype {
  std::vector<std::uint32_t> parts;  // into Scene::parts
  // The box of the parts' hull points in the prototype's space (the compiler fills
  // it): an instance's hull is its corners, not every vertex of a mesh again.
  Vec3 lo{0, 0, 0}, hi{0, 0, 0};
  SourceRef src;
};

// The triangles of mesh files, in object space.
struct MeshData {
  // A corner of a flat face in `normal_indices`.
  static constexpr std::uint32_t kNoNormal = 0xffffffffu;
  std::string path;                    // as resolved on disk
  std::vector<Vec3> positions;         // object space
  std::vector<std::uint32_t> indices;  // three per triangle
  // Smooth shading (OBJ `vn`): unit object-space normals and, parallel to
  // `indices`, the one each corner interpolates, or kNoNormal at all three corners
  // of a face that shades flat (a corner without a usable vn). Both are empty when
  // every face is flat: such a mesh renders exactly as one without normals.
  std::vector<Vec3> normals;
  std::vector<std::uint32_t> normal_indices;
  // Whether the triangles bound a solid (ir/mesh_topology.hpp: watertight after
  // welding equal positions, consistently wound, outward); when not, `open_reason`
  // says why in words an error can quote ("has 14 boundary edges, e.g. (v3, v7)").
  bool closed = false;
  std::string open_reason;
  // Texture coordinates (OBJ `vt`, §17 mapping "uv"): (u, v, 0) and, parallel to
  // `indices`, the one each corner takes. Both empty unless every kept face names
  // a usable vt at each corner (a mesh partly mapped has none: "uv" then falls
  // back to the triangles' barycentrics, as for a mesh without vt).
  std::vector<Vec3> texcoords;
  std::vector<std::uint32_t> texcoord_indices;
  bool smooth() const { return !normal_indices.empty(); }
};

// The composites' hulls: every leaf's hull points, placed in the composite's space
// (a difference's removed children add nothing: it lies inside its first child).
// The callback is type-erased: a part may itself be a composite, and a template
// over the callback would recurse in its instantiation.
template <class Scene>
void composite_hull(const Scene& scene, const Shape& part, const std::function<void(Vec3)>& f);
template <class Scene>
void csg_hull(const Scene& scene, std::uint32_t node, const std::function<void(Vec3)>& f) {
  if (node >= scene.csg_nodes.size()) return;
  const CsgNode& n = scene.csg_nodes[node];
  if (n.leaf()) {
    if (n.part < scene.parts.size()) composite_hull(scene, scene.parts[n.part], f);
    return;
  }
  std::size_t count =
      n.op == CsgOp::Difference ? std::min<std::size_t>(1, n.children.size()) : n.children.size();
  for (std::size_t i = 0; i < count; ++i) csg_hull(scene, n.children[i], f);
}
template <class Scene>
void composite_hull(const Scene& scene, const Shape& part, const std::function<void(Vec3)>& f) {
  std::function<void(Vec3)> placed = [&](Vec3 p) { f(part.world_from_object().point(p)); };
  std::visit([&](const auto& g) { g.hull(scene, placed); }, part.geom);
}
template <class Scene, class F>
void Csg::hull(const Scene& scene, F&& f) const {
  csg_hull(scene, node, std::function<void(Vec3)>(std::ref(f)));
}
template <class Scene, class F>
void Instance::hull(const Scene& scene, F&& f) const {
  if (prototype >= scene.prototypes.size()) return;
  const Prototype& p = scene.prototypes[prototype];
  for (int i = 0; i < 8; ++i)
    f(Vec3{i & 1 ? p.hi.x : p.lo.x, i & 2 ? p.hi.y : p.lo.y, i & 4 ? p.hi.z : p.lo.z});
}

}  // namespace snell::ir
