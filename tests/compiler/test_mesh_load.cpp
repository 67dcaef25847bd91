// Loading OBJ meshes (compiler/mesh_load.cpp): which faces shade smooth, what is
// left out, and the watertightness check, from small files written here.
#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <string>

#include "compiler/compile.hpp"
#include "compiler/mesh_load.hpp"

using namespace snell;
namespace fs = std::filesystem;

namespace {

fs::path write_file(const std::string& name, const std::string& text) {
  fs::path dir = fs::temp_directory_path() / ("snell-mesh-load-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  fs::path p = dir / name;
  std::ofstream(p) << text;
  return p;
}

// The unit cube: 8 shared vertices, 6 quads wound outward, each face naming its own
// normal (OBJ `f v//vn`); `skip` leaves one face out.
std::string cube_obj(bool normals, int skip = -1, const std::string& first_vn = "-1 0 0") {
  std::string s;
  for (int i = 0; i < 8; ++i)
    s += "v " + std::to_string(i & 1) + " " + std::to_string(i >> 1 & 1) + " " +
         std::to_string(i >> 2 & 1) + "\n";
  s += "vn " + first_vn + "\nvn 1 0 0\nvn 0 -1 0\nvn 0 1 0\nvn 0 0 -1\nvn 0 0 1\n";
  // (quad, its normal): x=0, x=1, y=0, y=1, z=0, z=1; 1-based.
  const int quads[6][4] = {{1, 5, 7, 3}, {2, 4, 8, 6}, {1, 2, 6, 5},
                           {3, 7, 8, 4}, {1, 3, 4, 2}, {5, 6, 8, 7}};
  for (int q = 0; q < 6; ++q) {
    if (q == skip) continue;
    s += "f";
    for (int k : quads[q])
      s += " " + std::to_string(k) + (normals ? "//" + std::to_string(q + 1) : "");
    s += "\n";
  }
  return s;
}

ir::MeshData load(const std::string& name, const std::string& text, compile::ObjReport& r) {
  ir::MeshData m;
  REQUIRE(compile::read_obj(write_file(name, text).string(), m, r));
  return m;
}

}  // namespace

TEST_CASE("an OBJ cube with vn: every face smooth, closed, normals unit", "[compiler][mesh]") {
  compile::ObjReport r;
  ir::MeshData m = load("smooth.obj", cube_obj(true), r);
  CHECK(m.indices.size() == 36);
  CHECK(m.normals.size() == 6);
  REQUIRE(m.normal_indices.size() == 36);
  for (std::uint32_t k : m.normal_indices) CHECK(k < 6);
  // Face x=0 (triangles 0, 1) names the first normal.
  CHECK(m.normals[m.normal_indices[0]] == ir::Vec3(-1, 0, 0));
  CHECK(m.closed);
  CHECK(m.open_reason.empty());
  CHECK(r.dropped == 0);
  CHECK(r.bad_normals == 0);
}

TEST_CASE("without vn in the faces a mesh keeps no normals at all", "[compiler][mesh]") {
  compile::ObjReport r;
  ir::MeshData m = load("flat.obj", cube_obj(false), r);  // vn lines present, unused
  CHECK_FALSE(m.smooth());
  CHECK(m.normals.empty());
  CHECK(m.normal_indices.empty());
  CHECK(m.closed);
}

TEST_CASE("a zero or non-finite vn makes its faces flat and is counted; vn is normalised",
          "[compiler][mesh]") {
  for (std::string bad : {"0 0 0", "nan 0 0", "1e400 0 0"}) {
    INFO(bad);
    compile::ObjReport r;
    ir::MeshData m = load("bad-vn.obj", cube_obj(true, -1, bad), r);
    CHECK(r.bad_normals == 2);  // face x=0's two triangles
    REQUIRE(m.normal_indices.size() == 36);
    for (int k = 0; k < 6; ++k) CHECK(m.normal_indices[k] == ir::MeshData::kNoNormal);
    for (int k = 6; k < 36; ++k) CHECK(m.normal_indices[k] != ir::MeshData::kNoNormal);
  }
  compile::ObjReport r;
  ir::MeshData m = load("long-vn.obj", cube_obj(true, -1, "-3 0 0"), r);
  CHECK(m.normals[m.normal_indices[0]] == ir::Vec3(-1, 0, 0));
}

TEST_CASE("a face with a corner without vn shades flat; the others stay smooth",
          "[compiler][mesh]") {
  std::string obj =
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvn 0 0 1\n"
      "f 1//1 2//1 3//1\nf 2//1 4 3//1\n";
  compile::ObjReport r;
  ir::MeshData m = load("partial.obj", obj, r);
  REQUIRE(m.normal_indices.size() == 6);
  CHECK(m.normal_indices[0] == 0);
  CHECK(m.normal_indices[3] == ir::MeshData::kNoNormal);
  CHECK(m.normal_indices[4] == ir::MeshData::kNoNormal);
  CHECK(r.bad_normals == 0);  // missing is not bad
  CHECK_FALSE(m.closed);
  CHECK(m.open_reason.find("has 4 boundary edges") == 0);
}

TEST_CASE("an OBJ cube missing a face is open and says so", "[compiler][mesh]") {
  compile::ObjReport r;
  ir::MeshData m = load("open.obj", cube_obj(true, 3), r);
  CHECK_FALSE(m.closed);
  CHECK(m.open_reason == "has 4 boundary edges, e.g. (v3, v4) (an edge used by one triangle only)");
}

TEST_CASE("the IR dump shows normals and closedness; has_inside follows it", "[compiler][mesh]") {
  fs::path closed = write_file("dump-closed.obj", cube_obj(true));
  fs::path open = write_file("dump-open.obj", cube_obj(false, 0));
  compile::CompileOptions opts;
  opts.stdlib_dir = std::string(SNELL_SOURCE_DIR) + "/stdlib";
  auto c = compile::compile_source(
      "test.scn",
      "mesh { file \"" + closed.string() + "\" }\nmesh { file \"" + open.string() + "\" }\n", opts);
  REQUIRE(c->status == compile::CompileStatus::Ok);
  std::string dump = ir::to_string(c->scene);
  INFO(dump);
  CHECK(dump.find("8 vertices 12 triangles 6 normals 12 smooth triangles closed") !=
        std::string::npos);
  CHECK(dump.find("8 vertices 10 triangles open (has 4 boundary edges, e.g. (v1, v3)") !=
        std::string::npos);
  REQUIRE(c->scene.meshes.size() == 2);
  CHECK(c->scene.meshes[0].closed);
  CHECK_FALSE(c->scene.meshes[1].closed);
}

TEST_CASE("a zero or non-finite vn is a warning that names the file", "[compiler][mesh]") {
  fs::path p = write_file("warn.obj", cube_obj(true, -1, "0 0 0"));
  compile::CompileOptions opts;
  opts.stdlib_dir = std::string(SNELL_SOURCE_DIR) + "/stdlib";
  auto c = compile::compile_source("test.scn", "mesh { file \"" + p.string() + "\" }\n", opts);
  REQUIRE(c->status == compile::CompileStatus::Ok);
  REQUIRE(c->diags.diagnostics().size() == 1);
  const auto& d = c->diags.diagnostics()[0];
  CHECK(d.kind == lang::DiagKind::DegenerateGeometry);
  CHECK(d.message.find("2 triangle(s) of '") == 0);
  CHECK(d.message.find("name a zero or non-finite normal (vn) and shade flat") !=
        std::string::npos);
}

TEST_CASE("OBJ vt: every corner's texture coordinate kept, or none", "[compiler][mesh]") {
  compile::ObjReport r;
  const std::string quad = "v 0 0 0\nv 2 0 0\nv 2 1 0\nv 0 1 0\nvt 1 0\nvt 0 0\nvt 0 1\nvt 1 1\n";
  ir::MeshData m = load("vt.obj", quad + "f 1/1 2/2 3/3 4/4\n", r);
  REQUIRE(m.indices.size() == 6);
  REQUIRE(m.texcoords.size() == 4);
  REQUIRE(m.texcoord_indices.size() == 6);
  for (std::size_t k = 0; k < 6; ++k) {
    INFO("corner " << k);
    CHECK(m.texcoord_indices[k] == m.indices[k]);  // vt i belongs to v i in this file
  }
  CHECK(m.texcoords[2].x == 0);
  CHECK(m.texcoords[2].y == 1);
  // One face without vt: the mesh keeps none (it maps as triangles, not partly).
  ir::MeshData partial = load("vt-partial.obj", quad + "f 1/1 2/2 3/3\nf 1 3 4\n", r);
  CHECK(partial.indices.size() == 6);
  CHECK(partial.texcoords.empty());
  CHECK(partial.texcoord_indices.empty());
  ir::MeshData none = load("no-vt.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", r);
  CHECK(none.texcoords.empty());
  CHECK(none.texcoord_indices.empty());
}
