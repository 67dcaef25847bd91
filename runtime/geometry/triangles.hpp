// Boxes, triangles and meshes (§5): triangle geometry of the BVH (the triangles
// class of traits.hpp). Each kind gives its triangles in object space, wound so
// that Ng points outward; hits are refined from their barycentrics with a
// per-triangle error bound. No Embree types.
#pragma once

#include <cstdint>
#include <vector>

#include "runtime/ir/ir.hpp"
#include "runtime/vec.hpp"

namespace snell::rt::geom {

// Triangle soup of one shape in object space, three vertices per triangle.
struct Soup {
  std::vector<ir::Vec3> verts;
  // Appends triangle abc, wound the other way when `flip`.
  void tri(ir::Vec3 a, ir::Vec3 b, ir::Vec3 c, bool flip) {
    verts.push_back(a);
    verts.push_back(flip ? c : b);
    verts.push_back(flip ? b : c);
  }
};

// The object-space triangles of each kind, wound so that Ng points outward after a
// transform whose determinant has the sign of `flip` (mirroring transforms reverse
// the winding).
void object_triangles(const ir::Box& b, const ir::Scene& scene, bool flip, Soup& out);
void object_triangles(const ir::Triangle& t, const ir::Scene& scene, bool flip, Soup& out);
void object_triangles(const ir::Mesh& m, const ir::Scene& scene, bool flip, Soup& out);

// The hit point of triangle `prim` of a float vertex/index buffer from Embree's
// barycentrics, p = v0 + u·e1 + v·e2 (why: triangles.cpp).
void triangle_point(const float* vb, const unsigned* ib, unsigned prim, float u, float v, Vec3f& p);

// How far a ray leaving a point of triangle abc must start (Hit::offset); 0 asks
// for the Wächter–Binder offset (triangles.cpp).
float triangle_offset(const float* a, const float* b, const float* c);

}  // namespace snell::rt::geom
