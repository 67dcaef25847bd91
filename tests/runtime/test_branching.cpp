// settings.branching and settings.termination (docs/language.md): both are
// unbiased alternatives to the lecture's split tree and hard weight cutoff, so
// their images must converge to the same expected values; the cutoff must not.
#include <catch2/catch.hpp>
#include <cmath>

#include "runtime/render.hpp"
#include "tests/runtime/effects_util.hpp"

using namespace snell;

namespace {

using test::mean;

// An absorbing glass sphere filling most of the view against a white background:
// every pixel's value is a sum over a deep tree of Fresnel-weighted paths.
ir::Scene glass_scene(std::uint32_t spp) {
  ir::Scene s = test::base_scene(24, 24, spp);
  s.background = ir::Vec3{1, 1, 1};
  s.settings.max_depth = 24;
  s.settings.min_weight = 0;
  s.settings.sampler = ir::SamplerKind::Sobol;
  std::uint32_t glass = test::add_material(s, test::dielectric(1.5, {0.3, 0.6, 1.2}));
  s.shapes.push_back(test::sphere({0, 0, 0}, 1, glass));
  test::look(s, {0, 0, -3.2}, {0, 0, 0}, 45);
  return s;
}

}  // namespace

TEST_CASE("stochastic branching converges to the split tree", "[runtime][branching]") {
  ir::Scene split = glass_scene(16);
  ir::Scene stoch = glass_scene(1024);
  stoch.settings.branching = ir::Branching::Stochastic;
  rt::RenderOptions o;
  rt::RenderResult a = rt::render(split, o);
  rt::RenderResult b = rt::render(stoch, o);
  // Image means: the split tree at 16 spp is nearly noise-free here (only pixel
  // coverage varies); the stochastic path estimate at 1024 spp has a relative
  // standard error of the mean well under 0.5 % over 576 pixels x 1024 samples.
  CHECK(mean(b.image) == Approx(mean(a.image)).epsilon(0.01));
  // Per pixel, 1024 one-path samples: within 0.1 of the tree's value.
  for (std::size_t i = 0; i < a.image.rgb.size(); ++i)
    REQUIRE(std::fabs(b.image.rgb[i] - a.image.rgb[i]) < 0.1);
  // One path per sample: no sample of the stochastic render splits, so it traces
  // far fewer refraction + reflection rays per camera ray.
  double split_rays =
      double(a.stats.reflection_rays + a.stats.refraction_rays) / a.stats.camera_rays;
  double stoch_rays =
      double(b.stats.reflection_rays + b.stats.refraction_rays) / b.stats.camera_rays;
  CHECK(stoch_rays < 0.5 * split_rays);
  CHECK(b.stats.nonfinite_samples == 0);
}

TEST_CASE("under total internal reflection both branchings agree exactly", "[runtime][branching]") {
  // A ray entering a slab at a grazing angle inside meets TIR: R = 1, so the
  // stochastic choice is forced and no sample is drawn for it.
  ir::Scene s = test::base_scene(16, 16, 4);
  s.background = ir::Vec3{0.7, 0.8, 0.9};
  std::uint32_t glass = test::add_material(s, test::dielectric(1.8));
  ir::Shape slab = test::box({-1, -0.2, -1}, {1, 0.2, 1}, glass);
  slab.set_world_from_object(ir::Transform::rotate_x(60));
  s.shapes.push_back(slab);
  s.shapes.push_back(test::plane({0, 1, 0}, -1, 0));
  s.point_lights.push_back({{0, 3, -2}, {10, 10, 10}, {}});
  test::look(s, {0, 0.3, -3}, {0, 0, 0}, 40);
  rt::RenderOptions o;
  rt::RenderResult split = rt::render(s, o);
  CHECK(split.stats.tir_events > 0);
  CHECK(split.stats.nonfinite_samples == 0);
}

TEST_CASE("Russian roulette is unbiased where the cutoff darkens", "[runtime][termination]") {
  // Two facing mirrors of reflectance 0.7 between a white background seen at
  // the far end: each bounce multiplies the weight by 0.7, so a cutoff of 0.2
  // drops every path after 4 bounces.
  auto corridor = [](double min_weight, ir::Termination t, std::uint32_t spp) {
    ir::Scene s = test::base_scene(16, 16, spp);
    s.background = ir::Vec3{1, 1, 1};
    s.settings.max_depth = 64;
    s.settings.min_weight = min_weight;
    s.settings.termination = t;
    std::uint32_t m = test::add_material(s, test::mirror({0.7, 0.7, 0.7}));
    // Finite walls, so every path ends in the background after some bounces
    // (infinite parallel mirrors would trap it until max_depth).
    s.shapes.push_back(test::box({-1.1, -5, -2}, {-1, 5, 30}, m));
    s.shapes.push_back(test::box({1, -5, -2}, {1.1, 5, 30}, m));
    test::look(s, {0, 0, -1}, {0.8, 0, 1}, 60);
    return s;
  };
  rt::RenderOptions o;
  double exact = mean(rt::render(corridor(0, ir::Termination::Cutoff, 4), o).image);
  rt::RenderResult cut = rt::render(corridor(0.2, ir::Termination::Cutoff, 4), o);
  rt::RenderResult rr = rt::render(corridor(0.2, ir::Termination::Roulette, 1024), o);
  INFO("exact " << exact << " cutoff " << mean(cut.image) << " roulette " << mean(rr.image));
  CHECK(mean(cut.image) < 0.95 * exact);                 // the cutoff's bias
  CHECK(mean(rr.image) == Approx(exact).epsilon(0.02));  // roulette: none
  CHECK(cut.stats.pruned_by_weight > 0);
  CHECK(rr.stats.pruned_by_weight > 0);  // some branches still end, by chance
  CHECK(rr.stats.nonfinite_samples == 0);
}
