// The numeric functions of the language (§3) on one component, written once for
// the compiler's builtins (scene-build time) and the shading-function interpreter
// (render time): both call these, so a value is the same bits wherever it is
// computed. Trigonometry is in degrees, exact at multiples of 90.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>

#include "runtime/ir/math.hpp"

namespace snell::ir::scalar {

inline constexpr double kDeg = 3.14159265358979323846 / 180.0;

inline double sin_deg(double d) {
  double s, c;
  detail::sincos_degrees(d, s, c);
  return s;
}
inline double cos_deg(double d) {
  double s, c;
  detail::sincos_degrees(d, s, c);
  return c;
}
inline double tan_deg(double d) {
  double s, c;
  detail::sincos_degrees(d, s, c);
  return s / c;  // tan(90) = ±inf: the caller reports it as non-finite
}
inline double asin_deg(double x) {
  return std::asin(x) / kDeg;
}
inline double acos_deg(double x) {
  return std::acos(x) / kDeg;
}
inline double atan_deg(double x) {
  return std::atan(x) / kDeg;
}
inline double atan2_deg(double y, double x) {
  return std::atan2(y, x) / kDeg;
}
// `%`: the floored modulo of reals, from fmod, which is exact (a − b·floor(a/b)
// rounds twice: 1.7 % 0.1 came out negative and 1e17 % 7 as 0). A remainder of
// the other sign than b takes b once, the one rounding; where that rounds onto b
// itself (a remainder below half of b's last ulp) the result is the double next
// to b towards 0, so it stays in [0, b) for b > 0 and (b, 0] for b < 0. A zero
// remainder is +0.
inline double floored_mod(double a, double b) {
  double r = std::fmod(a, b);
  if (r != 0 && ((r < 0) != (b < 0))) {
    r += b;
    if (r == b) r = std::nextafter(b, 0.0);
  }
  return r == 0 ? 0.0 : r;
}
inline double clamp(double x, double lo, double hi) {
  return std::fmin(std::fmax(x, lo), hi);
}
inline double mix(double a, double b, double t) {
  return a * (1 - t) + b * t;
}

// random(n): the IEEE-754 bits of n (−0 taken as +0) through the SplitMix64
// finaliser, top 53 bits scaled by 2^−53. Pure integer arithmetic: the same value
// on every machine and compiler.
inline double random_hash(double n) {
  if (n == 0) n = 0;  // -0 -> +0
  std::uint64_t z = std::bit_cast<std::uint64_t>(n);
  z += 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  z ^= z >> 31;
  return static_cast<double>(z >> 11) * 0x1p-53;
}

}  // namespace snell::ir::scalar
