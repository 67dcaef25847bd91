// Motion blur (§6 shutter, §8 motion): analytic streaks for a moving sphere (user
// geometry at the ray time) and a moving box (Embree time steps), exact rotation at
// mid-shutter, child rays keeping their parent's time, and static scenes that do not
// care about the shutter.
#include <catch2/catch.hpp>
#include <random>

#include "runtime/embree_scene.hpp"
#include "runtime/geometry/motion.hpp"
#include "runtime/geometry/sphere.hpp"
#include "runtime/shading/surface_uv.hpp"
#include "tests/runtime/effects_util.hpp"

using namespace snell;
using namespace snell::test;
using K = ir::TransformOp::Kind;

namespace {

// One row of 61 pixels spanning x in [-2, 2] at depth 10, black object on white.
ir::Scene streak_scene(ir::Shape s) {
  ir::Scene sc = base_scene(61, 1, 256);
  sc.settings.sampler = ir::SamplerKind::Sobol;
  sc.background = ir::Vec3{1, 1, 1};
  s.material = add_material(sc, diffuse({0, 0, 0}));
  sc.shapes.push_back(s);
  look(sc, {0, 0, 0}, {0, 0, 1}, 2 * std::atan(0.2) * 180 / kPi);
  sc.camera.shutter_open = 0;
  sc.camera.shutter_close = 1;
  return sc;
}

// 1 - (fraction of the shutter during which the ray at slope sx is covered),
// averaged over the pixel footprint; `cover(sx)` gives the covered u-interval.
template <class F>
double expected_streak(std::uint32_t x, F cover) {
  double sum = 0;
  const int n = 64;
  for (int k = 0; k < n; ++k) {
    // World x slope of the ray: the image's right is cross(forward, up) = -x.
    double sx = -((x + (k + 0.5) / n) / 61.0 * 2 - 1) * 0.2;
    auto [a, b] = cover(sx);
    a = std::fmax(a, 0.0), b = std::fmin(b, 1.0);
    sum += 1 - std::fmax(0.0, b - a);
  }
  return sum / n;
}
}  // namespace

TEST_CASE("motion streak of a black sphere: pixel = 1 - covered shutter fraction",
          "[motion][scene]") {
  const double r = 0.6;
  ir::Scene s = streak_scene(moving(sphere({-3, 0, 10}, r, 0), K::Translate, {6, 0, 0}));
  rt::RenderResult res = render_with(s);
  CHECK(res.stats.time_samples == 61u * 256u);
  double worst = 0, mid = 0;
  for (std::uint32_t x = 0; x < 61; ++x) {
    double e = expected_streak(x, [&](double sx) {
      double h = r * std::sqrt(1 + sx * sx);  // distance from the centre to the ray <= r
      return std::pair{(3 + 10 * sx - h) / 6, (3 + 10 * sx + h) / 6};
    });
    worst = std::fmax(worst, std::fabs(res.image.at(x, 0)[0] - e));
    if (x == 30) mid = res.image.at(x, 0)[0];
  }
  INFO("worst pixel error " << worst);
  CHECK(worst < 0.01);
  CHECK(mid == Approx(0.8).margin(0.01));  // 1 - 2r/6
}

TEST_CASE("motion streak of a black box through Embree time steps", "[motion][scene]") {
  // A thin square 1 wide moving 6 along x: mid-streak pixels 1 - 1/6.
  ir::Scene s =
      streak_scene(moving(box({-3.5, -0.5, 10}, {-2.5, 0.5, 10.01}, 0), K::Translate, {6, 0, 0}));
  rt::RenderResult res = render_with(s);
  double worst = 0;
  for (std::uint32_t x = 0; x < 61; ++x) {
    double e = expected_streak(x, [&](double sx) {
      double x0 = std::fmin(10 * sx, 10.01 * sx), x1 = std::fmax(10 * sx, 10.01 * sx);
      return std::pair{(x0 + 2.5) / 6, (x1 + 3.5) / 6};
    });
    worst = std::fmax(worst, std::fabs(res.image.at(x, 0)[0] - e));
  }
  INFO("worst pixel error " << worst);
  CHECK(worst < 0.01);
  CHECK(res.image.at(30, 0)[0] == Approx(1 - 1.0 / 6).margin(0.01));
}

TEST_CASE("a box spinning whole turns is blurred over every angle", "[motion][scene]") {
  // A thin square [-1, 1]² facing the camera spins about the view axis: the ray
  // at radius r is covered for 1 - 4·acos(1/r)/π of the turns (1 for r ≤ 1, 0
  // past √2), whatever the number of whole turns. Steps chosen by sampling alone
  // saw a box spinning 720° where it started at the open, middle and close of the
  // shutter, and traced it standing still.
  for (double turns : {1.0, 2.0, 4.0}) {
    ir::Scene s =
        streak_scene(moving(box({-1, -1, 10}, {1, 1, 10.01}, 0), K::Rotate, {0, 0, 360 * turns}));
    rt::RenderResult res = render_with(s);
    double worst = 0;
    for (std::uint32_t x = 0; x < 61; ++x) {
      double e = expected_streak(x, [&](double sx) {
        double r = std::fabs(10 * sx), covered = 1;
        if (r > 1) covered = std::fmax(0.0, 1 - 4 * std::acos(std::fmin(1.0, 1 / r)) / kPi);
        return std::pair{0.0, covered};
      });
      worst = std::fmax(worst, std::fabs(res.image.at(x, 0)[0] - e));
    }
    // 256 samples of a pixel half covered: binomial σ ≈ 0.03 at worst (Sobol does
    // better); at 4 turns the 128 segments' chords also pull the corners 0.4 % in.
    INFO(turns << " turns: worst pixel error " << worst);
    CHECK(worst < 0.04);
  }
}

TEST_CASE("rotating objects are placed exactly at the ray time", "[motion]") {
  ir::Scene s = base_scene(4, 4);
  s.camera.shutter_close = 1;
  s.shapes.push_back(moving(box({-1, -1, -1}, {1, 1, 1}, 0), K::Rotate, {0, 0, 90}));
  s.shapes.push_back(moving(sphere({3, 0, 20}, 0.5, 0), K::Rotate, {0, 0, 90}));
  rt::EmbreeScene e(s, {0, 0, 0});
  CHECK(e.has_motion());
  rt::Hit h;
  auto ray = [](rt::Vec3f o, rt::Vec3f d, float time) { return rt::Ray{o, d, INFINITY, time}; };
  // Box, a diamond at 45 degrees: its corner reaches y = sqrt 2.
  CHECK_FALSE(e.intersect(ray({5, 1.2f, 0}, {-1, 0, 0}, 0), h));
  REQUIRE(e.intersect(ray({5, 1.2f, 0}, {-1, 0, 0}, 0.5f), h));
  CHECK(h.t == Approx(5 - (std::sqrt(2.0) - 1.2)).epsilon(2e-4));
  CHECK_FALSE(e.intersect(ray({5, 1.2f, 0}, {-1, 0, 0}, 1), h));
  REQUIRE(e.intersect(ray({5, 0.5f, 0}, {-1, 0, 0}, 1), h));
  CHECK(h.t == Approx(4).epsilon(1e-5));  // a quarter turn: the square again
  // Sphere orbiting the z axis: at mid-shutter its centre is at 45 degrees.
  float c = float(3 * std::sqrt(0.5));
  CHECK_FALSE(e.intersect(ray({c, c, 0}, {0, 0, 1}, 0), h));
  REQUIRE(e.intersect(ray({c, c, 0}, {0, 0, 1}, 0.5f), h));
  CHECK(h.t == Approx(19.5).epsilon(1e-6));
  CHECK(e.occluded(ray({c, c, 0}, {0, 0, 1}, 0.5f)));
  CHECK_FALSE(e.occluded(ray({c, c, 0}, {0, 0, 1}, 0.f)));
}

TEST_CASE("shadow rays keep the camera ray's time", "[motion][scene]") {
  // A sphere receding from a point light at the camera: the lit point is at distance
  // 9 + 2u at time u, so the pixel is rho/pi * I * mean 1/(9+2u)^2 = rho/pi * I / 99.
  // A shadow ray at any other time would start inside the sphere and be blocked.
  ir::Scene s = base_scene(1, 1, 256);
  s.shapes.push_back(moving(sphere({0, 0, 10}, 1, 0), K::Translate, {0, 0, 2}));
  s.point_lights.push_back({{0, 0, 0}, {99 * kPi, 99 * kPi, 99 * kPi}, {}});
  look(s, {0, 0, 0}, {0, 0, 1}, 0.01);
  s.camera.shutter_close = 1;
  for (bool general : {false, true}) {
    rt::RenderResult r = render_with(s, 1, general);
    CHECK(r.image.at(0, 0)[0] == Approx(0.8).epsilon(1e-3));
  }
}

TEST_CASE("a static scene renders the same whatever the shutter", "[motion][scene]") {
  ir::Scene s = base_scene(40, 30, 4);
  s.shapes.push_back(plane({0, 1, 0}, 0, 0));
  s.shapes.push_back(sphere({0, 1, 0}, 1, add_material(s, glossy({0.9, 0.9, 0.9}, 0.2))));
  s.point_lights.push_back({{2, 5, -3}, {40, 40, 40}, {}});
  look(s, {0, 1.5, -4}, {0, 0.8, 0}, 50);
  rt::Image ref = render_with(s).image;
  for (double close : {0.0, 0.5, 1.0})
    for (bool general : {false, true}) {
      ir::Scene t = s;
      t.camera.shutter_close = close;
      CHECK(render_with(t, 1, general).image.rgb == ref.rgb);
    }
  // Motion with the shutter closed: the object stands at its open placement.
  ir::Scene m = s;
  m.shapes[1] = moving(m.shapes[1], K::Translate, {3, 0, 0});
  CHECK(render_with(m).image.rgb == ref.rgb);
  CHECK(render_with(m, 1, true).image.rgb == ref.rgb);
}

TEST_CASE("a pivot turns the motion's rotation about its point (§19)", "[motion][scene]") {
  // A black ball of radius 0.3 at (1.5, 0, 10) turning half a circle about the z
  // axis through the pivot (0.5, 0, 10): its centre sweeps the upper half of the
  // circle of radius 1 about the pivot. The row of pixels at y = 0 sees it at both
  // ends of the sweep; without the pivot the circle would be about x = 0, radius 1.5.
  const double r = 0.3;
  ir::Shape ball = moving(sphere({1.5, 0, 10}, r, 0), K::Rotate, {0, 0, 180});
  ir::Motion m = ball.motion();
  m.has_pivot = true;
  m.pivot = {0.5, 0, 10};
  ball.set_motion(m);
  ir::Scene s = streak_scene(ball);
  rt::RenderResult res = render_with(s);
  double worst = 0, peak = 0;
  for (std::uint32_t x = 0; x < 61; ++x) {
    // The shutter fraction during which the ray of slope sx passes within r of the
    // centre, by 4000 steps of u (the sweep's speed is constant), averaged over 32
    // points across the pixel.
    double e = 0;
    const int n = 32, steps = 4000;
    for (int k = 0; k < n; ++k) {
      double sx = -((x + (k + 0.5) / n) / 61.0 * 2 - 1) * 0.2;
      ir::Vec3 d = ir::normalize(ir::Vec3{sx, 0, 1});
      int covered = 0;
      for (int i = 0; i < steps; ++i) {
        double th = (i + 0.5) / steps * kPi;
        ir::Vec3 c{0.5 + std::cos(th), std::sin(th), 10};
        double along = ir::dot(c, d);
        covered += ir::dot(c, c) - along * along < r * r;
      }
      e += 1 - double(covered) / steps;
    }
    e /= n;
    double got = res.image.at(x, 0)[0];
    worst = std::fmax(worst, std::fabs(got - e));
    peak = std::fmax(peak, 1 - got);
  }
  INFO("worst pixel error " << worst);
  CHECK(worst < 0.01);
  CHECK(peak > 0.05);  // the ends of the sweep are seen on the row
}

TEST_CASE("a motion's inverse alone has the bits of the whole transform's inverse", "[motion]") {
  // Motion::inverse_at and rel_from_object_inverse_at skip the forward matrices
  // (a moving sphere needs only object_from_rel at each ray's time); they must be
  // the inverse the full chain computes, to the bit, or moving spheres would
  // change with the shortcut.
  ir::Motion m;
  m.ops = {{K::Translate, {3, -1, 0.5}}, {K::Rotate, {10, 200, -35}}, {K::Scale, {2, 0.5, 1.5}}};
  for (bool pivot : {false, true}) {
    m.has_pivot = pivot;
    m.pivot = {0.25, -4, 7};
    ir::Shape ball = sphere({1.5, 0, 10}, 0.3, 0);
    ball.set_world_from_object(ir::Transform::rotate_y(33) * ir::Transform::scale({1, 2, 3}));
    ball.set_motion(m);
    for (double u : {0.0, 0.125, 0.3, 0.77, 1.0}) {
      CHECK(m.inverse_at(u).inv == m.at(u).inv);
      ir::Vec3 origin{0.5, 1.25, -2};
      CHECK(rt::geom::rel_from_object_inverse_at(ball, origin, u) ==
            rt::geom::rel_at(ball, origin, u).inv);
    }
  }
}

TEST_CASE("a moving sphere's pre-test never turns away a ray that hits it", "[motion]") {
  // MovingSphereSet::hit first tests the ray against the box of the shutter part
  // its time falls in, and computes the placement only when that passes. Rays
  // aimed at the sphere as it stands at their time, grazing ones among them, from
  // near and far, under translation, rotation about a pivot and scale: every ray
  // the exact test hits must pass the pre-test, and the pre-test must turn away
  // rays that only cross the sweep (or it saves nothing).
  std::mt19937_64 rng(19);
  std::uniform_real_distribution<double> u01(0, 1), sym(-1, 1);
  std::size_t hits = 0, culled = 0;
  for (int motion = 0; motion < 3; ++motion) {
    ir::Motion m;
    if (motion == 0) m.ops = {{K::Translate, {1.2, 0, 0}}};
    if (motion == 1) m.ops = {{K::Rotate, {0, 120, 30}}}, m.has_pivot = true, m.pivot = {2, 0, 0};
    if (motion == 2) m.ops = {{K::Scale, {3, 0.5, 1}}, {K::Translate, {0, 0.4, 2}}};
    ir::Shape ball = sphere({0.5, 0.6, 4}, 0.6, 0);
    ball.set_motion(m);
    ir::Vec3 origin{0.25, 1, -3};
    rt::geom::MovingSphereSet set;
    set.add(ball, *ball.as<ir::Sphere>(), 0, origin);
    for (int i = 0; i < 20000; ++i) {
      float time = float(u01(rng));
      // One ray in four is aimed where the sphere stands at the other end of the
      // shutter: it crosses the sweep, mostly missing the sphere at its own time.
      double aim =
          i % 4 == 1 ? 1 - rt::geom::shutter_fraction(time) : rt::geom::shutter_fraction(time);
      ir::Transform rel = rt::geom::rel_at(ball, origin, aim);
      // A point on (or just off) the sphere at that time, seen from a random origin.
      ir::Vec3 dir_obj = ir::normalize({sym(rng), sym(rng), sym(rng)});
      double r = 0.6 * (i % 3 == 0 ? 1 + 1e-7 * sym(rng) : 1 + 0.2 * sym(rng));
      ir::Vec3 target = rel.point(ir::Vec3{0.5, 0.6, 4} + dir_obj * r);
      ir::Vec3 from = ir::Vec3{sym(rng), sym(rng), sym(rng)} * (i % 2 ? 3.0 : 30.0);
      rt::Vec3f o = rt::to_float(from.x, from.y, from.z);
      ir::Vec3 dd = target - from;
      rt::Vec3f d = rt::to_float(dd.x, dd.y, dd.z);
      float t;
      rt::Vec3f n;
      bool exact = set.hit_exact(0, time, o, d, 0, INFINITY, t, n);
      bool pass = set.may_hit(0, time, o, d, 0, INFINITY);
      INFO("motion " << motion << " ray " << i << " time " << time);
      if (exact) REQUIRE(pass);
      hits += exact;
      culled += !pass;
    }
  }
  CHECK(hits > 20000);
  CHECK(culled > 3000);
}

TEST_CASE("a nested motion is its blocks, each carried by its frame (§12, §13)", "[motion]") {
  // A child turning about a pivot of its parent's space, inside a parent placed by
  // P that moves by PM: at(u) = PM(u) · P · CM(u) · P⁻¹, so the child's world
  // placement is PM(u) · P · CM(u) · C when world_from_object is P · C.
  ir::Motion parent;
  parent.ops = {{K::Rotate, {0, 50, 0}}, {K::Translate, {1, 0.5, -2}}};
  parent.has_pivot = true, parent.pivot = {0.5, 0, 1};
  ir::Motion child;
  child.ops = {{K::Rotate, {20, 0, 90}}, {K::Scale, {1.5, 1, 0.5}}};
  child.has_pivot = true, child.pivot = {1, 2, 0};
  ir::Transform P = ir::Transform::translate({3, 1, 0}) * ir::Transform::rotate_xyz({0, 0, 30}) *
                    ir::Transform::scale({2, 2, 2});
  ir::Transform C = ir::Transform::rotate_xyz({10, 0, 0}) * ir::Transform::translate({0, 1, 0});
  ir::Motion m = ir::nest_motion(ir::nest_motion({}, {}, parent), P, child);
  REQUIRE(m.nested.size() == 1);
  CHECK(m.moves());
  ir::Vec3 p{0.3, -0.7, 1.1};
  for (double u : {0.0, 0.2, 0.5, 0.9, 1.0}) {
    ir::Vec3 want = parent.at(u).point(P.point(child.at(u).point(C.point(p))));
    ir::Vec3 got = m.at(u).point((P * C).point(p));
    INFO("u " << u);
    CHECK(ir::length(got - want) < 1e-12);
    // The inverse alone has the bits of the whole chain's (moving spheres use it).
    CHECK(m.inverse_at(u).inv == m.at(u).inv);
  }
  // The other order (the child's motion after the parent's) puts it elsewhere.
  ir::Vec3 at_rest = (P * C).point(p);
  ir::Vec3 wrong = P.point(child.at(0.5).point(P.inverse().point(parent.at(0.5).point(at_rest))));
  CHECK(ir::length(m.at(0.5).point(at_rest) - wrong) > 0.1);
}

TEST_CASE("a world motion block nested in nothing is the block itself, to the bit", "[motion]") {
  // A top-level object's motion, and a union's inherited by its children, are
  // computed as before nesting existed: the same operations, the same bits.
  ir::Motion own;
  own.ops = {{K::Translate, {3, -1, 0.5}}, {K::Rotate, {10, 200, -35}}, {K::Scale, {2, 0.5, 1.5}}};
  own.has_pivot = true, own.pivot = {0.25, -4, 7};
  ir::Motion m = ir::nest_motion({}, {}, own);
  CHECK(m.nested.empty());
  CHECK(m.ops.size() == 3);
  // In a static parent with transforms, the block acts in the parent's space.
  ir::Transform P = ir::Transform::rotate_xyz({0, 90, 0});
  ir::Motion in_parent = ir::nest_motion({}, P, own);
  REQUIRE(in_parent.nested.size() == 1);
  CHECK(in_parent.ops.empty());
  for (double u : {0.0, 0.3, 1.0}) {
    CHECK(m.at(u).m == own.at(u).m);
    ir::Transform want = P * own.at(u) * P.inverse();
    for (int k = 0; k < 16; ++k) CHECK(in_parent.at(u).m.m[k] == Approx(want.m.m[k]).margin(1e-12));
  }
}

TEST_CASE("a CSG leaf may move, an instanced prototype's part may not", "[motion]") {
  ir::Scene s = base_scene(1, 1);
  ir::Shape leaf = moving(sphere({0, 0, 4}, 1, 0), K::Translate, {1, 0, 0});
  s.parts.push_back(box({-1, -1, 4}, {1, 1, 6}, 0));
  s.parts.push_back(leaf);
  s.csg_nodes.push_back({ir::CsgOp::Union, 0, {}});
  s.csg_nodes.push_back({ir::CsgOp::Union, 1, {}});
  s.csg_nodes.push_back({ir::CsgOp::Difference, ir::kNoPart, {0, 1}});
  ir::Shape csg;
  csg.geom = ir::Csg{2};
  s.shapes.push_back(csg);
  CHECK(ir::validate(s).empty());
  CHECK(ir::moves(s.shapes[0], s));
  s.camera.shutter_close = 1;
  rt::EmbreeScene e(s, {0, 0, 0});
  CHECK(e.has_motion());
  // Along z at x = -0.5: at u = 0 the sphere centred on the box's front face cuts
  // it there; at u = 1 it has moved 1.5 away from the ray.
  rt::Hit h;
  REQUIRE(e.intersect(rt::Ray{{-0.5f, 0, 0}, {0, 0, 1}, INFINITY, 0}, h));
  CHECK(h.t == Approx(4 + std::sqrt(0.75)).epsilon(1e-6));  // the hole's far wall
  REQUIRE(e.intersect(rt::Ray{{-0.5f, 0, 0}, {0, 0, 1}, INFINITY, 1}, h));
  CHECK(h.t == Approx(4).epsilon(1e-6));  // the box's face, whole again
  // Mapping "uv" finds the leaf's own space at the ray's time: the sphere's centre
  // in the world at u is its object-space centre.
  for (double u : {0.0, 0.5, 1.0}) {
    rt::SurfaceFrame f = rt::surface_frame(s, s.shapes[0], 1, ir::kNoPart, 0, u);
    CHECK(f.leaf == &s.parts[1]);
    ir::Vec3 c = f.leaf_from_world.point({u, 0, 4});
    CHECK(ir::length(c - ir::Vec3{0, 0, 4}) < 1e-12);
  }
  // A prototype is static geometry the BVH instances.
  ir::Prototype proto;
  proto.parts = {1};
  s.prototypes.push_back(proto);
  CHECK_FALSE(ir::validate(s).empty());
}

TEST_CASE("a placement's quaternion form is the placement, and slerps along its arc", "[motion]") {
  namespace geom = rt::geom;
  using geom::quat_placement;
  // Rotations, a skewing non-uniform scale, a mirror and a shift: the product is
  // the matrix again to rounding (entries of order 10).
  ir::Transform t = ir::Transform::translate({3, -1, 2}) *
                    ir::Transform::rotate_xyz({20, 130, -75}) * ir::Transform::scale({2, 0.5, -3}) *
                    ir::Transform::rotate_xyz({0, 0, 33}) * ir::Transform::scale({1, 4, 1});
  const ir::Vec3 centre{0.5, -2, 1};
  std::optional<geom::QuatPlacement> p = quat_placement(t.m, centre);
  REQUIRE(p);
  ir::Mat4 back = geom::quat_matrix(*p);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) CHECK(back(r, c) == Approx(t.m(r, c)).margin(1e-12));
  CHECK(geom::xform_point(back, centre).x == Approx(p->translation.x).margin(1e-12));
  // A turn about a fixed axis through the centre's place: every fraction between
  // two steps 80° apart is the exact turn at that fraction.
  const ir::Vec3 w = t.point(centre);
  auto spin = [&](double deg) {
    return ir::Transform::translate(w) * ir::Transform::rotate_y(deg) *
           ir::Transform::translate(-w);
  };
  std::optional<geom::QuatPlacement> pa = quat_placement((spin(0) * t).m, centre),
                                     pb = quat_placement((spin(80) * t).m, centre);
  REQUIRE(pa);
  REQUIRE(pb);
  for (double f : {0.25, 0.5, 0.9}) {
    ir::Mat4 exact = (spin(80 * f) * t).m;
    ir::Mat4 between = geom::quat_matrix(geom::quat_between(*pa, *pb, f));
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) CHECK(between(r, c) == Approx(exact(r, c)).margin(1e-12));
  }
  // A singular placement has no quaternion form.
  CHECK_FALSE(quat_placement(ir::Transform::scale({1, 0, 1}).m, centre));
}
