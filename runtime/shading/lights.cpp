#include "runtime/shading/lights.hpp"

#include <fmt/format.h>

namespace snell::rt {

namespace {
Color to_color(ir::Vec3 v) {
  return to_float(v.x, v.y, v.z);
}
}  // namespace

Lights::Lights(const ir::Scene& scene, ir::Vec3 o) {
  for (const ir::AreaLight& l : scene.area_lights) {
    AreaLightF f;
    ir::Vec3 c = l.corner - o;
    ir::Vec3 n = ir::cross(l.edge1, l.edge2);
    double area = ir::length(n);
    f.corner = to_float(c.x, c.y, c.z);
    f.e1 = to_color(l.edge1);
    f.e2 = to_color(l.edge2);
    f.area = float(area);
    ir::Vec3 nu = area > 0 ? n / area : ir::Vec3(0, 1, 0);
    f.n = to_color(nu);
    // A light of zero area emits nothing (robustness.md #9): radiance 0.
    f.radiance = area > 0 ? to_color(l.radiance) : Color(0);
    f.nu = l.samples_u ? l.samples_u : 1;
    f.nv = l.samples_v ? l.samples_v : 1;
    f.two_sided = l.two_sided;
    areas.push_back(f);
  }
  for (const ir::PointLight& l : scene.point_lights) {
    ir::Vec3 p = l.position - o;
    points.push_back({to_float(p.x, p.y, p.z), to_color(l.intensity)});
  }
}

std::string to_string(const PointLightF& l) {
  return fmt::format("point_light_f {{ pos {} intensity {} }}", to_string(l.pos),
                     to_string(l.intensity));
}

std::string to_string(const AreaLightF& l) {
  return fmt::format(
      "area_light_f {{ corner {} e1 {} e2 {} n {} area {} radiance {} grid {}x{} {} }}",
      to_string(l.corner), to_string(l.e1), to_string(l.e2), to_string(l.n), l.area,
      to_string(l.radiance), l.nu, l.nv, l.two_sided ? "two_sided" : "one_sided");
}

}  // namespace snell::rt
