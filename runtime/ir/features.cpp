#include <variant>

#include "runtime/ir/dump.hpp"
#include "runtime/ir/ir.hpp"

namespace snell::ir {

namespace {
// "a marble pattern", "an image", "a shading-function pattern" (snell check).
std::string pattern_phrase(const Texture& t) {
  if (std::holds_alternative<ImageTexture>(t.pattern)) return "an image";
  if (std::holds_alternative<FunctionPattern>(t.pattern)) return "a shading-function pattern";
  return "a " + to_string(t.kind()) + " pattern";
}
}  // namespace

Features Features::all() {
  Features f;
  f.motion_blur = f.depth_of_field = f.point_lights = f.area_lights = f.mirror = f.glossy =
      f.dielectric = f.absorption = f.interiors = f.glazed = f.highlights = f.textures = f.bumps =
          f.finish = true;
  f.reasons.push_back({"all", "--features=all forces the general kernel"});
  return f;
}

Features analyze_features(const Scene& scene) {
  Features f;
  auto why = [&](const char* effect, std::string reason) {
    f.reasons.push_back({effect, std::move(reason)});
  };
  const Camera& cam = scene.camera;
  bool shutter_open = cam.shutter_close > cam.shutter_open;
  std::size_t movers = 0;
  std::size_t first_mover = 0;
  for (std::size_t i = 0; i < scene.shapes.size(); ++i)
    if (moves(scene.shapes[i], scene)) {
      if (movers++ == 0) first_mover = i;
    }
  if (shutter_open && movers > 0) {
    f.motion_blur = true;
    why("motion blur", std::to_string(movers) + " object(s) move, the first at " +
                           to_string(scene.shapes[first_mover].src, scene) +
                           ", and the shutter is open from " + num(cam.shutter_open) + " to " +
                           num(cam.shutter_close));
  } else if (movers > 0) {
    why("motion blur (off)", "objects have motion but the shutter is closed (shutter <" +
                                 num(cam.shutter_open) + ", " + num(cam.shutter_close) + ">)");
  } else if (shutter_open) {
    why("motion blur (off)", "the shutter is open but nothing moves");
  }
  if (cam.aperture > 0) {
    f.depth_of_field = true;
    why("depth of field", "camera aperture " + num(cam.aperture) + " > 0 at " +
                              to_string(cam.src, scene) + ", focused at " +
                              num(cam.focal_distance));
  }
  if (!scene.point_lights.empty()) {
    f.point_lights = true;
    why("point lights", std::to_string(scene.point_lights.size()) +
                            " point light(s): one shadow ray each per shading point");
  }
  if (!scene.area_lights.empty()) {
    f.area_lights = true;
    std::uint64_t rays = 0;
    for (const AreaLight& l : scene.area_lights) rays += std::uint64_t(l.samples_u) * l.samples_v;
    why("area lights", std::to_string(scene.area_lights.size()) + " area light(s): " +
                           std::to_string(rays) + " shadow rays per shading point in all");
  }
  std::vector<bool> used(scene.materials.size(), false);
  for (const Shape& s : scene.shapes)
    if (s.material < used.size()) used[s.material] = true;
  for (const Shape& s : scene.parts)
    if (s.material < used.size()) used[s.material] = true;
  for (std::size_t i = 0; i < scene.materials.size(); ++i) {
    if (!used[i]) continue;
    const Material& m = scene.materials[i];
    std::string where = to_string(m.src, scene);
    auto once = [&](bool& flag, const char* effect, std::string reason) {
      if (!flag) {
        flag = true;
        why(effect, std::move(reason));
      }
    };
    auto highlight = [&](double specular, double shininess) {
      if (specular > 0)
        once(f.highlights, "highlights",
             "specular " + num(specular) + " shininess " + num(shininess) + " at " + where +
                 ": a Blinn-Phong term per light sample");
    };
    auto textured = [&](const Texture& t) {
      if (!t.is_constant()) once(f.textures, "textures", pattern_phrase(t) + " at " + where);
    };
    if (m.bump.on())
      once(f.bumps, "bumps",
           "a bump of " + to_string(m.bump.pattern.kind()) + " amount " + num(m.bump.amount) +
               " at " + where);
    std::visit(
        Overloaded{
            [&](const Diffuse& d) {
              textured(d.color);
              highlight(d.specular, d.shininess);
            },
            [&](const Mirror& k) {
              textured(k.color);
              once(f.mirror, "mirror", "a mirror material at " + where);
            },
            [&](const Glossy& g) {
              textured(g.color);
              if (g.blur > 0)
                once(f.glossy, "glossy",
                     "a glossy material with blur " + num(g.blur) + " at " + where);
              else
                once(f.mirror, "mirror", "a glossy material with blur 0 (a mirror) at " + where);
            },
            [&](const Dielectric& d) {
              once(f.dielectric, "dielectric",
                   "a dielectric of ior " + num(d.ior) + " at " + where);
              if (max_component(d.absorb) > 0)
                once(f.absorption, "absorption", "absorb " + to_string(d.absorb) + " at " + where);
              if (d.priority > 0)
                once(f.interiors, "interiors",
                     "a dielectric of priority " + std::to_string(d.priority) + " at " + where +
                         ": rays track the prioritised solids they are inside");
            },
            [&](const Glazed& g) {
              textured(g.color);
              once(f.glazed, "glazed", "a glazed material at " + where);
              highlight(g.specular, g.shininess);
            },
        },
        m.model);
  }
  if (!scene.background.is_constant())
    why("background", pattern_phrase(scene.background) +
                          " as the background, evaluated at each escaping ray's direction");
  f.finish = f.highlights || f.bumps;
  return f;
}

}  // namespace snell::ir
