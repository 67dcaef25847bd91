#include "compiler/mesh_load.hpp"

#include <tiny_obj_loader.h>

#include <cmath>
#include <cstdint>
#include <filesystem>

#include "compiler/compile.hpp"
#include "compiler/lower.hpp"
#include "runtime/ir/mesh_topology.hpp"

namespace snell::compile {

using lang::DiagKind;
using lang::Span;

bool read_obj(const std::string& path, ir::MeshData& mesh, ObjReport& report) {
  tinyobj::ObjReaderConfig cfg;
  cfg.triangulate = true;
  cfg.vertex_color = false;
  cfg.mtl_search_path = "";
  tinyobj::ObjReader reader;
  if (!reader.ParseFromFile(path, cfg)) {
    report.error = reader.Error();
    return false;
  }
  mesh.path = path;
  const tinyobj::attrib_t& attrib = reader.GetAttrib();
  const auto& verts = attrib.vertices;
  for (std::size_t i = 0; i + 2 < verts.size(); i += 3)
    mesh.positions.push_back({verts[i], verts[i + 1], verts[i + 2]});
  // Normals: each usable vn once, normalised in double; kNoNormal for the unusable.
  const auto& vn = attrib.normals;
  std::vector<std::uint32_t> normal_id(vn.size() / 3, ir::MeshData::kNoNormal);
  for (std::size_t i = 0; i + 2 < vn.size(); i += 3) {
    ir::Vec3 n{vn[i], vn[i + 1], vn[i + 2]};
    double len = ir::length(n);
    if (!ir::is_finite(n) || !(len > 0) || !std::isfinite(len)) continue;
    normal_id[i / 3] = static_cast<std::uint32_t>(mesh.normals.size());
    mesh.normals.push_back(n / len);
  }
  const auto& vt = attrib.texcoords;
  for (std::size_t i = 0; i + 1 < vt.size(); i += 2)
    mesh.texcoords.push_back({vt[i], vt[i + 1], 0});
  std::vector<std::uint32_t> corner_normals;  // three per kept triangle
  std::vector<std::uint32_t> corner_uvs;
  bool all_uv = !mesh.texcoords.empty();
  bool any_smooth = false;
  for (const tinyobj::shape_t& sh : reader.GetShapes()) {
    const auto& idx = sh.mesh.indices;
    for (std::size_t i = 0; i + 2 < idx.size(); i += 3) {
      int a = idx[i].vertex_index, b = idx[i + 1].vertex_index, c = idx[i + 2].vertex_index;
      auto valid = [&](int k) {
        return k >= 0 && static_cast<std::size_t>(k) < mesh.positions.size();
      };
      if (!valid(a) || !valid(b) || !valid(c)) {
        ++report.dropped;
        continue;
      }
      ir::Vec3 pa = mesh.positions[a], pb = mesh.positions[b], pc = mesh.positions[c];
      if (!ir::is_finite(pa) || !ir::is_finite(pb) || !ir::is_finite(pc) ||
          ir::length(ir::cross(pb - pa, pc - pa)) == 0) {
        ++report.dropped;
        continue;
      }
      mesh.indices.insert(mesh.indices.end(),
                          {std::uint32_t(a), std::uint32_t(b), std::uint32_t(c)});
      std::uint32_t n[3];
      bool named = true, usable = true;
      for (int k = 0; k < 3; ++k) {
        int ni = idx[i + k].normal_index;
        named &= ni >= 0 && static_cast<std::size_t>(ni) < normal_id.size();
        n[k] = named ? normal_id[ni] : ir::MeshData::kNoNormal;
        usable &= n[k] != ir::MeshData::kNoNormal;
      }
      for (int k = 0; k < 3; ++k) {
        int ti = idx[i + k].texcoord_index;
        bool ok = ti >= 0 && static_cast<std::size_t>(ti) < mesh.texcoords.size() &&
                  ir::is_finite(mesh.texcoords[std::size_t(ti)]);
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
  return true;
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
    diags_.report(DiagKind::FileUnreadable, span,
                  "cannot read mesh '" + key + "': " + report.error);
    return false;
  }
  if (report.dropped > 0)
    diags_.report(DiagKind::DegenerateGeometry, span,
                  std::to_string(report.dropped) + " degenerate or invalid triangle(s) of '" + key +
                      "' are left out");
  if (report.bad_normals > 0)
    diags_.report(DiagKind::DegenerateGeometry, span,
                  std::to_string(report.bad_normals) + " triangle(s) of '" + key +
                      "' name a zero or non-finite normal (vn) and shade flat");
  if (mesh.indices.empty()) {
    diags_.report(DiagKind::FileUnreadable, span, "mesh '" + key + "' has no usable triangles");
    return false;
  }
  index = static_cast<std::uint32_t>(scene_.meshes.size());
  mesh_ids_[key] = index;
  scene_.meshes.push_back(std::move(mesh));
  return true;
}

}  // namespace snell::compile
