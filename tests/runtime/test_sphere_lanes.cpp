// The packet sphere test (geometry/sphere_lanes.hpp) against the one-ray test
// (hit_similar_sphere), lane by lane and bit for bit, on every path this CPU has:
// spheres from 1e-3 to 1e4 units at up to 1e5 from the camera, rays aimed at the
// sphere, past it and grazing its silhouette, with tnear/tfar windows that cut the
// roots, and random valid masks.
#include <bit>
#include <catch2/catch.hpp>
#include <cstring>
#include <random>

#include "runtime/geometry/sphere.hpp"
#include "runtime/geometry/sphere_lanes.hpp"
#include "tests/runtime/bits_util.hpp"

using namespace snell;
using namespace snell::rt;
using namespace snell::rt::geom;

using snell::test::same_bits;

TEST_CASE("a packet's sphere test is the one-ray test, bit for bit", "[shapes][sphere][lanes]") {
  auto paths = sphere_lanes_paths();
  if (paths.empty()) SUCCEED("no SIMD sphere path on this CPU: packets test lane by lane");
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u01(0, 1);
  std::normal_distribution<double> g;
  for (auto& [name, fn] : paths) {
    INFO("path " << name);
    std::uint64_t lanes = 0, hits = 0, grazing = 0, undecided_n = 0;
    for (int trial = 0; trial < 40000; ++trial) {
      double radius = std::pow(10.0, -3 + 7 * u01(rng));
      double dist = radius * std::pow(10.0, 0.1 + 4 * u01(rng));
      ir::Vec3 c = ir::normalize(ir::Vec3(g(rng), g(rng), g(rng))) * std::min(dist, 1e5);
      alignas(64) float ox[16], oy[16], oz[16], dx[16], dy[16], dz[16], tn[16], tf[16];
      alignas(64) int valid[16];
      for (int i = 0; i < 16; ++i) {
        // Origins near the camera (or near the sphere for secondary-like rays).
        ir::Vec3 o = (i % 4 == 3) ? c + ir::normalize(ir::Vec3(g(rng), g(rng), g(rng))) *
                                            (radius * (1 + 3 * u01(rng)))
                                  : ir::Vec3(g(rng), g(rng), g(rng)) * 0.01;
        // Aim at a point of the sphere's silhouette disc, its rim or beyond.
        double k = i % 3 == 0 ? 1 + 1e-7 * g(rng) : 1.3 * u01(rng);
        ir::Vec3 side = ir::normalize(ir::cross(c - o, ir::Vec3(g(rng), g(rng), g(rng))));
        ir::Vec3 d = ir::normalize(c + side * (radius * k) - o);
        ox[i] = float(o.x), oy[i] = float(o.y), oz[i] = float(o.z);
        dx[i] = float(d.x), dy[i] = float(d.y), dz[i] = float(d.z);
        tn[i] = i % 5 == 0 ? float(ir::length(c - o) * u01(rng)) : 0.0f;
        tf[i] = i % 7 == 0 ? float(ir::length(c - o) * 1.5 * u01(rng)) : INFINITY;
        valid[i] = u01(rng) < 0.85 ? -1 : 0;
        grazing += i % 3 == 0;
      }
      RayLanes rays{ox, oy, oz, dx, dy, dz, tn, tf, valid, 16};
      HitLanes out;
      std::uint32_t undecided = 0;
      std::uint32_t got = fn(c, radius, rays, &out, undecided);
      CHECK((got & undecided) == 0);
      // An occlusion query (no hits written) finds the same lanes.
      std::uint32_t undecided_only = 0;
      CHECK(fn(c, radius, rays, nullptr, undecided_only) == got);
      CHECK(undecided_only == undecided);
      // Eight rays (Embree's packets on AVX2 CPUs) are the first eight lanes of
      // sixteen.
      RayLanes rays8 = rays;
      rays8.n = 8;
      HitLanes out8;
      std::uint32_t undecided8 = 0;
      const std::uint32_t got8 = fn(c, radius, rays8, &out8, undecided8);
      REQUIRE(got8 == (got & 0xff));
      REQUIRE(undecided8 == (undecided & 0xff));
      for (std::uint32_t b = got8; b; b &= b - 1) {
        const int i = std::countr_zero(b);
        REQUIRE(same_bits(out8.t[i], out.t[i]));
        REQUIRE(same_bits(out8.nx[i], out.nx[i]));
        REQUIRE(same_bits(out8.ny[i], out.ny[i]));
        REQUIRE(same_bits(out8.nz[i], out.nz[i]));
      }
      for (int i = 0; i < 16; ++i) {
        bool on = valid[i] != 0;
        if (!on) {
          REQUIRE(((got >> i) & 1) == 0);
          continue;
        }
        if ((undecided >> i) & 1) {
          ++undecided_n;
          continue;
        }
        ++lanes;
        float t = 0;
        Vec3f n;
        bool hit = hit_similar_sphere(c, radius, ox[i], oy[i], oz[i], dx[i], dy[i], dz[i], tn[i],
                                      tf[i], t, n);
        INFO("trial " << trial << " lane " << i << " radius " << radius);
        REQUIRE(hit == bool((got >> i) & 1));
        if (!hit) continue;
        ++hits;
        REQUIRE(same_bits(t, out.t[i]));
        REQUIRE(same_bits(n.x, out.nx[i]));
        REQUIRE(same_bits(n.y, out.ny[i]));
        REQUIRE(same_bits(n.z, out.nz[i]));
      }
    }
    INFO("lanes " << lanes << " hits " << hits << " undecided " << undecided_n);
    CHECK(hits > lanes / 4);  // the rays were aimed: a real share of them hit
    CHECK(hits < lanes);
    CHECK(grazing > 0);
  }
}

TEST_CASE("normal_scale is the power of two that takes a radius to between 1 and 2",
          "[shapes][sphere]") {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u01(0, 1);
  for (int i = 0; i < 100000; ++i) {
    double r = std::pow(10.0, -300 + 600 * u01(rng));
    double s = normal_scale(r);
    int e;
    REQUIRE(std::frexp(s, &e) == 0.5);  // a power of two: the product is exact
    REQUIRE(r * s >= 1);
    REQUIRE(r * s < 2);
  }
  for (double r : {0x1p-1074, 0x1p-1030, 0x1p-1022, 0x1p1000, 0x1.fffffffffffffp1023}) {
    INFO("r " << r);
    CHECK(std::ldexp(r, std::ilogb(normal_scale(r))) >= 1);
    CHECK(normal_scale(r) == std::ldexp(1.0, -std::ilogb(r)));
  }
}

// The similar sphere's normal leaves the test unnormalised (o + t·d − c, scaled by a
// power of two) and is normalised in float by the hit's user. Against the exact unit
// normal at the same t (long double): within 4 float ulps per component of 1, for
// spheres 1e-6 to 1e6 across seen from up to 1e6 radii away.
TEST_CASE("a similar sphere's normal, normalised in float, is within ulps of the exact one",
          "[shapes][sphere]") {
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> u01(0, 1);
  std::normal_distribution<double> g;
  int hits = 0;
  double worst = 0;
  for (int trial = 0; trial < 50000; ++trial) {
    double radius = std::pow(10.0, -6 + 12 * u01(rng));
    ir::Vec3 c = ir::normalize(ir::Vec3(g(rng), g(rng), g(rng))) *
                 std::min(radius * std::pow(10.0, 0.1 + 6 * u01(rng)), 1e9);
    ir::Vec3 aim = c + ir::normalize(ir::Vec3(g(rng), g(rng), g(rng))) * (radius * u01(rng));
    ir::Vec3 d = ir::normalize(aim);
    float t;
    Vec3f n;
    if (!hit_similar_sphere(c, radius, 0, 0, 0, float(d.x), float(d.y), float(d.z), 0, INFINITY, t,
                            n))
      continue;
    ++hits;
    Vec3f nu = normalize(n);
    // The exact normal at the double root the test found: recompute it in long double
    // from the float ray (the test's inputs) and the same t.
    double t0, t1;
    ir::Vec3 df(float(d.x), float(d.y), float(d.z));
    REQUIRE(sphere_roots(ir::Vec3(0, 0, 0), df, c, radius, t0, t1));
    double tt = t0 > 0 ? t0 : t1;
    long double px = (long double)df.x * tt - c.x, py = (long double)df.y * tt - c.y,
                pz = (long double)df.z * tt - c.z;
    long double len = std::sqrt(px * px + py * py + pz * pz);
    double err = std::max({std::fabs(double(px / len) - nu.x), std::fabs(double(py / len) - nu.y),
                           std::fabs(double(pz / len) - nu.z)});
    worst = std::max(worst, err);
  }
  INFO("hits " << hits << " worst " << worst);
  CHECK(hits > 20000);
  CHECK(worst <= 4 * 0x1p-24);
}
