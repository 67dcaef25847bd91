#include "compiler/mesh_load.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "compiler/compile.hpp"
#include "compiler/lower.hpp"
#include "runtime/ir/mesh_topology.hpp"

namespace snell::compile {

using lang::DiagKind;
using lang::Span;

bool read_obj(const std::string& path, ir::MeshData& mesh, ObjReport& report) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    report.error = "cannot open it";
    return false;
  }
  // Line by line: the file is never held whole (a mesh may be gigabytes), and no
  // line is longer than kMaxObjLine (a file of 3 GB without a newline, NUL bytes
  // say, was read into one string of 3 GB).
  constexpr std::size_t kMaxObjLine = std::size_t(16) << 20;  // a 2 M-corner polygon
  ObjParser parser;
  std::string line;
  std::uint64_t line_no = 1;
  char buf[1 << 16];
  for (;;) {
    in.read(buf, sizeof buf);
    const std::size_t got = static_cast<std::size_t>(in.gcount());
    if (got == 0) break;
    std::size_t start = 0;
    while (start < got) {
      const char* nl = static_cast<const char*>(std::memchr(buf + start, '\n', got - start));
      const std::size_t end = nl ? std::size_t(nl - buf) : got;
      line.append(buf + start, end - start);
      if (line.size() > kMaxObjLine) {
        report.error = "line " + std::to_string(line_no) + " is longer than " +
                       std::to_string(kMaxObjLine) + " bytes: it is not an OBJ file";
        return false;
      }
      if (!nl) break;
      parser.line(line);
      line.clear();
      ++line_no;
      start = end + 1;
    }
  }
  if (in.bad()) {
    report.error = "reading it failed";
    return false;
  }
  if (!line.empty()) parser.line(line);
  ObjData obj = parser.finish();
  report.ignored_geometry = obj.ignored_geometry;
  report.first_ignored_line = obj.first_ignored_line;
  if (obj.error_count > 0) {
    report.errors = std::move(obj.errors);
    report.error_count = obj.error_count;
    return false;
  }
  mesh.path = path;
  build_mesh(std::move(obj), mesh, report);
  return true;
}

void build_mesh(ObjData&& obj, ir::MeshData& mesh, ObjReport& report) {
  mesh.positions = std::move(obj.positions);
  // Normals: each usable vn once, normalised in double; kNoNormal for the unusable.
  std::vector<std::uint32_t> normal_id(obj.normals.size(), ir::MeshData::kNoNormal);
  for (std::size_t i = 0; i < obj.normals.size(); ++i) {
    ir::Vec3 n = obj.normals[i];
    double len = ir::length(n);
    if (!ir::is_finite(n) || !(len > 0) || !std::isfinite(len)) continue;
    normal_id[i] = static_cast<std::uint32_t>(mesh.normals.size());
    mesh.normals.push_back(n / len);
  }
  mesh.texcoords = std::move(obj.texcoords);
  std::vector<std::uint32_t> corner_normals;  // three per kept triangle
  std::vector<std::uint32_t> corner_uvs;
  bool all_uv = !mesh.texcoords.empty();
  bool any_smooth = false;
  {
    // The reader checked every index against its array.
    const std::vector<ObjCorner>& idx = obj.corners;
    for (std::size_t i = 0; i + 2 < idx.size(); i += 3) {
      std::uint32_t a = idx[i].v, b = idx[i + 1].v, c = idx[i + 2].v;
      ir::Vec3 pa = mesh.positions[a], pb = mesh.positions[b], pc = mesh.positions[c];
      if (!ir::is_finite(pa) || !ir::is_finite(pb) || !ir::is_finite(pc) ||
          ir::length(ir::cross(pb - pa, pc - pa)) == 0) {
        ++report.dropped;
        continue;
      }
      mesh.indices.insert(mesh.indices.end(), {a, b, c});
      std::uint32_t n[3];
      bool named = true, usable = true;
      for (int k = 0; k < 3; ++k) {
        std::uint32_t ni = idx[i + k].vn;
        named &= ni < normal_id.size();
        n[k] = named ? normal_id[ni] : ir::MeshData::kNoNormal;
        usable &= n[k] != ir::MeshData::kNoNormal;
      }
      for (int k = 0; k < 3; ++k) {
        std::uint32_t ti = idx[i + k].vt;
        bool ok = ti < mesh.texcoords.size() && ir::is_finite(mesh.texcoords[ti]);
        all_uv &= ok;
        corner_uvs.push_back(ok ? std::uint32_t(ti) : 0);
      }
      if (named && !usable) ++report.bad_normals;
      if (!usable) n[0] = n[1] = n[2] = ir::MeshData::kNoNormal;
      any_smooth |= usable;
      corner_normals.insert(corner_normals.end(), {n[0], n[1], n[2]});
    }
  }
  if (all_uv)
    mesh.texcoord_indices = std::move(corner_uvs);
  else
    mesh.texcoords.clear();
  // A mesh without one smooth face keeps no normals: it is the flat mesh, exactly.
  if (any_smooth)
    mesh.normal_indices = std::move(corner_normals);
  else
    mesh.normals.clear();
  ir::MeshClosure closure = ir::mesh_closure(mesh);
  mesh.closed = closure.closed;
  mesh.open_reason = closure.reason;
}

bool SceneBuilder::load_mesh(const std::string& file, Span span, std::uint32_t& index) {
  namespace fs = std::filesystem;
  fs::path p(file);
  if (p.is_relative() && span.file < sources_.size())
    p = fs::path(sources_.file(span.file).path()).parent_path() / p;
  std::string key = p.lexically_normal().string();
  if (auto it = mesh_ids_.find(key); it != mesh_ids_.end()) {
    index = it->second;
    return true;
  }
  if (std::string why = not_a_file(p.string()); !why.empty()) {
    diags_.report(DiagKind::FileUnreadable, span, "mesh file '" + key + "' " + why);
    return false;
  }
  ir::MeshData mesh;
  ObjReport report;
  if (!read_obj(key, mesh, report)) {
    if (!report.error.empty()) {
      diags_.report(DiagKind::FileUnreadable, span,
                    "cannot read mesh '" + key + "': " + report.error);
      return false;
    }
    // One error at the `file` property; each malformed line a note at its place
    // in the OBJ file (file:line:col, as editors jump to), the first
    // kMaxObjErrors of them.
    std::size_t n = report.error_count;
    // MalformedMesh, not FileUnreadable: the file was read, its content is wrong —
    // an error in the scene (exit 1), not a file that could not be read (exit 3).
    auto b = diags_.report(DiagKind::MalformedMesh, span,
                           "mesh '" + key + "' is not a valid OBJ file: " + std::to_string(n) +
                               " malformed line" + (n == 1 ? "" : "s"));
    for (const ObjError& e : report.errors)
      b.note(key + ":" + std::to_string(e.line) + ":" + std::to_string(e.col) + ": " + e.message);
    if (n > report.errors.size())
      b.note("and " + std::to_string(n - report.errors.size()) + " more");
    return false;
  }
  if (report.ignored_geometry > 0)
    diags_.report(
        DiagKind::DegenerateGeometry, span,
        std::to_string(report.ignored_geometry) + " line, point or free-form statement(s) of '" +
            key + "' are not drawn (the first on line " +
            std::to_string(report.first_ignored_line) + "); Snell draws the faces (f) only");
  if (report.dropped > 0)
    diags_.report(DiagKind::DegenerateGeometry, span,
                  std::to_string(report.dropped) + " triangle(s) of '" + key +
                      "' have no area and are left out");
  if (report.bad_normals > 0)
    diags_.report(DiagKind::DegenerateGeometry, span,
                  std::to_string(report.bad_normals) + " triangle(s) of '" + key +
                      "' name a zero or non-finite normal (vn) and shade flat");
  if (mesh.indices.empty()) {
    // The file was read; what it holds draws nothing: an error in the scene (exit 1),
    // as a malformed line is, not an unreadable file (exit 3).
    diags_.report(DiagKind::MalformedMesh, span,
                  "mesh '" + key + "' has no usable triangles (no face with an area)");
    return false;
  }
  index = static_cast<std::uint32_t>(scene_.meshes.size());
  mesh_ids_[key] = index;
  scene_.meshes.push_back(std::move(mesh));
  return true;
}

}  // namespace snell::compile
