// The values of §15's patterns at a point of the pattern's own space, one overload
// per kind of runtime/ir/kinds.def, and the colour map. Pure functions of the
// point: the runtime calls them at hits (runtime/shading/textures.hpp), tests call
// them at exact points. Formulas as docs/language.md ("Patterns") gives them.
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "runtime/ir/materials.hpp"
#include "runtime/pattern/noise.hpp"

namespace snell::pattern {

// x − floor(x), in [0, 1) (1 − ulp for tiny negative x rounds up to 1: clamped).
inline double frac(double x) {
  double f = x - std::floor(x);
  return f < 1 ? f : std::nextafter(1.0, 0.0);
}
// The triangle wave 0 → 1 → 0 over each unit: 0 at integers, 1 halfway.
inline double triangle(double x) {
  return 1 - std::fabs(1 - 2 * frac(x));
}
// The wave sources of ripples and waves: ten points in [-0.5, 0.5]³ and their
// relative frequencies in [0.5, 1.5] (fixed, from Snell's own table).
struct WaveSource {
  ir::Vec3 c;
  double f;
};
const WaveSource* wave_sources();  // kWaves of them
inline constexpr int kWaves = 10;

inline double value(const ir::Gradient& g, ir::Vec3 p, int) {
  return frac(ir::dot(p, g.direction));
}
inline double value(const ir::Onion&, ir::Vec3 p, int) {
  return frac(ir::length(p));
}
// Around y: 0 along +z, growing towards +x.
inline double value(const ir::Radial&, ir::Vec3 p, int) {
  if (p.x == 0 && p.z == 0) return 0;
  double deg = std::atan2(p.x, p.z) * (180 / std::numbers::pi);
  return frac(deg / 360);
}
// How far below each multiple of the brick size brick's mortar ends, in the
// pattern's units. POV-Ray's mortar ends EPSILON below each multiple, so a face on
// a multiple shows bricks; Snell evaluates a face 1e-4 inside it, and a bump's
// gradient 1e-3 either side of that, so a top face on a multiple is seen from just
// below: 2e-3 keeps all of those points (with the float error of the hit) in the
// bricks, and moves the mortar by an invisible 1/125 of a default row.
inline constexpr double kBrickClearance = 2e-3;
// 1 in the mortar (the band of width `mortar` ending kBrickClearance below each
// multiple of the size, as in POV-Ray), 0 in a brick; rows (along y) of odd index
// are shifted half a brick in x and z.
inline double value(const ir::Brick& b, ir::Vec3 p, int) {
  // q counts from the bottom of a band of mortar, so a row is the mortar under it
  // and the bricks above: bricks standing on a multiple are that multiple's row.
  const ir::Vec3 q = p + ir::Vec3(b.mortar + kBrickClearance);
  double row = std::floor(q.y / b.size.y);
  double shift = std::fmod(row, 2.0) != 0 ? 0.5 : 0.0;
  auto in_mortar = [&](double x, double size, double s) {
    return frac(x / size + s) * size < b.mortar;
  };
  return in_mortar(q.x, b.size.x, shift) || in_mortar(q.y, b.size.y, 0) ||
                 in_mortar(q.z, b.size.z, shift)
             ? 1.0
             : 0.0;
}
inline double value(const ir::Noise&, ir::Vec3 p, int) {
  return noise(p);
}
inline double value(const ir::Fbm& f, ir::Vec3 p, int octaves) {
  return fbm(p, octaves, f.lacunarity, f.gain);
}
// POV-Ray's families. marble: a triangle wave along x; wood: rings around z.
inline double value(const ir::Marble&, ir::Vec3 p, int) {
  return triangle(p.x);
}
inline double value(const ir::Wood&, ir::Vec3 p, int) {
  return triangle(std::sqrt(p.x * p.x + p.y * p.y));
}
// Σ |0.5 − noise(4·2^i p)| / 2^i over the octaves (POV-Ray's granite sum).
inline double value(const ir::Granite&, ir::Vec3 p, int octaves) {
  double sum = 0, f = 1;
  for (int i = 0; i < std::clamp(octaves, 1, kMaxOctaves); ++i, f *= 2)
    sum += std::fabs(0.5 - noise(p * (4 * f))) / f;
  return std::clamp(sum, 0.0, 1.0);
}
// Bands along z bent by turbulence: (0.5 + 0.5 sin 2π(1.1 z + 1.3 turbulence(p)))^0.77.
inline double value(const ir::Agate&, ir::Vec3 p, int octaves) {
  double t = turbulence(p, octaves);
  double s = 0.5 + 0.5 * std::sin(2 * std::numbers::pi * (1.1 * p.z + 1.3 * t));
  return std::pow(std::clamp(s, 0.0, 1.0), 0.77);
}
// Spots on a lattice of period 2π: ((sin x + sin y + sin z) / 3)².
inline double value(const ir::Leopard&, ir::Vec3 p, int) {
  double s = (std::sin(p.x) + std::sin(p.y) + std::sin(p.z)) / 3;
  return s * s;
}
// Rings of unit wavelength around the ten sources, averaged.
inline double value(const ir::Ripples&, ir::Vec3 p, int) {
  const WaveSource* w = wave_sources();
  double sum = 0;
  for (int i = 0; i < kWaves; ++i) sum += std::sin(2 * std::numbers::pi * ir::length(p - w[i].c));
  return std::clamp(0.5 + 0.5 * sum / kWaves, 0.0, 1.0);
}
// The same with each source's own wavelength 1/f, weighted 1/f.
inline double value(const ir::Waves&, ir::Vec3 p, int) {
  const WaveSource* w = wave_sources();
  double sum = 0, norm = 0;
  for (int i = 0; i < kWaves; ++i) {
    sum += std::sin(2 * std::numbers::pi * w[i].f * ir::length(p - w[i].c)) / w[i].f;
    norm += 1 / w[i].f;
  }
  return std::clamp(0.5 + 0.5 * sum / norm, 0.0, 1.0);
}
inline double value(const ir::Cells&, ir::Vec3 p, int) {
  return std::clamp(cells(p), 0.0, 1.0);
}

// §15: linear in linear RGB between the stops around v, held outside them. Equal
// stops make a step (the later one wins at and above it). Empty: black to white.
inline ir::Vec3 map_color(const std::vector<ir::ColorStop>& map, double v) {
  if (map.empty()) return ir::Vec3(std::clamp(v, 0.0, 1.0));
  if (!(v >= map.front().at)) return map.front().color;  // NaN too
  if (v >= map.back().at) return map.back().color;
  // The first stop past v (map[i-1].at <= v < map[i].at), by bisection: a map may
  // hold 100 000 stops (a searched one took 9 us a lookup there).
  const auto it = std::upper_bound(map.begin() + 1, map.end(), v,
                                   [](double x, const ir::ColorStop& s) { return x < s.at; });
  const ir::ColorStop &a = *(it - 1), &b = *it;
  double t = (v - a.at) / (b.at - a.at);
  return a.color + (b.color - a.color) * t;
}

}  // namespace snell::pattern
