// Boxes, triangles and meshes (§5): triangle geometry of the BVH (the triangles
// class of traits.hpp). Each kind gives its triangles in object space, wound so
// that Ng points outward; hits are refined from their barycentrics with a
// per-triangle error bound. No Embree types.
#pragma once

#include <cstdint>
#include <vector>

#include "runtime/geometry/ray.hpp"
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

// The smooth-shading normals of a kind's triangles in object space, one per vertex
// of object_triangles' soup, in its order (the winding flip swaps them as it swaps
// the vertices), zero at the corners of flat faces. False, with nothing appended,
// for kinds and meshes that have none: they shade with Ng exactly as before.
template <class Kind>
bool object_normals(const Kind&, const ir::Scene&, bool, std::vector<ir::Vec3>&) {
  return false;
}
bool object_normals(const ir::Mesh& m, const ir::Scene& scene, bool flip,
                    std::vector<ir::Vec3>& out);

// The world-space corner normals of the static smooth triangles, by the index of the
// triangle in the BVH's static triangle buffer (float; unit). Empty when no static
// triangle is smooth, so flat scenes pay nothing.
class SmoothNormals {
 public:
  bool empty() const { return corners_.empty(); }
  // Triangles first_prim, first_prim + 1, ...: their object-space soup normals
  // (object_normals) and the object's transform; normals transform by its inverse
  // transpose and are renormalised per corner.
  void add(std::size_t first_prim, const std::vector<ir::Vec3>& normals, const ir::Transform& xf);
  // A hit on `prim` at Embree's barycentrics (u, v), its ng and p set, by a ray
  // along `dir`: sets hit.ns, (1-u-v)·n0 + u·n1 + v·n2 normalised and turned to the
  // side of ng, and hit.ps (see below). False for a flat face, or where the
  // interpolation cancels to zero (opposite corner normals): the face then shades
  // with ng. `vb`, `ib`: the static triangles' buffers as Embree holds them.
  //
  // hit.ps, the shadow rays' start (Hanika, "Hacking the shadow terminator", 2021):
  // a coarse smooth mesh is lit by its shading normal, but its flat facet hides
  // lights from the points near the terminator (black facets in a stair pattern).
  // p is lifted onto the surface the vertex normals suggest: for each corner i,
  // where p lies below the plane through p_i perpendicular to n_i (taken on the
  // ray's side), by that depth along n_i, blended by the barycentrics. Convex
  // parts rise by up to the facet's sag, concave and flat parts not at all; never
  // to the far side of the facet.
  bool shade(unsigned prim, float u, float v, Vec3f dir, const float* vb, const unsigned* ib,
             Hit& hit) const;
  std::size_t size() const { return corners_.size() / 3; }

 private:
  std::vector<Vec3f> corners_;  // three per triangle; zero for a flat face
};

// The hit point of triangle `prim` of a float vertex/index buffer from Embree's
// barycentrics, p = v0 + u·e1 + v·e2 (why: triangles.cpp).
void triangle_point(const float* vb, const unsigned* ib, unsigned prim, float u, float v, Vec3f& p);

// Ray o + t·d against triangle `prim`'s plane in double (Möller–Trumbore, no
// inside test: the caller knows the ray meets it): t, Embree's barycentrics (p =
// v0 + u·e1 + v·e2) and Embree's geometric normal cross(v2 − v0, v0 − v1). False
// where the ray runs in the plane. For a moving instance's hit (resolve_instance),
// whose Embree numbers depend on the packet the ray rode in.
bool triangle_retrace(const float* vb, const unsigned* ib, unsigned prim, Vec3f o, Vec3f d,
                      float& t, float& u, float& v, Vec3f& ng);

// How far a ray leaving a point of triangle abc must start (Hit::offset); 0 asks
// for the Wächter–Binder offset (triangles.cpp).
float triangle_offset(const float* a, const float* b, const float* c);

}  // namespace snell::rt::geom
