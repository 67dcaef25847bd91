// Uniform sampling of the solid angle a rectangle subtends at a point (Ureña,
// Fajardo, King 2013, "An Area-Preserving Parametrization for Spherical
// Rectangles"): a point of the rectangle whose direction is uniform over the
// spherical rectangle, so a light sample's density is 1/S in solid angle and its
// estimate L · cosθ · S has no 1/d² or cosθ_light in it, the terms that make area
// sampling noisy near a large light.
//
// Double precision throughout: S is the sum of four angles minus 2π, which cancels
// when the rectangle subtends little; in double that stays accurate to about 1e-15
// sr absolute, so callers use area sampling below kMinSolidAngle, where the two
// densities are equal to within the light's size over its distance anyway.
#pragma once

#include <algorithm>
#include <cmath>

#include "runtime/ir/ir.hpp"

namespace snell::rt {

struct SphericalRect {
  static constexpr double kMinSolidAngle = 1e-7;

  // The rectangle's frame at the reference point: x, y along its edges, z normal
  // pointing away from the point; (x0..x1) × (y0..y1) at height z0 < 0.
  ir::Vec3 o, x, y, z;
  double x0 = 0, x1 = 0, y0 = 0, y1 = 0, z0 = 0;
  double b0 = 0, b1 = 0, k = 0;
  double solid_angle = 0;  // S, steradians

  // corner, unit edge directions ux ⟂ uy with lengths lx, ly, reference point p.
  // False when the point lies (numerically) in the rectangle's plane: S = 0.
  bool init(ir::Vec3 corner, ir::Vec3 ux, double lx, ir::Vec3 uy, double ly, ir::Vec3 p) {
    o = p;
    x = ux;
    y = uy;
    z = ir::cross(ux, uy);
    ir::Vec3 d = corner - p;
    z0 = ir::dot(d, z);
    if (z0 > 0) {
      z = z * -1.0;
      z0 = -z0;
    }
    if (!(z0 < 0)) return false;
    x0 = ir::dot(d, x);
    y0 = ir::dot(d, y);
    x1 = x0 + lx;
    y1 = y0 + ly;
    // The inner normals of the four great-circle edges, written out in the local
    // frame (their components are the vertices' coordinates).
    auto unit = [](double a, double b, double c, double out[3]) {
      double l = std::sqrt(a * a + b * b + c * c);
      out[0] = a / l, out[1] = b / l, out[2] = c / l;
    };
    double n0[3], n1[3], n2[3], n3[3];
    unit(0, z0, -y0, n0);
    unit(-z0, 0, x1, n1);
    unit(0, -z0, y1, n2);
    unit(z0, 0, -x0, n3);
    auto angle = [](const double a[3], const double b[3]) {
      return std::acos(std::clamp(-(a[0] * b[0] + a[1] * b[1] + a[2] * b[2]), -1.0, 1.0));
    };
    double g0 = angle(n0, n1), g1 = angle(n1, n2), g2 = angle(n2, n3), g3 = angle(n3, n0);
    b0 = n0[2];
    b1 = n2[2];
    k = 2 * M_PI - g2 - g3;
    solid_angle = g0 + g1 - k;
    return solid_angle > 0;
  }

  // The point of the rectangle at (u, v) in [0, 1)²; uniform in solid angle.
  ir::Vec3 sample(double u, double v) const {
    double au = u * solid_angle + k;
    double fu = (std::cos(au) * b0 - b1) / std::sin(au);
    double cu = std::copysign(1.0, fu) / std::sqrt(fu * fu + b0 * b0);
    cu = std::clamp(cu, -1.0, 1.0);
    double xu = -(cu * z0) / std::sqrt(std::max(1e-300, 1 - cu * cu));
    xu = std::clamp(xu, x0, x1);
    double dd = std::sqrt(xu * xu + z0 * z0);
    double h0 = y0 / std::sqrt(dd * dd + y0 * y0), h1 = y1 / std::sqrt(dd * dd + y1 * y1);
    double hv = h0 + v * (h1 - h0), hv2 = hv * hv;
    double yv = hv2 < 1 - 1e-12 ? hv * dd / std::sqrt(1 - hv2) : y1;
    yv = std::clamp(yv, y0, y1);
    return o + x * xu + y * yv + z * z0;
  }
};

}  // namespace snell::rt
