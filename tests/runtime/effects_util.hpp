// Helpers shared by the distribution-effect tests (glossy, lens, motion, kernels).
#pragma once

#include <cmath>
#include <cstdint>

#include "runtime/camera.hpp"
#include "runtime/render.hpp"
#include "runtime/sampler.hpp"
#include "tests/runtime/scene_util.hpp"

namespace snell::test {

// The mean of every channel of every pixel.
inline double mean(const rt::Image& im) {
  double sum = 0;
  for (float v : im.rgb) sum += v;
  return sum / double(im.rgb.size());
}

// The camera ray of pixel (0, 0), sample 0, as the renderer makes it.
inline ir::Vec3 camera_dir(const ir::Scene& s) {
  rt::PinholeCamera cam(s.camera, s.settings.width, s.settings.height);
  rt::SamplerSpec spec{s.settings.sampler, s.settings.seed, s.settings.samples};
  rt::Sample2 j = rt::sample2(spec, 0, 0, 0, rt::kDimPixel);
  rt::Ray ray = cam.generate(double(j.u), double(j.v));
  return ir::normalize(ir::Vec3(ray.dir.x, ray.dir.y, ray.dir.z));
}

inline ir::Material glossy(ir::Vec3 c, double blur) {
  return ir::Glossy{c, blur};
}

inline ir::Shape moving(ir::Shape s, ir::TransformOp::Kind kind, ir::Vec3 v) {
  ir::Motion m = s.motion();
  m.ops.push_back({kind, v});
  s.set_motion(std::move(m));
  return s;
}

inline rt::RenderResult render_with(const ir::Scene& s, int threads = 1, bool general = false,
                                    bool measure_cost = false) {
  rt::RenderOptions o;
  o.threads = threads;
  o.general_kernel = general;
  o.measure_cost = measure_cost;
  return rt::render(s, o);
}

inline double mean_abs_diff(const rt::Image& a, const rt::Image& b) {
  double sum = 0;
  for (std::size_t i = 0; i < a.rgb.size(); ++i) sum += std::fabs(double(a.rgb[i]) - b.rgb[i]);
  return a.rgb.empty() ? 0 : sum / double(a.rgb.size());
}

// Fraction of the unit-radius disk with x > -h (h clamped to [-1, 1]).
inline double disk_fraction_right_of(double h) {
  h = std::fmax(-1.0, std::fmin(1.0, h));
  return 1 - (std::acos(h) - h * std::sqrt(1 - h * h)) / 3.14159265358979323846;
}

}  // namespace snell::test
