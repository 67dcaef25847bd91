// render(): build the Embree scene, then trace tiles in parallel with TBB. Each
// pixel's samples are a pure function of (seed, pixel, sample index, dimension), and
// each pixel is summed in sample order by one task, so the image is bit-identical
// whatever the thread count or tile schedule.
#include "runtime/render.hpp"

#include <xmmintrin.h>
#include <pmmintrin.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "runtime/camera.hpp"
#include "runtime/embree_scene.hpp"
#include "runtime/integrator.hpp"
#include "runtime/sampler.hpp"

namespace snell::rt {

namespace {
constexpr std::uint32_t kTile = 16;
using Clock = std::chrono::steady_clock;

void add(RenderStats& a, const RenderStats& b) {
  a.camera_rays += b.camera_rays;
  a.shadow_rays += b.shadow_rays;
  a.reflection_rays += b.reflection_rays;
  a.refraction_rays += b.refraction_rays;
  a.glossy_rays += b.glossy_rays;
  a.pruned_by_depth += b.pruned_by_depth;
  a.pruned_by_weight += b.pruned_by_weight;
  a.tir_events += b.tir_events;
  a.nonfinite_samples += b.nonfinite_samples;
}
std::uint64_t total_rays(const RenderStats& s) {
  return s.camera_rays + s.shadow_rays + s.reflection_rays + s.refraction_rays + s.glossy_rays;
}
}  // namespace

std::string to_string(Vec3f v) { return fmt::format("<{}, {}, {}>", v.x, v.y, v.z); }

std::string PinholeCamera::to_string() const {
  return fmt::format("pinhole {{ forward {} right {} up {} tan_x {} tan_y {} {}x{} }}",
                     rt::to_string(forward_), rt::to_string(right_), rt::to_string(up_),
                     tan_x_, tan_y_, width_, height_);
}

std::string RenderStats::to_string() const {
  std::uint64_t total = total_rays(*this);
  double mrays = render_seconds > 0 ? double(total) / render_seconds * 1e-6 : 0;
  return fmt::format(
      "rays: {} total ({} camera, {} shadow, {} reflection, {} refraction, {} glossy)\n"
      "pruned branches: {} by depth, {} by weight\n"
      "total internal reflections: {}\n"
      "non-finite samples dropped: {}\n"
      "time: build {:.3f} s, render {:.3f} s, {:.2f} Mrays/s\n",
      total, camera_rays, shadow_rays, reflection_rays, refraction_rays, glossy_rays,
      pruned_by_depth, pruned_by_weight, tir_events, nonfinite_samples, build_seconds,
      render_seconds, mrays);
}

std::string to_string(const Image& im) {
  return fmt::format("image {{ {}x{} rgb float32 }}", im.width, im.height);
}

std::string to_string(const RenderOptions& o) {
  std::string px = o.trace_pixel ? fmt::format("{},{}", o.trace_pixel->first,
                                               o.trace_pixel->second)
                                 : "none";
  return fmt::format("render_options {{ threads {} general_kernel {} trace_pixel {} }}",
                     o.threads, o.general_kernel, px);
}

std::string to_string(const OutputInfo& i) {
  return fmt::format("output_info {{ scene \"{}\" samples {} seed {} render_seconds {} }}",
                     i.scene_path, i.samples, i.seed, i.render_seconds);
}

// options.general_kernel: there is one kernel today; effects a scene does not use
// cost only an empty loop (no area lights: no grid; no dielectric: no Fresnel), so
// --features=all renders the same picture at the same cost. A specialised kernel
// (motion blur, lens sampling) will key on ir::analyze_features here.
RenderResult render(const ir::Scene& scene, const RenderOptions& options) {
  RenderResult result;
  const ir::Settings& st = scene.settings;
  Image& img = result.image;
  img.width = st.width;
  img.height = st.height;
  img.rgb.assign(std::size_t(img.width) * img.height * 3, 0.0f);
  if (img.width == 0 || img.height == 0) return result;

  auto t0 = Clock::now();
  EmbreeScene embree(scene, scene.camera.location);
  Integrator integrator(scene, embree);
  PinholeCamera camera(scene.camera, img.width, img.height);
  auto t1 = Clock::now();
  result.stats.build_seconds = std::chrono::duration<double>(t1 - t0).count();

  SamplerSpec spec{st.sampler, st.seed, st.samples ? st.samples : 1};
  std::uint32_t tiles_x = (img.width + kTile - 1) / kTile;
  std::uint32_t tiles_y = (img.height + kTile - 1) / kTile;
  std::uint32_t ntiles = tiles_x * tiles_y;
  std::atomic<std::uint32_t> done{0};

  tbb::enumerable_thread_specific<RenderStats> stats_tls;
  tbb::enumerable_thread_specific<std::vector<Node>> stack_tls;

  auto render_tile = [&](std::uint32_t tile) {
    // Denormals flushed to zero on every worker: Embree's recommendation, and
    // it keeps the slow path out of deep Beer attenuation (robustness.md §3.4).
    _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
    _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
    RenderStats& stats = stats_tls.local();
    std::vector<Node>& stack = stack_tls.local();
    std::uint32_t x0 = (tile % tiles_x) * kTile, y0 = (tile / tiles_x) * kTile;
    std::uint32_t x1 = std::min(x0 + kTile, img.width), y1 = std::min(y0 + kTile, img.height);
    for (std::uint32_t y = y0; y < y1; ++y)
      for (std::uint32_t x = x0; x < x1; ++x) {
        bool tracing = options.trace_pixel && options.trace_pixel->first == x &&
                       options.trace_pixel->second == y;
        double sum[3] = {0, 0, 0};
        std::uint32_t kept = 0;
        for (std::uint32_t s = 0; s < spec.spp; ++s) {
          SampleContext sc{spec, x, y, s};
          Sample2 j = sample2(spec, x, y, s, kDimPixel);
          Ray ray = camera.generate(x + double(j.u), y + double(j.v));
          std::string* tr = (tracing && s == 0) ? &result.trace : nullptr;
          if (tr) *tr += fmt::format("pixel ({}, {}) sample 0\n", x, y);
          Color c = integrator.li(ray, sc, stats, stack, tr);
          if (!is_finite(c)) {  // dropped and counted, never written
            ++stats.nonfinite_samples;
            continue;
          }
          sum[0] += c.x, sum[1] += c.y, sum[2] += c.z;
          ++kept;
        }
        float* px = img.at(x, y);
        for (int k = 0; k < 3; ++k) px[k] = kept ? float(sum[k] / kept) : 0.0f;
      }
    std::uint32_t n = ++done;
    if (options.progress) options.progress(double(n) / ntiles);
  };

  int threads = options.threads > 0 ? options.threads : tbb::this_task_arena::max_concurrency();
  tbb::task_arena arena(threads);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, ntiles, 1),
                      [&](const tbb::blocked_range<std::uint32_t>& r) {
                        for (std::uint32_t t = r.begin(); t != r.end(); ++t) render_tile(t);
                      });
  });
  for (const RenderStats& s : stats_tls) add(result.stats, s);
  result.stats.build_seconds = std::chrono::duration<double>(t1 - t0).count();
  result.stats.render_seconds = std::chrono::duration<double>(Clock::now() - t1).count();
  return result;
}

}  // namespace snell::rt
