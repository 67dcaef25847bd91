// Reading a Wavefront OBJ file (§8 `mesh { file }`) into ir::MeshData: positions,
// triangles (read and triangulated by the strict reader, obj_reader.hpp), the `vn`
// normals of smooth faces, and whether the triangles bound a solid
// (ir/mesh_topology.hpp).
#pragma once

#include <cstddef>
#include <string>

#include "compiler/obj_reader.hpp"
#include "runtime/ir/ir.hpp"

namespace snell::compile {

struct ObjReport {
  std::string error;                 // set when the file could not be read at all
  std::vector<ObjError> errors;      // malformed lines (the first kMaxObjErrors)
  std::size_t error_count = 0;       // all of them
  std::size_t dropped = 0;           // triangles left out: no area
  std::size_t bad_normals = 0;       // faces that shade flat because of a zero vn
  std::size_t ignored_geometry = 0;  // l, p, curv, curv2, surf: not drawn
  std::size_t first_ignored_line = 0;
};

// The rules, in order (docs/language.md, "Smooth meshes"):
// - a malformed line (obj_reader.hpp: a bad number or index, a missing
//   coordinate, a face of fewer than 3 corners) rejects the whole file;
// - a triangle with zero area is left out (ObjReport::dropped);
// - a triangle shades smooth only when each of its three corners names a `vn`
//   that is not zero (normalised here); otherwise it shades flat with its
//   geometric normal. A face with no vn at all is simply flat; one whose vn is
//   zero (or whose length overflows) is counted in bad_normals;
// - `closed` and `open_reason` from ir::mesh_closure, after the drop.
// False when the file cannot be read (report.error) or has malformed lines
// (report.errors).
bool read_obj(const std::string& path, ir::MeshData& out, ObjReport& report);
// The same from a parsed file without errors (the fuzz target's entry).
void build_mesh(ObjData&& obj, ir::MeshData& out, ObjReport& report);

}  // namespace snell::compile
