// §16 bumps (runtime/shading/bump.hpp): a pattern of known slope tilts the normal
// as normalize(n − A·∇ₜP) predicts; the normal's own component of the gradient is
// removed; a huge amount keeps the normal above the geometric surface.
#include <catch2/catch.hpp>
#include <cmath>

#include "runtime/shading/bump.hpp"
#include "tests/runtime/effects_util.hpp"

using namespace snell;
using Catch::Matchers::WithinAbs;

TEST_CASE("bump: a gradient of slope k tilts the normal by A·k", "[bump]") {
  // P = frac(dot(p, <k, 0, 0>)): slope k along x on a floor with normal +y (away
  // from the ramp's wrap, which is at integer k·x).
  const double k = 0.8, a = 0.5;
  ir::Bump b;
  ir::Texture t;
  t.pattern = ir::Gradient{{k, 0, 0}};
  b.pattern = t;
  b.amount = a;
  rt::TexturePoint tp{{0.3f, 0, 0.2f}, {0, 1, 0}, {0, 0, 0}};
  rt::Vec3f n = rt::bump_normal(b, tp, {0, 1, 0}, {0, 1, 0});
  // normalize(<0, 1, 0> − A·<k, 0, 0>); the central difference of a linear ramp is
  // exact up to rounding of the 1e-3 step (1e-13 relative), float output: 1e-6.
  double len = std::sqrt(1 + a * a * k * k);
  CHECK_THAT(n.x, WithinAbs(-a * k / len, 1e-6));
  CHECK_THAT(n.y, WithinAbs(1 / len, 1e-6));
  CHECK_THAT(n.z, WithinAbs(0, 1e-6));

  // The component along n is removed: a ramp along the normal itself changes nothing.
  t.pattern = ir::Gradient{{0, k, 0}};
  b.pattern = t;
  rt::TexturePoint up{{0.3f, 0.4f, 0.2f}, {0, 1, 0}, {0, 0, 0}};
  n = rt::bump_normal(b, up, {0, 1, 0}, {0, 1, 0});
  CHECK_THAT(n.y, WithinAbs(1, 1e-6));

  // Transformed patterns: scale 2 halves the slope in world units.
  t.pattern = ir::Gradient{{k, 0, 0}};
  t.world_from_pattern = ir::Transform::scale(ir::Vec3(2));
  b.pattern = t;
  n = rt::bump_normal(b, tp, {0, 1, 0}, {0, 1, 0});
  double len2 = std::sqrt(1 + a * a * k * k / 4);
  CHECK_THAT(n.x, WithinAbs(-a * k / 2 / len2, 1e-6));
}

TEST_CASE("bump: a huge amount stays above the geometric surface", "[bump]") {
  ir::Bump b;
  ir::Texture t;
  t.pattern = ir::Gradient{{1, 0, 0}};
  b.pattern = t;
  b.amount = 1e6;
  rt::TexturePoint tp{{0.3f, 0, 0.2f}, {0, 1, 0}, {0, 0, 0}};
  rt::Vec3f n = rt::bump_normal(b, tp, {0, 1, 0}, {0, 1, 0});
  CHECK(n.y >= 0.0099f);
  CHECK_THAT(rt::length(n), WithinAbs(1, 1e-6));
}

TEST_CASE("bump: noise bumps tilt, and are continuous", "[bump]") {
  ir::Bump b;
  ir::Texture t;
  t.pattern = ir::Noise{};
  t.world_from_pattern = ir::Transform::scale(ir::Vec3(0.1));
  b.pattern = t;
  b.amount = 0.02;
  double max_tilt = 0;
  rt::Vec3f prev{0, 1, 0};
  for (int i = 0; i < 1000; ++i) {
    rt::TexturePoint tp{{float(i * 1e-3), 0, 0.37f}, {0, 1, 0}, {0, 0, 0}};
    rt::Vec3f n = rt::bump_normal(b, tp, {0, 1, 0}, {0, 1, 0});
    max_tilt = std::fmax(max_tilt, std::acos(std::fmin(1.0f, n.y)));
    // Noise's gradient is smooth: a 1e-3 step moves the normal by far less than
    // the tilt itself (second derivative ~100 per unit² at scale 0.1 × A 0.02).
    if (i > 0) CHECK(rt::length(n - prev) < 0.01f);
    prev = n;
  }
  // |∇noise| ~ 1 per pattern unit, 10 per world unit: tilts of ~0.1 rad.
  CHECK(max_tilt > 0.05);
}

TEST_CASE("bump: a strongly bumped mirror sphere has no dark rims (hard case #20)",
          "[bump][hardcase]") {
  // A convex mirror of colour 0.5 under a uniform white sky: a reflection that
  // leaves above the real surface escapes at once (0.5); one that starts into the
  // surface (a shading normal facing away, uncorrected) meets the sphere again
  // (0.25 or less) or dies at max_depth (0). Tilts up to ~60° here.
  ir::Scene s = test::base_scene(96, 96, 1);
  test::look(s, {0, 0, -4}, {0, 0, 0}, 40);
  s.background = ir::Vec3(1);
  ir::Material m = test::mirror(ir::Vec3(0.5));
  ir::Texture t;
  t.pattern = ir::Noise{};
  t.world_from_pattern = ir::Transform::scale(ir::Vec3(0.05));
  m.bump = {t, 0.1};
  s.shapes.push_back(test::sphere({0, 0, 0}, 1, test::add_material(s, m)));
  rt::RenderResult r = test::render_with(s);
  int sphere = 0, dark = 0;
  for (std::size_t i = 0; i < r.image.rgb.size(); i += 3) {
    float v = r.image.rgb[i];
    if (v == 1.0f) continue;  // the sky
    ++sphere;
    if (!(std::fabs(v - 0.5f) < 1e-6f)) ++dark;
  }
  CHECK(sphere > 2000);  // the sphere covers a good part of the image
  CHECK(dark == 0);
}
