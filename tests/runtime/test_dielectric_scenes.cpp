// Analytic scenes for the specular materials: the glazed sphere's Fresnel curve, the
// glass-sphere white furnace with its truncation by max_depth, the Beer slab, deep
// mirror chains, and a scene far from the origin. Expected values come from
// robustness.md §3.5–§3.6, evaluated on the exact camera ray of each pixel (the test
// replays the sampler and camera), so tolerances only cover float rounding.
#include <catch2/catch.hpp>
#include <cmath>

#include "runtime/camera.hpp"
#include "runtime/render.hpp"
#include "runtime/sampler.hpp"
#include "runtime/shading/fresnel.hpp"
#include "scene_util.hpp"

using namespace snell;
using namespace snell::test;

namespace {

// Impact parameter b / r of pixel (x, y)'s camera ray (sample 0) on a sphere at
// camera-relative centre c, radius r; > 1 when it misses.
double impact(const ir::Scene& s, std::uint32_t x, std::uint32_t y, ir::Vec3 c, double r) {
  rt::PinholeCamera cam(s.camera, s.settings.width, s.settings.height);
  rt::SamplerSpec spec{s.settings.sampler, s.settings.seed, s.settings.samples};
  rt::Sample2 j = rt::sample2(spec, x, y, 0, rt::kDimPixel);
  rt::Ray ray = cam.generate(x + double(j.u), y + double(j.v));
  ir::Vec3 d = ir::normalize(ir::Vec3(ray.dir.x, ray.dir.y, ray.dir.z));
  if (ir::dot(c, d) < 0) return 2;
  return ir::length(ir::cross(c, d)) / r;
}

// L_N of §3.5 with sigma = 0: R + T² Σ_{k=0..N} R^k (N = -1: just R).
double furnace(double b, double eta, int n, ir::FresnelMode mode) {
  double R = rt::fresnel_dielectric(std::sqrt(1 - b * b), eta, mode);
  double T = 1 - R, sum = 0, rk = 1;
  for (int k = 0; k <= n; ++k) sum += rk, rk *= R;
  return R + T * T * sum;
}

ir::Scene sphere_in_white(ir::Material m) {
  ir::Scene s = base_scene(41, 41, 1);
  s.background = ir::Vec3{1, 1, 1};
  s.settings.min_weight = 0;
  s.shapes.push_back(sphere({0, 0, 0}, 1, add_material(s, m)));
  look(s, {0, 0, -4}, {0, 0, 0}, 32);
  return s;
}

}  // namespace

TEST_CASE("black glazed sphere in a white background shows R(theta)", "[scene][fresnel]") {
  for (auto mode : {ir::FresnelMode::Exact, ir::FresnelMode::Schlick}) {
    ir::Scene s = sphere_in_white(glazed({0, 0, 0}, 1.5));
    s.settings.fresnel = mode;
    rt::RenderResult r = rt::render(s, {});
    int checked = 0;
    for (std::uint32_t y = 0; y < 41; ++y)
      for (std::uint32_t x = 0; x < 41; ++x) {
        double b = impact(s, x, y, {0, 0, 4}, 1);
        float v = r.image.at(x, y)[0];
        if (b > 1.0001) {
          REQUIRE(v == 1.0f);
        } else if (b < 0.98) {
          INFO("pixel " << x << "," << y << " b/r " << b);
          REQUIRE(v ==
                  Approx(rt::fresnel_dielectric(std::sqrt(1 - b * b), 1.5, mode)).margin(1e-4));
          ++checked;
        }
      }
    CHECK(checked > 200);
  }
}

TEST_CASE("glass sphere white furnace and its truncation by max_depth", "[scene][fresnel]") {
  // §6: max_depth counts reflection/refraction rays after the camera ray. Camera ray
  // hits (depth 0); outer reflection and the refracted ray are depth 1; the exit
  // refraction and first internal reflection depth 2. So N internal reflections reach
  // the background with N = max_depth - 2 (N = -1 at max_depth 1: R alone), and
  // max_depth 0 is direct light only: the glass is black.
  for (auto mode : {ir::FresnelMode::Exact, ir::FresnelMode::Schlick})
    for (std::uint32_t depth : {0u, 1u, 2u, 3u, 4u, 6u, 60u}) {
      ir::Scene s = sphere_in_white(dielectric(1.5));
      s.settings.fresnel = mode;
      s.settings.max_depth = depth;
      rt::RenderResult r = rt::render(s, {});
      for (std::uint32_t y = 0; y < 41; ++y)
        for (std::uint32_t x = 0; x < 41; ++x) {
          double b = impact(s, x, y, {0, 0, 4}, 1);
          float v = r.image.at(x, y)[0];
          INFO("max_depth " << depth << " pixel " << x << "," << y << " b/r " << b);
          if (b > 1.0001) {
            REQUIRE(v == 1.0f);
          } else if (b < 0.97) {
            double expect = depth == 0 ? 0.0 : furnace(b, 1.5, int(depth) - 2, mode);
            if (depth == 60) REQUIRE(expect == Approx(1).margin(1e-6));
            REQUIRE(v == Approx(expect).margin(2e-4));
          }
        }
      CHECK(r.stats.nonfinite_samples == 0);
    }
}

TEST_CASE("glass sphere truncation matches the §3.5 table at the centre", "[scene][fresnel]") {
  // b/r = 0: N=0 0.9616, N=1 0.998464, N=2 0.99993856.
  const double table[] = {0.96160000, 0.99846400, 0.99993856};
  for (int n = 0; n < 3; ++n) {
    ir::Scene s = base_scene(1, 1, 1);
    s.background = ir::Vec3{1, 1, 1};
    s.settings.min_weight = 0;
    s.settings.max_depth = std::uint32_t(n + 2);
    s.shapes.push_back(sphere({0, 0, 0}, 1, add_material(s, dielectric(1.5))));
    look(s, {0, 0, -4}, {0, 0, 0}, 1e-4);  // one near-axial ray
    CHECK(rt::render(s, {}).image.at(0, 0)[0] == Approx(table[n]).margin(1e-5));
  }
}

TEST_CASE("glass slab at normal incidence: T = (1-R)^2 A / (1 - R^2 A^2)", "[scene][beer]") {
  // §3.6. Reflections return towards the camera and hit a black wall behind it, so
  // the pixel holds the transmitted part only.
  const std::pair<double, double> cases[] = {
      {1.0, 0.92307692}, {0.9, 0.83051635}, {0.5, 0.46098439}};
  for (auto [A, T] : cases) {
    ir::Scene s = base_scene(11, 11, 1);
    s.background = ir::Vec3{1, 1, 1};
    s.settings.min_weight = 0;
    s.settings.max_depth = 60;
    double sigma = -std::log(A);
    s.shapes.push_back(
        box({-5, -5, 0}, {5, 5, 1}, add_material(s, dielectric(1.5, ir::Vec3(sigma)))));
    s.shapes.push_back(plane({0, 0, 1}, -10, add_material(s, diffuse({0, 0, 0}))));
    look(s, {0, 0, -3}, {0, 0, 1}, 0.5);
    rt::RenderResult r = rt::render(s, {});
    INFO("A " << A);
    CHECK(r.image.at(5, 5)[0] == Approx(T).margin(1e-5));
  }
}

TEST_CASE("1000 facing mirrors neither overflow the stack nor loop", "[scene][depth]") {
  ir::Scene s = base_scene(3, 3, 1);
  s.settings.max_depth = 1000;
  s.settings.min_weight = 0;
  s.background = ir::Vec3{1, 1, 1};
  auto m = add_material(s, mirror({1, 1, 1}));
  s.shapes.push_back(plane({0, 0, 1}, 0, m));
  s.shapes.push_back(plane({0, 0, -1}, -1, m));
  look(s, {0, 0, 0.5}, {0, 0, 1}, 0.1);
  rt::RenderOptions opt;
  opt.trace_pixel = std::pair<std::uint32_t, std::uint32_t>{1, 1};
  rt::RenderResult r = rt::render(s, opt);
  CHECK(r.stats.reflection_rays == 9 * 1000);
  CHECK(r.stats.pruned_by_depth == 9);
  CHECK(r.image.at(1, 1)[0] == 0.0f);  // every branch ends past max_depth: black
  CHECK(r.trace.find("reflection depth 1000") != std::string::npos);
}

TEST_CASE("min_weight prunes a dim mirror chain", "[scene][depth]") {
  ir::Scene s = base_scene(1, 1, 1);
  s.settings.max_depth = 1000;
  s.settings.min_weight = 0.01;
  auto m = add_material(s, mirror({0.5, 0.5, 0.5}));
  s.shapes.push_back(plane({0, 0, 1}, 0, m));
  s.shapes.push_back(plane({0, 0, -1}, -1, m));
  look(s, {0, 0, 0.5}, {0, 0, 1}, 0.1);
  rt::RenderResult r = rt::render(s, {});
  CHECK(r.stats.reflection_rays == 6);  // 0.5^7 = 0.0078 < 0.01
  CHECK(r.stats.pruned_by_weight == 1);
  CHECK(r.stats.pruned_by_depth == 0);
}

TEST_CASE("a scene far from the origin renders like the original", "[scene][robust]") {
  auto make = [](ir::Vec3 off) {
    ir::Scene s = base_scene(48, 36, 2);
    s.background = ir::Vec3{0.2, 0.3, 0.4};
    s.shapes.push_back(plane({0, 1, 0}, off.y, 0));
    ir::Shape g = sphere({-0.8, 0.7, 0}, 0.7, add_material(s, dielectric(1.5, {0.2, 0.1, 0})));
    g.set_world_from_object(ir::Transform::translate(off));
    s.shapes.push_back(g);
    ir::Shape b = box({0, 0, 0}, {1, 1, 1}, add_material(s, glazed({0.6, 0.2, 0.1}, 1.5)));
    b.set_world_from_object(ir::Transform::translate(off + ir::Vec3(0.3, 0, -0.2)));
    s.shapes.push_back(b);
    s.point_lights.push_back({off + ir::Vec3(2, 4, -2), {30, 30, 30}, {}});
    look(s, off + ir::Vec3(0, 1.5, -4), off + ir::Vec3(0, 0.5, 0), 50);
    return s;
  };
  rt::RenderResult a = rt::render(make({0, 0, 0}), {});
  rt::RenderResult b = rt::render(make({1e5, -3e5, 2e5}), {});
  double worst = 0;
  for (std::size_t i = 0; i < a.image.rgb.size(); ++i)
    worst = std::fmax(worst, std::fabs(a.image.rgb[i] - b.image.rgb[i]));
  CHECK(worst <= 1e-4);
  CHECK(b.stats.nonfinite_samples == 0);
}

TEST_CASE("Beer absorbs along every stretch inside a dielectric, to whatever it meets",
          "[scene][beer]") {
  // §8: "light travelling a distance d inside is multiplied per channel by
  // exp(-B·d)". A mirror sphere (radius 0.5) inside a glass sphere (radius 2,
  // absorb σ per channel), seen head on: the light goes 1.5 in to the mirror and
  // 1.5 back out, so the pixel is R + T² e^{-3σ} (the reflection inside at the
  // exit goes back to the mirror at depth 3, past max_depth). Only the stretch that
  // ends on the glass's own surface used to count: T² e^{-1.5σ}.
  const ir::Vec3 sigma{0.5, 0.1, 0};
  ir::Scene s = base_scene(1, 1, 1);
  s.background = ir::Vec3{1, 1, 1};
  s.settings.min_weight = 0;
  s.settings.max_depth = 3;
  look(s, {0, 0, -5}, {0, 0, 0}, 1e-3);
  s.shapes.push_back(sphere({0, 0, 0}, 2, add_material(s, dielectric(1.5, sigma))));
  s.shapes.push_back(sphere({0, 0, 0}, 0.5, add_material(s, mirror({1, 1, 1}))));
  const double R = rt::fresnel_exact(rt::make_interface(1, 1.5)), T = 1 - R;
  rt::RenderResult r = rt::render(s, {});
  for (int c = 0; c < 3; ++c)
    CHECK(r.image.at(0, 0)[c] == Approx(R + T * T * std::exp(-3 * sigma[c])).epsilon(1e-5));

  // The sea seen from above, nothing under it: the refracted ray travels for ever
  // inside, so only the channel that does not absorb comes back (R + T there).
  ir::Scene sea = base_scene(1, 1, 1);
  sea.background = ir::Vec3{1, 1, 1};
  sea.settings.min_weight = 0;
  look(sea, {0, 5, 0}, {0, 0, 0.001}, 1e-3);
  sea.shapes.push_back(plane({0, 1, 0}, 0, add_material(sea, dielectric(1.5, sigma))));
  rt::RenderResult below = rt::render(sea, {});
  CHECK(below.image.at(0, 0)[0] == Approx(R).epsilon(1e-5));
  CHECK(below.image.at(0, 0)[1] == Approx(R).epsilon(1e-5));
  CHECK(below.image.at(0, 0)[2] == Approx(1).epsilon(1e-5));
}

TEST_CASE(
    "Beer inside a plain dielectric: from a camera inside it, to a light inside it, "
    "up to a prioritised solid inside it",
    "[scene][beer]") {
  const ir::Vec3 sigma{0.5, 0.1, 0};
  // A camera and a point light (I = π d², so a facing wall of albedo 1 is 1 without
  // absorption) inside one absorbing box without priority, a wall 2 ahead: the
  // light goes 2 to the wall and 2 back, e^{-4σ}. Rays from the camera took no
  // Beer to the wall, nor did the light to it (the picture was untinted).
  ir::Scene s = base_scene(1, 1, 1);
  look(s, {0, 0, 0}, {0, 0, 1}, 1e-3);
  s.shapes.push_back(box({-10, -10, -10}, {10, 10, 10}, add_material(s, dielectric(1.33, sigma))));
  s.shapes.push_back(box({-5, -5, 2}, {5, 5, 3}, add_material(s, diffuse({1, 1, 1}))));
  s.point_lights.push_back(ir::PointLight{{0, 0, 0}, ir::Vec3(3.14159265358979323846 * 4), {}});
  rt::RenderResult r = rt::render(s, {});
  for (int c = 0; c < 3; ++c)
    CHECK(r.image.at(0, 0)[c] == Approx(std::exp(-4 * sigma[c])).epsilon(1e-4));

  // An absorbing slab without priority (z 0..5) holding a clear prioritised one
  // (z 2..3), in front of a light of radiance 1: four air–glass interfaces as
  // far as priorities know (the plain slab is not tracked) and 4 inside the
  // absorbing one. The stretch from its face to the prioritised one (z 0..2)
  // took no Beer (T⁴ e^{-2σ} was rendered).
  ir::Scene n = base_scene(1, 1, 1);
  n.background = ir::Vec3{0, 0, 0};
  n.settings.min_weight = 0;
  n.settings.max_depth = 4;
  look(n, {0, 0, -10}, {0, 0, 0}, 1e-3);
  n.shapes.push_back(box({-20, -20, 0}, {20, 20, 5}, add_material(n, dielectric(1.5, sigma))));
  ir::Material clear = dielectric(1.5);
  std::get<ir::Dielectric>(clear.model).priority = 1;
  n.shapes.push_back(box({-20, -20, 2}, {20, 20, 3}, add_material(n, clear)));
  n.area_lights.push_back(area_light({-50, -50, 10}, {0, 100, 0}, {100, 0, 0}, {1, 1, 1}));
  const double T = 1 - rt::fresnel_exact(rt::make_interface(1, 1.5));
  rt::RenderResult rn = rt::render(n, {});
  // The inner reflections that reach the light within max_depth add ~T⁴R² ≈ 1e-3
  // of it; they are absorbed too, so 1e-3 relative bounds them.
  for (int c = 0; c < 3; ++c)
    CHECK(rn.image.at(0, 0)[c] == Approx(std::pow(T, 4) * std::exp(-4 * sigma[c])).epsilon(2e-3));
}
