// Helpers shared by the hard-case tests: scene builders from tests/runtime, pixel
// comparisons, the impact parameter of a pixel's camera ray, and compiling text.
#pragma once

#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <string>

#include "compiler/compile.hpp"
#include "runtime/camera.hpp"
#include "runtime/render.hpp"
#include "runtime/sampler.hpp"
#include "tests/runtime/scene_util.hpp"

namespace snell::hc {

using test::kPi;
// A uniformly distributed unit vector.
inline ir::Vec3 unit(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0, 1);
  double z = 2 * u(rng) - 1, a = 2 * kPi * u(rng), r = std::sqrt(1 - z * z);
  return {r * std::cos(a), r * std::sin(a), z};
}
inline rt::Vec3f f(ir::Vec3 v) {
  return rt::to_float(v.x, v.y, v.z);
}

using namespace snell::test;

// Largest and mean absolute difference over all channels of two same-size images.
struct Diff {
  double max = 0, mean = 0;
};
inline Diff diff(const rt::Image& a, const rt::Image& b) {
  Diff d;
  if (a.rgb.size() != b.rgb.size()) return {INFINITY, INFINITY};
  for (std::size_t i = 0; i < a.rgb.size(); ++i) {
    double e = std::fabs(double(a.rgb[i]) - double(b.rgb[i]));
    if (!(e == e)) e = INFINITY;  // NaN never compares equal
    d.max = std::fmax(d.max, e);
    d.mean += e;
  }
  if (!a.rgb.empty()) d.mean /= double(a.rgb.size());
  return d;
}

// Bit-identical: every float equal (and no NaN, which is never equal to itself).
inline bool identical(const rt::Image& a, const rt::Image& b) {
  if (a.width != b.width || a.height != b.height) return false;
  for (std::size_t i = 0; i < a.rgb.size(); ++i)
    if (!(a.rgb[i] == b.rgb[i])) return false;
  return true;
}

inline bool all_finite(const rt::Image& im) {
  for (float v : im.rgb)
    if (!std::isfinite(v)) return false;
  return true;
}

// Impact parameter b / r of pixel (x, y)'s sample-0 camera ray on a sphere whose
// centre is `c` relative to the camera; 2 when the sphere is behind. The test
// replays the renderer's own sampler and camera, so expected values follow the
// exact ray and tolerances only cover float rounding.
inline double impact(const ir::Scene& s, std::uint32_t x, std::uint32_t y, ir::Vec3 c, double r) {
  rt::PinholeCamera cam(s.camera, s.settings.width, s.settings.height);
  rt::SamplerSpec spec{s.settings.sampler, s.settings.seed, s.settings.samples};
  rt::Sample2 j = rt::sample2(spec, x, y, 0, rt::kDimPixel);
  rt::Ray ray = cam.generate(x + double(j.u), y + double(j.v));
  ir::Vec3 d = ir::normalize(ir::Vec3(ray.dir.x, ray.dir.y, ray.dir.z));
  if (ir::dot(c, d) < 0) return 2;
  return ir::length(ir::cross(c, d)) / r;
}

inline compile::CompileOptions compile_options() {
  compile::CompileOptions o;
  o.stdlib_dir = std::string(SNELL_SOURCE_DIR) + "/stdlib";
  o.max_errors = 0;  // all
  return o;
}

inline std::unique_ptr<compile::Compilation> compile_text(const std::string& text) {
  return compile::compile_source(std::string(SNELL_SOURCE_DIR) + "/tests/hardcases/inline.scn",
                                 text, compile_options());
}

// Every diagnostic of a compilation, one per line, for INFO() and matching.
inline std::string diagnostics(const compile::Compilation& c) {
  std::string all;
  for (const auto& d : c.diags.diagnostics()) all += c.diags.format(d) + "\n";
  return all;
}

// A closed UV sphere of `rings` × `segments` quads as one mesh, wound outward (or
// inward when `flip`), every vertex moved radially by up to `jitter`·r. Shared
// vertices are shared indices, so the mesh is closed and watertight by
// construction; the jitter makes its triangles irregular (pbrt's Watertight
// recipe).
inline ir::MeshData uv_sphere(int rings, int segments, double r, double jitter, std::uint64_t seed,
                              bool flip = false) {
  ir::MeshData m;
  m.path = "uv_sphere";
  auto rnd = [&](std::uint64_t i) {
    return double(rt::hash64(seed * 0x9E3779B97F4A7C15ull + i) >> 11) * 0x1p-53;
  };
  std::uint64_t n = 0;
  auto radius = [&] { return r * (1 + jitter * (2 * rnd(n++) - 1)); };
  const double pi = 3.14159265358979323846;
  m.positions.push_back({0, radius(), 0});  // north pole: index 0
  for (int i = 1; i < rings; ++i) {
    double th = pi * i / rings;
    for (int j = 0; j < segments; ++j) {
      double ph = 2 * pi * j / segments, q = radius();
      m.positions.push_back(
          {q * std::sin(th) * std::cos(ph), q * std::cos(th), q * std::sin(th) * std::sin(ph)});
    }
  }
  m.positions.push_back({0, -radius(), 0});  // south pole: last
  auto ring = [&](int i, int j) { return std::uint32_t(1 + (i - 1) * segments + (j % segments)); };
  std::uint32_t south = std::uint32_t(m.positions.size() - 1);
  auto tri = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    // With y up and phi growing from +x towards +z, (a, b, c) below is counter-
    // clockwise seen from outside (outward Ng, checked by hc06); flip swaps two.
    if (flip)
      m.indices.insert(m.indices.end(), {a, c, b});
    else
      m.indices.insert(m.indices.end(), {a, b, c});
  };
  for (int j = 0; j < segments; ++j) tri(0, ring(1, j + 1), ring(1, j));
  for (int i = 1; i + 1 < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      tri(ring(i, j), ring(i, j + 1), ring(i + 1, j + 1));
      tri(ring(i, j), ring(i + 1, j + 1), ring(i + 1, j));
    }
  for (int j = 0; j < segments; ++j) tri(south, ring(rings - 1, j), ring(rings - 1, j + 1));
  return m;
}

inline std::uint32_t add_mesh(ir::Scene& s, ir::MeshData m, std::uint32_t material) {
  s.meshes.push_back(std::move(m));
  ir::Shape sh;
  sh.geom = ir::Mesh{std::uint32_t(s.meshes.size() - 1)};
  sh.material = material;
  s.shapes.push_back(sh);
  return std::uint32_t(s.shapes.size() - 1);
}

}  // namespace snell::hc
