// §16 bumps (runtime/shading/bump.hpp): a pattern of known slope tilts the normal
// as normalize(n − A·∇ₜP) predicts; the normal's own component of the gradient is
// removed; a huge amount keeps the normal above the geometric surface.
#include <catch2/catch.hpp>
#include <cmath>

#include "runtime/shading/bump.hpp"
#include "runtime/shading/shading_normal.hpp"
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

// A brick face on a multiple of the size shows bricks (test_patterns.cpp), and the
// bump's difference points 1e-3 either side of it must too: on a face tilted 10°
// (a rotated wall or roof), the world y step reaches 1.085e-3 below the face in
// the pattern's y, where mortar would jump the value by 1 and tilt the normal far
// more than any brick's edge does.
TEST_CASE("bump: a brick face on a multiple of the size is flat away from the joints", "[bump]") {
  ir::Bump b;
  b.pattern.pattern = ir::Brick{};
  b.pattern.world_from_pattern = ir::Transform::rotate_z(10);
  b.amount = 0.05;
  const ir::Transform& wp = b.pattern.world_from_pattern;
  // The pattern's plane y = 0 (a floor of bricks), mid-brick.
  ir::Vec3 w = wp.point({0.25, 0, 0.125});
  ir::Vec3 up = ir::normalize(wp.normal({0, 1, 0}));
  for (double side : {1.0, -1.0}) {
    INFO("outward normal " << side);
    rt::Vec3f n{float(up.x * side), float(up.y * side), float(up.z * side)};
    rt::TexturePoint tp{{float(w.x), float(w.y), float(w.z)}, n, {0, 0, 0}};
    rt::Vec3f got = rt::bump_normal(b, tp, n, n);
    CHECK_THAT(got.x, WithinAbs(n.x, 1e-6));
    CHECK_THAT(got.y, WithinAbs(n.y, 1e-6));
    CHECK_THAT(got.z, WithinAbs(n.z, 1e-6));
  }
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

TEST_CASE(
    "bump: a diffuse surface is lit about normalize(n - A grad P) where that faces the viewer",
    "[bump]") {
  // §16: the shading normal is normalize(n − A·∇ₜP), pulled back only where it
  // faces away from the viewer. A floor bumped by a ramp of slope 0.5 (A = 1) has
  // the shading normal of a plane tilted to (−0.5, 1, 0); seen and lit from a point
  // where the mirror direction about that normal dips below the floor (where hard
  // case #20 bends the normal for reflections), its Lambert radiance at the looked-at
  // point is the tilted plane's there. The bent normal gave 21 % more.
  const ir::Vec3 eye{0, 2, 0}, at{-1.975, 0, -1.037};
  auto render_floor = [&](bool bumped) {
    ir::Scene s = test::base_scene(3, 3, 1);
    test::look(s, eye, at, 0.01);
    s.point_lights.push_back({eye, {4, 4, 4}, {}});
    ir::Material m = test::diffuse(ir::Vec3(1));
    ir::Vec3 n{0, 1, 0};
    if (bumped) {
      ir::Texture t;
      t.pattern = ir::Gradient{{0.5, 0, 0}};
      m.bump = {t, 1.0};
    } else {
      n = ir::normalize(ir::Vec3{-0.5, 1, 0});
    }
    s.shapes.push_back(test::plane(n, ir::dot(n, at), test::add_material(s, m)));
    rt::RenderResult r = test::render_with(s);
    return double(r.image.rgb[3 * 4]);  // the centre pixel
  };
  const double bumped = render_floor(true), tilted = render_floor(false);
  INFO("bumped " << bumped << " tilted " << tilted);
  CHECK(bumped > 0.04);
  CHECK_THAT(bumped, Catch::Matchers::WithinRel(tilted, 1e-3));
}

TEST_CASE("bump: the lit normal is the bump's own unless it faces away", "[bump]") {
  // HitFrame: under a bump, nl is the raw shading normal where dot(wo, n) > 0 even
  // when ns is bent for the mirror direction; facing away, nl is ns (it faces the
  // viewer). A smooth mesh's frame lights about ns.
  const rt::Vec3f nf{0, 1, 0};
  const rt::Vec3f raw = rt::normalize(rt::Vec3f{-0.5f, 1, 0});
  const rt::Vec3f wo = rt::normalize(rt::Vec3f{1.975f, 2, 1.037f});  // mirror about raw dips below
  rt::HitFrame bump = rt::HitFrame::make(wo, nf, true, true, raw, true);
  CHECK(rt::dot(wo, raw) > 0);
  CHECK(rt::length(bump.ns - raw) > 1e-3f);  // bent for reflections
  CHECK(rt::length(bump.nl - raw) == 0.0f);
  rt::HitFrame smooth = rt::HitFrame::make(wo, nf, true, true, raw, false);
  CHECK(rt::length(smooth.nl - smooth.ns) == 0.0f);
  const rt::Vec3f away = rt::normalize(rt::Vec3f{-2, 1, 0});  // dot(wo, away) < 0
  rt::HitFrame back = rt::HitFrame::make(wo, nf, true, true, away, true);
  CHECK(rt::dot(wo, away) < 0);
  CHECK(rt::length(back.nl - back.ns) == 0.0f);
  CHECK(rt::dot(wo, back.nl) > 0);
}
