// The packet plane test (geometry/plane_lanes.hpp) against the one-ray test
// (PlaneSet::occluded), lane by lane, on every path this CPU has: planes at up to
// 1e6 from the camera in any direction, shadow segments that end short of the
// plane, just past it, start on it (a floor's own shadow rays), run along it or
// cross it far out (grazing: the far-hit cut), cross it so close that t is 0 in
// float, and random live masks.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "runtime/geometry/plane.hpp"
#include "runtime/geometry/plane_lanes.hpp"

using namespace snell;
using namespace snell::rt;
using namespace snell::rt::geom;

TEST_CASE("a shadow packet's plane test is the one-ray test, lane by lane",
          "[shapes][plane][lanes]") {
  auto paths = plane_lanes_paths();
  if (paths.empty()) SUCCEED("no SIMD plane path on this CPU: packets test lane by lane");
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> u01(0, 1);
  std::normal_distribution<double> g;
  for (auto& [name, fn] : paths) {
    INFO("path " << name);
    std::uint64_t lanes = 0, blocked_n = 0, kinds[7] = {};
    for (int trial = 0; trial < 20000; ++trial) {
      const ir::Vec3 n =
          trial % 4 == 0 ? ir::Vec3(0, 1, 0) : ir::normalize(ir::Vec3(g(rng), g(rng), g(rng)));
      const double d = (u01(rng) - 0.5) * std::pow(10.0, -2 + 8 * u01(rng));
      ir::Shape shape;
      ir::Plane plane{n, d};
      PlaneSet set;
      set.add(shape, plane, 0, ir::Vec3(0, 0, 0), false);
      alignas(64) float ox[16], oy[16], oz[16], dx[16], dy[16], dz[16], tm[16];
      for (int i = 0; i < 16; ++i) {
        const int kind = int(u01(rng) * 7);
        ++kinds[kind];
        // A point on the plane near its closest point to the camera.
        ir::Vec3 on = n * d + ir::Vec3(g(rng), g(rng), g(rng)) * (1 + std::fabs(d));
        on = on - n * (ir::dot(n, on) - d);
        ir::Vec3 o, to;
        const ir::Vec3 away = n * (1 + std::fabs(d)) * (0.01 + u01(rng));
        switch (kind) {
          case 0:  // from one side to the other
            o = on + away, to = on - away * u01(rng) * 2;
            break;
          case 1:  // ending short of the plane or just past it
            o = on + away, to = on + away * (1e-6 * g(rng));
            break;
          case 2:  // starting on it (a floor's shadow rays)
            o = on, to = on + away * (u01(rng) < 0.5 ? 1 : -1) + ir::Vec3(g(rng), g(rng), g(rng));
            break;
          case 3: {  // grazing: crossing it far out, on either side of kMaxPlaneHit
            const ir::Vec3 along = ir::normalize(ir::cross(n, ir::Vec3(g(rng), g(rng), g(rng))));
            o = on + n * (1 + std::fabs(d)),
            to = o + along * std::pow(10.0, 15 + 5 * u01(rng)) - n * (1 + std::fabs(d)) * 2;
            break;
          }
          case 6:  // from on it, rounded to float, into it along a vast segment:
                   // t positive, and 0 in float
            o = on, to = on - n * std::pow(10.0, 25 + 10 * u01(rng)) * (u01(rng) < 0.5 ? 1 : -1);
            break;
          case 4:  // anywhere
            o = ir::Vec3(g(rng), g(rng), g(rng)) * std::pow(10.0, 6 * u01(rng)),
            to = ir::Vec3(g(rng), g(rng), g(rng)) * std::pow(10.0, 6 * u01(rng));
            break;
          default:  // a zero-length or exactly parallel segment
            o = on + away, to = u01(rng) < 0.5 ? o : o + ir::cross(n, ir::Vec3(1, 2, 3));
            break;
        }
        ox[i] = float(o.x), oy[i] = float(o.y), oz[i] = float(o.z);
        dx[i] = float(to.x - o.x), dy[i] = float(to.y - o.y), dz[i] = float(to.z - o.z);
        tm[i] = float(u01(rng));
      }
      const std::uint32_t live = trial % 3 == 0 ? 0xffffu : std::uint32_t(rng()) & 0xffffu;
      const ShadowLanes16 rays{ox, oy, oz, dx, dy, dz, tm};
      const std::uint32_t got = set.occluded_lanes(rays, live, fn);
      for (int i = 0; i < 16; ++i) {
        if (!((live >> i) & 1)) {
          REQUIRE(((got >> i) & 1) == 0);
          continue;
        }
        ++lanes;
        const Ray r{{ox[i], oy[i], oz[i]}, {dx[i], dy[i], dz[i]}, kAreaShadowEnd, tm[i]};
        const bool one = set.occluded(r);
        INFO("trial " << trial << " lane " << i);
        REQUIRE(one == bool((got >> i) & 1));
        blocked_n += one;
      }
      // Lane by lane (the path for moving planes and CPUs without one) too.
      REQUIRE(set.occluded_lanes(rays, live, nullptr) == got);
    }
    INFO(lanes << " lanes, " << blocked_n << " blocked");
    CHECK(blocked_n > lanes / 10);
    CHECK(blocked_n < lanes * 9 / 10);
  }
}

TEST_CASE("a packet's nearest plane hits are the one-ray query's, lane by lane",
          "[shapes][plane][lanes]") {
  // Several planes (a floor, walls, one across the others), rays from near the
  // camera and from on a plane, with tnear 0 or past a plane (an index-matched
  // continuation), tmax from a nearer BVH hit or none, and a tie window: the plane
  // each lane ends on, its t and the Hit written are those of intersect().
  if (!plane_hit_lanes()) {
    SUCCEED("no SIMD plane path on this CPU: packets test lane by lane");
    return;
  }
  std::mt19937 rng(29);
  std::uniform_real_distribution<double> u01(0, 1);
  std::normal_distribution<double> g;
  std::uint64_t lanes = 0, hits = 0, tied = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    PlaneSet set;
    ir::Shape shape;
    const int np = 1 + trial % 4;
    std::vector<ir::Plane> planes(np);
    for (int i = 0; i < np; ++i) {
      planes[i].normal =
          i == 0 ? ir::Vec3(0, 1, 0) : ir::normalize(ir::Vec3(g(rng), g(rng), g(rng)));
      planes[i].distance = (u01(rng) - 0.5) * 20;
      set.add(shape, planes[i], std::uint32_t(i), ir::Vec3(0, 0, 0), false);
    }
    alignas(64) float ox[16], oy[16], oz[16], dx[16], dy[16], dz[16], tn[16];
    alignas(64) double tmax[16], tie[16];
    Ray rays[16];
    for (int k = 0; k < 16; ++k) {
      ir::Vec3 o = ir::Vec3(g(rng), g(rng), g(rng)) * (k % 4 == 0 ? 0.01 : 5.0);
      if (k % 5 == 1) o = planes[0].normal * planes[0].distance + ir::Vec3(g(rng), 0, g(rng));
      const ir::Vec3 d = ir::Vec3(g(rng), g(rng), g(rng)) * std::pow(10.0, 2 * u01(rng) - 1);
      rays[k].org = {float(o.x), float(o.y), float(o.z)};
      rays[k].dir = {float(d.x), float(d.y), float(d.z)};
      rays[k].tnear = k % 7 == 3 ? float(u01(rng) * 2) : 0.0f;
      rays[k].tmax = INFINITY;
      ox[k] = rays[k].org.x, oy[k] = rays[k].org.y, oz[k] = rays[k].org.z;
      dx[k] = rays[k].dir.x, dy[k] = rays[k].dir.y, dz[k] = rays[k].dir.z, tn[k] = rays[k].tnear;
      tmax[k] = k % 3 == 0 ? 1 + 10 * u01(rng) : double(INFINITY);  // a BVH hit before
      tie[k] = k % 3 == 0 && k % 2 == 0 ? 1e-3 * u01(rng) : 0;
      if (k % 6 == 0) {  // a BVH hit just short of the floor: the floor wins by the tie
        const ir::Vec3 of(ox[k], oy[k], oz[k]), df(dx[k], dy[k], dz[k]);
        const double t0 =
            (planes[0].distance - ir::dot(planes[0].normal, of)) / ir::dot(planes[0].normal, df);
        if (t0 > 1e-3) tmax[k] = t0 * (1 - 1e-9), tie[k] = 1e-3;
      }
    }
    const std::uint32_t live = trial % 2 ? 0xffffu : std::uint32_t(rng()) & 0xffffu;
    double lt[16], le[16];
    std::copy(tmax, tmax + 16, lt), std::copy(tie, tie + 16, le);
    std::uint32_t which[16], hit_lanes = 0;
    REQUIRE(set.intersect_lanes({ox, oy, oz, dx, dy, dz, tn}, live, lt, le, which, hit_lanes));
    REQUIRE((hit_lanes & ~live) == 0);
    for (int k = 0; k < 16; ++k) {
      if (!((live >> k) & 1)) continue;
      ++lanes;
      double t1 = tmax[k];
      Hit one;
      const bool hit1 = set.intersect(rays[k], t1, tie[k], one);
      INFO("trial " << trial << " lane " << k);
      REQUIRE(hit1 == bool((hit_lanes >> k) & 1));
      if (!hit1) {
        REQUIRE(lt[k] == tmax[k]);
        continue;
      }
      ++hits;
      tied += tie[k] > 0 && t1 >= tmax[k];
      REQUIRE(lt[k] == t1);
      Hit two;
      set.plane_hit(which[k], rays[k], lt[k], two);
      REQUIRE(two.t == one.t);
      REQUIRE(two.index == one.index);
      REQUIRE((two.ng.x == one.ng.x && two.ng.y == one.ng.y && two.ng.z == one.ng.z));
      REQUIRE((two.p.x == one.p.x && two.p.y == one.p.y && two.p.z == one.p.z));
      REQUIRE(two.offset == one.offset);
    }
  }
  INFO(lanes << " lanes, " << hits << " hits, " << tied << " within a tie");
  CHECK(hits > lanes / 5);
  CHECK(hits < lanes * 9 / 10);
  CHECK(tied > 0);
}
