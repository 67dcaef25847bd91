// render(): build the Embree scene, then trace tiles in parallel with TBB. Each
// pixel's samples are a pure function of (seed, pixel, sample index, dimension), and
// each pixel is summed in sample order by one task, so the image is bit-identical
// whatever the thread count or tile schedule. The per-pixel loop (render/tile.hpp)
// is a template on the render kernel (render/kernel.hpp: the effects it simulates)
// and the integrator; render() picks the kernel from ir::Features (docs/effects.md)
// and the integrator from the settings.
#include "runtime/render.hpp"

#include <fmt/format.h>
#include <pmmintrin.h>
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/global_control.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <xmmintrin.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <optional>
#include <utility>

#include "runtime/camera.hpp"
#include "runtime/embree_scene.hpp"
#include "runtime/integrators/integrator.hpp"
#include "runtime/render/kernel.hpp"
#include "runtime/render/tile.hpp"
#include "runtime/sampler.hpp"

namespace snell::rt {

namespace {
using Clock = std::chrono::steady_clock;

// The cost of one CostClock::now_ns() pair, subtracted from every timed interval.
double clock_overhead_ns() {
  double best = INFINITY;
  for (int i = 0; i < 256; ++i) {
    double a = CostClock::now_ns(), b = CostClock::now_ns();
    best = std::fmin(best, b - a);
  }
  return std::isfinite(best) ? best : 0;
}

}  // namespace

std::string to_string(Vec3f v) {
  return fmt::format("<{}, {}, {}>", v.x, v.y, v.z);
}

std::string Camera::to_string() const {
  return fmt::format(
      "camera {{ forward {} right {} up {} tan_x {} tan_y {} {}x{} lens_radius {} "
      "focal_distance {} }}",
      rt::to_string(forward_), rt::to_string(right_), rt::to_string(up_), tan_x_, tan_y_, width_,
      height_, lens_radius_, focal_distance_);
}

std::string to_string(const Image& im) {
  return fmt::format("image {{ {}x{} rgb float32 }}", im.width, im.height);
}

std::string to_string(const RenderOptions& o) {
  std::string px =
      o.trace_pixel ? fmt::format("{},{}", o.trace_pixel->first, o.trace_pixel->second) : "none";
  return fmt::format("render_options {{ threads {} general_kernel {} trace_pixel {} }}", o.threads,
                     o.general_kernel, px);
}

std::string to_string(const OutputInfo& i) {
  return fmt::format("output_info {{ scene \"{}\" samples {} seed {} render_seconds {} }}",
                     i.scene_path, i.samples, i.seed, i.render_seconds);
}

// options.general_kernel (--features=all) runs the kernel with every effect compiled
// in; otherwise the kernel is chosen by ir::analyze_features. The Embree scene is
// the same either way (only objects that move while the shutter is open get motion
// geometry), so both kernels see the same surfaces and draw the same samples.
RenderResult render(const ir::Scene& scene, const RenderOptions& options) {
  RenderResult result;
  const ir::Settings& st = scene.settings;
  Image& img = result.image;
  // §18: the window rendered (the whole image unless cropped) and the samples.
  RenderOptions::Window win{0, 0, st.width, st.height};
  if (options.crop) {
    win.x0 = std::min(options.crop->x0, st.width);
    win.y0 = std::min(options.crop->y0, st.height);
    win.x1 = std::clamp(options.crop->x1, win.x0, st.width);
    win.y1 = std::clamp(options.crop->y1, win.y0, st.height);
    img.x0 = win.x0;
    img.y0 = win.y0;
    img.full_width = st.width;
    img.full_height = st.height;
  }
  const std::uint32_t spp = st.samples ? st.samples : 1;
  std::uint32_t s0 = 0, s1 = spp;
  if (options.sample_range) {
    s0 = std::min(options.sample_range->first, spp);
    s1 = std::clamp(options.sample_range->second, s0, spp);
  }
  img.width = win.x1 - win.x0;
  img.height = win.y1 - win.y0;
  img.rgb.assign(std::size_t(img.width) * img.height * 3, 0.0f);
  KernelChoice kernel = choose_kernel(scene, options.general_kernel);
  if (!kernel.general && options.extra_axes)
    kernel.bits = canonical_kernel(kernel.bits | options.extra_axes);
  result.stats.kernel = kernel.name();
  result.stats.cost_stride = options.measure_cost ? kCostStride : 0;
  if (img.width == 0 || img.height == 0 || s0 == s1) return result;

  auto t0 = Clock::now();
  EmbreeScene embree(scene, scene.camera.location);
  // §17: the texture system is set up once per render and shared by its threads;
  // an image that cannot be opened (the CLI checks them first, check_images) is
  // black and said so in the statistics.
  std::unique_ptr<ImageTextures> images;
  if (!scene.images.empty()) {
    std::string err;
    images = ImageTextures::open(scene, options.ocio_config, err);
    if (!images) result.texture_stats = "images: " + err + "\n";
  }
  std::unique_ptr<Integrator> integrator = make_integrator(scene, embree, images.get());
  // The full image's camera: a crop's pixels are the full render's pixels.
  Camera camera(scene.camera, st.width, st.height);
  auto t1 = Clock::now();

  TileContext ctx;
  ctx.img = &img;
  ctx.camera = &camera;
  ctx.integrator = integrator.get();
  ctx.embree = &embree;
  // The full spp, whatever the sample range: stratification depends on it.
  ctx.spec = SamplerSpec{st.sampler, st.seed, spp};
  ctx.sample_begin = s0;
  ctx.sample_end = s1;
  ctx.motion_on = embree.has_motion();
  ctx.tiles_x = (img.width + kTile - 1) / kTile;
  ctx.options = &options;
  ctx.trace = &result.trace;
  ctx.rgb = img.rgb.data();
  ctx.measure_cost = options.measure_cost;
  std::uint32_t tiles_y = (img.height + kTile - 1) / kTile;
  std::uint32_t ntiles = ctx.tiles_x * tiles_y;
  std::atomic<std::uint64_t> work_done{0};
  std::atomic<std::uint32_t> work_permille{0};
  ctx.work_done = &work_done, ctx.work_permille = &work_permille;
  ctx.work_total = std::uint64_t(img.width) * img.height * (s1 - s0);
  ctx.kernel_bits = kernel.bits;
  TileFn run = integrator->tile_kernel(kernel.bits);
  double overhead = options.measure_cost ? clock_overhead_ns() : 0;
  tbb::enumerable_thread_specific<Worker> workers([&] {
    Worker w;
    w.cost.overhead_ns = overhead;
    return w;
  });

  std::atomic<bool> skipped{false};
  auto render_one = [&](std::uint32_t tile) {
    if (cancelled(ctx)) {
      skipped.store(true, std::memory_order_relaxed);
      return;
    }
    // Denormals flushed to zero while a tile renders: Embree's recommendation, and
    // it keeps the slow path out of deep Beer attenuation (robustness.md §3.4).
    // The thread's own mode comes back after it: the calling thread runs tiles too,
    // and left on, the flags leaked into whatever it computed next (a test of
    // libm's bits after a render in the same process failed on them).
    struct FlushDenormals {
      const unsigned saved = _mm_getcsr();
      FlushDenormals() {
        _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
        _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
      }
      ~FlushDenormals() { _mm_setcsr(saved); }
    } flush;
    run(ctx, tile, workers.local());
    // Cancelled while it ran: the tile may have stopped part way.
    if (cancelled(ctx)) {
      skipped.store(true, std::memory_order_relaxed);
      return;
    }
    // The tile's pixel-samples not yet reported from inside it.
    Worker& wk = workers.local();
    const std::uint32_t tx = (tile % ctx.tiles_x) * kTile, ty = (tile / ctx.tiles_x) * kTile;
    const std::uint64_t pixels =
        std::uint64_t(std::min(kTile, img.width - tx)) * std::min(kTile, img.height - ty);
    report_work(ctx, pixels * (s1 - s0) - wk.ticked);
    wk.ticked = 0;
  };

  int threads = options.threads > 0 ? options.threads : tbb::this_task_arena::max_concurrency();
  // TBB keeps its workers to the machine's cores unless told otherwise: --threads 8
  // on 2 cores ran 2 and printed a "TBB Warning" on stderr. More threads than cores
  // is the user's choice (the image is the same for any count).
  std::optional<tbb::global_control> allow;
  if (threads > tbb::info::default_concurrency())
    allow.emplace(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
  tbb::task_arena arena(threads);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, ntiles, 1),
                      [&](const tbb::blocked_range<std::uint32_t>& r) {
                        for (std::uint32_t t = r.begin(); t != r.end(); ++t) render_one(t);
                      });
  });
  result.cancelled = skipped.load();
  double ns[kCostKinds] = {};
  RenderStats& rs = result.stats;
  for (const Worker& w : workers) {
    rs.merge(w.stats);
    for (int k = 0; k < kCostKinds; ++k) ns[k] += w.cost.ns[k];
  }
  std::uint64_t samples = std::uint64_t(img.width) * img.height * (s1 - s0);
  double scale = rs.timed_samples ? 1e-9 * double(samples) / double(rs.timed_samples) : 0;
  rs.camera_seconds = ns[kCostCamera] * scale;
  rs.reflection_seconds = ns[kCostReflection] * scale;
  rs.refraction_seconds = ns[kCostRefraction] * scale;
  rs.glossy_seconds = ns[kCostGlossy] * scale;
  rs.shadow_seconds = ns[kCostShadow] * scale;
  rs.lens_seconds = ns[kCostLens] * scale;
  rs.time_seconds = ns[kCostTime] * scale;
  rs.build_seconds = std::chrono::duration<double>(t1 - t0).count();
  rs.render_seconds = std::chrono::duration<double>(Clock::now() - t1).count();
  if (images) result.texture_stats = images->stats();
  return result;
}

}  // namespace snell::rt
