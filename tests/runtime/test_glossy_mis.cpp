// glossy_sampling "mis" (shading/glossy_mis.hpp): the weights of the glossy ray and
// a light sample sum to one, the lobe's cone test never turns away a light the lobe
// reaches, and a scene renders the lobe's image (the same mean) with less noise.
#include <catch2/catch.hpp>
#include <random>

#include "runtime/shading/glossy.hpp"
#include "runtime/shading/glossy_mis.hpp"
#include "tests/runtime/effects_util.hpp"

using namespace snell;
using namespace snell::test;

TEST_CASE("glossy MIS: the ray's and the light sample's weights sum to one", "[glossy][mis]") {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> e(-30, 30);
  for (int i = 0; i < 100000; ++i) {
    double p_b = std::pow(10.0, e(rng)), p_c = std::pow(10.0, e(rng));
    // The light technique's weight is its factor x/(1+x²) times p_c/p_b.
    double w_b = rt::mis_ray_weight(p_b, p_c);
    double w_c = rt::mis_light_factor(p_b, p_c) * (p_c / p_b);
    INFO("p_b " << p_b << " p_c " << p_c);
    REQUIRE(std::isfinite(w_b));
    REQUIRE(w_b >= 0);
    REQUIRE(w_b <= 1);
    REQUIRE(w_b + w_c == Approx(1).epsilon(1e-12));
  }
  // Where the lobe cannot reach, the light sample adds nothing and the ray is whole.
  CHECK(rt::mis_light_factor(0, 3) == 0);
  CHECK(rt::mis_ray_weight(0, 3) == 1);
  CHECK(rt::mis_light_factor(INFINITY, 3) == 0);
  CHECK(rt::mis_light_factor(NAN, 3) == 0);
  CHECK(rt::mis_ray_weight(2, INFINITY) == 1);
  // Equal densities: half each.
  CHECK(rt::mis_ray_weight(5, 5) == 0.5);
  CHECK(rt::mis_light_factor(5, 5) == 0.5);
}

TEST_CASE("glossy MIS: the lobe's cone test keeps every light the lobe reaches", "[glossy][mis]") {
  std::mt19937 rng(5);
  std::normal_distribution<float> g;
  std::uniform_real_distribution<float> u01(0, 1);
  int kept = 0, culled = 0;
  for (int i = 0; i < 200000; ++i) {
    rt::Vec3f nf = rt::normalize(rt::Vec3f(g(rng), g(rng), g(rng)));
    rt::Vec3f d = rt::normalize(rt::Vec3f(g(rng), g(rng), g(rng)));
    if (rt::dot(d, nf) > 0) d = -d;
    float cos_i = -rt::dot(d, nf);
    rt::Vec3f r = rt::normalize(d + nf * (2 * cos_i));
    float blur = 2.0f * u01(rng) * u01(rng);
    rt::Vec3f w = rt::glossy_direction(r, nf, blur, u01(rng), u01(rng));
    // A ball that w passes through (its centre a little off w), which must be kept,
    double dist = std::pow(10.0, 4 * u01(rng) - 2), radius = dist * 0.5 * u01(rng) + 1e-9;
    rt::Vec3f off = rt::normalize(rt::cross(w, rt::Vec3f(g(rng), g(rng), g(rng))));
    rt::Vec3f centre = w * float(dist) + off * float(0.9 * radius * u01(rng));
    INFO("blur " << blur << " dist " << dist << " radius " << radius);
    REQUIRE(rt::lobe_meets_ball(r, nf, blur, centre, radius));
    // and the same ball straight below the surface, which the test turns away when
    // neither cone reaches it: half-angles below 47° (blur < 1, radius < dist/5),
    // and the folded cone's axis (r mirrored) more than 47° from -nf (r less than
    // 37° above the surface).
    if (rt::dot(r, nf) < 0.6f && blur < 1 && radius < 0.2 * dist)
      rt::lobe_meets_ball(r, nf, blur, -nf * float(dist), radius) ? ++kept : ++culled;
  }
  // Below the surface, straight down: no lobe direction goes there.
  CHECK(culled > 0);
  CHECK(kept == 0);
}

namespace {
// A glossy floor seen at a slant, reflecting a small bright light: the case the
// glossy ray alone finds rarely.
ir::Scene glossy_floor(ir::GlossySampling mode, std::uint32_t spp, std::uint64_t seed) {
  ir::Scene s = base_scene(32, 24, spp);
  s.settings.sampler = ir::SamplerKind::Independent;
  s.settings.seed = seed;
  s.settings.glossy_sampling = mode;
  s.background = ir::Vec3{0.02, 0.02, 0.03};
  s.shapes.push_back(plane({0, 1, 0}, 0, add_material(s, glossy({0.9, 0.8, 0.6}, 0.35))));
  s.area_lights.push_back(
      area_light({-0.25, 1.5, 1.75}, {0.5, 0, 0}, {0, 0, 0.5}, {80, 80, 80}, 2));
  look(s, {0, 1, -2}, {0, 0, 1}, 60);
  return s;
}
double rmse(const rt::Image& a, const rt::Image& b) {
  double sum = 0;
  for (std::size_t i = 0; i < a.rgb.size(); ++i) {
    double d = double(a.rgb[i]) - b.rgb[i];
    sum += d * d;
  }
  return std::sqrt(sum / double(a.rgb.size()));
}
}  // namespace

TEST_CASE("glossy_sampling mis renders the lobe's image with less noise", "[glossy][mis][scene]") {
  using GS = ir::GlossySampling;
  // A converged MIS reference; the lobe and MIS at 1024 spp must both agree with it
  // in the mean (the same expected image), and at 16 spp MIS must be much closer.
  rt::Image ref = render_with(glossy_floor(GS::Mis, 4096, 99), 2).image;
  rt::RenderResult lobe = render_with(glossy_floor(GS::Lobe, 1024, 1), 2);
  rt::RenderResult mis = render_with(glossy_floor(GS::Mis, 1024, 1), 2);
  CHECK(lobe.stats.nonfinite_samples == 0);
  CHECK(mis.stats.nonfinite_samples == 0);
  // More shadow rays: the light samples of the glossy hits.
  CHECK(mis.stats.shadow_rays > lobe.stats.shadow_rays);
  double m_ref = mean(ref), m_lobe = mean(lobe.image), m_mis = mean(mis.image);
  INFO("means: reference " << m_ref << " lobe " << m_lobe << " mis " << m_mis);
  CHECK(m_ref > 0.05);
  // Measured spread of the lobe's mean at 1024 spp over seeds: ~0.5 %; of MIS's
  // ~0.1 %. A cell density of d instead of d² makes the MIS images 2.7x brighter.
  CHECK(m_lobe == Approx(m_ref).epsilon(0.03));
  CHECK(m_mis == Approx(m_ref).epsilon(0.01));
  double e_lobe = rmse(render_with(glossy_floor(GS::Lobe, 16, 3), 2).image, ref);
  double e_mis = rmse(render_with(glossy_floor(GS::Mis, 16, 3), 2).image, ref);
  INFO("RMSE at 16 spp: lobe " << e_lobe << " mis " << e_mis);
  CHECK(e_mis < 0.5 * e_lobe);
}
