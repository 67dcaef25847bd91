// A closed mesh as a CSG solid (§12): every crossing of its triangles along a
// ray, in the mesh's object space and in double, entering where the outward
// normal (the file's winding, checked outward at load: ir/mesh_topology.hpp)
// faces the ray. Embree finds the candidate triangles (a BVH of the mesh's float
// triangles, every hit collected by a filter function); each crossing's t is then
// recomputed in double from the file's vertices, so a mesh leaf composes as
// exactly as the analytic solids do. Crossings are taken as alternating (enter,
// exit, ...): a second crossing of the same sense, as a ray through a shared edge
// reports from both triangles, is that same crossing.
//
// One per mesh (a process-wide cache keyed by the MeshData, which outlives the
// scene's geometry), shared by every CSG object that uses the mesh. No Embree
// types here.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "runtime/geometry/xform.hpp"
#include "runtime/ir/ir.hpp"

namespace snell::rt::geom {

class MeshSolid {
 public:
  struct Crossing {
    double t;
    Vec3 n;  // outward, any length
    bool enter;
    std::uint32_t tri;  // into MeshData::indices / 3
  };
  // The solid of `mesh` (which must be closed), built once and shared.
  static std::shared_ptr<const MeshSolid> of(const ir::MeshData& mesh);
  ~MeshSolid();
  MeshSolid(const MeshSolid&) = delete;
  MeshSolid& operator=(const MeshSolid&) = delete;

  // The crossings with t >= tnear, in order of t, alternating; `inside`: whether
  // o + tnear·d is inside (the first crossing leaves).
  void crossings(Vec3 o, Vec3 d, double tnear, std::vector<Crossing>& out, bool& inside) const;

  struct Impl;

 private:
  explicit MeshSolid(const ir::MeshData& mesh);
  std::unique_ptr<Impl> impl_;
};

}  // namespace snell::rt::geom
