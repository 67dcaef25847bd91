// §16 highlights against the formula: f = S·(E + 8)/(8π)·max(0, n·h)^E added to the
// Lambertian ρ/π in the direct light, h halfway between the directions to the light
// and to where the ray came from, and nothing else (no point light in a mirror, no
// change to the rays leaving the surface).
//
// The scenes are one pixel, one sample, looking at a floor y = 0 through a 1e-3°
// field of view; the camera ray is replayed from the sampler and camera as the
// renderer makes it and followed in double, so the expected radiance is exact for
// that ray. The renderer differs by float rounding: directions and hit points good
// to a few 1e-7, which c^E can turn into E · 1e-7 relative (2e-5 for E = 200;
// measured: at most 5e-6). The tolerance is 5e-5 relative.
#include <catch2/catch.hpp>
#include <cmath>

#include "runtime/camera.hpp"
#include "runtime/render.hpp"
#include "runtime/sampler.hpp"
#include "tests/runtime/effects_util.hpp"

using namespace snell;
using namespace snell::test;

namespace {

constexpr double kTol = 5e-5;

ir::Material shiny(ir::Vec3 c, double specular, double shininess) {
  ir::Diffuse d{c};
  d.specular = specular;
  d.shininess = shininess;
  return d;
}

// The spec's f, in double.
double blinn_phong(ir::Vec3 n, ir::Vec3 wo, ir::Vec3 wi, double S, double E) {
  double c = ir::dot(n, ir::normalize(wo + wi));
  return c > 0 ? S * (E + 8) / (8 * kPi) * std::pow(c, E) : 0;
}

ir::Scene one_pixel(ir::Vec3 from, ir::Vec3 at) {
  ir::Scene s = base_scene(1, 1, 1);
  look(s, from, at, 1e-3);
  return s;
}

// Where a ray from `o` along `d` meets the floor y = 0.
ir::Vec3 on_floor(ir::Vec3 o, ir::Vec3 d) {
  return o + d * (-o.y / d.y);
}

// The radiance a floor point x of albedo rho and highlight (S, E) sends towards wo
// under a point light: (ρ/π + f) · I · cosθ / d².
ir::Vec3 lit_floor(ir::Vec3 x, ir::Vec3 wo, ir::Vec3 rho, double S, double E,
                   const ir::PointLight& l) {
  ir::Vec3 to = l.position - x;
  double d2 = ir::dot(to, to);
  ir::Vec3 wi = ir::normalize(to);
  double f = blinn_phong({0, 1, 0}, wo, wi, S, E);
  return (rho / kPi + ir::Vec3(f, f, f)) * l.intensity * (wi.y / d2);
}

void check_pixel(const rt::RenderResult& r, ir::Vec3 expect, double tol = kTol) {
  for (int c = 0; c < 3; ++c) {
    INFO("channel " << c);
    CHECK(r.image.at(0, 0)[c] == Approx(expect[c]).epsilon(tol));
  }
  CHECK(r.stats.nonfinite_samples == 0);
  CHECK(r.stats.kernel.find("highlights") != std::string::npos);
}

const ir::PointLight kLight{{1.5, 2, 0}, {10, 20, 30}, {}};
const ir::Vec3 kRho{0.5, 0.25, 0.8};

}  // namespace

TEST_CASE("a floor's highlight under a point light is the formula's", "[runtime][highlights]") {
  struct View {
    ir::Vec3 from, at;
  };
  // (-3, 4, 0) looks at the origin along the light's mirror direction (n·h = 1);
  // the others are off the peak by growing angles, the last far out in the tail.
  const View views[] = {{{-3, 4, 0}, {0, 0, 0}},
                        {{-3, 4, 0.5}, {0, 0, 0}},
                        {{-2, 3, 1}, {0.3, 0, -0.2}},
                        {{0, 5, -0.5}, {0, 0, 0}}};
  for (double E : {10.0, 50.0, 200.0})
    for (const View& v : views) {
      ir::Scene s = one_pixel(v.from, v.at);
      s.shapes.push_back(plane({0, 1, 0}, 0, add_material(s, shiny(kRho, 0.6, E))));
      s.point_lights.push_back(kLight);
      ir::Vec3 d = camera_dir(s);
      ir::Vec3 x = on_floor(v.from, d);
      INFO("shininess " << E << " from " << v.from.x << " " << v.from.y << " " << v.from.z);
      check_pixel(rt::render(s, {}), lit_floor(x, -d, kRho, 0.6, E, kLight));
    }
  // Sensitivity: at the peak the highlight is most of the light, far more than the
  // tolerance; the same floor without it is the plain Lambertian value.
  ir::Scene s = one_pixel({-3, 4, 0}, {0, 0, 0});
  std::uint32_t m = add_material(s, shiny(kRho, 0.6, 50));
  s.shapes.push_back(plane({0, 1, 0}, 0, m));
  s.point_lights.push_back(kLight);
  ir::Vec3 d = camera_dir(s), x = on_floor(s.camera.location, d);
  ir::Vec3 with = lit_floor(x, -d, kRho, 0.6, 50, kLight),
           without = lit_floor(x, -d, kRho, 0, 50, kLight);
  CHECK(with.x > 5 * without.x);
  s.materials[m] = shiny(kRho, 0, 50);
  rt::RenderResult plain = rt::render(s, {});
  CHECK(plain.image.at(0, 0)[0] == Approx(without.x).epsilon(kTol));
  CHECK(plain.stats.kernel.find("highlights") == std::string::npos);
}

TEST_CASE("a mirror shows no point light, highlights or not", "[runtime][highlights]") {
  // A mirror and a glossy floor whose reflected rays pass by the point light: a
  // point light is invisible (§7), and the highlight (on a sphere elsewhere, so the
  // highlight kernel runs) is no lobe of the rays the floor sends.
  for (ir::Material floor : {mirror({1, 1, 1}), glossy({1, 1, 1}, 0.05)}) {
    ir::Scene s = one_pixel({-2, 2, 0}, {0, 0, 0});
    s.shapes.push_back(plane({0, 1, 0}, 0, add_material(s, floor)));
    s.shapes.push_back(sphere({0, 1, 20}, 1, add_material(s, shiny(kRho, 1, 50))));
    s.point_lights.push_back({{2.001, 2.001, 0}, {1000, 1000, 1000}, {}});
    rt::RenderResult r = rt::render(s, {});
    for (int c = 0; c < 3; ++c) CHECK(r.image.at(0, 0)[c] == 0.0f);
    CHECK(r.stats.kernel.find("highlights") != std::string::npos);
    CHECK(r.stats.reflection_rays + r.stats.glossy_rays == 1);
  }
}

TEST_CASE("a highlight seen in a mirror is the one for the reflected view",
          "[runtime][highlights]") {
  // A mirror of colour 0.9 in the plane x = -1.5 facing +x. The camera at (0, 4, 0)
  // sees in it the floor's origin from (-3, 4, 0), its mirror image: the light's
  // mirror direction there, so the floor shows its peak. Seen directly from the
  // camera the same point would show far less.
  ir::Scene s = one_pixel({0, 4, 0}, {-1.5, 2, 0});
  s.shapes.push_back(plane({0, 1, 0}, 0, add_material(s, shiny(kRho, 0.6, 50))));
  s.shapes.push_back(plane({1, 0, 0}, -1.5, add_material(s, mirror({0.9, 0.9, 0.9}))));
  s.point_lights.push_back(kLight);
  ir::Vec3 d = camera_dir(s);
  ir::Vec3 m = s.camera.location + d * ((-1.5 - s.camera.location.x) / d.x);
  ir::Vec3 r{-d.x, d.y, d.z};  // reflected off the plane x = -1.5
  ir::Vec3 x = on_floor(m, r);
  ir::Vec3 expect = lit_floor(x, -r, kRho, 0.6, 50, kLight) * 0.9;
  rt::RenderResult out = rt::render(s, {});
  check_pixel(out, expect);
  CHECK(out.stats.reflection_rays == 1);
  ir::Vec3 direct_view = lit_floor(x, ir::normalize(s.camera.location - x), kRho, 0.6, 50, kLight);
  CHECK(expect.x > 3 * direct_view.x);
}

TEST_CASE("glazed: the highlight is added whole, on top of the coat and its base",
          "[runtime][highlights]") {
  // §16 has no Fresnel factor in f, so the coat does not scale it: a glazed floor
  // with a highlight minus the same floor without it is f · I · cosθ / d² exactly,
  // and the coat's reflection ray (into a black background) is the same ray.
  ir::Scene s = one_pixel({-3, 4, 0.5}, {0, 0, 0});
  ir::Glazed g{ir::Vec3{0.2, 0.1, 0.05}, 1.5};
  g.specular = 0.5;
  g.shininess = 30;
  std::uint32_t m = add_material(s, g);
  s.shapes.push_back(plane({0, 1, 0}, 0, m));
  s.point_lights.push_back(kLight);
  rt::RenderResult with = rt::render(s, {});
  g.specular = 0;
  s.materials[m] = g;
  rt::RenderResult without = rt::render(s, {});
  ir::Vec3 d = camera_dir(s), x = on_floor(s.camera.location, d);
  ir::Vec3 f = lit_floor(x, -d, {0, 0, 0}, 0.5, 30, kLight);
  for (int c = 0; c < 3; ++c) {
    INFO("channel " << c);
    // Relative to the whole pixel: the difference of two float renders.
    double diff = double(with.image.at(0, 0)[c]) - without.image.at(0, 0)[c];
    CHECK(std::fabs(diff - f[c]) < kTol * with.image.at(0, 0)[c]);
    CHECK(diff > 0.5 * with.image.at(0, 0)[c]);  // the highlight is most of it
  }
  CHECK(with.stats.reflection_rays == without.stats.reflection_rays);
}

TEST_CASE("an area light's highlight converges to the integral", "[runtime][highlights][area]") {
  // A black floor (only the highlight reflects), S = 1, E = 20, under a 1 × 1
  // one-sided light at height 2 emitting down; the camera sees the origin from
  // (-1, 2.5, 0.3), whose mirror direction meets the light inside, at
  // (0.8, 2, -0.24): the lobe is whole on the light. The expected radiance is
  //   ∫ f(wo, wi(q)) · L · cosθ_surf · cosθ_light / d² dA
  // by the midpoint rule on a 1000² grid (h² error ~1e-7 relative). The render
  // has 16 × 16 jittered light cells and 64 samples, stratified within each cell:
  // 16 384 light samples over a smooth integrand, measured 1e-5 off. The
  // tolerance is 0.1 %, and shininess 20 -> 22 moves the integral by 5 %.
  const ir::Vec3 from{-1, 2.5, 0.3}, corner{0, 2, -0.5}, e1{1, 0, 0}, e2{0, 0, 1};
  const double L = 3;
  auto integral = [&](ir::Vec3 x, ir::Vec3 wo, double E) {
    const int n = 1000;
    double sum = 0;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        ir::Vec3 q = corner + e1 * ((i + 0.5) / n) + e2 * ((j + 0.5) / n);
        ir::Vec3 to = q - x;
        double d2 = ir::dot(to, to), d = std::sqrt(d2);
        double cos_s = to.y / d, cos_l = to.y / d;  // the light faces -y
        sum += blinn_phong({0, 1, 0}, wo, to / d, 1, E) * L * cos_s * cos_l / d2;
      }
    return sum / (double(n) * n);  // × area 1
  };
  ir::Scene s = base_scene(1, 1, 64);
  look(s, from, {0, 0, 0}, 1e-3);
  s.shapes.push_back(plane({0, 1, 0}, 0, add_material(s, shiny({0, 0, 0}, 1, 20))));
  s.area_lights.push_back(area_light(corner, e1, e2, {L, L, L}, 16));
  rt::RenderResult r = rt::render(s, {});
  ir::Vec3 d = camera_dir(s), x = on_floor(from, d);
  double expect = integral(x, -d, 20);
  INFO("integral " << expect << " pixel " << r.image.at(0, 0)[0]);
  CHECK(r.image.at(0, 0)[0] == Approx(expect).epsilon(1e-3));
  CHECK(r.image.at(0, 0)[1] == r.image.at(0, 0)[0]);
  CHECK(r.stats.nonfinite_samples == 0);
  CHECK(std::fabs(integral(x, -d, 22) - expect) > 0.02 * expect);
}
