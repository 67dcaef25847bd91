#include <catch2/catch.hpp>

#include "runtime/sampler.hpp"

using namespace snell;
using namespace snell::rt;

TEST_CASE("sampler values lie in 0..1 and never reach 1", "[sampler]") {
  CHECK(to_unit_float(0xffffffffu) < 1.0f);
  for (auto kind :
       {ir::SamplerKind::Independent, ir::SamplerKind::Stratified, ir::SamplerKind::Sobol}) {
    for (std::uint32_t spp : {1u, 5u, 16u, 64u}) {
      SamplerSpec spec{kind, 3, spp};
      for (std::uint32_t px = 0; px < 16; ++px)
        for (std::uint32_t i = 0; i < spp; ++i)
          for (std::uint32_t dim = 0; dim < 20; ++dim) {
            Sample2 s = sample2(spec, px, 7, i, dim * 977);
            REQUIRE(s.u >= 0.0f);
            REQUIRE(s.u < 1.0f);
            REQUIRE(s.v >= 0.0f);
            REQUIRE(s.v < 1.0f);
          }
    }
  }
}

TEST_CASE("samplers are pure functions of their inputs", "[sampler]") {
  SamplerSpec spec{ir::SamplerKind::Sobol, 9, 16};
  Sample2 a = sample2(spec, 3, 4, 5, 6), b = sample2(spec, 3, 4, 5, 6);
  CHECK(a.u == b.u);
  CHECK(a.v == b.v);
  SamplerSpec other = spec;
  other.seed = 10;
  Sample2 c = sample2(other, 3, 4, 5, 6);
  CHECK((c.u != a.u || c.v != a.v));
}

TEST_CASE("stratified and sobol put one sample in each stratum", "[sampler]") {
  // 16 samples: a 4×4 grid (stratified) and every 4×4 elementary interval (sobol,
  // a (0,2)-sequence in base 2 whose scrambling keeps the property).
  for (auto kind : {ir::SamplerKind::Stratified, ir::SamplerKind::Sobol}) {
    SamplerSpec spec{kind, 1, 16};
    for (std::uint32_t dim : {0u, 5u, 123456u}) {
      int cells[16] = {};
      for (std::uint32_t i = 0; i < 16; ++i) {
        Sample2 s = sample2(spec, 2, 9, i, dim);
        cells[int(s.v * 4) * 4 + int(s.u * 4)]++;
      }
      for (int c : cells) CHECK(c == 1);
    }
  }
}

TEST_CASE("permutation is a bijection", "[sampler]") {
  for (std::uint32_t n : {1u, 2u, 7u, 16u, 100u}) {
    std::vector<int> seen(n, 0);
    for (std::uint32_t i = 0; i < n; ++i) seen[permute(i, n, 12345)]++;
    for (int c : seen) CHECK(c == 1);
  }
}
