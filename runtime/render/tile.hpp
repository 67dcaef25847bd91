// The pixel loop of one tile, as a template on the render kernel's shading axes
// (kernel.hpp) and the integrator that gives the radiance of a camera ray. Each
// integrator instantiates it once per such kernel (its tile_kernel table), so the
// radiance call inlines into the loop. The camera's axes are read at run time
// (TileContext::kernel_bits) except in camera_rays, the packets' ray generation,
// which is compiled once per camera: in the loops they are a branch per sample,
// and as template arguments they had made 4 copies of every loop (80 instead of
// 20, a quarter of the integrator's code). Lens: a lens sample (dimension
// kDimLens) for every camera ray; Time: a shutter fraction (kDimTime), the ray
// time when motion is on. The dimensions do not depend on the kernel, so every
// kernel gives every decision the same number.
#pragma once

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include "runtime/camera.hpp"
#include "runtime/integrators/integrator.hpp"
#include "runtime/integrators/probe.hpp"
#include "runtime/render.hpp"
#include "runtime/render/kernel.hpp"
#include "runtime/sampler.hpp"
#include "runtime/uninit.hpp"

namespace snell::rt {

inline constexpr std::uint32_t kTile = 16;
// 1 in kCostStride camera samples is timed for the per-effect cost (a power of 2).
inline constexpr std::uint32_t kCostStride = 16;

// Everything a tile needs; shared read-only by all workers.
struct TileContext {
  const Image* img = nullptr;
  const Camera* camera = nullptr;
  const Integrator* integrator = nullptr;
  const EmbreeScene* embree = nullptr;  // the camera rays' packets
  SamplerSpec spec;
  // §18: samples [sample_begin, sample_end) of each pixel; the pixels of `img`, a
  // window of the full image whose top-left is (img->x0, img->y0). Tiles are laid
  // over the window, but every sample is keyed by full-image coordinates.
  std::uint32_t sample_begin = 0, sample_end = 1;
  bool motion_on = false;    // some object has motion geometry: ray times matter
  unsigned kernel_bits = 0;  // the render kernel's axes (Kernel<B>::bits), the camera's read here
  std::uint32_t tiles_x = 1;
  const RenderOptions* options = nullptr;
  std::string* trace = nullptr;
  float* rgb = nullptr;
  bool measure_cost = false;
  // Progress inside tiles, in pixel-samples done of `work_total`: told through
  // options->progress each time another thousandth is done. Tile by tile, one
  // tile of a huge sample count (one pixel at 1e9 spp) ran for minutes unsaid.
  std::atomic<std::uint64_t>* work_done = nullptr;
  std::atomic<std::uint32_t>* work_permille = nullptr;
  std::uint64_t work_total = 1;
};

// One thread's state: counters, cost clock and the integrator's scratch (made by
// the integrator on first use, e.g. the ray tree's stack).
struct Worker {
  RenderStats stats;
  CostClock cost;
  std::uint64_t ticked = 0;  // pixel-samples of the tile under way already reported
  std::shared_ptr<void> scratch;
  template <class T>
  T& scratch_as() {
    if (!scratch) scratch = std::make_shared<T>();
    return *static_cast<T*>(scratch.get());
  }
};

// n more pixel-samples done: the progress callback is told when they complete
// another thousandth of the render (a few hundred calls at most, from any thread).
inline void report_work(const TileContext& c, std::uint64_t n) {
  if (!c.work_done || n == 0) return;
  const std::uint64_t done = c.work_done->fetch_add(n, std::memory_order_relaxed) + n;
  const auto permille = std::uint32_t(double(done) / double(c.work_total) * 1000);
  std::uint32_t last = c.work_permille->load(std::memory_order_relaxed);
  while (permille > last)
    if (c.work_permille->compare_exchange_weak(last, permille, std::memory_order_relaxed)) {
      if (c.options->progress) c.options->progress(double(done) / double(c.work_total));
      return;
    }
}
// The same from inside a tile, counted in the worker's `ticked` (render.cpp adds
// the rest of the tile's work when it ends).
inline void tile_work(const TileContext& c, Worker& wk, std::uint64_t n) {
  wk.ticked += n;
  report_work(c, n);
}

// Where a camera sample comes from: the sampler inputs the tree draws dimensions from.
// `dims`, when set, is the pixel's key cache (DimCache): the same numbers, fewer hashes.
struct SampleContext {
  SamplerSpec spec;
  std::uint32_t px = 0, py = 0, index = 0;
  std::uint64_t pixel = 0;  // pixel_hash(spec, px, py)
  DimCache* dims = nullptr;
};
std::string to_string(const SampleContext& c);

// The key of 2-D dimension `dim` of the sample's pixel (what draw2 draws from).
[[gnu::always_inline]] inline DimKey key2(const SampleContext& sc, std::uint32_t dim) {
  if (sc.dims) return sc.dims->get<false>(sc.spec, sc.pixel, dim);
  return dim_key(sc.spec, sc.pixel, dim);
}

// Dimension `dim` of the sample: what sample2 / sample1 give for (pixel, index, dim).
[[gnu::always_inline]] inline Sample2 draw2(const SampleContext& sc, std::uint32_t dim) {
  if (sc.dims) return sample2(sc.spec, sc.dims->get<false>(sc.spec, sc.pixel, dim), sc.index);
  return sample2(sc.spec, sc.pixel, sc.index, dim);
}
[[gnu::always_inline]] inline float draw1(const SampleContext& sc, std::uint32_t dim) {
  if (sc.dims) return sample1(sc.spec, sc.dims->get<true>(sc.spec, sc.pixel, dim), sc.index);
  return sample1(sc.spec, sc.pixel, sc.index, dim);
}

// Up to kDrawLanes 2-D dimensions of one sample at once (a shading point's light
// cells): u[j], v[j] what draw2(sc, dims[j]) gives, the stratified and sobol draws
// as SIMD lanes (one lane per dimension, the sample index shared), where draw2 one
// by one pays the scalar permutation or scramble per cell. u and v need room for
// kDrawLanes floats (a path may write every lane).
inline constexpr std::uint32_t kDrawLanes = StrataLanes::kLanes;
static_assert(SobolLanes::kLanes == kDrawLanes);
inline void draw2_dims(const SampleContext& sc, const std::uint32_t* dims, std::uint32_t n,
                       float* u, float* v) {
  switch (sc.spec.kind) {
    case ir::SamplerKind::Stratified: {
      StrataLanes k;  // lanes past n stay 0: read by the SIMD paths, never used
      for (std::uint32_t j = 0; j < n; ++j) k.set(j, key2(sc, dims[j]));
      stratified2_lanes(sc.spec, k, n, sc.index, u, v);
      return;
    }
    case ir::SamplerKind::Sobol: {
      SobolLanes k;
      for (std::uint32_t j = 0; j < n; ++j) k.set(j, key2(sc, dims[j]));
      sobol2_lanes(k, n, sc.index, u, v);
      return;
    }
    case ir::SamplerKind::Independent:
      break;
  }
  for (std::uint32_t j = 0; j < n; ++j) {
    const Sample2 s = draw2(sc, dims[j]);
    u[j] = s.u, v[j] = s.v;
  }
}

// A pixel's keys of the camera's fixed dimensions (film, lens, time).
struct CameraKeys {
  DimKey film, lens, time;
  CameraKeys() = default;
  CameraKeys(const SamplerSpec& spec, std::uint64_t pixel)
      : film(dim_key(spec, pixel, kDimPixel)),
        lens(dim_key(spec, pixel, kDimLens)),
        time(dim_key1(spec, pixel, kDimTime)) {}
};

// RenderOptions::cancel, asked every 16 samples inside a tile as well as between
// tiles: a 16×16 tile at 2^20 spp took seconds to give way to an edit or a ^C.
// A tile left this way is incomplete, and so is the render (RenderResult::cancelled).
inline bool cancelled(const TileContext& c) {
  return c.options->cancel && c.options->cancel->load(std::memory_order_relaxed);
}

// A deterministic 1-in-kCostStride choice of camera samples to time; it never
// changes the picture.
inline bool timed_sample(std::uint32_t x, std::uint32_t y, std::uint32_t s) {
  std::uint32_t h = (x * 0x9e3779b1u) ^ (y * 0x85ebca77u) ^ (s * 0xc2b2ae3du);
  h ^= h >> 15;
  h *= 0x2c1b3c6du;
  h ^= h >> 12;
  return (h & (kCostStride - 1)) == 0;
}

// A block's keys of the camera's dimensions as SIMD lanes, for the samplers that
// draw a packet's pixels at once (sobol2_lanes, stratified*_lanes).
struct CameraLanes {
  SobolLanes film, lens, time;
  StrataLanes sfilm, slens, stime;
  void set(std::uint32_t lane, const CameraKeys& k) {
    film.set(lane, k.film), lens.set(lane, k.lens), time.set(lane, k.time);
    sfilm.set(lane, k.film), slens.set(lane, k.lens), stime.set(lane, k.time);
  }
};

// The kernel axes camera_rays reads: camera_rays_for picks it by these bits of
// the kernel, so it is compiled once per camera (4), not per kernel (80).
inline constexpr unsigned kCameraAxes = (1u << kAxis_lens) | (1u << kAxis_time);

// Camera sample s of n pixels (px[i], py[i]): the rays, their lens and time samples
// drawn. The draws go lane by lane (independent) or as SIMD lanes (sobol,
// stratified: the same numbers), the rays as one block (Camera::generate_block):
// each ray is what Camera::generate makes of its draws.
template <class K>
void camera_rays(const TileContext& c, std::uint32_t n, const CameraKeys* keys,
                 const CameraLanes& lanes, const std::uint32_t* px, const std::uint32_t* py,
                 std::uint32_t s, Ray* rays, RenderStats& stats) {
  double fx[Camera::kMaxBlock], fy[Camera::kMaxBlock];
  static_assert(Camera::kMaxBlock >= SobolLanes::kLanes);  // the lanes write kLanes
  static_assert(Camera::kMaxBlock >= StrataLanes::kLanes);
  alignas(64) float ju[Camera::kMaxBlock], jv[Camera::kMaxBlock];
  alignas(64) float lu[Camera::kMaxBlock], lv[Camera::kMaxBlock];
  alignas(64) float tu[Camera::kMaxBlock], tv[Camera::kMaxBlock];
  const bool timed = K::time && c.motion_on;
  if (c.spec.kind == ir::SamplerKind::Sobol) {
    sobol2_lanes(lanes.film, n, s, ju, jv);
    if constexpr (K::lens) sobol2_lanes(lanes.lens, n, s, lu, lv);
    if (timed) sobol2_lanes(lanes.time, n, s, tu, tv);  // sample1 is the 2-D draw's u
  } else if (c.spec.kind == ir::SamplerKind::Stratified) {
    if constexpr (K::lens) {  // together: their permutations' walks interleave
      const StrataLanes* k[2] = {&lanes.sfilm, &lanes.slens};
      float* u[2] = {ju, lu};
      float* v[2] = {jv, lv};
      stratified2_lanes(c.spec, k, 2, n, s, u, v);
    } else {
      stratified2_lanes(c.spec, lanes.sfilm, n, s, ju, jv);
    }
    if (timed) stratified1_lanes(c.spec, lanes.stime, n, s, tu);
  } else {
    for (std::uint32_t i = 0; i < n; ++i) {
      Sample2 j = sample2(c.spec, keys[i].film, s);
      ju[i] = j.u, jv[i] = j.v;
      if constexpr (K::lens) {
        Sample2 l = sample2(c.spec, keys[i].lens, s);
        lu[i] = l.u, lv[i] = l.v;
      }
      if (timed) tu[i] = sample1(c.spec, keys[i].time, s);
    }
  }
  if constexpr (!K::lens)
    for (std::uint32_t i = 0; i < n; ++i) lu[i] = lv[i] = 0.5f;
  for (std::uint32_t i = 0; i < n; ++i)
    fx[i] = px[i] + double(ju[i]), fy[i] = py[i] + double(jv[i]);
  c.camera->generate_block(n, fx, fy, lu, lv, rays);
  if constexpr (K::lens) stats.lens_samples += n;
  if constexpr (K::time) {
    // Shutter fraction in [0, 1): exactly what Embree's ray time means.
    for (std::uint32_t i = 0; i < n; ++i) rays[i].time = timed ? tu[i] : 0.0f;
    stats.time_samples += n;
  }
}

// camera_rays of the camera axes of kernel `bits`.
using CameraRaysFn = void (*)(const TileContext&, std::uint32_t, const CameraKeys*,
                              const CameraLanes&, const std::uint32_t*, const std::uint32_t*,
                              std::uint32_t, Ray*, RenderStats&);
inline CameraRaysFn camera_rays_for(unsigned bits) {
  constexpr unsigned kLens = 1u << kAxis_lens, kTime = 1u << kAxis_time;
  switch (bits & kCameraAxes) {
    case 0:
      return &camera_rays<Kernel<0>>;
    case kLens:
      return &camera_rays<Kernel<kLens>>;
    case kTime:
      return &camera_rays<Kernel<kTime>>;
    default:
      return &camera_rays<Kernel<kLens | kTime>>;
  }
}

template <class K, class I>
Color sample_alone(const TileContext& c, std::uint32_t x, std::uint32_t y, std::uint32_t s,
                   std::uint64_t pixel, const CameraKeys& keys, DimCache& dims, Worker& wk,
                   bool tracing, bool draws_counted);

// The tile in blocks of kBlock × kBlock pixels: sample s of every pixel of a block
// is one packet of camera rays (EmbreeScene::intersect over a span, rtcIntersect16),
// and the rays' trees go through I::radiance_packet side by side from their
// packet hits: each step traces the lanes' next rays as one packet and the shadow
// rays of their lit nodes to each light sample cell as one packet (neighbouring
// hits to one cell are coherent rays). A packet hit or shadow answer is bit for
// bit the ray's traced alone (tests/hardcases/test_packets.cpp), each tree sums
// its nodes in its own order, and every pixel still sums its samples in order, so
// the image is what the one-ray loop makes. Coherent camera rays trace 2.4-2.9x
// faster as packets, shadow rays 2.3-3.1x (bench_trace's query rows).
inline constexpr std::uint32_t kBlock = 4;
template <class K, class I>
void render_tile_packets(const TileContext& c, std::uint32_t x0, std::uint32_t y0, std::uint32_t x1,
                         std::uint32_t y1, Worker& wk) {
  const I& integrator = static_cast<const I&>(*c.integrator);
  auto& scratch = wk.scratch_as<typename I::Scratch>();
  const Image& img = *c.img;
  RenderStats& stats = wk.stats;
  constexpr std::uint32_t kN = kBlock * kBlock;
  static_assert(kN <= Camera::kMaxBlock && kN <= SobolLanes::kLanes);
  Ray rays[kN];
  Hit hits[kN];
  SampleContext sc[kN];  // per pixel of the block; the index is set per sample
  std::uint8_t found[kN];
  std::uint64_t pixel[kN];
  CameraKeys keys[kN];
  CameraLanes lanes;  // the same keys, as SIMD lanes
  DimCache dims[kN];
  double sum[kN][3];
  std::uint32_t kept[kN], px[kN], py[kN];
  const CameraRaysFn make_rays = camera_rays_for(c.kernel_bits);
  for (std::uint32_t by = y0; by < y1; by += kBlock)
    for (std::uint32_t bx = x0; bx < x1; bx += kBlock) {
      std::uint32_t n = 0;
      for (std::uint32_t y = by; y < std::min(y1, by + kBlock); ++y)
        for (std::uint32_t x = bx; x < std::min(x1, bx + kBlock); ++x, ++n) {
          px[n] = x, py[n] = y, pixel[n] = pixel_hash(c.spec, x, y);
          keys[n] = CameraKeys(c.spec, pixel[n]);
          lanes.set(n, keys[n]);
          dims[n].reset();
          sc[n] = SampleContext{c.spec, x, y, 0, pixel[n], &dims[n]};
          sum[n][0] = sum[n][1] = sum[n][2] = 0, kept[n] = 0;
        }
      for (std::uint32_t s = c.sample_begin; s < c.sample_end; ++s) {
        if (((s - c.sample_begin) & 15) == 15) {
          tile_work(c, wk, std::uint64_t(n) * 16);
          if (cancelled(c)) return;
        }
        make_rays(c, n, keys, lanes, px, py, s, rays, stats);
        c.embree->intersect(std::span<const Ray>(rays, n), std::span<Hit>(hits, n),
                            std::span<std::uint8_t>(found, n));
        Uninit<Color, kN> cols;  // every lane's colour is set below before it is read
        Color* const col = cols.v;
        std::uint32_t todo = 0;  // the lanes whose trees go through the packet
        for (std::uint32_t i = 0; i < n; ++i) {
          sc[i].index = s;
          if (c.measure_cost && timed_sample(px[i], py[i], s)) {
            // Its clock is its own: traced alone (the packet's answer for it unused).
            col[i] =
                sample_alone<K, I>(c, px[i], py[i], s, pixel[i], keys[i], dims[i], wk, false, true);
            continue;
          }
          todo |= 1u << i;
        }
        integrator.template radiance_packet<K>(n, todo, rays, hits, found, sc, scratch, stats, col);
        for (std::uint32_t i = 0; i < n; ++i) {
          if (!is_finite(col[i])) {
            ++stats.nonfinite_samples;
            continue;
          }
          sum[i][0] += col[i].x, sum[i][1] += col[i].y, sum[i][2] += col[i].z;
          ++kept[i];
        }
      }
      for (std::uint32_t i = 0; i < n; ++i) {
        float* out = c.rgb + 3 * (std::size_t(py[i] - img.y0) * img.width + (px[i] - img.x0));
        for (int k = 0; k < 3; ++k) out[k] = kept[i] ? float(sum[i][k] / kept[i]) : 0.0f;
      }
    }
}

// Camera sample s of pixel (x, y) traced alone: the ray made by Camera::generate
// (what generate_block makes of the same draws), its tree with the probe's clock
// when the sample is one --stats times, and the --pixel trace when `tracing`.
// `draws_counted`: the packet that holds the sample already counted its lens and
// time draws.
template <class K, class I>
Color sample_alone(const TileContext& c, std::uint32_t x, std::uint32_t y, std::uint32_t s,
                   std::uint64_t pixel, const CameraKeys& keys, DimCache& dims, Worker& wk,
                   bool tracing, bool draws_counted) {
  const I& integrator = static_cast<const I&>(*c.integrator);
  auto& scratch = wk.scratch_as<typename I::Scratch>();
  RenderStats& stats = wk.stats;
  CostClock& clock = wk.cost;
  const SamplerSpec& spec = c.spec;
  const std::uint64_t draws = draws_counted ? 0 : 1;
  bool timed = c.measure_cost && timed_sample(x, y, s);
  double t_cam = timed ? CostClock::now_ns() : 0, t_effects = 0;
  SampleContext sc{spec, x, y, s, pixel, &dims};
  Sample2 j = sample2(spec, keys.film, s);
  Ray ray;
  if ((c.kernel_bits >> kAxis_lens) & 1) {
    double t0 = timed ? CostClock::now_ns() : 0;
    Sample2 l = sample2(spec, keys.lens, s);
    ray = c.camera->generate(x + double(j.u), y + double(j.v), l.u, l.v);
    stats.lens_samples += draws;
    if (timed) {
      double dt = clock.since(t0);
      clock.ns[kCostLens] += dt;
      t_effects += dt + clock.overhead_ns;
    }
  } else {
    ray = c.camera->generate(x + double(j.u), y + double(j.v));
  }
  if ((c.kernel_bits >> kAxis_time) & 1) {
    double t0 = timed ? CostClock::now_ns() : 0;
    float u = sample1(spec, keys.time, s);
    // Shutter fraction in [0, 1): exactly what Embree's ray time means.
    ray.time = c.motion_on ? u : 0.0f;
    stats.time_samples += draws;
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
  if (tr || timed) {
    Probe<true> probe{stats, tr, timed ? &clock : nullptr};
    return integrator.template radiance<K>(ray, sc, scratch, probe);
  }
  Probe<false> probe{stats};
  return integrator.template radiance<K>(ray, sc, scratch, probe);
}

// `I::radiance<K, Probe<on>>(ray, sc, scratch, probe)` gives a camera ray's radiance;
// I::Scratch is its per-thread scratch. A tile that holds the --pixel being traced
// goes one ray at a time (sample_alone), and so does every tile without an Embree
// scene or with RenderOptions::packets off (tests); every other tile goes as
// packets (render_tile_packets), the samples --stats times among them alone.
template <class K, class I>
void render_tile(const TileContext& c, std::uint32_t tile, Worker& wk) {
  const Image& img = *c.img;
  RenderStats& stats = wk.stats;
  const SamplerSpec& spec = c.spec;
  std::uint32_t x0 = img.x0 + (tile % c.tiles_x) * kTile, y0 = img.y0 + (tile / c.tiles_x) * kTile;
  std::uint32_t x1 = std::min(x0 + kTile, img.x0 + img.width);
  std::uint32_t y1 = std::min(y0 + kTile, img.y0 + img.height);
  const auto& tp = c.options->trace_pixel;
  bool traced_here = tp && tp->first >= x0 && tp->first < x1 && tp->second >= y0 && tp->second < y1;
  if (c.embree && c.options->packets && !traced_here) {
    render_tile_packets<K, I>(c, x0, y0, x1, y1, wk);
    return;
  }
  for (std::uint32_t y = y0; y < y1; ++y)
    for (std::uint32_t x = x0; x < x1; ++x) {
      bool tracing = tp && tp->first == x && tp->second == y;
      const std::uint64_t pixel = pixel_hash(spec, x, y);
      const CameraKeys keys(spec, pixel);
      DimCache dims;
      double sum[3] = {0, 0, 0};
      std::uint32_t kept = 0;
      for (std::uint32_t s = c.sample_begin; s < c.sample_end; ++s) {
        if (((s - c.sample_begin) & 15) == 15) {
          tile_work(c, wk, 16);
          if (cancelled(c)) return;
        }
        Color col = sample_alone<K, I>(c, x, y, s, pixel, keys, dims, wk, tracing, false);
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
