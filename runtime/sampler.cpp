#include "runtime/sampler.hpp"

#include <fmt/format.h>

#include <cmath>

namespace snell::rt {

std::uint32_t permute(std::uint32_t i, std::uint32_t l, std::uint32_t p) {
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

namespace {

std::uint32_t reverse_bits(std::uint32_t x) {
  x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
  x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
  x = ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
  x = ((x >> 8) & 0x00ff00ffu) | ((x & 0x00ff00ffu) << 8);
  return (x >> 16) | (x << 16);
}

// Laine–Karras style hash that only lets lower bits affect higher ones; applied to
// bit-reversed values it is a nested uniform (Owen) scramble.
std::uint32_t lk_permutation(std::uint32_t x, std::uint32_t seed) {
  x += seed;
  x ^= x * 0x6c50b47cu;
  x ^= x * 0xb82f1e52u;
  x ^= x * 0xc7afe638u;
  x ^= x * 0x8d22f6e6u;
  return x;
}

std::uint32_t owen_scramble(std::uint32_t x, std::uint32_t seed) {
  return reverse_bits(lk_permutation(reverse_bits(x), seed));
}

// Sobol' dimension 0 (van der Corput) and dimension 1, as 32-bit fractions.
std::uint32_t sobol0(std::uint32_t i) {
  return reverse_bits(i);
}
std::uint32_t sobol1(std::uint32_t i) {
  std::uint32_t r = 0;
  for (std::uint32_t v = 1u << 31; i; i >>= 1, v ^= v >> 1)
    if (i & 1) r ^= v;
  return r;
}

constexpr float kOneMinusUlp = 0x1.fffffep-1f;

float unit(double x) {  // [0, 1) in float, guarding the rounding up to 1
  float f = static_cast<float>(x);
  return f < 1.0f ? f : kOneMinusUlp;
}

}  // namespace

Sample2 sample2(const SamplerSpec& spec, std::uint64_t pixel, std::uint32_t index,
                std::uint32_t dim) {
  std::uint64_t pixel_key = hash_combine(pixel, dim);
  switch (spec.kind) {
    case ir::SamplerKind::Independent: {
      std::uint64_t h = hash_combine(pixel_key, index);
      return {to_unit_float(std::uint32_t(h)), to_unit_float(std::uint32_t(h >> 32))};
    }
    case ir::SamplerKind::Stratified: {
      std::uint32_t n = spec.spp == 0 ? 1 : spec.spp;
      std::uint32_t m = static_cast<std::uint32_t>(std::sqrt(double(n)));
      if (m == 0) m = 1;
      std::uint32_t k = (n + m - 1) / m;
      std::uint32_t cells = m * k;
      std::uint32_t cell = index < cells ? permute(index, cells, std::uint32_t(pixel_key))
                                         : std::uint32_t(hash_combine(pixel_key, index) % cells);
      std::uint64_t h = hash_combine(pixel_key ^ 0x5bd1e995u, index);
      float ju = to_unit_float(std::uint32_t(h)), jv = to_unit_float(std::uint32_t(h >> 32));
      std::uint32_t cx = cell % k, cy = cell / k;
      return {unit((cx + double(ju)) / k), unit((cy + double(jv)) / m)};
    }
    case ir::SamplerKind::Sobol: {
      std::uint32_t seed = std::uint32_t(pixel_key);
      std::uint32_t i = owen_scramble(index, seed);
      std::uint32_t x = owen_scramble(sobol0(i), std::uint32_t(hash64(pixel_key + 1)));
      std::uint32_t y = owen_scramble(sobol1(i), std::uint32_t(hash64(pixel_key + 2)));
      return {to_unit_float(x), to_unit_float(y)};
    }
  }
  return {};
}

float sample1(const SamplerSpec& spec, std::uint64_t pixel, std::uint32_t index,
              std::uint32_t dim) {
  if (spec.kind != ir::SamplerKind::Stratified) return sample2(spec, pixel, index, dim).u;
  // 1-D jitter over spp strata, the sample-to-stratum map a hashed permutation.
  std::uint64_t pixel_key = hash_combine(pixel, dim ^ 0x1d1du);
  std::uint32_t n = spec.spp == 0 ? 1 : spec.spp;
  std::uint32_t cell = index < n ? permute(index, n, std::uint32_t(pixel_key))
                                 : std::uint32_t(hash_combine(pixel_key, index) % n);
  float j = to_unit_float(std::uint32_t(hash_combine(pixel_key ^ 0x5bd1e995u, index)));
  return unit((cell + double(j)) / n);
}

std::string to_string(Sample2 s) {
  return fmt::format("({}, {})", s.u, s.v);
}

std::string to_string(const SamplerSpec& s) {
  return fmt::format("sampler {{ kind {} seed {} spp {} }}", ir::to_string(s.kind), s.seed, s.spp);
}

}  // namespace snell::rt
