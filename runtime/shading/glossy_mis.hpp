// settings { glossy_sampling "mis" } (docs/language.md): a glossy surface gathers
// the area lights it reflects through two techniques, combined by multiple
// importance sampling with the power heuristic (Veach and Guibas 1995):
//   - its glossy ray (the lobe's sample, GlossySquare, density p_b per unit solid
//     angle), which sees a light's radiance where it hits one;
//   - one light sample per cell of each area light's nu × nv grid, uniform over
//     the cell's area: density p_c = d² / (cosθ_light · A_cell) per unit solid
//     angle at the shading point.
// Every point y of a light is reached by the ray and by exactly one cell (the cells
// tile the light), so the weights of the two techniques that can reach y are
//     w_b = p_b² / (p_b² + p_c²),   w_c = p_c² / (p_b² + p_c²),
// which sum to 1: the expected image is the lobe's alone (the core's meaning). A
// jittered grid draws cell c only inside c, so its sample is an unbiased estimate
// of that cell's share; the cells' sum is the light's.
//
// The glossy "BSDF" of §8 is f·cos = color · p_b (every sample of the lobe has
// weight `color`), so a light sample adds
//     color · Le · p_b / p_c · w_c = color · Le · x / (1 + x²),   x = p_b / p_c,
// and the ray that hits the light adds color · Le · w_b = color · Le · x² / (1 + x²).
// Both in double from the ratio: p_b reaches 1/blur² and overflows float's square
// for blur below ~1e-10; the ratio keeps the weights finite while either density is.
#pragma once

#include <algorithm>
#include <cmath>

#include "runtime/vec.hpp"

namespace snell::rt {

// The light sample's factor x / (1 + x²), x = p_b / p_c; 0 where the lobe cannot
// reach (p_b = 0) or either density is not a finite positive number.
inline double mis_light_factor(double p_b, double p_c) {
  if (!(p_b > 0) || !(p_c > 0) || !std::isfinite(p_b) || !std::isfinite(p_c)) return 0;
  double x = p_b / p_c;
  if (!std::isfinite(x)) return 0;  // p_c far below p_b: the ray alone
  return x / (1 + x * x);
}

// The ray's weight x² / (1 + x²) where it hits a light cell of density p_c; 1 when
// the light technique could not have drawn it (p_c not finite: a grazing light).
inline double mis_ray_weight(double p_b, double p_c) {
  if (!(p_b > 0) || !std::isfinite(p_b)) return 1;
  if (!(p_c > 0)) return 1;
  if (!std::isfinite(p_c)) return 1;
  double r = p_c / p_b;
  return 1 / (1 + r * r);
}

// p_c: a cell of area `cell_area` seen at distance² `d2` under cosθ_light
// `cos_light` (of unit vectors), per unit solid angle.
inline double cell_density(double d2, double cos_light, double cell_area) {
  double c = std::fabs(cos_light) * cell_area;
  return c > 0 ? d2 / c : INFINITY;
}

// Whether any direction of the glossy lobe around the unit mirror direction `r`
// (square of side `blur`, folded above the surface of unit normal `nf`) can meet a
// ball of radius `radius` whose centre is `to_centre` away: the lobe lies within
// the cone of half-angle atan((blur/2 + slack)·√2) about r, and its folded part
// within the same cone about r mirrored in the surface. Conservative by 1e-3 rad,
// so a light it turns away has p_b = 0 at every point: skipping it changes no
// value (the cells' dimensions are their own), it only saves the draws.
inline bool lobe_meets_ball(Vec3f r, Vec3f nf, double blur, Vec3f to_centre, double radius) {
  double d = double(length(to_centre));
  if (!(d > radius)) return true;  // inside the ball (or NaN): do not cull
  double beta = std::asin(std::min(1.0, radius / d));
  double alpha = std::atan((0.5 * blur + 1e-6) * std::sqrt(2.0));
  double reach = std::cos(std::min(3.14159, alpha + beta + 1e-3));
  Vec3f u = to_centre * float(1 / d);
  Vec3f mr = r - nf * (2 * dot(r, nf));
  return double(dot(u, r)) >= reach || double(dot(u, mr)) >= reach;
}

}  // namespace snell::rt
