// Whether a mesh's triangles bound a solid (§12: closed meshes are solids), decided
// once when the mesh is loaded and recorded in MeshData::closed. The definition
// (docs/language.md, "Closed meshes"):
//   1. Weld: vertices with equal positions (every coordinate ==, so -0 and +0 are
//      one) are one vertex; OBJ files often repeat a position per face.
//   2. Triangles with a repeated welded vertex have no area and are ignored (the
//      loader has already dropped zero-area faces).
//   3. Every undirected edge {a, b} of the remaining triangles must be used by
//      exactly two triangles, once as a->b and once as b->a: no boundary (1 use),
//      no fin (3 or more) and consistent winding (two uses in one direction flip
//      one face inside out).
//   4. The signed volume (1/6 Σ a·(b×c), about the centroid) must be > 0: the
//      triangles are wound counter-clockwise seen from outside, as Ng points out.
// Not checked (each would be O(n²) or need exact predicates): self-intersections
// and faces that overlap without sharing edges. Several shells (a hollow ball: an
// outward shell with an inward one in it) are one closed mesh; touching at a
// single vertex is allowed. Math only.
#pragma once

#include <string>

#include "runtime/ir/shapes.hpp"

namespace snell::ir {

struct MeshClosure {
  bool closed = false;
  // Empty when closed; otherwise a verb phrase that follows "mesh 'x.obj' is not
  // closed: it ": "has 14 boundary edges, e.g. (v3, v7) ...", "has an edge (v12, v40)
  // used by 3 triangles", "is wound inconsistently: ...", "is inside out: ...".
  // Vertices are named by
  // their 1-based number in MeshData::positions (the file's `v` lines), the
  // smallest of the welded group.
  std::string reason;
};

MeshClosure mesh_closure(const MeshData& m);
std::string to_string(const MeshClosure& c);

}  // namespace snell::ir
