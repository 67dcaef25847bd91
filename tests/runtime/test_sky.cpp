// §17 backgrounds that are patterns: evaluated at the escaping ray's unit direction
// (the direction is the pattern point, in world space, not moved inward).
#include <catch2/catch.hpp>
#include <cmath>

#include "runtime/render.hpp"
#include "scene_util.hpp"

using namespace snell;
using namespace snell::test;

namespace {

// One pixel seen through a very narrow camera looking along `dir`: every camera
// ray is within ~1e-5 rad of dir, so a smooth pattern's value is known to ~1e-5.
float sky_seen(const ir::Texture& bg, ir::Vec3 dir) {
  ir::Scene s = base_scene(1, 1, 4);
  s.background = bg;
  ir::Vec3 up = std::fabs(dir.y) > 0.9 ? ir::Vec3{1, 0, 0} : ir::Vec3{0, 1, 0};
  look(s, {0, 0, 0}, dir, 1e-3, up);
  rt::RenderResult r = rt::render(s, {});
  return r.image.at(0, 0)[0];
}

}  // namespace

TEST_CASE("a gradient background is its value at the escaping ray's direction", "[sky]") {
  ir::Texture g;
  g.pattern = ir::Gradient{{0, 0.5, 0}};  // frac(0.5 y) of the unit direction
  // The default colour map is black at 0 to white at 1: the colour is the value.
  CHECK(sky_seen(g, {0, 1, 0}) == Approx(0.5).margin(1e-4));
  // (Not y = 0: the ramp jumps from 1 to 0 there, and the pixel's samples straddle it.)
  CHECK(sky_seen(g, {0, 0.28, 0.96}) == Approx(0.14).margin(1e-4));
  CHECK(sky_seen(g, {0, 0.6, 0.8}) == Approx(0.3).margin(1e-4));
  CHECK(sky_seen(g, {0, -0.6, 0.8}) == Approx(0.7).margin(1e-4));  // frac(-0.3)
  // The pattern's transforms move it: scaled by 1.5 along y, the value at y = 1
  // is frac(0.5 / 1.5).
  g.world_from_pattern = ir::Transform::scale({1, 1.5, 1});
  CHECK(sky_seen(g, {0, 1, 0}) == Approx(1.0 / 3).margin(1e-4));
}

TEST_CASE("a constant background is the colour it always was", "[sky]") {
  CHECK(sky_seen(ir::Texture(ir::Vec3{0.25, 0.5, 0.75}), {0, 0, 1}) == 0.25f);
}
