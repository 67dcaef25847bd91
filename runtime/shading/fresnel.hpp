// Fresnel reflectance, refraction and Beer absorption: pure functions in double.
// Double because `ior` is user-chosen and unbounded; float32 loses ~1e-3 for extreme
// ratios (robustness.md §3.9). One `Interface` value carries the single TIR test
// that both the reflectance and the refracted direction use, so they never disagree.
#pragma once

#include <algorithm>
#include <cmath>
#include <string>

#include "runtime/ir/ir.hpp"

namespace snell::rt {

// The interface as seen by one incident ray. cos_i: cosine of the incidence angle,
// measured on the incident side (>= 0). eta = n_transmitted / n_incident.
struct Interface {
  double cos_i = 1, cos_t = 1, eta = 1;
  bool tir = false;  // total internal reflection: no refracted ray exists
};

inline Interface make_interface(double cos_i, double eta) {
  Interface f;
  f.cos_i = std::clamp(cos_i, 0.0, 1.0);
  f.eta = eta;
  if (eta == 1) {  // index-matched: reflects nothing, refracts straight
    f.cos_t = f.cos_i;
    return f;
  }
  double sin2_t = (1 - f.cos_i * f.cos_i) / (eta * eta);
  if (sin2_t >= 1) {
    f.tir = true;
    f.cos_t = 0;
    return f;
  }
  f.cos_t = std::sqrt(1 - sin2_t);
  return f;
}

// Unpolarised Fresnel reflectance from Fresnel's equations.
inline double fresnel_exact(const Interface& f) {
  if (f.tir) return 1;
  if (f.eta == 1) return 0;
  double ci = f.cos_i, ct = f.cos_t, n = f.eta;
  double rs = (ci - n * ct) / (ci + n * ct);
  double rp = (n * ci - ct) / (n * ci + ct);
  return 0.5 * (rs * rs + rp * rp);
}

// Schlick's approximation with the cosine taken on the less dense side (cos_t when
// leaving the denser medium), and exactly 1 under TIR (robustness.md §3.2).
inline double fresnel_schlick(const Interface& f) {
  if (f.tir) return 1;
  if (f.eta == 1) return 0;
  double r0 = (1 - f.eta) / (1 + f.eta);
  r0 *= r0;
  double c = f.eta < 1 ? f.cos_t : f.cos_i;
  double m = 1 - c;
  double m2 = m * m;
  return r0 + (1 - r0) * m2 * m2 * m;
}

inline double reflectance(const Interface& f, ir::FresnelMode mode) {
  return mode == ir::FresnelMode::Schlick ? fresnel_schlick(f) : fresnel_exact(f);
}

// Convenience in the convention of robustness.md's script: cos_i signed against
// the normal; negative means the ray arrives from inside (the normal's back side),
// so the ratio inverts.
inline double fresnel_dielectric(double cos_i, double eta, ir::FresnelMode mode) {
  if (cos_i < 0) {
    eta = 1 / eta;
    cos_i = -cos_i;
  }
  return reflectance(make_interface(cos_i, eta), mode);
}

inline std::string to_string(const Interface& f) {
  return "interface { cos_i " + std::to_string(f.cos_i) + " cos_t " + std::to_string(f.cos_t) +
         " eta " + std::to_string(f.eta) + (f.tir ? " tir" : "") + " }";
}

struct Vec3d {
  double x, y, z;
};

// Refracted direction for the unit incident direction `d` (travelling towards the
// surface) and the unit normal `n` on the incident side (dot(d, n) = -cos_i).
// Precondition: !f.tir. Snell: eta·sinθt = sinθi.
inline Vec3d refract(Vec3d d, Vec3d n, const Interface& f) {
  if (f.eta == 1) return d;
  double inv = 1 / f.eta;
  double k = inv * f.cos_i - f.cos_t;
  return {inv * d.x + k * n.x, inv * d.y + k * n.y, inv * d.z + k * n.z};
}

// Beer–Lambert transmittance over distance d with coefficient sigma (per channel).
// exp(-0·∞) is 1 (nothing absorbs over no distance / no absorber over any distance),
// never NaN; huge products give exactly 0.
inline double beer(double sigma, double d) {
  if (sigma == 0 || d == 0) return 1;
  return std::exp(-sigma * d);
}

}  // namespace snell::rt
