#include "runtime/scene_checks.hpp"

#include <fmt/format.h>

#include "runtime/geometry/intervals.hpp"

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

// Whether the world point p lies inside shape s (a solid kind that does not move).
bool contains(const ir::Shape& s, ir::Vec3 p) {
  if (s.motion().moves()) return false;
  ir::Vec3 o = s.world_from_object().inverse().point(p);
  // Any direction: a point inside starts its first span at t = 0. An oblique one,
  // so that a camera on a box's axis does not graze an edge.
  const ir::Vec3 d = ir::normalize(ir::Vec3{0.3141, 0.8731, 0.2718});
  return std::visit(
      [&](const auto& g) {
        using K = std::decay_t<decltype(g)>;
        if constexpr (geom::kSolid<K> && !std::is_same_v<K, ir::Plane>) {
          if (!geom::has_inside(s)) return false;
          geom::Spans spans = geom::solid_intervals(g, o, d, 0.0, INFINITY);
          return spans.count > 0 && spans.span[0].t_in == 0 && spans.span[0].t_out > 0;
        } else {
          return false;
        }
      },
      s.geom);
}

}  // namespace

std::vector<std::string> scene_warnings(const ir::Scene& scene) {
  std::vector<std::string> out;
  if (scene.shapes.empty()) {
    out.push_back("the scene has no object: the image will be the background alone");
    return out;
  }
  if (scene.point_lights.empty() && scene.area_lights.empty())
    for (const ir::Shape& s : scene.shapes)
      if (s.material < scene.materials.size() && needs_light(scene.materials[s.material])) {
        out.push_back(fmt::format(
            "the scene has no light: diffuse and glazed surfaces (the first at {}) will be black",
            ir::to_string(s.src, scene)));
        break;
      }
  for (const ir::Shape& s : scene.shapes)
    if (contains(s, scene.camera.location)) {
      const ir::Vec3 c = scene.camera.location;
      out.push_back(fmt::format(
          "the camera at <{}, {}, {}> is inside the {} at {}: it will see only that object's "
          "inside",
          c.x, c.y, c.z, ir::to_string(s.kind()), ir::to_string(s.src, scene)));
    }
  return out;
}

}  // namespace snell::rt
