#include "runtime/scene_checks.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "runtime/geometry/intervals.hpp"
#include "runtime/geometry/mesh_solid.hpp"

namespace snell::rt {

namespace {

bool black(const ir::Texture& t) {
  const ir::Constant* c = std::get_if<ir::Constant>(&t.pattern);
  return c && c->color.x == 0 && c->color.y == 0 && c->color.z == 0;
}

// Whether a surface of material `m` shows nothing but black without a light:
// diffuse and glazed colours are lit only by the scene's lights (§6: the
// background lights no diffuse surface); mirrors and glass see the background.
bool needs_light(const ir::Material& m) {
  if (const ir::Diffuse* d = m.as<ir::Diffuse>()) return !black(d->color);
  if (const ir::Glazed* g = m.as<ir::Glazed>()) return !black(g->color);
  return false;
}

// An oblique direction for the inside tests, so that a camera on a box's axis does
// not graze an edge. A point inside starts its first span at t = 0 along any one.
const ir::Vec3 kProbe = ir::normalize(ir::Vec3{0.3141, 0.8731, 0.2718});

bool contains(const ir::Scene& scene, const ir::Shape& s, ir::Vec3 p, int depth);

// Whether the point p of a CSG object's space lies inside its tree below `node`
// (merge and union are the same solid; a difference is its first child less the
// others).
bool csg_contains(const ir::Scene& scene, std::uint32_t node, ir::Vec3 p, int depth) {
  if (node >= scene.csg_nodes.size()) return false;
  const ir::CsgNode& n = scene.csg_nodes[node];
  if (n.leaf())
    return n.part < scene.parts.size() && contains(scene, scene.parts[n.part], p, depth);
  auto in = [&](std::uint32_t c) { return csg_contains(scene, c, p, depth); };
  const auto& ch = n.children;
  switch (n.op) {
    case ir::CsgOp::Intersection:
      return !ch.empty() && std::all_of(ch.begin(), ch.end(), in);
    case ir::CsgOp::Difference:
      return !ch.empty() && in(ch[0]) && std::none_of(ch.begin() + 1, ch.end(), in);
    case ir::CsgOp::Union:
    case ir::CsgOp::Merge:
      break;
  }
  return std::any_of(ch.begin(), ch.end(), in);
}

// Whether the point p, in the space shape s is placed in, lies inside s: a solid
// primitive, a closed mesh, a CSG object, or an instance (inside one of its
// value's parts; a plane only as a CSG leaf). Shapes that move have no one inside to test;
// composites nest at most kMaxDepth deep here (the compiler bounds nesting far below).
bool contains(const ir::Scene& scene, const ir::Shape& s, ir::Vec3 p, int depth) {
  constexpr int kMaxDepth = 64;
  if (ir::moves(s, scene) || depth > kMaxDepth) return false;
  ir::Vec3 o = s.world_from_object().inverse().point(p);
  return std::visit(
      [&](const auto& g) {
        using K = std::decay_t<decltype(g)>;
        if constexpr (std::is_same_v<K, ir::Csg>) {
          return csg_contains(scene, g.node, o, depth + 1);
        } else if constexpr (std::is_same_v<K, ir::Instance>) {
          if (g.prototype >= scene.prototypes.size()) return false;
          const ir::Prototype& proto = scene.prototypes[g.prototype];
          for (int k = 0; k < 3; ++k)
            if (!(o[k] >= proto.lo[k] && o[k] <= proto.hi[k])) return false;
          for (std::uint32_t part : proto.parts)
            if (part < scene.parts.size() && contains(scene, scene.parts[part], o, depth + 1))
              return true;
          return false;
        } else if constexpr (std::is_same_v<K, ir::Mesh>) {
          if (!geom::has_inside(s, scene)) return false;
          const ir::MeshData& m = scene.meshes[g.mesh];
          ir::Vec3 lo = m.positions.front(), hi = lo;  // a closed mesh has vertices
          for (const ir::Vec3& v : m.positions)
            for (int k = 0; k < 3; ++k)
              lo[k] = std::fmin(lo[k], v[k]), hi[k] = std::fmax(hi[k], v[k]);
          for (int k = 0; k < 3; ++k)
            if (!(o[k] >= lo[k] && o[k] <= hi[k])) return false;
          std::vector<geom::MeshSolid::Crossing> crossings;
          bool inside = false;
          geom::MeshSolid::of(m)->crossings(o, kProbe, 0.0, crossings, inside);
          return inside;
        } else if constexpr (geom::kSolid<K>) {
          // A plane is a half-space: a solid inside CSG, but a floor at the top
          // level, which a camera above or below is not "inside".
          if (std::is_same_v<K, ir::Plane> && depth == 0) return false;
          if (!geom::has_inside(s)) return false;
          geom::Spans spans = geom::solid_intervals(g, o, kProbe, 0.0, INFINITY);
          return spans.count > 0 && spans.span[0].t_in == 0 && spans.span[0].t_out > 0;
        } else {
          return false;
        }
      },
      s.geom);
}

// The object's kind as the scene writes it: a CSG object by its operation, an
// instance as `object`.
std::string written_kind(const ir::Scene& scene, const ir::Shape& s) {
  if (const ir::Csg* c = s.as<ir::Csg>())
    if (c->node < scene.csg_nodes.size())
      return std::string(ir::spelling(scene.csg_nodes[c->node].op));
  if (s.as<ir::Instance>()) return "object";
  return ir::to_string(s.kind());
}

}  // namespace

std::vector<std::string> scene_warnings(const ir::Scene& scene) {
  std::vector<std::string> out;
  if (scene.shapes.empty()) {
    out.push_back("the scene has no object: the image will be the background alone");
    return out;
  }
  if (scene.point_lights.empty() && scene.area_lights.empty())
    for (const ir::Shape& s : scene.shapes) {
      bool dark = false;
      ir::surface_materials(scene, s, [&](std::uint32_t m) {
        dark = dark || (m < scene.materials.size() && needs_light(scene.materials[m]));
      });
      if (dark) {
        out.push_back(fmt::format(
            "the scene has no light: diffuse and glazed surfaces (the first at {}) will be black",
            ir::to_string(s.src, scene)));
        break;
      }
    }
  for (const ir::Shape& s : scene.shapes)
    if (contains(scene, s, scene.camera.location, 0)) {
      const ir::Vec3 c = scene.camera.location;
      out.push_back(fmt::format(
          "the camera at <{}, {}, {}> is inside the {} at {}: it will see only that object's "
          "inside",
          c.x, c.y, c.z, written_kind(scene, s), ir::to_string(s.src, scene)));
    }
  return out;
}

}  // namespace snell::rt
