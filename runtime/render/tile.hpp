// The pixel loop of one tile, as a template on the render kernel (kernel.hpp) and
// the integrator that gives the radiance of a camera ray. Each integrator
// instantiates it once per kernel (its tile_kernel table), so the radiance call
// inlines into the loop. Lens: a lens sample (dimension kDimLens) for every camera
// ray; Time: a shutter fraction (kDimTime), the ray time when motion is on. The
// dimensions do not depend on the kernel, so every kernel gives every decision the
// same number.
#pragma once

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>

#include "runtime/camera.hpp"
#include "runtime/integrators/integrator.hpp"
#include "runtime/integrators/probe.hpp"
#include "runtime/render.hpp"
#include "runtime/sampler.hpp"

namespace snell::rt {

inline constexpr std::uint32_t kTile = 16;
// 1 in kCostStride camera samples is timed for the per-effect cost (a power of 2).
inline constexpr std::uint32_t kCostStride = 16;

// Everything a tile needs; shared read-only by all workers.
struct TileContext {
  const Image* img = nullptr;
  const Camera* camera = nullptr;
  const Integrator* integrator = nullptr;
  SamplerSpec spec;
  // §18: samples [sample_begin, sample_end) of each pixel; the pixels of `img`, a
  // window of the full image whose top-left is (img->x0, img->y0). Tiles are laid
  // over the window, but every sample is keyed by full-image coordinates.
  std::uint32_t sample_begin = 0, sample_end = 1;
  bool motion_on = false;  // some object has motion geometry: ray times matter
  std::uint32_t tiles_x = 1;
  const RenderOptions* options = nullptr;
  std::string* trace = nullptr;
  float* rgb = nullptr;
  bool measure_cost = false;
};

// One thread's state: counters, cost clock and the integrator's scratch (made by
// the integrator on first use, e.g. the ray tree's stack).
struct Worker {
  RenderStats stats;
  CostClock cost;
  std::shared_ptr<void> scratch;
  template <class T>
  T& scratch_as() {
    if (!scratch) scratch = std::make_shared<T>();
    return *static_cast<T*>(scratch.get());
  }
};

// Where a camera sample comes from: the sampler inputs the tree draws dimensions from.
struct SampleContext {
  SamplerSpec spec;
  std::uint32_t px = 0, py = 0, index = 0;
  std::uint64_t pixel = 0;  // pixel_hash(spec, px, py)
};
std::string to_string(const SampleContext& c);

// A deterministic 1-in-kCostStride choice of camera samples to time; it never
// changes the picture.
inline bool timed_sample(std::uint32_t x, std::uint32_t y, std::uint32_t s) {
  std::uint32_t h = (x * 0x9e3779b1u) ^ (y * 0x85ebca77u) ^ (s * 0xc2b2ae3du);
  h ^= h >> 15;
  h *= 0x2c1b3c6du;
  h ^= h >> 12;
  return (h & (kCostStride - 1)) == 0;
}

// `I::radiance<K, Probe<on>>(ray, sc, scratch, probe)` gives a camera ray's radiance;
// I::Scratch is its per-thread scratch.
template <class K, class I>
void render_tile(const TileContext& c, std::uint32_t tile, Worker& wk) {
  const I& integrator = static_cast<const I&>(*c.integrator);
  auto& scratch = wk.scratch_as<typename I::Scratch>();
  const Image& img = *c.img;
  RenderStats& stats = wk.stats;
  CostClock& clock = wk.cost;
  const SamplerSpec& spec = c.spec;
  std::uint32_t x0 = img.x0 + (tile % c.tiles_x) * kTile, y0 = img.y0 + (tile / c.tiles_x) * kTile;
  std::uint32_t x1 = std::min(x0 + kTile, img.x0 + img.width);
  std::uint32_t y1 = std::min(y0 + kTile, img.y0 + img.height);
  for (std::uint32_t y = y0; y < y1; ++y)
    for (std::uint32_t x = x0; x < x1; ++x) {
      bool tracing = c.options->trace_pixel && c.options->trace_pixel->first == x &&
                     c.options->trace_pixel->second == y;
      const std::uint64_t pixel = pixel_hash(spec, x, y);
      double sum[3] = {0, 0, 0};
      std::uint32_t kept = 0;
      for (std::uint32_t s = c.sample_begin; s < c.sample_end; ++s) {
        bool timed = c.measure_cost && timed_sample(x, y, s);
        double t_cam = timed ? CostClock::now_ns() : 0, t_effects = 0;
        SampleContext sc{spec, x, y, s, pixel};
        Sample2 j = sample2(spec, pixel, s, kDimPixel);
        Ray ray;
        if constexpr (K::lens) {
          double t0 = timed ? CostClock::now_ns() : 0;
          Sample2 l = sample2(spec, pixel, s, kDimLens);
          ray = c.camera->generate(x + double(j.u), y + double(j.v), l.u, l.v);
          ++stats.lens_samples;
          if (timed) {
            double dt = clock.since(t0);
            clock.ns[kCostLens] += dt;
            t_effects += dt + clock.overhead_ns;
          }
        } else {
          ray = c.camera->generate(x + double(j.u), y + double(j.v));
        }
        if constexpr (K::time) {
          double t0 = timed ? CostClock::now_ns() : 0;
          float u = sample1(spec, pixel, s, kDimTime);
          // Shutter fraction in [0, 1): exactly what Embree's ray time means.
          ray.time = c.motion_on ? u : 0.0f;
          ++stats.time_samples;
          if (timed) {
            double dt = clock.since(t0);
            clock.ns[kCostTime] += dt;
            t_effects += dt + clock.overhead_ns;
          }
        }
        if (timed) {
          clock.ns[kCostCamera] += std::fmax(0.0, clock.since(t_cam) - t_effects);
          ++stats.timed_samples;
        }
        std::string* tr = (tracing && s == c.sample_begin) ? c.trace : nullptr;
        if (tr) *tr += fmt::format("pixel ({}, {}) sample {}\n", x, y, s);
        Color col;
        if (tr || timed) {
          Probe<true> probe{stats, tr, timed ? &clock : nullptr};
          col = integrator.template radiance<K>(ray, sc, scratch, probe);
        } else {
          Probe<false> probe{stats};
          col = integrator.template radiance<K>(ray, sc, scratch, probe);
        }
        if (!is_finite(col)) {  // dropped and counted, never written
          ++stats.nonfinite_samples;
          continue;
        }
        sum[0] += col.x, sum[1] += col.y, sum[2] += col.z;
        ++kept;
      }
      float* px = c.rgb + 3 * (std::size_t(y - img.y0) * img.width + (x - img.x0));
      for (int k = 0; k < 3; ++k) px[k] = kept ? float(sum[k] / kept) : 0.0f;
    }
}

}  // namespace snell::rt
