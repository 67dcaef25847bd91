#include "runtime/geometry/point_inside.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "runtime/geometry/intervals.hpp"
#include "runtime/geometry/mesh_solid.hpp"

namespace snell::rt::geom {

namespace {

// An oblique direction for the inside tests, so that a camera on a box's axis does
// not graze an edge. A point inside starts its first span at t = 0 along any one.
const ir::Vec3 kProbe = ir::normalize(ir::Vec3{0.3141, 0.8731, 0.2718});

bool contains(const ir::Scene& scene, const ir::Shape& s, ir::Vec3 p, InsideRule rule, int depth);

// Whether the point p of a CSG object's space lies inside its tree below `node`
// (merge and union are the same solid; a difference is its first child less the
// others).
bool csg_contains(const ir::Scene& scene, std::uint32_t node, ir::Vec3 p, InsideRule rule,
                  int depth) {
  if (node >= scene.csg_nodes.size()) return false;
  const ir::CsgNode& n = scene.csg_nodes[node];
  if (n.leaf())
    return n.part < scene.parts.size() && contains(scene, scene.parts[n.part], p, rule, depth);
  auto in = [&](std::uint32_t c) { return csg_contains(scene, c, p, rule, depth); };
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
// value's parts). Composites nest at most kMaxDepth deep here (the compiler bounds
// nesting far below).
bool contains(const ir::Scene& scene, const ir::Shape& s, ir::Vec3 p, InsideRule rule, int depth) {
  constexpr int kMaxDepth = 64;
  if (depth > kMaxDepth || (rule == InsideRule::Object && ir::moves(s, scene))) return false;
  ir::Vec3 o = s.world_from_object().inverse().point(p);
  return std::visit(
      [&](const auto& g) {
        using K = std::decay_t<decltype(g)>;
        if constexpr (std::is_same_v<K, ir::Csg>) {
          return csg_contains(scene, g.node, o, rule, depth + 1);
        } else if constexpr (std::is_same_v<K, ir::Instance>) {
          if (g.prototype >= scene.prototypes.size()) return false;
          const ir::Prototype& proto = scene.prototypes[g.prototype];
          for (int k = 0; k < 3; ++k)
            if (!(o[k] >= proto.lo[k] && o[k] <= proto.hi[k])) return false;
          for (std::uint32_t part : proto.parts)
            if (part < scene.parts.size() && contains(scene, scene.parts[part], o, rule, depth + 1))
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
          // A plane is a half-space: a solid inside CSG and as a medium (the sea),
          // but a floor at the top level, which a camera above or below is not
          // "inside" as an object.
          if (std::is_same_v<K, ir::Plane> && depth == 0 && rule == InsideRule::Object)
            return false;
          if (!geom::has_inside(s)) return false;
          geom::Spans spans = geom::solid_intervals(g, o, kProbe, 0.0, INFINITY);
          return spans.count > 0 && spans.span[0].t_in == 0 && spans.span[0].t_out > 0;
        } else {
          return false;
        }
      },
      s.geom);
}

}  // namespace

bool point_inside(const ir::Scene& scene, const ir::Shape& shape, ir::Vec3 world_point,
                  InsideRule rule) {
  return contains(scene, shape, world_point, rule, 0);
}

bool point_inside_part(const ir::Scene& scene, const ir::Shape& instance, const ir::Shape& part,
                       ir::Vec3 world_point, InsideRule rule) {
  if (rule == InsideRule::Object && ir::moves(instance, scene)) return false;
  return contains(scene, part, instance.world_from_object().inverse().point(world_point), rule, 1);
}

}  // namespace snell::rt::geom
