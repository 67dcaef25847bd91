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
