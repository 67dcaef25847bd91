// CSG objects (§12), composed from their solids' ray intervals (intervals.hpp).
// A ray's hit is where it crosses the boundary of the result: every leaf's entry
// and exit along the ray are events; swept in order of t, the tree's inside test
// is re-evaluated after each group of events, and the first group that changes it
// is the hit. The surface is the leaf whose event it is; its normal is turned to
// point out of the result (so in a difference, the removed children's surfaces
// face into the removed region).
//
// Coincident faces (a face of FIRST lying on a face of REST, or two children
// sharing a face): events closer in t than a tolerance far below any rounding of
// the spawned rays' offsets (kCoincident of the ray's scale) are one group, applied
// together, so a shared face is decided by the tree — present or absent for the
// whole face — and never by which rounding error happens to be smaller. Within a
// group the leaf written first owns the surface (its material, its normal).
//
// Leaves may move inside the CSG object (§12: a child's own motion, in the CSG
// object's space): such a leaf is placed at the ray's time, and its box is the one
// it sweeps over the shutter. The sets below take a CSG object with moving leaves
// as a moving primitive (ir::moves).
//
// Cost: the leaves' boxes are in a BVH of their own, and the tree's inside test is
// kept up to date one leaf at a time (each operation counts its operands that are
// inside, so an event costs the depth of its leaf, not the size of the tree). A
// ray pays for the leaves whose boxes it meets and the log of the rest: a box with
// 10 000 holes drilled costs about what one with ten does per hole the ray meets.
// A closed mesh leaf is a MeshSolid (its own BVH; every crossing along the ray).
// No Embree types.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "runtime/geometry/intervals.hpp"
#include "runtime/geometry/mesh_solid.hpp"
#include "runtime/geometry/motion.hpp"
#include "runtime/geometry/ray.hpp"
#include "runtime/geometry/xform.hpp"
#include "runtime/ir/ir.hpp"
#include "runtime/vec.hpp"

namespace snell::rt::geom {

// A CSG tree prepared for rays, in the CSG object's space.
class CsgProgram {
 public:
  // `motion`: the leaves move as their motion says (the shutter is open); without
  // it they stand at their shutter-open placement.
  CsgProgram(const ir::Scene& scene, std::uint32_t root, bool motion = false);

  // The nearest boundary crossing in (tnear, tfar) of o + t·d (any length of d) at
  // shutter fraction u: its t, the outward normal of the result there (any
  // length), and the leaf.
  bool intersect(Vec3 o, Vec3 d, double tnear, double tfar, double& t, Vec3& n, std::uint32_t& leaf,
                 double u = 0) const;
  // The crossing of leaf `leaf`'s surface nearest `t` at shutter fraction u (for
  // refining a float t); `tri`: a mesh leaf's triangle there.
  double leaf_crossing(std::uint32_t leaf, Vec3 o, Vec3 d, double t, std::uint32_t* tri = nullptr,
                       double u = 0) const;
  std::uint32_t material(std::uint32_t leaf) const { return leaves_[leaf].material; }
  std::uint32_t part(std::uint32_t leaf) const { return leaves_[leaf].part; }
  // The corners of a box holding the result (an unbounded one clamped to `clamp`
  // around the origin of the CSG space).
  template <class F>
  void corners(double clamp, F&& f) const {
    for (int i = 0; i < 8; ++i) {
      Vec3 c;
      for (int k = 0; k < 3; ++k)
        c[k] = std::fmin(clamp, std::fmax(-clamp, (i >> k) & 1 ? box_.hi[k] : box_.lo[k]));
      f(c);
    }
  }
  std::size_t leaf_count() const { return leaves_.size(); }
  std::string to_string() const;

 private:
  struct Leaf {
    ir::ShapeGeom geom;
    // A cylinder's, cone's or torus's local surface, made once: it was made on
    // every ray (its frame, an inverse, a hypot), 5 % of a glass of water.
    std::variant<std::monostate, TruncatedCone, TorusSurface> surface;
    ir::Mat4 leaf_from_csg;            // at shutter open
    const ir::Shape* moves = nullptr;  // the part, when it moves (its motion, its placement)
    Box3 box;  // in CSG space (swept over the shutter when it moves); infinite for a plane
    bool bounded = true;
    std::uint32_t material = 0, part = 0;
    std::shared_ptr<const MeshSolid> mesh;  // a closed mesh's crossings
  };
  // The tree: a leaf is inside or not; an operation is inside when its operands
  // are (Any: one of them, All: every one, FirstNotRest: the first and none of the
  // rest). `count`: the operands; `first`: this node is its parent's first operand.
  // A ray keeps, per node, whether it is inside and how many of its operands are
  // (FirstNotRest: of the rest), starting from every leaf outside (`inside0`,
  // `true0`), in a thread's scratch stamped per ray (csg.cpp's RayState).
  struct Node {
    enum Kind : std::uint8_t { Leaf, Any, All, FirstNotRest } kind;
    bool first = false, inside0 = false;
    std::uint32_t parent = kNone, count = 0, true0 = 0;
    std::uint32_t first_child = kNone;  // FirstNotRest: its first operand
  };
  // The leaves' boxes as a binary tree: an inner node's children are the next
  // node and `right`; a leaf node holds bounded_[first, first + count).
  struct BvhNode {
    Box3 box;  // padded: it holds its leaves' boxes as ray_box sees them
    std::uint32_t first = 0, count = 0, right = 0;
  };
  static constexpr std::uint32_t kNone = ~0u;
  std::uint32_t compile(const ir::Scene& scene, std::uint32_t node, bool motion, Box3& box);
  std::uint32_t build_bvh(std::uint32_t begin, std::uint32_t end);
  // A leaf's spans along o + t·d in its own space (intervals.hpp).
  static Spans leaf_spans(const Leaf& l, Vec3 o, Vec3 d, double lo, double hi);
  // leaf_from_csg at shutter fraction u.
  const ir::Mat4& leaf_at(const Leaf& l, double u, ir::Mat4& scratch) const;
  // Visits the leaves whose boxes the ray may meet within [lo, hi].
  template <class F>
  void for_each_leaf(Vec3 o, Vec3 d, double lo, double hi, F&& f) const;

  std::vector<Leaf> leaves_;
  std::vector<Node> nodes_;               // the root last
  std::vector<std::uint32_t> leaf_node_;  // leaf -> its node
  std::vector<BvhNode> bvh_;
  std::vector<std::uint32_t> bounded_, unbounded_;  // leaves by whether they have a box
  Box3 box_;
};

// The user primitive sets of CSG objects (traits.hpp's interface, plus the leaf a
// hit is on through `hit(..., sub)` and `refine(..., sub)`): one primitive per
// CSG object, static or moving.
template <bool kMoving>
class CsgSetT {
 public:
  void add(const ir::Shape& s, const ir::Csg& g, std::uint32_t index, Vec3 origin,
           const ir::Scene& scene);
  std::size_t size() const { return prims_.size(); }
  std::uint32_t shape(unsigned prim) const { return prims_[prim].shape; }
  const CsgProgram& program(unsigned prim) const { return prims_[prim].program; }
  void bounds(unsigned prim, Box3& box) const;
  bool hit(unsigned prim, float time, Vec3f o, Vec3f d, float tnear, float tfar, float& t, Vec3f& n,
           unsigned& sub) const;
  // The hit point on leaf `sub` in double (static: the leaf's crossing, the bounded
  // offset of spheres; moving: o + t·d and the Wächter–Binder offset), and its
  // material.
  void refine(unsigned prim, const Ray& r, float t, Hit& hit, unsigned sub) const;

 private:
  struct Prim {
    CsgProgram program;
    const ir::Shape* shape_ir = nullptr;
    Vec3 origin;
    ir::Mat4 csg_from_rel, rel_from_csg;  // the static placement
    std::uint32_t shape = 0;
  };
  std::vector<Prim> prims_;
};
using CsgSet = CsgSetT<false>;
using MovingCsgSet = CsgSetT<true>;

}  // namespace snell::rt::geom
