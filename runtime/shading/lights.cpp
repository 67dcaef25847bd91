#include "runtime/shading/lights.hpp"

#include <fmt/format.h>

#include <cmath>

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
    for (Vec3f q : {f.corner, f.corner + f.e1, f.corner + f.e2, (f.corner + f.e1) + f.e2})
      f.reach = std::fmax(f.reach, max_abs(q));
    ir::Vec3 nu = area > 0 ? n / area : ir::Vec3(0, 1, 0);
    f.n = to_color(nu);
    // A light of zero area emits nothing (robustness.md #9): radiance 0.
    f.radiance = area > 0 ? to_color(l.radiance) : Color(0);
    f.nu = l.samples_u ? l.samples_u : 1;
    f.nv = l.samples_v ? l.samples_v : 1;
    f.two_sided = l.two_sided;
    // Solid-angle sampling needs a rectangle; a parallelogram whose edges are not
    // perpendicular (to 1e-9 of their lengths) keeps area sampling.
    double l1 = ir::length(l.edge1), l2 = ir::length(l.edge2);
    if (scene.settings.light_sampling != ir::LightSampling::Area && area > 0 &&
        std::fabs(ir::dot(l.edge1, l.edge2)) <= 1e-9 * l1 * l2) {
      f.solid_angle = true;
      if (scene.settings.light_sampling == ir::LightSampling::Adaptive) {
        double cu = l1 / f.nu, cv = l2 / f.nv;
        f.near_cell2 = float((cu * cu + cv * cv) * (AreaLightF::kNearCell * AreaLightF::kNearCell));
      }
      f.ux = l.edge1 / l1;
      f.uy = l.edge2 / l2;
      f.lx = l1;
      f.ly = l2;
      f.corner_d = c;
    }
    areas.push_back(f);
  }
  for (const ir::PointLight& l : scene.point_lights) {
    ir::Vec3 p = l.position - o;
    points.push_back({to_float(p.x, p.y, p.z), to_color(l.intensity)});
  }
}

bool AreaLightF::sample_li_solid_angle(Vec3f p, Vec3f o, Vec3f nf, float time, std::uint32_t iu,
                                       std::uint32_t iv, float ju, float jv, float scale,
                                       LightSample& s) const {
  ir::Vec3 pd(p.x, p.y, p.z);
  // A one-sided light emits nothing towards a point behind (or in) its plane.
  if (!two_sided && !(ir::dot(ir::Vec3(n.x, n.y, n.z), pd - corner_d) > 0)) return false;
  double cx = lx / nu, cy = ly / nv;
  ir::Vec3 cell = corner_d + ux * (cx * iu) + uy * (cy * iv);
  SphericalRect sr;
  if (!sr.init(cell, ux, cx, uy, cy, pd)) return false;
  if (sr.solid_angle < SphericalRect::kMinSolidAngle)
    return sample_li_area(p, o, nf, time, iu, iv, ju, jv, scale, s);
  ir::Vec3 qd = sr.sample(ju, jv);
  float cos_s, cos_l, d2;
  if (!shadow_to(to_float(qd.x, qd.y, qd.z), p, o, nf, time, scale, s, cos_s, cos_l, d2))
    return false;
  s.g = float(cos_s / std::sqrt(double(d2)) * sr.solid_angle);
  return true;
}

std::string to_string(const PointLightF& l) {
  return fmt::format("point_light_f {{ pos {} intensity {} }}", to_string(l.pos),
                     to_string(l.intensity));
}

std::string to_string(const AreaLightF& l) {
  return fmt::format(
      "area_light_f {{ corner {} e1 {} e2 {} n {} area {} radiance {} grid {}x{} {} sampling {} }}",
      to_string(l.corner), to_string(l.e1), to_string(l.e2), to_string(l.n), l.area,
      to_string(l.radiance), l.nu, l.nv, l.two_sided ? "two_sided" : "one_sided",
      !l.solid_angle     ? "area"
      : l.near_cell2 > 0 ? "adaptive"
                         : "solid_angle");
}

}  // namespace snell::rt
