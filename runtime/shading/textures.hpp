// Colour sources evaluated at a hit (§8): constants and patterns, one overload per
// pattern kind of runtime/ir/kinds.def. Points arrive camera-relative in float and
// are taken back to world space in double here.
#pragma once

#include <cmath>
#include <variant>

#include "runtime/ir/ir.hpp"
#include "runtime/vec.hpp"

namespace snell::rt {

// The parity of floor(x) for every finite x, without converting a huge x to an
// integer (undefined behaviour past 2^63): every double of magnitude >= 2^53 is an
// even integer. (A checker of size 1e-9 seen 1e10 away has cell indices ~1e19.)
inline int floor_parity(double x) {
  double f = std::floor(x);
  if (!(std::fabs(f) < 9007199254740992.0)) return 0;
  return int(static_cast<long long>(f) & 1);
}

// Where a pattern is looked up: the camera-relative hit point, the outward normal,
// and the world point of the camera-relative origin.
struct TexturePoint {
  Vec3f p, n_out;
  ir::Vec3 origin;
};

inline Color pattern_color(const ir::Constant& c, const TexturePoint&) {
  return to_float(c.color.x, c.color.y, c.color.z);
}

// §8 checker: p (world space) moved inward by S/100 along the outward normal, cell
// floor(p / S), even i + j + k takes color1.
inline Color pattern_color(const ir::Checker& c, const TexturePoint& tp) {
  const ir::Vec3 o = tp.origin;
  const Vec3f p = tp.p, n = tp.n_out;
  double s = c.size;
  ir::Vec3 w(double(p.x) + o.x - n.x * s / 100, double(p.y) + o.y - n.y * s / 100,
             double(p.z) + o.z - n.z * s / 100);
  // i + j + k is even exactly when the three parities cancel.
  int odd = floor_parity(w.x / s) ^ floor_parity(w.y / s) ^ floor_parity(w.z / s);
  const ir::Vec3& k = odd == 0 ? c.color1 : c.color2;
  return to_float(k.x, k.y, k.z);
}

inline Color texture_color(const ir::Texture& t, const TexturePoint& tp) {
  return std::visit([&](const auto& pattern) { return pattern_color(pattern, tp); }, t.pattern);
}

}  // namespace snell::rt
