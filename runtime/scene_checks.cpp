#include "runtime/scene_checks.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "runtime/geometry/motion.hpp"
#include "runtime/geometry/point_inside.hpp"

namespace snell::rt {

namespace {

// A max_depth past which the scene is warned of its time (scene_warnings).
constexpr std::uint32_t kDeepTree = 1000;
// Rays per camera ray a split tree may make before the scene is warned: 2^20, a
// tree 20 deep with none pruned (at 640x480 and 16 spp, 5e12 rays: days). 31
// nested glass spheres at max_depth 24 and min_weight 1e-30 ran past a minute at
// 8x6 pixels without a word while the limit was 2^24 and asked only past depth 24.
constexpr double kSplitRays = 1048576.0;
// Shadow rays per shading point, over all area lights, past which the scene is
// warned: as many as one light may take (lower.cpp). 1000 lights of 256x256 took
// about 40 minutes at 16x12 pixels.
constexpr std::uint64_t kShadowRaysPerPoint = 65536;

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

std::vector<SceneWarning> scene_warnings(const ir::Scene& scene) {
  std::vector<SceneWarning> out;
  if (scene.shapes.empty()) {
    // An area light is a visible surface (§7): the image is not the background alone.
    if (scene.area_lights.empty())
      out.push_back({"the scene has no object: the image will be the background alone", {}});
    return out;
  }
  if (scene.point_lights.empty() && scene.area_lights.empty())
    for (const ir::Shape& s : scene.shapes) {
      bool dark = false;
      ir::surface_materials(scene, s, [&](std::uint32_t m) {
        dark = dark || (m < scene.materials.size() && needs_light(scene.materials[m]));
      });
      if (dark) {
        out.push_back({fmt::format("the scene has no light: diffuse and glazed surfaces (the "
                                   "first at {}) will be black",
                                   ir::to_string(s.src, scene)),
                       s.src});
        break;
      }
    }
  for (const ir::Shape& s : scene.shapes)
    if (geom::point_inside(scene, s, scene.camera.location, geom::InsideRule::Object)) {
      const ir::Vec3 c = scene.camera.location;
      // A dielectric is a medium the camera looks out of (water around a diver),
      // not a wall it sees the inside of: an object all of whose surfaces are
      // dielectrics (an instance of a glass of water, whose own material is none).
      bool medium = true, any = false;
      ir::surface_materials(scene, s, [&](std::uint32_t m) {
        any = true;
        medium = medium && m < scene.materials.size() && scene.materials[m].as<ir::Dielectric>();
      });
      medium = medium && any;
      out.push_back(
          {fmt::format("the camera at <{}, {}, {}> is inside the {} at {}: {}", c.x, c.y, c.z,
                       written_kind(scene, s), ir::to_string(s.src, scene),
                       medium ? "its rays start in that dielectric and see out through its surface"
                              : "it will see only that object's inside"),
           s.src});
    }
  // A ray tree as deep as asked is traced (mirrors that face each other reflect to
  // the last level, min_weight 0 prunes nothing): a render's time grows with it,
  // and at a million levels a 64×48 image took minutes, at 2^32 it would take days.
  if (scene.settings.max_depth > kDeepTree)
    out.push_back({fmt::format("max_depth {} lets a ray tree be that deep (mirrors facing each "
                               "other reflect to the last level), and a render takes time in "
                               "proportion; scenes seldom need more than 100",
                               scene.settings.max_depth),
                   scene.settings.src});
  // Without min_weight nothing prunes a split tree: each dielectric hit traces both
  // the reflection and the refraction, so nested or facing glass makes up to 2^D
  // rays per camera ray (30 glass shells at max_depth 50 ran for years). A tiny one
  // prunes little: near normal incidence a reflection keeps R0 = ((n-1)/(n+1))^2 of
  // the weight, so a branch survives about log(w)/log(R0) reflections, and the
  // tree holds the paths of D levels with at most that many (1e-30 at max_depth 40
  // in ten glass shells ran past a minute at 16x12).
  if (scene.settings.branching == ir::Branching::Split && scene.settings.max_depth <= kDeepTree) {
    double r0 = 0;  // the largest reflectance at normal incidence
    for (const ir::Material& m : scene.materials)
      if (const ir::Dielectric* d = m.as<ir::Dielectric>()) {
        const double n = std::max(d->ior, 1 / d->ior), r = (n - 1) / (n + 1);
        r0 = std::max(r0, std::max(r * r, 1e-6));
      }
    const std::uint32_t depth = scene.settings.max_depth;
    const double w = scene.settings.min_weight;
    // Paths of `depth` splits with at most j reflections: sum of C(depth, i), i <= j.
    const double j = w > 0 && r0 > 0 ? std::floor(std::log(w) / std::log(r0)) : double(depth);
    double rays = 0, c = 1;
    for (std::uint32_t i = 0; i <= depth && i <= j; ++i) {
      rays += c;
      c = c * double(depth - i) / double(i + 1);
    }
    if (r0 > 0 && w == 0 && rays > kSplitRays)
      out.push_back({fmt::format("min_weight 0 prunes no ray: at every dielectric hit a ray splits "
                                 "in two, so max_depth {} lets a camera ray make up to 2^{} rays "
                                 "and a render may not end; min_weight 0.001 (the default) drops "
                                 "only what cannot be seen, or branching \"stochastic\" follows "
                                 "one branch",
                                 depth, depth),
                     scene.settings.src});
    else if (r0 > 0 && rays > kSplitRays)
      out.push_back({fmt::format("min_weight {} prunes little: a reflection off this glass keeps "
                                 "at least {:.2g} of a ray's weight, so at max_depth {} a camera "
                                 "ray may make about {:.2g} rays and a render may not end; "
                                 "min_weight 0.001 (the default) drops only what cannot be seen, "
                                 "or branching \"stochastic\" follows one branch",
                                 w, r0, depth, rays),
                     scene.settings.src});
  }
  std::uint64_t shadow_rays = 0;
  for (const ir::AreaLight& l : scene.area_lights)
    shadow_rays += std::uint64_t(l.samples_u) * l.samples_v;
  if (shadow_rays > kShadowRaysPerPoint)
    out.push_back({fmt::format("the area lights take {} shadow rays per shading point in all (at "
                               "most {} for one light), and a render takes time in proportion; "
                               "fewer samples per light, or more camera samples, cost less for "
                               "the same noise",
                               shadow_rays, kShadowRaysPerPoint),
                   {}});
  // Boxes, triangles, meshes and instances move in linear steps (at most 128, each
  // turning at most 90°); spheres and the other shapes are placed exactly per ray.
  for (const ir::Shape& s : scene.shapes) {
    const ir::ShapeKind k = s.kind();
    if (k != ir::ShapeKind::Box && k != ir::ShapeKind::Triangle && k != ir::ShapeKind::Mesh &&
        k != ir::ShapeKind::Instance)
      continue;
    const double deg = geom::turn_degrees(s.motion());
    if (deg > geom::kMaxFollowedTurn)
      out.push_back(
          {fmt::format(
               "the {} at {} turns {:.6g}° during the shutter; a moving {} is traced in at most "
               "128 steps of 90°, {:g}° in all, so its blur will not follow the spin (a sphere or "
               "a CSG object of it would)",
               written_kind(scene, s), ir::to_string(s.src, scene), deg, written_kind(scene, s),
               geom::kMaxFollowedTurn),
           s.src});
  }
  return out;
}

}  // namespace snell::rt
