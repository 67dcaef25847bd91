// Loading OBJ meshes (compiler/mesh_load.cpp): which faces shade smooth, what is
// left out, and the watertightness check, from small files written here.
#include <unistd.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "compiler/compile.hpp"
#include "compiler/mesh_load.hpp"

using namespace snell;
namespace fs = std::filesystem;

namespace {

// The folder of this process's files, removed when the process ends (ctest runs each
// case in a process of its own, so a folder per case was left behind before).
struct ScratchDir {
  fs::path dir = fs::temp_directory_path() / ("snell-mesh-load-" + std::to_string(::getpid()));
  ~ScratchDir() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
};

fs::path write_file(const std::string& name, const std::string& text) {
  static ScratchDir scratch;
  fs::create_directories(scratch.dir);
  fs::path p = scratch.dir / name;
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

// A file read_obj must refuse for malformed lines (not for being unreadable).
compile::ObjReport reject(const std::string& name, const std::string& text) {
  ir::MeshData m;
  compile::ObjReport r;
  CHECK_FALSE(compile::read_obj(write_file(name, text).string(), m, r));
  CHECK(r.error.empty());
  CHECK(r.error_count >= 1);
  return r;
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

TEST_CASE("a zero vn makes its faces flat and is counted, vn is normalised", "[compiler][mesh]") {
  compile::ObjReport r;
  ir::MeshData m = load("bad-vn.obj", cube_obj(true, -1, "0 0 0"), r);
  CHECK(r.bad_normals == 2);  // face x=0's two triangles
  REQUIRE(m.normal_indices.size() == 36);
  for (int k = 0; k < 6; ++k) CHECK(m.normal_indices[k] == ir::MeshData::kNoNormal);
  for (int k = 6; k < 36; ++k) CHECK(m.normal_indices[k] != ir::MeshData::kNoNormal);
  ir::MeshData l = load("long-vn.obj", cube_obj(true, -1, "-3 0 0"), r);
  CHECK(l.normals[l.normal_indices[0]] == ir::Vec3(-1, 0, 0));
}

TEST_CASE("a non-finite or overflowing vn is an error at its line (was: flat)",
          "[compiler][mesh]") {
  for (std::string bad : {"nan 0 0", "1e400 0 0", "-inf 0 0"}) {
    INFO(bad);
    compile::ObjReport r = reject("nan-vn.obj", cube_obj(true, -1, bad));
    REQUIRE(r.errors.size() == 1);
    CHECK(r.errors[0].line == 9);  // after the 8 v lines
    CHECK(r.errors[0].col == 4);
  }
}

TEST_CASE("a face with a corner without vn shades flat, the others stay smooth",
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

TEST_CASE("the IR dump shows normals and closedness, has_inside follows it", "[compiler][mesh]") {
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

// --- Strict OBJ (#18): every malformed line is an error at its line and column. ---

TEST_CASE("each malformed OBJ line is an error at its line and column", "[compiler][mesh]") {
  // Three vertices, one vt, one vn (lines 1-5), then the line under test (line 6).
  const std::string head = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n";
  struct Case {
    std::string line;
    std::size_t col;
    std::string message;
  };
  const Case cases[] = {
      {"v nan 0 0", 3, "'nan' is not a finite number"},
      {"v inf 0 0", 3, "'inf' is not a finite number"},
      {"v 0 zero 0", 5, "'zero' is not a number"},
      {"v 1,5 0 0", 3, "'1,5' is not a number"},
      {"v 1 2", 6, "'v' needs 3 coordinates (x y z), found 2"},
      {"v 1 2 3 4 5", 1, "'v' takes x y z [w] or x y z r g b [a], found 5 numbers"},
      {"v 1e39 0 0", 3, "'1e39' is beyond float range (3.4e38)"},
      {"v 0x10 0 0", 3, "'0x10' is not a number"},
      {"v 0 \x01\xff 0", 5, "'\\x01\\xff' is not a number"},  // bytes shown escaped
      {"vn 0 1", 7, "'vn' needs 3 coordinates (x y z), found 2"},
      {"vt", 3, "'vt' needs a u coordinate, found 0"},
      {"vt 0 0 0 0", 1, "'vt' takes u [v [w]], found 4 numbers"},
      {"f 1 2", 6, "a face needs at least 3 corners, this one has 2"},
      {"f", 2, "a face needs at least 3 corners, this one has 0"},
      {"f 1 2 4", 7, "v index 4 is out of range (the file has 3 'v' lines)"},
      {"f 1/1 2/9 3/1", 9, "vt index 9 is out of range (the file has 1 'vt' lines)"},
      {"f 1//1 2//1 3//2", 16, "vn index 2 is out of range (the file has 1 'vn' lines)"},
      {"f 0 1 2", 3, "v index 0: OBJ indices start at 1 (-1 is the latest)"},
      {"f 1 2 99999999999999999999", 7,
       "v index 99999999999999999999 is out of range (the file has 3 'v' lines so far)"},
      {"f 1 2 -99999999999999999999", 7, "v index -99999999999999999999 is out of range"},
      {"f 1 2 -9223372036854775808", 7, "v index -9223372036854775808 counts back past the first"},
      {"f -4 -2 -1", 3, "v index -4 counts back past the first one (the file has 3 'v' lines"},
      {"f 1/ 2 3", 3, "corner '1/' is not v, v/vt, v//vn or v/vt/vn"},
      {"f 1// 2 3", 3, "corner '1//' is not v, v/vt, v//vn or v/vt/vn"},
      {"f /1 2 3", 3, "corner '/1' is not v, v/vt, v//vn or v/vt/vn"},
      {"f 1/1/1/1 2 3", 3, "corner '1/1/1/1' has more than v/vt/vn"},
      {"f 1 2 3x", 7, "'3x' is not a v index"},
      {"f 1 2 +3", 7, "'+3' is not a v index"},
  };
  for (const Case& c : cases) {
    INFO(c.line);
    compile::ObjReport r = reject("bad.obj", head + c.line + "\n");
    REQUIRE(r.errors.size() == 1);
    CHECK(r.error_count == 1);
    CHECK(r.errors[0].line == 6);
    CHECK(r.errors[0].col == c.col);
    CHECK(r.errors[0].message.find(c.message) == 0);
  }
}

TEST_CASE("OBJ numbers: the decimal forms are read, rounded to float", "[compiler][mesh]") {
  compile::ObjData d =
      compile::parse_obj("v +1 -2. .5\nv 1e3 1E-2 -0.25e+1\nv 1e-400 0.1 16777217\nf 1 2 3\n");
  REQUIRE(d.error_count == 0);
  REQUIRE(d.positions.size() == 3);
  CHECK(d.positions[0] == ir::Vec3(1, -2, 0.5));
  CHECK(d.positions[1] == ir::Vec3(1000, double(0.01f), -2.5));
  CHECK(d.positions[2].x == 0);             // underflow reads as 0, as strtod does
  CHECK(d.positions[2].y == double(0.1f));  // float precision, as before
  CHECK(d.positions[2].z == 16777216);      // the tie rounds to even
}

TEST_CASE("OBJ indices: negative ones count back, positive ones may name a later v",
          "[compiler][mesh]") {
  compile::ObjData d = compile::parse_obj(
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nf 4 5 6\nv 0 0 1\nv 1 0 1\nv 0 1 1\n"
      "f 6/-1 -2/-1 -1/-1\nvt 0 0\n");
  // The last face's vt -1 counts back from what was read so far: none yet.
  REQUIRE(d.error_count == 1);
  CHECK(d.errors[0].line == 9);
  compile::ObjData ok = compile::parse_obj(
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nf 4 5 6\nv 0 0 1\nv 1 0 1\nv 0 1 1\n");
  REQUIRE(ok.error_count == 0);
  REQUIRE(ok.corners.size() == 6);
  const std::uint32_t want[6] = {0, 1, 2, 3, 4, 5};
  for (int k = 0; k < 6; ++k) CHECK(ok.corners[k].v == want[k]);
}

TEST_CASE("OBJ errors: all at once, in line order, the first 20 kept", "[compiler][mesh]") {
  std::string text = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  for (int i = 0; i < 30; ++i) text += i % 2 ? "v 0 x 0\n" : "f 1 2 99\n";  // line 4 + i
  compile::ObjReport r = reject("many.obj", text);
  CHECK(r.error_count == 30);
  REQUIRE(r.errors.size() == compile::kMaxObjErrors);
  for (std::size_t i = 0; i < r.errors.size(); ++i) CHECK(r.errors[i].line == 4 + i);
  // Through the compiler: one error at the `file` property, a note per line, exit 1.
  fs::path p = write_file("many.obj", text);
  compile::CompileOptions opts;
  opts.stdlib_dir = std::string(SNELL_SOURCE_DIR) + "/stdlib";
  auto c = compile::compile_source("test.scn", "mesh { file \"" + p.string() + "\" }\n", opts);
  CHECK(c->status == compile::CompileStatus::SceneErrors);  // exit 1, not 3
  REQUIRE(c->diags.diagnostics().size() == 1);
  const auto& d = c->diags.diagnostics()[0];
  CHECK(d.kind == lang::DiagKind::MalformedMesh);
  CHECK(d.message == "mesh '" + p.string() + "' is not a valid OBJ file: 30 malformed lines");
  REQUIRE(d.notes.size() == 21);
  CHECK(d.notes[0].message ==
        p.string() + ":4:7: v index 99 is out of range (the file has 18 'v' lines)");
  CHECK(d.notes[1].message == p.string() + ":5:5: 'x' is not a number");
  CHECK(d.notes[20].message == "and 10 more");
  std::string shown = c->diags.format(d);
  INFO(shown);
  CHECK(shown.find("test.scn:1:13: error: mesh '") == 0);
}

TEST_CASE("a 1M-corner polygon is a fan read in linear time", "[compiler][mesh]") {
  // A convex polygon (a circle) of n corners on one line: 7 MB. tinyobjloader's ear
  // clipping was quadratic (40 k corners 3.3 s; this never ended). ctest's timeout
  // catches a quadratic reader; the time is printed, not asserted.
  const std::size_t n = 1000000;
  std::string text;
  text.reserve(n * 40);
  for (std::size_t i = 0; i < n; ++i) {
    double a = 6.283185307179586 * double(i) / double(n);
    char line[64];
    std::snprintf(line, sizeof line, "v %.9g %.9g 0\n", std::cos(a), std::sin(a));
    text += line;
  }
  text += "f";
  for (std::size_t i = 1; i <= n; ++i) text += " " + std::to_string(i);
  text += "\n";
  fs::path p = write_file("huge-polygon.obj", text);
  auto t0 = std::chrono::steady_clock::now();
  ir::MeshData m;
  compile::ObjReport r;
  REQUIRE(compile::read_obj(p.string(), m, r));
  double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  WARN("read_obj of a " << n << "-corner polygon: " << s << " s");
  // A thin fan triangle of float corners may come out with no area (left out).
  CHECK(m.indices.size() + 3 * r.dropped == 3 * (n - 2));
  CHECK(r.dropped < n / 100);
  REQUIRE(m.indices.size() >= 3);
  CHECK(m.indices[0] == 0);
  fs::remove(p);
}

TEST_CASE("OBJ triangulation: quads by the shorter diagonal, larger polygons as a fan",
          "[compiler][mesh]") {
  auto v = [](const compile::ObjData& d) {
    std::vector<std::uint32_t> out;
    for (const auto& c : d.corners) out.push_back(c.v);
    return out;
  };
  // v0-v2 shorter: (0 1 2)(0 2 3); v1-v3 shorter or equal: (0 1 3)(1 2 3)
  // (tinyobjloader's rule, kept so quad meshes read to the same triangles).
  CHECK(v(compile::parse_obj("v 0 0 0\nv 2 -1 0\nv 1 0 0\nv 2 1 0\nf 1 2 3 4\n")) ==
        std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3});
  CHECK(v(compile::parse_obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n")) ==
        std::vector<std::uint32_t>{0, 1, 3, 1, 2, 3});
  // A quad naming later vertices is split once they are read, in its place.
  CHECK(v(compile::parse_obj("v 0 0 0\nf 1 2 3\nf 1 2 3 4\nv 2 -1 0\nv 1 0 0\nv 2 1 0\n")) ==
        std::vector<std::uint32_t>{0, 1, 2, 0, 1, 2, 0, 2, 3});
  CHECK(v(compile::parse_obj("v 0 0 0\nv 1 0 0\nv 2 1 0\nv 1 2 0\nv 0 1 0\nf 1 2 3 4 5\n")) ==
        std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3, 0, 3, 4});
}

TEST_CASE("OBJ text: CR LF, comments, continuations, no final newline, other statements",
          "[compiler][mesh]") {
  const std::string plain = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.5 1\nf 1/1 2/1 3/1\n";
  auto same = [&](const std::string& text) {
    INFO(text);
    compile::ObjData a = compile::parse_obj(plain), b = compile::parse_obj(text);
    REQUIRE(b.error_count == 0);
    CHECK(b.positions == a.positions);
    CHECK(b.texcoords == a.texcoords);
    REQUIRE(b.corners.size() == a.corners.size());
    for (std::size_t k = 0; k < a.corners.size(); ++k) {
      CHECK(b.corners[k].v == a.corners[k].v);
      CHECK(b.corners[k].vt == a.corners[k].vt);
    }
  };
  same("v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nvt 0.5 1\r\nf 1/1 2/1 3/1\r\n");
  same(
      "# a comment\nv 0 0 0 # after a vertex\nv 1 0 0\n\n   \nv 0 1 0\nvt 0.5 1\n#f 9 9 9\n"
      "f 1/1 2/1 3/1");
  same("v 0 0 0\nv 1 0 0\nv 0 1 \\\n 0\nvt 0.5 1\nf 1/1 \\  \n2/1 \\\r\n3/1\n");
  same(
      "mtllib a.mtl\no thing\ng part\ns 1\nusemtl red\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvp 0.5\n"
      "vt 0.5 1\ncstype bezier\nf 1/1 2/1 3/1\nmystery 1 2 3\n");
  // A continued line's error is at its own line and column.
  compile::ObjData d = compile::parse_obj("v 0 0 0\nv 1 \\\n  0 x\n");
  REQUIRE(d.errors.size() == 1);
  CHECK(d.errors[0].line == 3);
  CHECK(d.errors[0].col == 5);
  // Lines and points are read past, and counted for a warning.
  compile::ObjData lp = compile::parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nl 1 2\np 3\n");
  CHECK(lp.error_count == 0);
  CHECK(lp.ignored_geometry == 2);
  CHECK(lp.first_ignored_line == 5);
}

TEST_CASE("OBJ lines and points are a warning: they are not drawn", "[compiler][mesh]") {
  fs::path p = write_file("lines.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nl 1 2\nl 2 3\n");
  compile::CompileOptions opts;
  opts.stdlib_dir = std::string(SNELL_SOURCE_DIR) + "/stdlib";
  auto c = compile::compile_source("test.scn", "mesh { file \"" + p.string() + "\" }\n", opts);
  REQUIRE(c->status == compile::CompileStatus::Ok);
  REQUIRE(c->diags.diagnostics().size() == 1);
  CHECK(c->diags.diagnostics()[0].message ==
        "2 line, point or free-form statement(s) of '" + p.string() +
            "' are not drawn (the first on line 5); Snell draws the faces (f) only");
}

TEST_CASE("an OBJ is read a line at a time, and a line past 16 MB ends the read",
          "[compiler][mesh]") {
  // The last line needs no newline (the triangle is read); a file of 17 MB without
  // one (NUL bytes, a binary file) is refused at its first line instead of being
  // read whole into one string (3 GB of them took 4 GB).
  compile::ObjReport r;
  ir::MeshData tri = load("no-final-newline.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3", r);
  CHECK(tri.indices.size() == 3);
  ir::MeshData m;
  compile::ObjReport big;
  CHECK_FALSE(compile::read_obj(
      write_file("binary.obj", std::string(std::size_t(17) << 20, '\0')).string(), m, big));
  INFO(big.error);
  CHECK(big.error.find("line 1 is longer than") != std::string::npos);
}
