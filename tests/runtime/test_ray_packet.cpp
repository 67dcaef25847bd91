// The rays of a span query in Embree's packet layout (ray_packet.hpp): every path
// this CPU has writes each lane's fields as the rays hold them, bit for bit, for
// every batch size, with the lanes past the batch repeating its first ray.
#include <catch2/catch.hpp>
#include <cstring>
#include <random>

#include "runtime/ray_packet.hpp"
#include "tests/runtime/bits_util.hpp"

using namespace snell;
using namespace snell::rt;

using snell::test::same_bits;

TEST_CASE("a batch of rays goes into the packet layout field by field", "[packets][lanes]") {
  auto paths = store_rays16_paths();
  REQUIRE(!paths.empty());
  CHECK(paths.back().first == "generic");
  std::mt19937 rng(5);
  auto any = [&] {  // any bits but a NaN's, which a gather would copy as well
    float f;
    do {
      std::uint32_t b = rng();
      std::memcpy(&f, &b, 4);
    } while (f != f);
    return f;
  };
  for (auto& [name, fn] : paths) {
    INFO("path " << name);
    for (std::size_t n = 1; n <= 16; ++n) {
      Ray rays[16];
      for (Ray& r : rays) {
        r.org = {any(), any(), any()}, r.dir = {any(), any(), any()};
        r.tmax = any(), r.time = any(), r.tnear = any();
      }
      alignas(64) RTCRay16 p;
      std::memset(&p, 0x5a, sizeof p);
      fn(rays, n, p);
      for (std::size_t k = 0; k < 16; ++k) {
        INFO("n " << n << " lane " << k);
        const Ray& r = rays[k < n ? k : 0];
        CHECK(same_bits(p.org_x[k], r.org.x));
        CHECK(same_bits(p.org_y[k], r.org.y));
        CHECK(same_bits(p.org_z[k], r.org.z));
        CHECK(same_bits(p.dir_x[k], r.dir.x));
        CHECK(same_bits(p.dir_y[k], r.dir.y));
        CHECK(same_bits(p.dir_z[k], r.dir.z));
        CHECK(same_bits(p.tfar[k], r.tmax));
        CHECK(same_bits(p.time[k], r.time));
        CHECK(same_bits(p.tnear[k], r.tnear));
        CHECK(p.mask[k] == ~0u);
        CHECK(p.id[k] == 0u);
        CHECK(p.flags[k] == 0u);
      }
    }
  }
}
