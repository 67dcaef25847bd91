// Hard cases on ray queries (robustness.md §1): self-intersection over coordinates
// 1e-8..1e8 (#1), shadow rays to area-light samples (#2), spheres seen from far away
// (#5), watertightness of a closed mesh (#6) and origins exactly on a triangle (#7).
// These call rt::EmbreeScene directly, spawning rays exactly as the integrator does
// (offset_ray_origin along the normal of the side the ray leaves on).
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "hc_util.hpp"
#include "runtime/embree_scene.hpp"
#include "runtime/integrators/whitted.hpp"

using namespace snell;
using namespace snell::hc;

TEST_CASE("hc01 reintersection: spawned rays never re-hit their triangle, 1e-8..1e8",
          "[hardcase][robust][property]") {
  // pbrt's Triangle.Reintersect recipe: 1000 random triangles whose vertices have
  // coordinates of magnitude log-uniform in [1e-8, 1e8] (one magnitude per
  // triangle), a hit from a random outside point, then 500 random directions on the
  // reflect side and 500 on the transmit side (1e6 rays). The world is not rebased
  // (origin 0), as for a scene whose camera is far from the triangle: the hardest
  // position for float. tests/runtime/test_robust.cpp covers spheres at 1e-2..1e5.
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(0, 1);
  long spawned = 0, self_hits = 0, triangles = 0;
  for (int trial = 0; trial < 1000; ++trial) {
    double mag = std::pow(10.0, -8 + 16 * u(rng));
    auto coord = [&] { return (2 * u(rng) - 1) * mag; };
    ir::Scene s = base_scene(1, 1);
    ir::Triangle t;
    t.a = {coord(), coord(), coord()};
    t.b = {coord(), coord(), coord()};
    t.c = {coord(), coord(), coord()};
    s.shapes.push_back(shape_of(t, 0));
    ir::Vec3 n = ir::cross(t.b - t.a, t.c - t.a);
    if (!(ir::length(n) > 0)) continue;
    rt::EmbreeScene es(s, {0, 0, 0});
    double b1 = u(rng), b2 = u(rng);
    if (b1 + b2 > 1) b1 = 1 - b1, b2 = 1 - b2;
    ir::Vec3 target = t.a + (t.b - t.a) * b1 + (t.c - t.a) * b2;
    ir::Vec3 from = target + unit(rng) * mag;
    rt::Ray ray{f(from), rt::normalize(f(target - from)), INFINITY, 0};
    rt::Hit hit;
    if (!es.intersect(ray, hit)) continue;  // the float ray may just miss a sliver
    ++triangles;
    rt::Vec3f toward = rt::dot(ray.dir, hit.ng) < 0 ? hit.ng : -hit.ng;  // reflect side
    for (int k = 0; k < 1000; ++k) {
      rt::Vec3f side = k % 2 ? toward : -toward;  // reflect, then transmit
      rt::Vec3f dir = f(unit(rng));
      if (rt::dot(dir, side) < 0) dir = -dir;
      rt::Ray out{rt::spawn_origin(hit, side, 1), dir, INFINITY, 0};
      rt::Hit h2;
      ++spawned;
      if (es.intersect(out, h2)) ++self_hits;
    }
  }
  INFO(triangles << " triangles hit, " << spawned << " rays spawned");
  CHECK(triangles > 900);
  CHECK(self_hits == 0);
}

TEST_CASE("hc01 spheres: spawned rays never re-enter their sphere, 1e-6..1e6, any transform",
          "[hardcase][robust][property]") {
  // hc01's recipe for spheres: 2000 spheres of radius log-uniform in [1e-6, 1e6],
  // centred up to 100 radii from the camera (sphere hit points are projected onto
  // the sphere in double and leave by 8 ulps, not Wächter–Binder's 256), half of
  // them under a non-uniform scale and rotation (intersected in object space).
  // From a hit, 250 directions on each side: a ray leaving outward may hit nothing;
  // one leaving inward must next leave the sphere (an exiting hit), never re-enter.
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  long spawned = 0, self_hits = 0, hits = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    double r = std::pow(10.0, -6 + 12 * u(rng));
    ir::Scene s = base_scene(1, 1);
    ir::Vec3 center = unit(rng) * (r * 100 * u(rng));
    ir::Shape sp = sphere(center, r, 0);
    if (trial % 2)
      sp.set_world_from_object(ir::Transform::translate(center) *
                               ir::Transform::rotate_xyz({360 * u(rng), 360 * u(rng), 0}) *
                               ir::Transform::scale({1, 0.5 + 2 * u(rng), 0.3 + u(rng)}) *
                               ir::Transform::translate(center * -1.0));
    s.shapes.push_back(sp);
    rt::EmbreeScene es(s, {0, 0, 0});
    ir::Vec3 target = sp.world_from_object().point(center + unit(rng) * r);
    ir::Vec3 from = target + unit(rng) * (4 * r);
    rt::Ray ray{f(from), rt::normalize(f(target - from)), INFINITY, 0};
    rt::Hit hit;
    if (!es.intersect(ray, hit)) continue;
    ++hits;
    for (int k = 0; k < 500; ++k) {
      rt::Vec3f dir = f(unit(rng));
      rt::Vec3f side = rt::dot(dir, hit.ng) > 0 ? hit.ng : -hit.ng;
      rt::Ray out{rt::spawn_origin(hit, side, 1), dir, INFINITY, 0};
      rt::Hit h2;
      ++spawned;
      bool inward = rt::dot(dir, hit.ng) < 0;
      if (es.intersect(out, h2) && !(inward && rt::dot(dir, h2.ng) > 0)) ++self_hits;
    }
  }
  INFO(hits << " spheres hit, " << spawned << " rays spawned");
  CHECK(hits > 1500);
  CHECK(self_hits == 0);
}

namespace {
// Shadow rays from points of an open floor to samples of a quad light at height
// `scale` above it, built as Integrator::direct builds them (origin offset off the
// floor, target offset off the light towards the point); with `occluder`, a slab
// 1e-3..2e-3·h below the light. Returns how many of n were occluded.
long shadow_blocked(double scale, bool occluder, int n, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0, 1);
  {
    {
      ir::Scene s = base_scene(1, 1);
      s.shapes.push_back(plane({0, 1, 0}, 0, 0));
      ir::AreaLight l;
      l.corner = ir::Vec3(-1, 1, -1) * scale;
      l.edge1 = ir::Vec3(2, 0, 0) * scale;
      l.edge2 = ir::Vec3(0, 0, 2) * scale;  // cross(e1, e2) = -y: emits down
      s.area_lights.push_back(l);
      if (occluder)
        s.shapes.push_back(box(ir::Vec3(-3, 0.998, -3) * scale, ir::Vec3(3, 0.999, 3) * scale, 0));
      ir::Vec3 cam = ir::Vec3(0.3, 2, -4) * scale;  // the world is rebased to a camera
      rt::EmbreeScene es(s, cam);
      const float k = rt::offset_scale(s, cam);  // as the integrator offsets
      long blocked = 0;
      for (int i = 0; i < n; ++i) {
        // The floor point as the integrator gets it: a hit of a ray from above.
        ir::Vec3 pw = ir::Vec3(4 * u(rng) - 2, 0, 4 * u(rng) - 2) * scale - cam;
        rt::Hit floor;
        ir::Vec3 above = pw + ir::Vec3(0, 0.5 * scale, 0);
        if (!es.intersect(rt::Ray{f(above), {0, -1, 0}, INFINITY, 0}, floor)) {
          ++blocked;  // a miss would be a failure too
          continue;
        }
        ir::Vec3 qw = l.corner + l.edge1 * u(rng) + l.edge2 * u(rng) - cam;
        rt::Vec3f q = f(qw);
        rt::Vec3f o = rt::spawn_origin(floor, {0, 1, 0}, k);
        rt::Vec3f target = rt::offset_ray_origin(q, {0, -1, 0}, k);
        rt::Ray shadow{o, target - o, 1.0f, 0};
        if (es.occluded(shadow)) ++blocked;
      }
      return blocked;
    }
  }
}
}  // namespace

TEST_CASE("hc02 shadow rays to area-light samples are never blocked by the light itself",
          "[hardcase][robust][area]") {
  // 1e5 rays in all, at scene scales 1e-3..1e4: none is occluded.
  std::mt19937_64 rng(2);
  for (double scale : {1e-3, 1e-1, 1.0, 1e2, 1e4}) {
    INFO("scale " << scale);
    CHECK(shadow_blocked(scale, false, 20000, rng) == 0);
  }
}

TEST_CASE("hc02 an occluder 1e-3 h in front of an area light blocks every shadow ray",
          "[hardcase][robust][area]") {
  // At scale 1e-3 the gap is 1e-6. The Wächter-Binder offset used to be a fixed
  // 2^-16 ≈ 1.5e-5 within 1/32 of the camera, so light leaked; the offset now
  // scales with the scene's size (rt::offset_scale, docs/hardcases.md #2).
  std::mt19937_64 rng(3);
  for (double scale : {1e-3, 1e-1, 1.0, 1e2, 1e4}) {
    INFO("scale " << scale);
    CHECK(shadow_blocked(scale, true, 5000, rng) == 5000);
  }
}

TEST_CASE("hc05 a unit sphere seen from 1e2..1e5 away: no misses, no false hits",
          "[hardcase][robust][property]") {
  // Rays from the origin aimed at impact parameter b: b ≤ 0.99 must hit, b ≥ 1.01
  // must miss (1e5 rays per distance). Spheres are intersected in double with the
  // robust discriminant; the only error left is the float direction (~6e-8 rad,
  // 6e-3 at 1e5, under the 1 % band).
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  for (double D : {1e2, 1e3, 1e4, 1e5}) {
    ir::Scene s = base_scene(1, 1);
    ir::Vec3 c = ir::normalize(ir::Vec3(0.3, -0.2, 1)) * D;
    s.shapes.push_back(sphere(c, 1, 0));
    rt::EmbreeScene es(s, {0, 0, 0});
    ir::Vec3 w = ir::normalize(c), a, b;
    a = ir::normalize(ir::cross(w, {0, 1, 0}));
    b = ir::cross(w, a);
    long miss = 0, false_hit = 0;
    for (int i = 0; i < 100000; ++i) {
      bool inside = i % 2 == 0;
      double bb = inside ? 0.99 * std::sqrt(u(rng)) : 1.01 + 2 * u(rng);
      double ang = 2 * kPi * u(rng);
      // The point at distance bb from the centre, perpendicular to the view axis.
      ir::Vec3 target = c + (a * std::cos(ang) + b * std::sin(ang)) * bb;
      rt::Ray r{{0, 0, 0}, rt::normalize(f(target)), INFINITY, 0};
      rt::Hit h;
      bool hit = es.intersect(r, h);
      // Closest approach of the float ray (double), to classify fairly.
      ir::Vec3 d = ir::normalize(ir::Vec3(r.dir.x, r.dir.y, r.dir.z));
      double closest = ir::length(ir::cross(c, d));
      if (closest <= 0.99 && !hit) ++miss;
      if (closest >= 1.01 && hit) ++false_hit;
    }
    INFO("distance " << D);
    CHECK(miss == 0);
    CHECK(false_hit == 0);
  }
}

TEST_CASE("hc06 watertight: rays from inside a closed jittered mesh sphere always hit it",
          "[hardcase][robust][property]") {
  // pbrt's Triangle.Watertight recipe: a closed 16×16 UV sphere, each vertex moved
  // radially by up to 10 %, shared vertices shared; 1e6 random rays from random
  // points inside (within half the radius). The scene is built without
  // RTC_SCENE_FLAG_ROBUST (embree_scene.hpp), so this is the test that would show
  // cracks on shared edges.
  std::mt19937_64 rng(6);
  std::uniform_real_distribution<double> u(0, 1);
  ir::Scene s = base_scene(1, 1);
  add_mesh(s, uv_sphere(16, 16, 1, 0.1, 6), 0);
  rt::EmbreeScene es(s, {0, 0, 0});
  long misses = 0, inward = 0;
  const int n = 1000000;
  for (int i = 0; i < n; ++i) {
    ir::Vec3 o = unit(rng) * (0.5 * std::cbrt(u(rng)));
    rt::Ray r{f(o), f(unit(rng)), INFINITY, 0};
    rt::Hit h;
    if (!es.intersect(r, h))
      ++misses;
    else if (rt::dot(h.ng, r.dir) <= 0)
      ++inward;  // exiting: along the outward normal
  }
  CHECK(misses == 0);
  CHECK(inward == 0);  // the winding is outward (uv_sphere's contract)
}

TEST_CASE("hc06 rays aimed exactly at mesh vertices miss less than 1e-4 of the time",
          "[hardcase][robust][property]") {
  // Embree's maintainers say exact vertex hits are not handled perfectly (Embree
  // #181, #381); robustness.md asks for < 1e-4 and to record the rate. Known to
  // fail without RTC_SCENE_FLAG_ROBUST (docs/hardcases.md #6).
  std::mt19937_64 rng(60);
  std::uniform_real_distribution<double> u(0, 1);
  ir::Scene s = base_scene(1, 1);
  add_mesh(s, uv_sphere(16, 16, 1, 0.1, 6), 0);
  rt::EmbreeScene es(s, {0, 0, 0});
  {
    const ir::MeshData& m = s.meshes[0];
    long vm = 0, total = 0;
    for (int rep = 0; rep < 40; ++rep)
      for (const ir::Vec3& v : m.positions) {
        ir::Vec3 o = unit(rng) * (0.3 * u(rng));
        rt::Ray r{f(o), rt::normalize(f(v) - f(o)), INFINITY, 0};
        rt::Hit h;
        ++total;
        if (!es.intersect(r, h)) ++vm;
      }
    INFO(vm << " of " << total << " vertex rays missed");
    CHECK(double(vm) / double(total) < 1e-4);
  }
}

TEST_CASE("hc07 a ray starting exactly on a triangle and leaving it finds no hit",
          "[hardcase][robust]") {
  // The origin is a barycentric point of the triangle, rounded to float; the spawn
  // path offsets it to the side the ray leaves on, so the ray cannot see its own
  // surface. Both sides, 1000 triangles × 20 directions. (A raw Embree query with
  // tnear = 0 from the un-offset point may report t = 0; Snell never makes one.)
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  long hits = 0, rays = 0;
  for (int trial = 0; trial < 1000; ++trial) {
    double mag = std::pow(10.0, -3 + 7 * u(rng));
    ir::Scene s = base_scene(1, 1);
    ir::Triangle t;
    ir::Vec3 centre = unit(rng) * (mag * 10 * u(rng));
    t.a = centre + unit(rng) * mag, t.b = centre + unit(rng) * mag, t.c = centre + unit(rng) * mag;
    s.shapes.push_back(shape_of(t, 0));
    ir::Vec3 n = ir::cross(t.b - t.a, t.c - t.a);
    if (!(ir::length(n) > 1e-3 * mag * mag)) continue;
    rt::EmbreeScene es(s, {0, 0, 0});
    double b1 = u(rng), b2 = u(rng);
    if (b1 + b2 > 1) b1 = 1 - b1, b2 = 1 - b2;
    rt::Vec3f p = f(t.a + (t.b - t.a) * b1 + (t.c - t.a) * b2);
    rt::Vec3f nf = rt::normalize(f(n));
    for (int k = 0; k < 20; ++k) {
      rt::Vec3f side = k % 2 ? nf : -nf;
      rt::Vec3f dir = f(unit(rng));
      if (rt::dot(dir, side) < 0) dir = -dir;
      rt::Ray r{rt::offset_ray_origin(p, side), dir, INFINITY, 0};
      rt::Hit h;
      ++rays;
      if (es.intersect(r, h)) ++hits;
    }
  }
  CHECK(rays > 15000);
  CHECK(hits == 0);
}
