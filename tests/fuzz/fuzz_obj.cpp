// libFuzzer target over the strict OBJ reader (compiler/obj_reader.cpp) and what
// the compiler builds from its result (compile::build_mesh: normals, texture
// coordinates, the degenerate-triangle drop, ir::mesh_closure).
//
// What it looks for: crashes, sanitizer reports (ASan/UBSan), hangs (libFuzzer's
// -timeout: a reader that is not linear in its input shows as one) and runaway
// memory (-rss_limit_mb). Beyond those, the reader's own contract, checked here
// with __builtin_trap():
// - the errors kept are at most kMaxObjErrors, in line order, each with a line
//   and column inside the input, and counted in error_count;
// - a file without errors names only elements it has: every corner's v, vt and
//   vn index is in range (kNone for vt and vn allowed), three corners a
//   triangle; and the mesh built from it indexes only its own arrays.
// The input is read as one file split at '\n', as read_obj reads one from disk.
// Seeds: tests/fuzz/obj/*.obj and the repository's meshes (bench/fuzz.sh).
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string_view>

#include "compiler/mesh_load.hpp"
#include "compiler/obj_reader.hpp"

namespace {

void require(bool ok, const char* what) {
  if (ok) return;
  std::fprintf(stderr, "fuzz_obj: %s\n", what);
  __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace snell;
  std::string_view text(reinterpret_cast<const char*>(data), size);
  std::size_t lines = static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n')) + 1;
  compile::ObjData obj = compile::parse_obj(text);
  require(obj.errors.size() <= compile::kMaxObjErrors, "more errors kept than the limit");
  require(obj.errors.size() <= obj.error_count, "kept errors not counted");
  require((obj.error_count == 0) == obj.errors.empty(), "errors counted but none kept");
  for (std::size_t i = 0; i < obj.errors.size(); ++i) {
    const compile::ObjError& e = obj.errors[i];
    require(e.line >= 1 && e.line <= lines && e.col >= 1 && e.col <= size + 1,
            "an error outside the input");
    require(!e.message.empty(), "an error without words");
    if (i > 0) {
      const compile::ObjError& p = obj.errors[i - 1];
      require(p.line < e.line || (p.line == e.line && p.col <= e.col), "errors out of order");
    }
  }
  if (obj.error_count > 0) return 0;
  require(obj.corners.size() % 3 == 0, "corners not three per triangle");
  for (const compile::ObjCorner& c : obj.corners) {
    require(c.v < obj.positions.size(), "a v index out of range");
    require(c.vt == compile::ObjCorner::kNone || c.vt < obj.texcoords.size(),
            "a vt index out of range");
    require(c.vn == compile::ObjCorner::kNone || c.vn < obj.normals.size(),
            "a vn index out of range");
  }
  ir::MeshData mesh;
  compile::ObjReport report;
  compile::build_mesh(std::move(obj), mesh, report);
  require(mesh.indices.size() % 3 == 0, "mesh indices not three per triangle");
  for (std::uint32_t k : mesh.indices)
    require(k < mesh.positions.size(), "mesh index out of range");
  require(mesh.normal_indices.empty() || mesh.normal_indices.size() == mesh.indices.size(),
          "normal_indices not parallel to indices");
  for (std::uint32_t k : mesh.normal_indices)
    require(k == ir::MeshData::kNoNormal || k < mesh.normals.size(), "normal index out of range");
  require(mesh.texcoord_indices.empty() || mesh.texcoord_indices.size() == mesh.indices.size(),
          "texcoord_indices not parallel to indices");
  for (std::uint32_t k : mesh.texcoord_indices)
    require(k < mesh.texcoords.size(), "texcoord index out of range");
  return 0;
}
