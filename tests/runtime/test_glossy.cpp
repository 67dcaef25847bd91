// Glossy reflection (§8): the Duff et al. basis, the below-surface policy, blur 0 as
// the mirror bit for bit, continuity as blur -> 0, and energy in a white furnace.
#include <catch2/catch.hpp>
#include <random>

#include "runtime/shading/glossy.hpp"
#include "tests/runtime/effects_util.hpp"

using namespace snell;
using namespace snell::test;

namespace {
double onb_error(rt::Vec3f n) {
  rt::Vec3f a, b;
  rt::orthonormal_basis(n, a, b);
  auto sq = [](double x) { return x * x; };
  return (sq(rt::length(a) - 1) + sq(rt::length(b) - 1) + sq(rt::length(n) - 1) +
          sq(rt::dot(a, b)) + sq(rt::dot(a, n)) + sq(rt::dot(b, n))) /
         6;
}

ir::Scene sphere_on_checker(ir::Material m) {
  ir::Scene s = base_scene(48, 36, 4);
  s.background = ir::Vec3{0.3, 0.4, 0.6};
  ir::Material check = checker({0.9, 0.9, 0.9}, {0.1, 0.1, 0.1}, 0.5);
  s.shapes.push_back(plane({0, 1, 0}, 0, add_material(s, check)));
  s.shapes.push_back(sphere({0, 1, 0}, 1, add_material(s, m)));
  s.point_lights.push_back({{2, 5, -3}, {40, 40, 40}, {}});
  look(s, {0, 1.5, -4}, {0, 0.8, 0}, 50);
  return s;
}
}  // namespace

TEST_CASE("Duff orthonormal basis on axes, bad vectors and random normals", "[glossy][onb]") {
  for (rt::Vec3f n : {rt::Vec3f(1, 0, 0), rt::Vec3f(-1, 0, 0), rt::Vec3f(0, 1, 0),
                      rt::Vec3f(0, -1, 0), rt::Vec3f(0, 0, 1), rt::Vec3f(0, 0, -1),
                      rt::normalize(rt::Vec3f(0.00038527316f, 0.00038460016f, -0.99999988079f))})
    CHECK(onb_error(n) < 1e-10);
  std::mt19937 rng(7);
  std::normal_distribution<float> g;
  double worst = 0;
  for (int i = 0; i < 100000; ++i) {
    rt::Vec3f n = rt::normalize(rt::Vec3f(g(rng), g(rng), g(rng)));
    worst = std::fmax(worst, onb_error(n));
  }
  CHECK(worst < 1e-10);
}

TEST_CASE("glossy directions never go below the surface at 85 degrees", "[glossy][property]") {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u01(0, 0.99999994f);
  rt::Vec3f nf(0, 0, 1);
  double th = 85 * 3.14159265358979323846 / 180;
  rt::Vec3f d(float(std::sin(th)), 0, -float(std::cos(th)));  // incoming
  rt::Vec3f r = rt::normalize(d + nf * (2 * -rt::dot(d, nf)));
  long below = 0, mirrored = 0;
  for (int i = 0; i < 1000000; ++i) {
    float a = u01(rng), b = u01(rng);
    rt::Vec3f w = rt::glossy_direction(r, nf, 0.8f, a, b);
    if (!(rt::dot(w, nf) > 0)) ++below;
    if (std::fabs(rt::length(w) - 1) > 1e-5f) ++mirrored;
  }
  CHECK(below == 0);
  CHECK(mirrored == 0);  // every direction unit length
  // blur 0 returns the mirror direction bit for bit
  rt::Vec3f m = rt::glossy_direction(r, nf, 0.0f, 0.3f, 0.7f);
  CHECK((m.x == r.x && m.y == r.y && m.z == r.z));
}

TEST_CASE("glossy blur 0 renders the mirror image bit for bit", "[glossy][scene]") {
  for (auto kind :
       {ir::SamplerKind::Independent, ir::SamplerKind::Stratified, ir::SamplerKind::Sobol}) {
    ir::Scene a = sphere_on_checker(mirror({0.9, 0.85, 0.7}));
    ir::Scene b = sphere_on_checker(glossy({0.9, 0.85, 0.7}, 0));
    a.settings.sampler = b.settings.sampler = kind;
    rt::RenderResult ra = render_with(a), rb = render_with(b);
    CHECK(ra.image.rgb == rb.image.rgb);
    CHECK(rb.stats.glossy_rays == ra.stats.reflection_rays);
  }
}

TEST_CASE("glossy converges to the mirror as blur goes to 0", "[glossy][scene]") {
  ir::Scene ref = sphere_on_checker(mirror({0.9, 0.9, 0.9}));
  rt::Image mirror_img = render_with(ref).image;
  double prev = 1e9;
  for (double blur : {0.3, 0.1, 0.01, 0.001}) {
    double d = mean_abs_diff(render_with(sphere_on_checker(glossy({0.9, 0.9, 0.9}, blur))).image,
                             mirror_img);
    INFO("blur " << blur << " mean abs diff " << d);
    CHECK(d < prev);
    prev = d;
  }
  CHECK(prev < 2e-3);
}

TEST_CASE("glossy sphere in a white furnace conserves energy", "[glossy][scene]") {
  for (double c : {1.0, 0.6}) {
    ir::Scene s = base_scene(33, 33, 8);
    s.background = ir::Vec3{1, 1, 1};
    s.settings.min_weight = 0;
    s.shapes.push_back(sphere({0, 0, 0}, 1, add_material(s, glossy({c, c, c}, 0.7))));
    look(s, {0, 0, -4}, {0, 0, 0}, 40);
    rt::RenderResult r = render_with(s);
    double lo = 2, hi = -1;
    for (float v : r.image.rgb) lo = std::fmin(lo, v), hi = std::fmax(hi, v);
    CHECK(lo == Approx(c).margin(1e-6));  // sphere pixels: c; the rest: 1
    CHECK(hi == Approx(1).margin(1e-6));
    CHECK(r.stats.glossy_rays > 0);
  }
}
