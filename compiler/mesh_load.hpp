// Reading a Wavefront OBJ file (§8 `mesh { file }`) into ir::MeshData: positions,
// triangles (polygons triangulated by tinyobjloader), the `vn` normals of smooth
// faces, and whether the triangles bound a solid (ir/mesh_topology.hpp).
#pragma once

#include <cstddef>
#include <string>

#include "runtime/ir/ir.hpp"

namespace snell::compile {

struct ObjReport {
  std::string error;            // set when the file could not be read at all
  std::size_t dropped = 0;      // triangles left out: bad indices, non-finite, no area
  std::size_t bad_normals = 0;  // faces that shade flat because of a zero/non-finite vn
};

// The rules, in order (docs/language.md, "Smooth meshes"):
// - a triangle with an index out of range, a non-finite vertex or zero area is
//   left out (ObjReport::dropped);
// - a triangle shades smooth only when each of its three corners names a `vn`
//   that is finite and not zero (normalised here); otherwise it shades flat with
//   its geometric normal. A face with no vn at all is simply flat; one whose vn
//   is zero or non-finite is counted in bad_normals;
// - `closed` and `open_reason` from ir::mesh_closure, after the drop.
// False (with report.error) when the file does not parse.
bool read_obj(const std::string& path, ir::MeshData& out, ObjReport& report);

}  // namespace snell::compile
