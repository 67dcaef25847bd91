// render(): build the Embree scene, then trace tiles in parallel with TBB. Each
// pixel's samples are a pure function of (seed, pixel, sample index, dimension), and
// each pixel is summed in sample order by one task, so the image is bit-identical
// whatever the thread count or tile schedule. The per-pixel loop is a template on
// the effects it simulates (lens, time) and on the shading kernel's flags; render()
// picks one instantiation from ir::Features (docs/effects.md).
#include "runtime/render.hpp"

#include <fmt/format.h>
#include <pmmintrin.h>
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <xmmintrin.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <utility>

#include "runtime/camera.hpp"
#include "runtime/embree_scene.hpp"
#include "runtime/integrator.hpp"
#include "runtime/sampler.hpp"

namespace snell::rt {

namespace {
constexpr std::uint32_t kTile = 16;
// 1 in kCostStride camera samples is timed for the per-effect cost (a power of 2).
constexpr std::uint32_t kCostStride = 16;
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
  a.lens_samples += b.lens_samples;
  a.time_samples += b.time_samples;
  a.timed_samples += b.timed_samples;
}

// Which kernel to run: the effects the scene uses, or all of them.
struct KernelChoice {
  bool lens = true, time = true, area = true, dielectric = true, absorption = true;
  bool general = true;
  unsigned bits() const {
    return (lens ? 1u : 0u) | (time ? 2u : 0u) | (area ? 4u : 0u) | (dielectric ? 8u : 0u) |
           (dielectric && absorption ? 16u : 0u);
  }
  std::string name() const {
    if (general) return "general (every effect compiled in)";
    return fmt::format(
        "specialised: {}, {}, {}, {}", lens ? "thin lens" : "pinhole",
        time ? "motion (time sampled)" : "static", area ? "area lights" : "point lights only",
        dielectric ? (absorption ? "dielectrics with absorption" : "clear dielectrics")
                   : "no dielectrics");
  }
};

KernelChoice choose_kernel(const ir::Scene& scene, bool general) {
  KernelChoice k;
  if (general) return k;
  ir::Features f = ir::analyze_features(scene);
  k.general = false;
  k.lens = f.depth_of_field;
  k.time = f.motion_blur;
  k.area = f.area_lights;
  k.dielectric = f.dielectric;
  k.absorption = f.absorption;
  return k;
}

// Everything a tile needs; shared read-only by all workers.
struct TileContext {
  const Image* img = nullptr;
  const Camera* camera = nullptr;
  const Integrator* integrator = nullptr;
  SamplerSpec spec;
  bool motion_on = false;  // some object has motion geometry: ray times matter
  std::uint32_t tiles_x = 1;
  const RenderOptions* options = nullptr;
  std::string* trace = nullptr;
  float* rgb = nullptr;
  bool measure_cost = false;
};

struct Worker {
  RenderStats stats;
  std::vector<Node> stack;
  CostClock cost;
};

// A deterministic 1-in-kCostStride choice of camera samples to time; it never
// changes the picture.
bool timed_sample(std::uint32_t x, std::uint32_t y, std::uint32_t s) {
  std::uint32_t h = (x * 0x9e3779b1u) ^ (y * 0x85ebca77u) ^ (s * 0xc2b2ae3du);
  h ^= h >> 15;
  h *= 0x2c1b3c6du;
  h ^= h >> 12;
  return (h & (kCostStride - 1)) == 0;
}

// The per-pixel loop of one kernel. Lens: draw a lens sample (dimension kDimLens)
// for every camera ray; Time: draw a shutter fraction (kDimTime), the ray time when
// motion is on. The dimensions do not depend on the kernel, so every kernel gives
// every decision the same number.
template <bool Lens, bool Time, class K>
void render_tile(const TileContext& c, std::uint32_t tile, Worker& wk) {
  const Image& img = *c.img;
  RenderStats& stats = wk.stats;
  CostClock& clock = wk.cost;
  const SamplerSpec& spec = c.spec;
  std::uint32_t x0 = (tile % c.tiles_x) * kTile, y0 = (tile / c.tiles_x) * kTile;
  std::uint32_t x1 = std::min(x0 + kTile, img.width), y1 = std::min(y0 + kTile, img.height);
  for (std::uint32_t y = y0; y < y1; ++y)
    for (std::uint32_t x = x0; x < x1; ++x) {
      bool tracing = c.options->trace_pixel && c.options->trace_pixel->first == x &&
                     c.options->trace_pixel->second == y;
      const std::uint64_t pixel = pixel_hash(spec, x, y);
      double sum[3] = {0, 0, 0};
      std::uint32_t kept = 0;
      for (std::uint32_t s = 0; s < spec.spp; ++s) {
        bool timed = c.measure_cost && timed_sample(x, y, s);
        double t_cam = timed ? CostClock::now_ns() : 0, t_effects = 0;
        SampleContext sc{spec, x, y, s, pixel};
        Sample2 j = sample2(spec, pixel, s, kDimPixel);
        Ray ray;
        if constexpr (Lens) {
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
        if constexpr (Time) {
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
        std::string* tr = (tracing && s == 0) ? c.trace : nullptr;
        if (tr) *tr += fmt::format("pixel ({}, {}) sample 0\n", x, y);
        Color col = c.integrator->li<K>(ray, sc, stats, wk.stack, tr, timed ? &clock : nullptr);
        if (!is_finite(col)) {  // dropped and counted, never written
          ++stats.nonfinite_samples;
          continue;
        }
        sum[0] += col.x, sum[1] += col.y, sum[2] += col.z;
        ++kept;
      }
      float* px = c.rgb + 3 * (std::size_t(y) * img.width + x);
      for (int k = 0; k < 3; ++k) px[k] = kept ? float(sum[k] / kept) : 0.0f;
    }
}

using TileFn = void (*)(const TileContext&, std::uint32_t, Worker&);

template <unsigned B>
void tile_fn(const TileContext& c, std::uint32_t tile, Worker& wk) {
  constexpr bool kDiel = (B & 8) != 0;
  render_tile<(B & 1) != 0, (B & 2) != 0, ShadeFlags<(B & 4) != 0, kDiel, kDiel && (B & 16) != 0>>(
      c, tile, wk);
}
template <unsigned... B>
constexpr std::array<TileFn, sizeof...(B)> make_table(std::integer_sequence<unsigned, B...>) {
  return {&tile_fn<B>...};
}
constexpr auto kKernels = make_table(std::make_integer_sequence<unsigned, 32>{});

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
  img.width = st.width;
  img.height = st.height;
  img.rgb.assign(std::size_t(img.width) * img.height * 3, 0.0f);
  KernelChoice kernel = choose_kernel(scene, options.general_kernel);
  result.stats.kernel = kernel.name();
  result.stats.cost_stride = options.measure_cost ? kCostStride : 0;
  if (img.width == 0 || img.height == 0) return result;

  auto t0 = Clock::now();
  EmbreeScene embree(scene, scene.camera.location);
  Integrator integrator(scene, embree);
  Camera camera(scene.camera, img.width, img.height);
  auto t1 = Clock::now();

  TileContext ctx;
  ctx.img = &img;
  ctx.camera = &camera;
  ctx.integrator = &integrator;
  ctx.spec = SamplerSpec{st.sampler, st.seed, st.samples ? st.samples : 1};
  ctx.motion_on = embree.has_motion();
  ctx.tiles_x = (img.width + kTile - 1) / kTile;
  ctx.options = &options;
  ctx.trace = &result.trace;
  ctx.rgb = img.rgb.data();
  ctx.measure_cost = options.measure_cost;
  std::uint32_t tiles_y = (img.height + kTile - 1) / kTile;
  std::uint32_t ntiles = ctx.tiles_x * tiles_y;
  std::atomic<std::uint32_t> done{0};
  TileFn run = kKernels[kernel.bits()];
  double overhead = options.measure_cost ? clock_overhead_ns() : 0;
  tbb::enumerable_thread_specific<Worker> workers([&] {
    Worker w;
    w.cost.overhead_ns = overhead;
    return w;
  });

  auto render_one = [&](std::uint32_t tile) {
    // Denormals flushed to zero on every worker: Embree's recommendation, and
    // it keeps the slow path out of deep Beer attenuation (robustness.md §3.4).
    _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
    _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
    run(ctx, tile, workers.local());
    std::uint32_t n = ++done;
    if (options.progress) options.progress(double(n) / ntiles);
  };

  int threads = options.threads > 0 ? options.threads : tbb::this_task_arena::max_concurrency();
  tbb::task_arena arena(threads);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, ntiles, 1),
                      [&](const tbb::blocked_range<std::uint32_t>& r) {
                        for (std::uint32_t t = r.begin(); t != r.end(); ++t) render_one(t);
                      });
  });
  double ns[kCostKinds] = {};
  RenderStats& rs = result.stats;
  for (const Worker& w : workers) {
    add(rs, w.stats);
    for (int k = 0; k < kCostKinds; ++k) ns[k] += w.cost.ns[k];
  }
  std::uint64_t samples = std::uint64_t(img.width) * img.height * ctx.spec.spp;
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
  return result;
}

}  // namespace snell::rt
