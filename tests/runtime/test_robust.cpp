// Self-intersection (robustness.md §1 #1): rays spawned from a hit with the
// Wächter–Binder offset never re-hit their own surface, at any scale.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "effects_util.hpp"
#include "runtime/embree_scene.hpp"
#include "runtime/render.hpp"
#include "scene_util.hpp"

using namespace snell;
using namespace snell::test;

TEST_CASE("offset rays never re-hit their triangle or sphere", "[robust][property]") {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0, 1);
  auto unit = [&] {
    double z = 2 * u(rng) - 1, a = 2 * 3.14159265358979 * u(rng), r = std::sqrt(1 - z * z);
    return ir::Vec3(r * std::cos(a), r * std::sin(a), z);
  };
  long self_hits = 0, spawned = 0;
  for (int trial = 0; trial < 300; ++trial) {
    double scale = std::pow(10.0, -2 + 7 * u(rng));  // 1e-2 .. 1e5
    ir::Vec3 where = unit() * (scale * 10 * u(rng));
    ir::Scene s = base_scene(1, 1);
    bool is_sphere = trial % 2;
    if (is_sphere) {
      s.shapes.push_back(sphere(where, scale * (0.1 + u(rng)), 0));
    } else {
      ir::Vec3 a = where + unit() * scale, b = where + unit() * scale, c = where + unit() * scale;
      s.shapes.push_back(triangle(a, b, c, 0));
    }
    rt::EmbreeScene es(s, {0, 0, 0});
    // Aim at a point of the surface from outside.
    const ir::Triangle* t = s.shapes[0].as<ir::Triangle>();
    ir::Vec3 target = is_sphere ? where + unit() * s.shapes[0].as<ir::Sphere>()->radius
                                : t->a + (t->b - t->a) * 0.3 + (t->c - t->a) * 0.3;
    ir::Vec3 from = target + unit() * (3 * scale);
    rt::Ray ray;
    ray.org = rt::to_float(from.x, from.y, from.z);
    ir::Vec3 dd = target - from;
    ray.dir = rt::normalize(rt::to_float(dd.x, dd.y, dd.z));
    rt::Hit hit;
    if (!es.intersect(ray, hit)) continue;
    for (int k = 0; k < 50; ++k) {
      ir::Vec3 w = unit();
      rt::Vec3f dir = rt::to_float(w.x, w.y, w.z);
      rt::Vec3f n = rt::dot(dir, hit.ng) > 0 ? hit.ng : -hit.ng;  // the side it leaves on
      rt::Ray out{rt::spawn_origin(hit, n, 1), dir, INFINITY, 0};
      rt::Hit h2;
      ++spawned;
      if (es.intersect(out, h2)) {
        // A ray into a sphere legitimately leaves it again (an exiting hit: its normal
        // along the ray), however near for a grazing ray that starts just inside;
        // a self-hit is a re-entry of the surface it left.
        if (!(is_sphere && rt::dot(dir, hit.ng) < 0 && rt::dot(dir, h2.ng) > 0)) ++self_hits;
      }
    }
  }
  CHECK(spawned > 5000);
  CHECK(self_hits == 0);
}

TEST_CASE("box normals point outward under mirroring transforms", "[robust]") {
  for (double sx : {1.0, -1.0}) {
    ir::Scene s = base_scene(1, 1);
    ir::Shape b = box({-1, -1, -1}, {1, 1, 1}, 0);
    b.set_world_from_object(ir::Transform::scale({sx, 2, 1}));
    s.shapes.push_back(b);
    rt::EmbreeScene es(s, {0, 0, 0});
    const rt::Vec3f dirs[] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (rt::Vec3f d : dirs) {
      rt::Ray r{d * -10.0f + rt::Vec3f(0.1f, 0.2f, 0.3f) * 0.1f, d, INFINITY, 0};
      rt::Hit h;
      REQUIRE(es.intersect(r, h));
      CHECK(rt::dot(h.ng, d) == Approx(-1));  // entering: against the outward normal
    }
  }
}

TEST_CASE("a grazing plane hit beyond 1e17 counts as a miss, so no ray leaves from there",
          "[robust]") {
  // Embree rejects rays that start beyond 1.8e18 (an assertion in Debian's build);
  // planes are intersected outside it and may be hit arbitrarily far at grazing
  // angles. A hit whose point lies past 1e17 of the camera is a miss.
  ir::Scene s = base_scene(1, 1);
  s.shapes.push_back(plane({0, 1, 0}, -1, 0));
  s.shapes.push_back(sphere({0, 0, 5}, 1, 0));  // something in Embree's BVH too
  rt::EmbreeScene es(s, {0, 0, 0});
  rt::Hit h;
  CHECK(es.intersect(rt::Ray{{0, 0, 0}, rt::normalize(rt::Vec3f{1, -1e-10f, 0}), INFINITY, 0}, h));
  CHECK(h.t == Approx(1e10).epsilon(1e-6));
  CHECK_FALSE(es.intersect(rt::Ray{{0, 0, 0}, {1, -1e-18f, 0}, INFINITY, 0}, h));
}

TEST_CASE("a face lying on a plane loses to the plane every time: no speckle", "[robust]") {
  // A glass block resting on the floor: its bottom face and the plane coincide, the
  // face in float and the plane in double, so the nearer hit used to flip with
  // rounding from ray to ray (a speckled band at the block's foot, examples/glass).
  // Rays from inside the block towards its bottom must all report the floor.
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0, 1);
  ir::Scene s = base_scene(1, 1);
  s.shapes.push_back(box({-0.6, 0, -0.3}, {0.6, 1.6, 0.3}, 0));
  s.shapes.back().set_world_from_object(ir::Transform::translate({0.3, 0, 0.8}) *
                                        ir::Transform::rotate_xyz({0, 30, 0}));
  s.shapes.push_back(plane({0, 1, 0}, 0, 0));
  ir::Vec3 cam(0.37, 1.73, -4.1);
  rt::EmbreeScene es(s, cam);
  long rays = 0, floor_hits = 0;
  for (int i = 0; i < 20000; ++i) {
    // A point inside the block (object space), placed, camera-relative.
    ir::Vec3 q(-0.55 + 1.1 * u(rng), 0.01 + 1.5 * u(rng), -0.25 + 0.5 * u(rng));
    ir::Vec3 w = s.shapes[0].world_from_object().point(q) - cam;
    ir::Vec3 dir(2 * u(rng) - 1, -1, 2 * u(rng) - 1);
    rt::Ray r{rt::to_float(w.x, w.y, w.z), rt::normalize(rt::to_float(dir.x, dir.y, dir.z)),
              INFINITY, 0};
    rt::Hit h;
    if (!es.intersect(r, h) || h.ng.y > -0.5f && h.ng.y < 0.5f) continue;  // side faces
    ++rays;
    if (h.index == 1) ++floor_hits;
  }
  INFO(floor_hits << " of " << rays << " rays towards the bottom report the floor");
  CHECK(rays > 5000);
  CHECK(floor_hits == rays);
}

TEST_CASE("a torus far larger than its tube does not shadow or reflect onto itself", "[robust]") {
  // Major radius 1e11, minor 1, seen from beside the tube: locally a cylinder, so a
  // mirror of it shows only the white background. The projected hit is good to
  // ulps of its object-space coordinates (1e11), which the offset measured from
  // the camera (a few units) did not cover: reflections re-hit the torus (a
  // minimum of 0, 3 % of the picture dark).
  ir::Scene s = base_scene(40, 30, 1);
  s.background = ir::Vec3{1, 1, 1};
  look(s, {1e11, 1.5, -5}, {1e11, 0, 0}, 60);
  s.shapes.push_back(shape_of(ir::Torus{1e11, 1}, add_material(s, mirror({1, 1, 1}))));
  rt::RenderResult r = rt::render(s, {});
  float lowest = 1;
  for (float v : r.image.rgb) lowest = std::min(lowest, v);
  CHECK(lowest == Approx(1).margin(1e-5));
}

TEST_CASE("a small area light just beside the camera lights the floor", "[robust]") {
  // A light 0.02 across, 0.003 above the camera, over a floor 1 below: the light's
  // coordinates in Embree's camera-relative space are tiny, so its shadow rays'
  // ends (moved off the light by ulps of those coordinates) were closer to it than
  // t's rounding over a ray of length 1 can tell, and every ray was shadowed by
  // the light itself: a black image. Expected: ρ/π · L·A·cos/r² at the centre.
  for (int n : {1, 2}) {
    INFO("grid " << n << "x" << n);
    ir::Scene s = base_scene(9, 9, 4);
    look(s, {0, 1, 0}, {0, 0, 0}, 10);
    s.camera.up = {0, 0, 1};
    s.shapes.push_back(plane({0, 1, 0}, 0, add_material(s, diffuse({0.5, 0.5, 0.5}))));
    s.area_lights.push_back(
        area_light({-0.01, 1.003, -0.01}, {0.02, 0, 0}, {0, 0, 0.02}, {2500, 2500, 2500}, n));
    for (bool packets : {true, false}) {
      rt::RenderOptions o;
      o.threads = 1;
      if (!packets) o.general_kernel = true;
      rt::RenderResult r = rt::render(s, o);
      const float centre = r.image.at(4, 4)[0];
      CHECK(centre == Approx(0.5 / M_PI * 2500 * 0.0004 / (1.003 * 1.003)).epsilon(0.01));
    }
  }
}

TEST_CASE("a tiny subject near the camera renders the same beside a far object", "[robust]") {
  // A scene 1e-6 across at the camera, lit by a small area light or a point light,
  // with a moving sphere; and the same with a sphere 1000 away behind the camera,
  // which makes the scene's size around the camera 1 and so the near-origin step of
  // the ray offsets 2^-16, fifteen times the subject. The area-lit image was black
  // and the moving sphere unlit; both must match the scene without the far sphere.
  const double k = 1e-6;
  auto scene = [&](bool far, bool area, bool moves) {
    ir::Scene s = base_scene(32, 24, 1);
    look(s, {0, 0, 0}, {0, -k, 4 * k}, 50);
    s.shapes.push_back(plane({0, 1, 0}, -k, 0));
    ir::Shape ball = sphere({0, -0.5 * k, 4 * k}, 0.5 * k, 0);
    if (moves) {
      s.camera.shutter_close = 1;
      ball = moving(ball, ir::TransformOp::Kind::Translate, {0.3 * k, 0, 0});
    }
    s.shapes.push_back(ball);
    if (area)
      s.area_lights.push_back(
          area_light({-0.5 * k, 2 * k, 3.5 * k}, {k, 0, 0}, {0, 0, k}, {8, 8, 8}, 2));
    else
      s.point_lights.push_back({{0, 3 * k, 4 * k}, {1e-11, 1e-11, 1e-11}, {}});
    if (far) s.shapes.push_back(sphere({0, 0, -1000}, 1, 0));
    return s;
  };
  for (bool area : {true, false})
    for (bool moves : {false, true}) {
      INFO((area ? "area light" : "point light") << (moves ? ", moving sphere" : ""));
      rt::RenderResult alone = render_with(scene(false, area, moves));
      rt::RenderResult beside = render_with(scene(true, area, moves));
      double sum_alone = 0, sum_beside = 0, worst = 0;
      for (std::size_t i = 0; i < alone.image.rgb.size(); ++i) {
        sum_alone += alone.image.rgb[i];
        sum_beside += beside.image.rgb[i];
        worst = std::max(worst, double(std::fabs(alone.image.rgb[i] - beside.image.rgb[i])));
      }
      CHECK(sum_alone > 0);
      CHECK(sum_beside == Approx(sum_alone).epsilon(0.01));
      CHECK(worst < 0.05);
    }
}
