// A packet's light samples (shading/area_lanes.hpp) against the one-lane sample
// (AreaLightF::sample_li_area), lane by lane and bit for bit, on every path this
// CPU has: lights from 1e-3 to 1e3 units across, one- and two-sided, grids of 1-5
// cells a side, some across the coordinate planes (where offset_coord takes its
// absolute step), shading points above, beside and behind them, with random lane
// masks and offset scales.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <random>

#include "runtime/shading/area_lanes.hpp"
#include "runtime/shading/lights.hpp"
#include "tests/runtime/bits_util.hpp"

using namespace snell;
using namespace snell::rt;

using snell::test::same_bits;

TEST_CASE("a packet's light samples are the one-lane samples, bit for bit",
          "[lights][area][lanes]") {
  auto paths = area_lanes_paths();
  if (paths.empty()) SUCCEED("no SIMD light-sample path on this CPU: lanes go one by one");
  std::mt19937 rng(29);
  std::uniform_real_distribution<float> u01(0, 1);
  std::normal_distribution<float> g;
  auto unit = [&] { return normalize(Vec3f(g(rng), g(rng), g(rng))); };
  for (auto& [name, fn] : paths) {
    INFO("path " << name);
    std::uint64_t lanes = 0, lit = 0, unlit = 0;
    for (int trial = 0; trial < 20000; ++trial) {
      const float size = std::pow(10.0f, -3 + 6 * u01(rng));
      AreaLightF l;
      // A fifth of the lights straddle the origin's coordinate planes.
      l.corner = trial % 5 == 0 ? Vec3f(g(rng), g(rng), g(rng)) * (0.02f * size) - unit() * size
                                : unit() * (size * (1 + 20 * u01(rng)));
      l.e1 = unit() * size, l.e2 = unit() * (size * (0.2f + u01(rng)));
      const Vec3f c = cross(l.e1, l.e2);
      l.area = length(c);
      l.n = normalize(c);
      l.radiance = Color(1, 2, 3);
      l.nu = 1 + rng() % 5, l.nv = 1 + rng() % 5;
      l.two_sided = trial % 3 == 0;
      const std::uint32_t iu = rng() % l.nu, iv = rng() % l.nv;
      const float scale = trial % 4 == 0 ? std::pow(10.0f, -4 * u01(rng)) : 1.0f;
      PointLanes pt;
      alignas(64) float ju[16], jv[16];
      for (int i = 0; i < 16; ++i) {
        const Vec3f p = l.corner + unit() * (size * 3 * u01(rng));
        const Vec3f nf = unit();
        const Vec3f o = offset_ray_origin(p, nf, scale);
        pt.px[i] = p.x, pt.py[i] = p.y, pt.pz[i] = p.z;
        pt.ox[i] = o.x, pt.oy[i] = o.y, pt.oz[i] = o.z;
        pt.nx[i] = nf.x, pt.ny[i] = nf.y, pt.nz[i] = nf.z;
        pt.time[i] = u01(rng);
        ju[i] = u01(rng), jv[i] = u01(rng);
      }
      const std::uint32_t mask = trial % 2 ? 0xffffu : std::uint32_t(rng()) & 0xffffu;
      ShadowLanes out;
      const std::uint32_t got = fn({&l, iu, iv, scale}, pt, ju, jv, mask, out);
      REQUIRE((got & ~mask) == 0);
      for (int i = 0; i < 16; ++i) {
        if (!((mask >> i) & 1)) continue;
        ++lanes;
        LightSample s;
        const bool want = l.sample_li_area(
            {pt.px[i], pt.py[i], pt.pz[i]}, {pt.ox[i], pt.oy[i], pt.oz[i]},
            {pt.nx[i], pt.ny[i], pt.nz[i]}, pt.time[i], iu, iv, ju[i], jv[i], scale, s);
        INFO("trial " << trial << " lane " << i);
        REQUIRE(want == bool((got >> i) & 1));
        if (!want) {
          ++unlit;
          continue;
        }
        ++lit;
        // The shadow ray leaves o (the caller's lanes) with tmax kAreaShadowEnd, tnear 0.
        REQUIRE(same_bits(s.shadow.org.x, pt.ox[i]));
        REQUIRE(s.shadow.tmax == rt::kAreaShadowEnd);
        REQUIRE(s.shadow.tnear == 0.0f);
        REQUIRE(same_bits(s.shadow.time, pt.time[i]));
        REQUIRE(same_bits(s.shadow.dir.x, out.dx[i]));
        REQUIRE(same_bits(s.shadow.dir.y, out.dy[i]));
        REQUIRE(same_bits(s.shadow.dir.z, out.dz[i]));
        REQUIRE(same_bits(s.g, out.g[i]));
        REQUIRE(same_bits(s.to.x, out.tx[i]));
        REQUIRE(same_bits(s.to.y, out.ty[i]));
        REQUIRE(same_bits(s.to.z, out.tz[i]));
      }
    }
    INFO("lanes " << lanes << " lit " << lit << " unlit " << unlit);
    CHECK(lit > lanes / 8);  // both answers are common
    CHECK(unlit > lanes / 8);
  }
}
