// RenderStats::to_string: the text of `snell render --stats`.
#include <fmt/format.h>

#include "runtime/geometry/plane_lanes.hpp"
#include "runtime/geometry/sphere_lanes.hpp"
#include "runtime/ray_packet.hpp"
#include "runtime/render.hpp"
#include "runtime/sampler.hpp"
#include "runtime/shading/area_lanes.hpp"

namespace snell::rt {

// Every counter a worker keeps (the timings are set once, after the render).
void RenderStats::merge(const RenderStats& b) {
  RenderStats& a = *this;
  a.camera_rays += b.camera_rays;
  a.shadow_rays += b.shadow_rays;
  a.reflection_rays += b.reflection_rays;
  a.refraction_rays += b.refraction_rays;
  a.glossy_rays += b.glossy_rays;
  a.pruned_by_depth += b.pruned_by_depth;
  a.pruned_by_weight += b.pruned_by_weight;
  a.tir_events += b.tir_events;
  a.nonfinite_samples += b.nonfinite_samples;
  a.interior_passes += b.interior_passes;
  a.interior_overflows += b.interior_overflows;
  a.interior_lost += b.interior_lost;
  a.function_nonfinite += b.function_nonfinite;
  a.lens_samples += b.lens_samples;
  a.time_samples += b.time_samples;
  a.timed_samples += b.timed_samples;
}

namespace {
// The path a packet kernel runs (simd_paths.hpp: the first it offers), or what
// its caller does without one.
std::string best(const std::vector<std::string>& paths) {
  return paths.empty() ? "one by one" : paths.front();
}
template <class Fn>
std::string best(const std::vector<std::pair<std::string, Fn>>& paths) {
  return paths.empty() ? "one by one" : paths.front().first;
}
std::string seconds_line(const char* name, double s, double total) {
  double pct = total > 0 ? 100.0 * s / total : 0;
  return fmt::format("  {:<11} {:9.3f} s  {:5.1f} %\n", name, s, pct);
}
}  // namespace

std::string RenderStats::to_string() const {
  std::uint64_t total = camera_rays + shadow_rays + reflection_rays + refraction_rays + glossy_rays;
  double mrays = render_seconds > 0 ? double(total) / render_seconds * 1e-6 : 0;
  std::string s = fmt::format(
      "kernel: {}\n"
      "rays: {} total ({} camera, {} shadow, {} reflection, {} refraction, {} glossy)\n"
      "samples drawn: {} lens, {} time\n"
      "pruned branches: {} by depth, {} by weight\n"
      "total internal reflections: {}\n"
      "non-finite samples dropped: {}\n"
      "time: build {:.3f} s, render {:.3f} s, {:.2f} Mrays/s\n",
      kernel.empty() ? "?" : kernel, total, camera_rays, shadow_rays, reflection_rays,
      refraction_rays, glossy_rays, lens_samples, time_samples, pruned_by_depth, pruned_by_weight,
      tir_events, nonfinite_samples, build_seconds, render_seconds, mrays);
  // Which SIMD path each packet kernel took on this CPU (SNELL_SIMD caps them):
  // the speed depends on it, never the image.
  s += fmt::format(
      "simd: stratified {}, sobol {}, light keys {}, light samples {}, spheres {}, planes {}, "
      "ray store {}\n",
      best(stratified_lanes_paths()), best(sobol2_lanes_paths()), best(cell_keys_lanes_paths()),
      best(area_lanes_paths()), best(geom::sphere_lanes_paths()), best(geom::plane_lanes_paths()),
      best(store_rays16_paths()));
  if (interior_passes + interior_overflows + interior_lost > 0)
    s += fmt::format(
        "interiors: {} surfaces passed through, {} entries forgotten (full), {} branches "
        "lost\n",
        interior_passes, interior_overflows, interior_lost);
  if (function_nonfinite > 0)
    s += fmt::format("shading functions: {} non-finite values (each replaced by 0)\n",
                     function_nonfinite);
  if (cost_stride == 0) return s;  // RenderOptions::measure_cost was off
  double cost = camera_seconds + shadow_seconds + reflection_seconds + refraction_seconds +
                glossy_seconds + lens_seconds + time_seconds;
  s += fmt::format(
      "cost by effect (thread-seconds, estimated from {} of the camera samples, 1 in {}):\n",
      timed_samples, cost_stride);
  s += seconds_line("camera", camera_seconds, cost);
  s += seconds_line("shadow", shadow_seconds, cost);
  s += seconds_line("reflection", reflection_seconds, cost);
  s += seconds_line("refraction", refraction_seconds, cost);
  s += seconds_line("glossy", glossy_seconds, cost);
  s += seconds_line("lens", lens_seconds, cost);
  s += seconds_line("time", time_seconds, cost);
  return s;
}

}  // namespace snell::rt
