#include "runtime/primaries.hpp"

#include <fmt/format.h>

#include <cmath>

namespace snell::rt {

namespace {

struct M3 {
  double a[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
};

M3 mul(const M3& x, const M3& y) {
  M3 r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double s = 0;
      for (int k = 0; k < 3; ++k) s += x.a[i][k] * y.a[k][j];
      r.a[i][j] = s;
    }
  return r;
}

// Inverse by the adjugate; false when (nearly) singular.
bool invert(const M3& m, M3& out) {
  const auto& a = m.a;
  double c00 = a[1][1] * a[2][2] - a[1][2] * a[2][1];
  double c01 = a[1][2] * a[2][0] - a[1][0] * a[2][2];
  double c02 = a[1][0] * a[2][1] - a[1][1] * a[2][0];
  double det = a[0][0] * c00 + a[0][1] * c01 + a[0][2] * c02;
  if (!std::isfinite(det) || std::fabs(det) < 1e-9) return false;
  double k = 1 / det;
  out.a[0][0] = c00 * k;
  out.a[0][1] = (a[0][2] * a[2][1] - a[0][1] * a[2][2]) * k;
  out.a[0][2] = (a[0][1] * a[1][2] - a[0][2] * a[1][1]) * k;
  out.a[1][0] = c01 * k;
  out.a[1][1] = (a[0][0] * a[2][2] - a[0][2] * a[2][0]) * k;
  out.a[1][2] = (a[0][2] * a[1][0] - a[0][0] * a[1][2]) * k;
  out.a[2][0] = c02 * k;
  out.a[2][1] = (a[0][1] * a[2][0] - a[0][0] * a[2][1]) * k;
  out.a[2][2] = (a[0][0] * a[1][1] - a[0][1] * a[1][0]) * k;
  return true;
}

// XYZ (Y = 1) of chromaticity (x, y).
void xyz_of(double x, double y, double out[3]) {
  out[0] = x / y;
  out[1] = 1;
  out[2] = (1 - x - y) / y;
}

// XYZ from linear RGB of primaries `c`: each primary's XYZ scaled so that RGB
// (1, 1, 1) is the white with Y = 1 (SMPTE RP 177).
bool xyz_from_rgb(const Chromaticities& c, M3& m) {
  for (float v : c)
    if (!std::isfinite(v)) return false;
  for (int i = 0; i < 4; ++i)
    if (!(c[2 * i + 1] > 0)) return false;
  M3 p;
  for (int j = 0; j < 3; ++j) {
    double col[3];
    xyz_of(c[2 * j], c[2 * j + 1], col);
    for (int i = 0; i < 3; ++i) p.a[i][j] = col[i];
  }
  M3 inv;
  if (!invert(p, inv)) return false;
  double w[3], s[3];
  xyz_of(c[6], c[7], w);
  for (int i = 0; i < 3; ++i) s[i] = inv.a[i][0] * w[0] + inv.a[i][1] * w[1] + inv.a[i][2] * w[2];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m.a[i][j] = p.a[i][j] * s[j];
  return true;
}

// Bradford cone response (Lam 1985).
constexpr M3 kBradford = {
    {{0.8951, 0.2664, -0.1614}, {-0.7502, 1.7135, 0.0367}, {0.0389, -0.0685, 1.0296}}};

// XYZ under white (sx, sy) to XYZ under white (dx, dy), von Kries in Bradford's
// cone space.
M3 adapt(double sx, double sy, double dx, double dy) {
  double s[3], d[3], cs[3], cd[3];
  xyz_of(sx, sy, s);
  xyz_of(dx, dy, d);
  for (int i = 0; i < 3; ++i) {
    cs[i] = kBradford.a[i][0] * s[0] + kBradford.a[i][1] * s[1] + kBradford.a[i][2] * s[2];
    cd[i] = kBradford.a[i][0] * d[0] + kBradford.a[i][1] * d[1] + kBradford.a[i][2] * d[2];
  }
  M3 scale;
  for (int i = 0; i < 3; ++i) scale.a[i][i] = cd[i] / cs[i];
  M3 inv;
  invert(kBradford, inv);
  return mul(inv, mul(scale, kBradford));
}

}  // namespace

bool is_rec709(const Chromaticities& c) {
  for (int i = 0; i < 8; ++i)
    if (!(std::fabs(c[i] - kRec709Chromaticities[i]) <= 1e-4f)) return false;
  return true;
}

bool rec709_from(const Chromaticities& c, Mat3f& out, std::string& error) {
  M3 to_xyz, from_709, rec709_to_xyz;
  if (!xyz_from_rgb(c, to_xyz)) {
    error = "its chromaticities " + to_string(c) + " are not a set of RGB primaries";
    return false;
  }
  xyz_from_rgb(kRec709Chromaticities, rec709_to_xyz);
  invert(rec709_to_xyz, from_709);
  M3 m = mul(from_709,
             mul(adapt(c[6], c[7], kRec709Chromaticities[6], kRec709Chromaticities[7]), to_xyz));
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      if (!std::isfinite(m.a[i][j])) {
        error = "its chromaticities " + to_string(c) + " are not a set of RGB primaries";
        return false;
      }
      out[3 * i + j] = float(m.a[i][j]);
    }
  return true;
}

std::string to_string(const Chromaticities& c) {
  return fmt::format("(red {} {}, green {} {}, blue {} {}, white {} {})", c[0], c[1], c[2], c[3],
                     c[4], c[5], c[6], c[7]);
}

}  // namespace snell::rt
