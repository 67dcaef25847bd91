// The lights (§7) in camera-relative float, as the integrators see them:
// `le(dir)` the radiance a ray along dir sees on the light, and `sample_li` the
// shadow ray towards one light sample with the geometry factor G that turns the
// light's radiance or intensity into what a Lambertian surface receives:
//   point light   I · cosθ / d²                          (one sample)
//   area light    L · cosθ_surf · cosθ_light · A / (d² · n) per cell of its
//                 jittered nu × nv grid (area-to-solid-angle), or with
//                 light_sampling "solid_angle" L · cosθ_surf · S_cell, the cell
//                 sampled uniformly over the solid angle S_cell it subtends
//                 (spherical_rect.hpp; rectangles only, a skewed parallelogram
//                 keeps area sampling)
// A sample the surface cannot see (behind it, in its plane within the ray offset,
// facing away) is reported as none: it adds exactly 0 (robustness #4, #27).
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "runtime/geometry/ray.hpp"
#include "runtime/ir/ir.hpp"
#include "runtime/shading/spherical_rect.hpp"
#include "runtime/vec.hpp"

namespace snell::rt {

// A shadow ray from the shading point towards a light sample, and the sample's
// geometry factor; the contribution is value · g when g is finite and the ray is
// not occluded.
struct LightSample {
  Ray shadow;
  Color value;  // intensity (point light) or radiance (area light)
  float g = 0;
  // From the shading point to the light sample, not normalised: the direction a
  // highlight needs (the shadow ray's leaves the offset origin for an offset target).
  Vec3f to;
};

struct PointLightF {
  Vec3f pos;
  Color intensity;

  // `p`: the shading point, `o`: the shadow rays' origin (p moved off the surface,
  // spawn_origin), `nf`: the normal on the viewer's side.
  bool sample_li(Vec3f p, Vec3f o, Vec3f nf, float time, LightSample& s) const {
    Vec3f to = pos - p;
    float d2 = dot(to, to);
    float cos_s = dot(nf, to);
    // A light at (numerically) zero distance has no defined direction: it adds
    // nothing rather than an infinity (robustness #4: d² underflows at 1e-20).
    if (!(cos_s > 0) || !(d2 > 0)) return false;
    // The light must also lie beyond the offset origin: p is off the true surface
    // by rounding, so cos_s of a light in the receiver's plane is ±1e-7, not 0.
    // Within the offset the side is unknowable; such a light adds exactly 0
    // (robustness #27). It changes nothing for a light clearly above the surface.
    if (!(dot(nf, pos - o) > 0)) return false;
    s.shadow = Ray{o, pos - o, 1.0f, time};
    s.to = to;
    float d = std::sqrt(d2);
    s.g = cos_s / (d * d2);
    s.value = intensity;
    return true;
  }
};

struct AreaLightF {
  Vec3f corner, e1, e2, n;  // n: unit cross(e1, e2)
  float area = 0;
  // The largest coordinate of its corners (camera-relative): a sample's rounding
  // comes from coordinates no larger, so its shadow-ray target's offset scale is
  // near_scale(scale, reach) (vec.hpp).
  float reach = 0;
  Color radiance;
  std::uint32_t nu = 1, nv = 1;
  bool two_sided = false;
  // light_sampling "solid_angle" on a rectangle: its unit edges and their lengths.
  bool solid_angle = false;
  ir::Vec3 corner_d, ux, uy;  // corner_d: `corner` in double
  double lx = 0, ly = 0;
  // light_sampling "adaptive": a cell is sampled by solid angle only when the
  // shading point is nearer its centre than kNearCell cell diagonals (the squared
  // distance below near_cell2); farther, 1/d² and cosθ_light barely vary over the
  // cell, area sampling has as little noise, and it costs half as much. 0: always.
  static constexpr double kNearCell = 4;
  float near_cell2 = 0;

  bool dark() const { return radiance.x == 0 && radiance.y == 0 && radiance.z == 0; }
  // The area of one cell of the nu × nv grid.
  double cell_area() const { return double(area) / double(nu * nv); }
  // Radiance sent along `dir` (the ray's direction, towards the light): one-sided
  // lights emit only towards cross(edge1, edge2).
  Color le(Vec3f dir) const {
    if (two_sided || dot(dir, n) < 0) return radiance;
    return Color(0);
  }
  // The sample of grid cell (iu, iv) at jitter (u, v); `scale`: offset_scale. The
  // shadow ray ends at the sample moved off the light towards p, so the light's own
  // surface never blocks it.
  bool sample_li(Vec3f p, Vec3f o, Vec3f nf, float time, std::uint32_t iu, std::uint32_t iv,
                 float ju, float jv, float scale, LightSample& s) const {
    if (solid_angle && (near_cell2 == 0 || near(p, iu, iv)))
      return sample_li_solid_angle(p, o, nf, time, iu, iv, ju, jv, scale, s);
    return sample_li_area(p, o, nf, time, iu, iv, ju, jv, scale, s);
  }
  bool sample_li_area(Vec3f p, Vec3f o, Vec3f nf, float time, std::uint32_t iu, std::uint32_t iv,
                      float ju, float jv, float scale, LightSample& s) const {
    float u = (float(iu) + ju) / float(nu), v = (float(iv) + jv) / float(nv);
    Vec3f q = corner + e1 * u + e2 * v;
    float cos_s, cos_l, d2;
    if (!shadow_to(q, p, o, nf, time, scale, s, cos_s, cos_l, d2)) return false;
    float inv_n = 1.0f / float(nu * nv);
    s.g = cos_s * std::fabs(cos_l) / (d2 * d2) * area * inv_n;
    return true;
  }
  bool near(Vec3f p, std::uint32_t iu, std::uint32_t iv) const {
    Vec3f c =
        corner + e1 * ((float(iu) + 0.5f) / float(nu)) + e2 * ((float(iv) + 0.5f) / float(nv));
    Vec3f d = c - p;
    return dot(d, d) < near_cell2;
  }
  // What every sampling shares for a point q on the light: the visibility checks,
  // the shadow ray, `to` and the radiance; cos_s, cos_l (against the unnormalised
  // `to`) and d2 are left for the caller's geometry factor.
  bool shadow_to(Vec3f q, Vec3f p, Vec3f o, Vec3f nf, float time, float scale, LightSample& s,
                 float& cos_s, float& cos_l, float& d2) const {
    Vec3f to = q - p;
    d2 = dot(to, to);
    cos_s = dot(nf, to);
    cos_l = -dot(n, to);
    if (!(cos_s > 0) || !(d2 > 0) || !(dot(nf, q - o) > 0)) return false;  // as point lights
    if (!two_sided && !(cos_l > 0)) return false;
    Vec3f side = cos_l > 0 ? n : -n;  // the light's face towards p
    Vec3f target = offset_ray_origin(q, side, near_scale(scale, reach));
    s.shadow = Ray{o, target - o, kAreaShadowEnd, time};
    s.to = to;
    s.value = radiance;
    return true;
  }
  // The same cell sampled by solid angle (lights.cpp); a cell subtending less than
  // SphericalRect::kMinSolidAngle falls back to the area sample above.
  bool sample_li_solid_angle(Vec3f p, Vec3f o, Vec3f nf, float time, std::uint32_t iu,
                             std::uint32_t iv, float ju, float jv, float scale,
                             LightSample& s) const;
};

// Every light of a scene, moved by -origin (the camera) into float.
struct Lights {
  std::vector<PointLightF> points;
  std::vector<AreaLightF> areas;
  Lights(const ir::Scene& scene, ir::Vec3 origin);
};

std::string to_string(const PointLightF& l);
std::string to_string(const AreaLightF& l);

}  // namespace snell::rt
