#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "runtime/render/tile.hpp"
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

namespace {

// The samplers as first written (per draw: sqrt, integer divisions, Kensler's
// permutation with its modulo, Sobol' dimension 1 bit by bit). The renderer's
// inline versions precompute and table these; they must draw the same numbers,
// or every reference image would change.
std::uint32_t reference_permute(std::uint32_t i, std::uint32_t l, std::uint32_t p) {
  if (l <= 1) return 0;
  std::uint32_t w = l - 1;
  w |= w >> 1;
  w |= w >> 2;
  w |= w >> 4;
  w |= w >> 8;
  w |= w >> 16;
  do {
    i ^= p;
    i *= 0xe170893d;
    i ^= p >> 16;
    i ^= (i & w) >> 4;
    i ^= p >> 8;
    i *= 0x0929eb3f;
    i ^= p >> 23;
    i ^= (i & w) >> 1;
    i *= 1 | p >> 27;
    i *= 0x6935fa69;
    i ^= (i & w) >> 11;
    i *= 0x74dcb303;
    i ^= (i & w) >> 2;
    i *= 0x9e501cc3;
    i ^= (i & w) >> 2;
    i *= 0xc860a3df;
    i &= w;
    i ^= i >> 5;
  } while (i >= l);
  return (i + p) % l;
}

std::uint32_t reference_reverse(std::uint32_t x) {
  std::uint32_t r = 0;
  for (int b = 0; b < 32; ++b) r |= (x >> b & 1u) << (31 - b);
  return r;
}

std::uint32_t reference_owen(std::uint32_t x, std::uint32_t seed) {
  x = reference_reverse(x);
  x += seed;
  x ^= x * 0x6c50b47cu;
  x ^= x * 0xb82f1e52u;
  x ^= x * 0xc7afe638u;
  x ^= x * 0x8d22f6e6u;
  return reference_reverse(x);
}

std::uint32_t reference_sobol1(std::uint32_t i) {
  std::uint32_t r = 0;
  for (std::uint32_t v = 1u << 31; i; i >>= 1, v ^= v >> 1)
    if (i & 1) r ^= v;
  return r;
}

float reference_unit(double x) {
  float f = static_cast<float>(x);
  return f < 1.0f ? f : 0x1.fffffep-1f;
}

Sample2 reference_sample2(ir::SamplerKind kind, std::uint32_t spp, std::uint64_t pixel,
                          std::uint32_t index, std::uint32_t dim) {
  std::uint64_t pixel_key = hash_combine(pixel, dim);
  switch (kind) {
    case ir::SamplerKind::Independent: {
      std::uint64_t h = hash_combine(pixel_key, index);
      return {to_unit_float(std::uint32_t(h)), to_unit_float(std::uint32_t(h >> 32))};
    }
    case ir::SamplerKind::Stratified: {
      std::uint32_t n = spp == 0 ? 1 : spp;
      std::uint32_t m = static_cast<std::uint32_t>(std::sqrt(double(n)));
      if (m == 0) m = 1;
      std::uint32_t k = (n + m - 1) / m;
      std::uint32_t cells = m * k;
      std::uint32_t cell = index < cells ? reference_permute(index, cells, std::uint32_t(pixel_key))
                                         : std::uint32_t(hash_combine(pixel_key, index) % cells);
      std::uint64_t h = hash_combine(pixel_key ^ 0x5bd1e995u, index);
      float ju = to_unit_float(std::uint32_t(h)), jv = to_unit_float(std::uint32_t(h >> 32));
      std::uint32_t cx = cell % k, cy = cell / k;
      return {reference_unit((cx + double(ju)) / k), reference_unit((cy + double(jv)) / m)};
    }
    case ir::SamplerKind::Sobol: {
      std::uint32_t i = reference_owen(index, std::uint32_t(pixel_key));
      std::uint32_t x = reference_owen(reference_reverse(i), std::uint32_t(hash64(pixel_key + 1)));
      std::uint32_t y = reference_owen(reference_sobol1(i), std::uint32_t(hash64(pixel_key + 2)));
      return {to_unit_float(x), to_unit_float(y)};
    }
  }
  return {};
}

float reference_sample1(ir::SamplerKind kind, std::uint32_t spp, std::uint64_t pixel,
                        std::uint32_t index, std::uint32_t dim) {
  if (kind != ir::SamplerKind::Stratified) return reference_sample2(kind, spp, pixel, index, dim).u;
  std::uint64_t pixel_key = hash_combine(pixel, dim ^ 0x1d1du);
  std::uint32_t n = spp == 0 ? 1 : spp;
  std::uint32_t cell = index < n ? reference_permute(index, n, std::uint32_t(pixel_key))
                                 : std::uint32_t(hash_combine(pixel_key, index) % n);
  float j = to_unit_float(std::uint32_t(hash_combine(pixel_key ^ 0x5bd1e995u, index)));
  return reference_unit((cell + double(j)) / n);
}

}  // namespace

TEST_CASE("the precomputed samplers draw the numbers of the original formulas", "[sampler]") {
  // Every count up to 300 (squares, primes, m·k > spp) and some large ones, indices
  // past spp (the unpermuted fallback), fixed and hashed dimensions.
  std::vector<std::uint32_t> counts;
  for (std::uint32_t n = 0; n <= 300; ++n) counts.push_back(n);
  for (std::uint32_t n : {1023u, 1024u, 4097u, 65536u, 1000003u}) counts.push_back(n);
  std::uint64_t mismatches = 0, draws = 0;
  for (auto kind :
       {ir::SamplerKind::Independent, ir::SamplerKind::Stratified, ir::SamplerKind::Sobol})
    for (std::uint32_t spp : counts) {
      SamplerSpec spec{kind, 0x1234 + spp, spp};
      for (std::uint32_t p = 0; p < 3; ++p) {
        std::uint64_t pixel = pixel_hash(spec, p * 7, p * 3);
        for (std::uint32_t dim : {0u, 1u, 2u, 3u, 0x9e3779b9u, 0xffffffffu}) {
          std::uint32_t step = spp > 400 ? spp / 97 : 1;
          for (std::uint32_t i = 0; i < spp + 3; i += step) {
            Sample2 a = sample2(spec, pixel, i, dim);
            Sample2 b = reference_sample2(kind, spp, pixel, i, dim);
            float c = sample1(spec, pixel, i, dim), d = reference_sample1(kind, spp, pixel, i, dim);
            mismatches += (a.u != b.u) + (a.v != b.v) + (c != d);
            ++draws;
          }
        }
      }
    }
  INFO(draws << " draws");
  CHECK(mismatches == 0);
}

TEST_CASE("keyed draws and the pixel's key cache give the unkeyed numbers", "[sampler]") {
  // More dimensions than the cache has slots, drawn in an order that makes them
  // evict each other, each both as 2-D and as 1-D (the tags keep them apart).
  std::vector<std::uint32_t> dims = {0, 1, 2, 3, 0xffffffffu};
  for (std::uint32_t d = 0; d < 3 * DimCache::kSlots; ++d) dims.push_back(0x9e3779b9u * (d + 17));
  std::uint64_t mismatches = 0, draws = 0;
  for (auto kind :
       {ir::SamplerKind::Independent, ir::SamplerKind::Stratified, ir::SamplerKind::Sobol})
    for (std::uint32_t spp : {1u, 5u, 16u, 100u}) {
      SamplerSpec spec{kind, 0x77 + spp, spp};
      for (std::uint32_t p = 0; p < 4; ++p) {
        std::uint64_t pixel = pixel_hash(spec, p * 5, p * 11);
        DimCache cache;
        for (std::uint32_t i = 0; i < spp + 2; ++i)
          for (std::uint32_t dim : dims) {
            Sample2 a = sample2(spec, pixel, i, dim);
            Sample2 b = sample2(spec, dim_key(spec, pixel, dim), i);
            Sample2 c = sample2(spec, cache.get<false>(spec, pixel, dim), i);
            float e = sample1(spec, pixel, i, dim);
            float f = sample1(spec, dim_key1(spec, pixel, dim), i);
            float g = sample1(spec, cache.get<true>(spec, pixel, dim), i);
            mismatches +=
                (a.u != b.u) + (a.v != b.v) + (a.u != c.u) + (a.v != c.v) + (e != f) + (e != g);
            ++draws;
          }
      }
    }
  INFO(draws << " draws");
  CHECK(mismatches == 0);
}

TEST_CASE("sobol draws in lanes give the one-by-one numbers, on every SIMD path", "[sampler]") {
  // Every block size 1..16 (a block at the image's edge is smaller), lanes left over
  // from a larger block beyond n, indices across power-of-two boundaries; each path
  // this CPU runs (the generic one always; avx512 where the CPU has it).
  const std::vector<std::string> paths = sobol2_lanes_paths();
  REQUIRE(!paths.empty());
  CHECK(paths.back() == "generic");
  for (const std::string& path : paths) {
    INFO("path " << path);
    std::uint64_t mismatches = 0, draws = 0;
    for (std::uint32_t spp : {1u, 16u, 64u, 1000u, 1u << 20}) {
      SamplerSpec spec{ir::SamplerKind::Sobol, 0x51 + spp, spp};
      SobolLanes lanes;
      for (std::uint32_t n = 16; n >= 1; --n)
        for (std::uint32_t dim : {std::uint32_t(kDimPixel), std::uint32_t(kDimLens), 0x9e3779b9u}) {
          DimKey keys[SobolLanes::kLanes];
          for (std::uint32_t l = 0; l < n; ++l) {
            keys[l] = dim_key(spec, pixel_hash(spec, l * 3 + n, dim % 7), dim);
            lanes.set(l, keys[l]);
          }
          for (std::uint32_t i = 0; i < spp + 2; i += 1 + spp / 50) {
            float u[SobolLanes::kLanes], v[SobolLanes::kLanes];
            REQUIRE(sobol2_lanes_with(path, lanes, n, i, u, v));
            for (std::uint32_t l = 0; l < n; ++l) {
              Sample2 one = sample2(spec, keys[l], i);
              mismatches += (one.u != u[l]) + (one.v != v[l]);
              ++draws;
            }
          }
        }
    }
    INFO(draws << " draws");
    CHECK(draws > 10000);
    CHECK(mismatches == 0);
  }
  // The dispatched entry point is the first (best) path.
  SamplerSpec spec{ir::SamplerKind::Sobol, 3, 64};
  SobolLanes lanes;
  for (std::uint32_t l = 0; l < SobolLanes::kLanes; ++l)
    lanes.set(l, dim_key(spec, pixel_hash(spec, l, 1), kDimLens));
  float u[SobolLanes::kLanes], v[SobolLanes::kLanes], u2[SobolLanes::kLanes],
      v2[SobolLanes::kLanes];
  sobol2_lanes(lanes, SobolLanes::kLanes, 37, u, v);
  REQUIRE(sobol2_lanes_with(paths.front(), lanes, SobolLanes::kLanes, 37, u2, v2));
  CHECK(std::memcmp(u, u2, sizeof u) == 0);
  CHECK(std::memcmp(v, v2, sizeof v) == 0);
  CHECK_FALSE(sobol2_lanes_with("no such path", lanes, 1, 0, u, v));
}

TEST_CASE("a jitter placed in its cell by a product and two FMAs is the division's float",
          "[sampler]") {
  // Divisor32::recip's claim: for d < 2^26 and x = c + j / 2^24 (c < d, j < 2^24),
  // q = x·r, q + (x − q·d)·r (r = 1/d rounded, FMAs) rounds to the float of x / d.
  // Counts even and odd, small and near 2^26; cells at the ends and at random.
  std::mt19937 rng(61);
  std::vector<std::uint32_t> ds = {2,
                                   3,
                                   5,
                                   6,
                                   7,
                                   9,
                                   10,
                                   12,
                                   24,
                                   100,
                                   1000,
                                   65537,
                                   (1u << 20) + 1,
                                   (1u << 26) - 1,
                                   (1u << 26) - 5};
  for (int i = 0; i < 40; ++i) ds.push_back(2 + rng() % ((1u << 26) - 2));
  std::uint64_t checked = 0, mismatches = 0;
  for (std::uint32_t d : ds) {
    const Divisor32 div(d);
    REQUIRE(div.recip == 1.0 / d);
    for (int i = 0; i < 20000; ++i) {
      const std::uint32_t c = i == 0 ? 0 : i == 1 ? d - 1 : std::uint32_t(rng() % d);
      const std::uint32_t j = i < 4 ? (i % 2 ? (1u << 24) - 1 : 0) : rng() >> 8;
      const double x = c + double(j) * 0x1p-24;
      const double q = x * div.recip;
      const double fast = std::fma(std::fma(-q, double(d), x), div.recip, q);
      mismatches += float(x / d) != float(fast);
      ++checked;
    }
  }
  INFO(checked << " quotients");
  CHECK(mismatches == 0);
  CHECK(Divisor32(1u << 26).recip == 0);
  CHECK(Divisor32((1u << 26) + 3).recip == 0);
}

TEST_CASE("stratified draws in lanes give the one-by-one numbers, on every SIMD path",
          "[sampler]") {
  // 2-D and 1-D draws; sample counts whose grids are square, oblong, prime, a
  // power of two (no cycle-walking) or not (walks of different lengths per lane),
  // and large enough that the remainders and quotients need their high halves;
  // indices up to and past the grid (the scalar fallback); every block size.
  const std::vector<std::string> paths = stratified_lanes_paths();
  REQUIRE(!paths.empty());
  CHECK(paths.back() == "generic");
  for (const std::string& path : paths) {
    INFO("path " << path);
    std::uint64_t mismatches = 0, draws = 0;
    // (1-D draws over 2^26 - 5 and 2^26 + 3 strata: the last quotients with and the
    // first without Divisor32::recip.)
    for (std::uint32_t spp : {1u, 2u, 3u, 4u, 5u, 7u, 16u, 50u, 100u, 1000u, 65537u, 1u << 20,
                              (1u << 26) - 5, (1u << 26) + 3}) {
      SamplerSpec spec{ir::SamplerKind::Stratified, 0x77 + spp, spp};
      for (std::uint32_t n : {16u, 13u, 1u})
        for (std::uint32_t dim : {std::uint32_t(kDimPixel), std::uint32_t(kDimTime), 0x9e3779b9u})
          for (bool two_d : {true, false}) {
            StrataLanes lanes;
            DimKey keys[StrataLanes::kLanes];
            for (std::uint32_t l = 0; l < n; ++l) {
              std::uint64_t pixel = pixel_hash(spec, l * 5 + n, dim % 11);
              keys[l] = two_d ? dim_key(spec, pixel, dim) : dim_key1(spec, pixel, dim);
              lanes.set(l, keys[l]);
            }
            for (std::uint32_t i = 0; i < spp + spp / 2 + 3; i += 1 + spp / 40) {
              alignas(64) float u[StrataLanes::kLanes], v[StrataLanes::kLanes];
              REQUIRE(stratified_lanes_with(path, spec, lanes, n, i, u, two_d ? v : nullptr));
              for (std::uint32_t l = 0; l < n; ++l) {
                if (two_d) {
                  Sample2 one = sample2(spec, keys[l], i);
                  mismatches += (one.u != u[l]) + (one.v != v[l]);
                } else {
                  mismatches += sample1(spec, keys[l], i) != u[l];
                }
                ++draws;
              }
            }
          }
    }
    INFO(draws << " draws");
    CHECK(draws > 20000);
    CHECK(mismatches == 0);
  }
  CHECK_FALSE(
      stratified_lanes_with("no such path", SamplerSpec{}, StrataLanes{}, 1, 0, nullptr, nullptr));
}

TEST_CASE("stratified dimensions drawn together give the numbers of each drawn alone",
          "[sampler]") {
  // One to kMaxStrataDims key sets in one call, whose permutations walk different
  // numbers of rounds (a grid that is not a power of two), 2-D and 1-D, on every path.
  for (const std::string& path : stratified_lanes_paths()) {
    INFO("path " << path);
    const StratifiedLanesFn fn = stratified_lanes_path(path);
    REQUIRE(fn);
    std::uint64_t mismatches = 0, draws = 0;
    for (std::uint32_t spp : {3u, 16u, 100u, 1000u}) {
      SamplerSpec spec{ir::SamplerKind::Stratified, 0x99 + spp, spp};
      for (std::uint32_t count = 1; count <= kMaxStrataDims; ++count)
        for (bool two_d : {true, false}) {
          StrataLanes lanes[kMaxStrataDims];
          const StrataLanes* kp[kMaxStrataDims];
          DimKey keys[kMaxStrataDims][StrataLanes::kLanes];
          for (std::uint32_t c = 0; c < count; ++c) {
            for (std::uint32_t l = 0; l < StrataLanes::kLanes; ++l) {
              std::uint64_t pixel = pixel_hash(spec, l + 3 * c, spp);
              keys[c][l] = two_d ? dim_key(spec, pixel, 40 + c) : dim_key1(spec, pixel, 40 + c);
              lanes[c].set(l, keys[c][l]);
            }
            kp[c] = &lanes[c];
          }
          for (std::uint32_t i = 0; i < spp; i += 1 + spp / 50) {
            alignas(64) float u[kMaxStrataDims][StrataLanes::kLanes];
            alignas(64) float v[kMaxStrataDims][StrataLanes::kLanes];
            float *up[kMaxStrataDims], *vp[kMaxStrataDims];
            for (std::uint32_t c = 0; c < kMaxStrataDims; ++c) up[c] = u[c], vp[c] = v[c];
            fn(spec, kp, count, StrataLanes::kLanes, i, up, two_d ? vp : nullptr);
            for (std::uint32_t c = 0; c < count; ++c)
              for (std::uint32_t l = 0; l < StrataLanes::kLanes; ++l, ++draws) {
                if (two_d) {
                  Sample2 one = sample2(spec, keys[c][l], i);
                  mismatches += (one.u != u[c][l]) + (one.v != v[c][l]);
                } else {
                  mismatches += sample1(spec, keys[c][l], i) != u[c][l];
                }
              }
          }
        }
    }
    INFO(draws << " draws");
    CHECK(draws > 10000);
    CHECK(mismatches == 0);
  }
}

TEST_CASE("a light cell's keys in lanes are the one-by-one keys, on every SIMD path", "[sampler]") {
  // node_dim of the cell, then the pixel's key of it, then (independent) the
  // sample's: the scalar composition the one-lane draw makes (draw2 of node_dim).
  const std::vector<std::string> paths = cell_keys_lanes_paths();
  REQUIRE(!paths.empty());
  CHECK(paths.back() == "generic");
  for (const std::string& path : paths) {
    INFO("path " << path);
    std::uint64_t mismatches = 0, n = 0;
    for (std::uint64_t round = 0; round < 64; ++round) {
      alignas(64) std::uint64_t keys[kHashLanes], pixels[kHashLanes], indices[kHashLanes],
          out[kHashLanes];
      const std::uint64_t cell = round % 2 ? (std::uint64_t(round) << 40) | round : ~round;
      for (std::uint32_t l = 0; l < kHashLanes; ++l) {
        keys[l] = round == 0 ? 0 : round == 1 ? ~0ull : hash64(round * 131 + l);
        pixels[l] = hash64(round ^ (std::uint64_t(l) << 40));
        indices[l] = l % 3 == 0 ? l : round * 1000 + l;
      }
      for (const std::uint64_t* idx : {static_cast<const std::uint64_t*>(indices),
                                       static_cast<const std::uint64_t*>(nullptr)}) {
        REQUIRE(cell_keys_lanes_with(path, keys, cell, pixels, idx, out));
        for (std::uint32_t l = 0; l < kHashLanes; ++l, ++n) {
          const std::uint32_t dim =
              kDimFirstFree + std::uint32_t(hash_combine(keys[l], cell) & 0x7fffffffu);
          std::uint64_t want = hash_combine(pixels[l], dim);
          if (idx) want = hash_combine(want, idx[l]);
          mismatches += out[l] != want;
        }
      }
    }
    CHECK(n == 2 * 64 * kHashLanes);
    CHECK(mismatches == 0);
  }
  CHECK_FALSE(cell_keys_lanes_with("no such path", nullptr, 0, nullptr, nullptr, nullptr));
}

TEST_CASE("the exact divisor agrees with division for every kind of divisor", "[sampler]") {
  for (std::uint32_t d :
       {1u, 2u, 3u, 7u, 10u, 255u, 256u, 65535u, 1000003u, 0x7fffffffu, 0xfffffffeu, 0xffffffffu}) {
    Divisor32 div(d);
    for (std::uint32_t a :
         {0u, 1u, d - 1, d, d + 1, 12345678u, 0x80000000u, 0xfffffffeu, 0xffffffffu}) {
      CHECK(div.quot(a) == a / d);
      CHECK(div.rem(a) == a % d);
    }
  }
  for (std::uint32_t d : {1u, 2u, 3u, 5u, 17u, 100u, 0xfffffffbu})
    for (std::uint64_t a = 0; a < (1u << 20); a += 3) {
      REQUIRE(Divisor32(d).quot(std::uint32_t(a * 4099)) == std::uint32_t(a * 4099) / d);
      REQUIRE(Divisor32(d).rem(std::uint32_t(a * 4099)) == std::uint32_t(a * 4099) % d);
    }
}

// The SIMD draws place a jitter in its cell by a product where the grid side is a
// power of two: the same bits as the division, for every cell and jitter a draw
// can have (cells below 2^32, jitters k * 2^-24).
TEST_CASE("the divisor's quotient in double is the division's, by product or not", "[sampler]") {
  for (std::uint32_t d : {1u, 2u, 3u, 4u, 8u, 10u, 16u, 64u, 1024u, 1u << 31, 0xffffffffu}) {
    const Divisor32 div(d);
    CHECK(div.pow2 == ((d & (d - 1)) == 0));
    if (div.pow2) CHECK((1u << div.shift) == d);
    std::uint64_t h = d;
    for (int i = 0; i < 20000; ++i) {
      h = hash64(h);
      const double x =
          double(std::uint32_t(h) % (d == 1 ? 1 : d)) + to_unit_float(std::uint32_t(h >> 32));
      const double q = div.over(x), ref = x / d;
      REQUIRE(std::memcmp(&q, &ref, sizeof q) == 0);
    }
  }
}

TEST_CASE("a sample's dimensions drawn as lanes give what draw2 gives each", "[sampler]") {
  // Lane counts 1..16 (the SIMD paths read all sixteen lanes), with and without
  // the pixel's key cache, at sample indices past the grid too.
  std::uint64_t mismatches = 0, draws = 0;
  for (auto kind :
       {ir::SamplerKind::Independent, ir::SamplerKind::Stratified, ir::SamplerKind::Sobol})
    for (std::uint32_t spp : {1u, 9u, 16u, 36u, 100u}) {
      SamplerSpec spec{kind, 0x1234 + spp, spp};
      for (std::uint32_t n = 1; n <= kDrawLanes; ++n) {
        DimCache cache;
        SampleContext sc{spec, 3 * n, 7, 0, pixel_hash(spec, 3 * n, 7), n % 2 ? &cache : nullptr};
        std::uint32_t dims[kDrawLanes];
        for (std::uint32_t j = 0; j < n; ++j) dims[j] = kDimFirstFree + 0x9e3779b9u * (j + n);
        for (std::uint32_t i = 0; i < spp + 3; ++i) {
          sc.index = i;
          alignas(64) float u[kDrawLanes], v[kDrawLanes];
          draw2_dims(sc, dims, n, u, v);
          for (std::uint32_t j = 0; j < n; ++j) {
            Sample2 s = sample2(spec, sc.pixel, i, dims[j]);
            mismatches += (s.u != u[j]) + (s.v != v[j]);
            ++draws;
          }
        }
      }
    }
  INFO(draws << " draws");
  CHECK(mismatches == 0);
}
