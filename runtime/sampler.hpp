// Samplers: every value is a pure function of (seed, pixel, sample index, dimension)
// plus the pixel's sample count, so the image does not depend on threads or tile
// order. Values lie in [0, 1) and are never exactly 1: they are built from 24-bit
// integers (k · 2^-24), which float represents exactly.
//
// - independent: a hash of all inputs.
// - stratified: per dimension pair, a jittered m×k grid (m = floor(sqrt(spp)),
//   k = ceil(spp / m)); the pixel's samples take distinct cells through a hashed
//   permutation (Kensler 2013), different per dimension pair, so pairs decorrelate.
//   When m·k > spp the unused cells are random, so each sample is still uniform.
// - sobol: the first two Sobol' dimensions, Owen-scrambled with a hash seeded by
//   (seed, pixel, dimension) and with a shuffled index (Burley 2020, "Practical
//   Hash-based Owen Scrambling"). Best with power-of-two sample counts.
//
// Dimensions are requested in pairs (`sample2`) or alone (`sample1`). A 1-D request
// is stratified on its own axis: the stratified sampler uses spp strata (not the
// columns of the 2-D grid) and sobol uses its first, (0,1)-sequence dimension.
//
// Allocation (the same for every sampler kind and every kernel, so specialising on
// ir::Features never changes which numbers a decision gets, docs/effects.md):
//   0 pixel (2-D), 1 lens (2-D), 2 time (1-D), then per ray-tree node dimensions
//   hashed from the node's path key: glossy jitter, and each area-light grid cell.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "runtime/ir/ir.hpp"

namespace snell::rt {

struct Sample2 {
  float u = 0, v = 0;
};

// Fixed dimensions of a camera sample; the ray tree draws further dimensions from
// hashed per-node keys (integrator.cpp).
enum : std::uint32_t {
  kDimPixel = 0,  // film position inside the pixel
  kDimLens = 1,   // lens position (depth of field)
  kDimTime = 2,   // shutter fraction (motion blur), 1-D
  kDimFirstFree = 3,
};

// A divisor fixed per render, so the hot path divides by multiplying (Lemire,
// Kaser, Kurz 2019, "Faster remainder by direct computation"): exact for every
// 32-bit numerator and every divisor >= 1.
// A power of two (the grids of 4, 16, 64 or 256 samples) also keeps its shift and
// its reciprocal, which is exact: the SIMD draws mask, shift and multiply instead,
// with the same results.
struct Divisor32 {
  std::uint32_t d = 1;
  std::uint64_t magic = 0;  // ceil(2^64 / d); 0 (wrapped) for d = 1, handled apart
  bool pow2 = true;
  std::uint32_t shift = 0;  // log2(d) when pow2
  double inv = 1;           // 1 / d when pow2 (exact), else 0
  // 1 / d rounded, when d < 2^26: then a quotient x / d of an x < d with 24
  // fraction bits (a jitter placed in its cell) rounds to the same float through
  // Markstein's correction, q = x·recip, q + (x − q·d)·recip in two FMAs, as through
  // the division (the SIMD paths; test_sampler.cpp). Else 0.
  double recip = 0;
  Divisor32() = default;
  explicit Divisor32(std::uint32_t divisor) : d(divisor ? divisor : 1) {
    magic = d == 1 ? 0 : ~std::uint64_t(0) / d + 1;
    pow2 = (d & (d - 1)) == 0;
    shift = pow2 ? std::uint32_t(__builtin_ctz(d)) : 0;
    inv = pow2 ? 1.0 / d : 0;
    recip = d < (1u << 26) ? 1.0 / d : 0;
  }
  // x / d in double, correctly rounded: a product when 1/d is exact (a product by
  // a power of two is exact, as is the quotient, so both give the same bits).
  double over(double x) const { return pow2 ? x * inv : x / d; }
  std::uint32_t quot(std::uint32_t a) const {
    return d == 1 ? a : std::uint32_t((__uint128_t(magic) * a) >> 64);
  }
  std::uint32_t rem(std::uint32_t a) const {
    return std::uint32_t((__uint128_t(magic * a) * d) >> 64);
  }
};

// What a render asks of its sampler, and what every draw would otherwise recompute:
// the stratified grid (m × k cells for 2-D, spp strata for 1-D), the bit masks of
// their hashed permutations and the divisors. `spp` is read-only after
// construction because the rest derives from it.
class SamplerSpec {
 public:
  ir::SamplerKind kind = ir::SamplerKind::Stratified;
  std::uint64_t seed = 0;

  SamplerSpec() : SamplerSpec(ir::SamplerKind::Stratified, 0, 1) {}
  SamplerSpec(ir::SamplerKind kind_, std::uint64_t seed_, std::uint32_t spp);
  std::uint32_t spp() const { return spp_; }

  // Derived. 2-D: m = floor(sqrt(n)) rows, k = ceil(n / m) columns; 1-D: n strata.
  std::uint32_t n = 1, m = 1, k = 1, cells = 1;
  std::uint32_t cells_mask = 0, n_mask = 0;  // 2^ceil(log2 x) - 1: the permutation's domain
  Divisor32 div_cells, div_k, div_m, div_n;

 private:
  std::uint32_t spp_ = 1;
};

// Helpers, exposed for the integrator and tests. Inline: every sample hashes.
[[gnu::always_inline]] inline std::uint64_t hash64(std::uint64_t x) {  // splitmix64 finaliser
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}
[[gnu::always_inline]] inline std::uint64_t hash_combine(std::uint64_t a, std::uint64_t b) {
  return hash64(a ^ (hash64(b) + 0x9e3779b97f4a7c15ull + (a << 6) + (a >> 2)));
}

// The pixel's part of every sample's key; the render loop computes it once per
// pixel and passes it to the keyed overloads below.
inline std::uint64_t pixel_hash(const SamplerSpec& spec, std::uint32_t px, std::uint32_t py) {
  return hash_combine(spec.seed, (std::uint64_t(py) << 32) | px);
}

// 24-bit float in [0, 1) from the top bits of a 32-bit integer.
// (Through int32, exact below 2^24: SSE2 converts only signed integers, so an
// unsigned conversion keeps a loop of draws from vectorising.)
inline float to_unit_float(std::uint32_t bits) {
  return static_cast<float>(static_cast<std::int32_t>(bits >> 8)) * (1.0f / 16777216.0f);
}
// 2^ceil(log2 n) - 1 (0 for n <= 1): the domain mask of permute().
inline std::uint32_t permute_mask(std::uint32_t n) {
  if (n <= 1) return 0;
  std::uint32_t w = n - 1;
  w |= w >> 1;
  w |= w >> 2;
  w |= w >> 4;
  w |= w >> 8;
  w |= w >> 16;
  return w;
}
// Kensler's hashed permutation of [0, l) ("Correlated Multi-Jittered Sampling",
// 2013), with the mask and divisor of l precomputed; cycle-walks when l is not a
// power of two (fewer than 2 rounds on average).
inline std::uint32_t permute(std::uint32_t i, const Divisor32& l, std::uint32_t w,
                             std::uint32_t p) {
  if (l.d <= 1) return 0;
  // The round's i *= 1 | p >> 27 and i *= 0x6935fa69, as one product (mod 2^32).
  const std::uint32_t mul = (1 | p >> 27) * 0x6935fa69u;
  do {
    i ^= p;
    i *= 0xe170893d;
    i ^= p >> 16;
    i ^= (i & w) >> 4;
    i ^= p >> 8;
    i *= 0x0929eb3f;
    i ^= p >> 23;
    i ^= (i & w) >> 1;
    i *= mul;
    i ^= (i & w) >> 11;
    i *= 0x74dcb303;
    i ^= (i & w) >> 2;
    i *= 0x9e501cc3;
    i ^= (i & w) >> 2;
    i *= 0xc860a3df;
    i &= w;
    i ^= i >> 5;
  } while (i >= l.d);
  return l.rem(i + p);
}
// The same, for an n known only here (tests).
std::uint32_t permute(std::uint32_t i, std::uint32_t n, std::uint32_t key);

namespace detail {

// On std::uint32_t, or four lanes of it (U32x4, sobol2_lanes): one body for both.
template <class U>
[[gnu::always_inline]] constexpr U reverse_bits(U x) {
  x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
  x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
  x = ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
  x = ((x >> 8) & 0x00ff00ffu) | ((x & 0x00ff00ffu) << 8);
  return (x >> 16) | (x << 16);
}
// Laine–Karras style hash that only lets lower bits affect higher ones; applied to
// bit-reversed values it is a nested uniform (Owen) scramble.
// (The multipliers are shared with the SIMD paths of sampler_lanes.cpp, which
// cannot call this template on their wide vectors under clang.)
inline constexpr std::uint32_t kLkMultipliers[4] = {0x6c50b47cu, 0xb82f1e52u, 0xc7afe638u,
                                                    0x8d22f6e6u};
template <class U>
[[gnu::always_inline]] inline U lk_permutation(U x, U seed) {
  x += seed;
  for (std::uint32_t c : kLkMultipliers) x ^= x * c;
  return x;
}
inline std::uint32_t owen_scramble(std::uint32_t x, std::uint32_t seed) {
  return reverse_bits(lk_permutation(reverse_bits(x), seed));
}
// Sobol' dimension 1 as a 32-bit fraction, bit-reversed (the scramble works on
// reversed values; reversal is linear over XOR, so the table holds reversed
// direction numbers): the XOR of the direction numbers v_j (v_0 = 2^31,
// v_j+1 = v_j ^ v_j >> 1) of i's set bits, a byte at a time from four 256-entry
// tables (4 KiB) instead of a loop over all 32 bits of the scrambled index.
struct Sobol1Tables {
  std::uint32_t t[4][256] = {};
  constexpr Sobol1Tables() {
    std::uint32_t v[32] = {};
    v[0] = 1u << 31;
    for (int j = 1; j < 32; ++j) v[j] = v[j - 1] ^ (v[j - 1] >> 1);
    for (int b = 0; b < 4; ++b)
      for (std::uint32_t x = 0; x < 256; ++x) {
        std::uint32_t r = 0;
        for (int bit = 0; bit < 8; ++bit)
          if (x >> bit & 1) r ^= v[8 * b + bit];
        t[b][x] = reverse_bits(r);
      }
  }
};
inline constexpr Sobol1Tables kSobol1{};
inline std::uint32_t reversed_sobol1(std::uint32_t i) {
  return kSobol1.t[0][i & 255] ^ kSobol1.t[1][i >> 8 & 255] ^ kSobol1.t[2][i >> 16 & 255] ^
         kSobol1.t[3][i >> 24];
}
// [0, 1) in float, guarding the rounding up to 1.
inline float unit(double x) {
  float f = static_cast<float>(x);
  return f < 1.0f ? f : 0x1.fffffep-1f;
}

}  // namespace detail

// What a draw needs of (seed, pixel, dimension): the same for every sample index of
// a pixel, so a pixel loop computes it once per dimension (dim_key) and each draw
// costs only its index's work. `key` is hash_combine(pixel, dim) (for a 1-D
// stratified draw hash_combine(pixel, dim ^ 0x1d1d)); sobol also keeps the seeds of
// its two value scrambles, which the other kinds leave 0.
struct DimKey {
  std::uint64_t key = 0;
  std::uint32_t seed_u = 0, seed_v = 0;
};
// The DimKey of a dimension whose key hash_combine(pixel, dim) is `key` (found
// for many lanes at once by cell_keys_lanes): with sobol, its seeds too.
[[gnu::always_inline]] inline DimKey dim_key_of_hash(const SamplerSpec& spec, std::uint64_t key) {
  DimKey k{key};
  if (spec.kind == ir::SamplerKind::Sobol) {
    k.seed_u = std::uint32_t(hash64(k.key + 1));
    k.seed_v = std::uint32_t(hash64(k.key + 2));
  }
  return k;
}
[[gnu::always_inline]] inline DimKey dim_key(const SamplerSpec& spec, std::uint64_t pixel,
                                             std::uint32_t dim) {
  return dim_key_of_hash(spec, hash_combine(pixel, dim));
}
// The key of a 1-D draw (sample1): the stratified sampler stratifies a 1-D draw on
// its own axis, under its own key; the others take the u of the 2-D draw.
[[gnu::always_inline]] inline DimKey dim_key1(const SamplerSpec& spec, std::uint64_t pixel,
                                              std::uint32_t dim) {
  if (spec.kind == ir::SamplerKind::Stratified) return DimKey{hash_combine(pixel, dim ^ 0x1d1du)};
  return dim_key(spec, pixel, dim);
}

// Inline with the spec's precomputed grid: a draw is hashes, a permutation and
// multiplications, with no division but the two that place the value in its cell
// (kept in double so the numbers stay those of the original formula; products
// where the grid's sides are powers of two).
// The independent sampler's draw from its hash hash_combine(key, index): the low
// and high halves as two floats.
[[gnu::always_inline]] inline Sample2 independent_sample(std::uint64_t h) {
  return {to_unit_float(std::uint32_t(h)), to_unit_float(std::uint32_t(h >> 32))};
}
[[gnu::always_inline]] inline Sample2 sample2(const SamplerSpec& spec, const DimKey& dk,
                                              std::uint32_t index) {
  const std::uint64_t pixel_key = dk.key;
  switch (spec.kind) {
    case ir::SamplerKind::Independent:
      return independent_sample(hash_combine(pixel_key, index));
    case ir::SamplerKind::Stratified: {
      std::uint32_t cell =
          index < spec.cells
              ? permute(index, spec.div_cells, spec.cells_mask, std::uint32_t(pixel_key))
              : std::uint32_t(hash_combine(pixel_key, index) % spec.cells);
      std::uint64_t h = hash_combine(pixel_key ^ 0x5bd1e995u, index);
      float ju = to_unit_float(std::uint32_t(h)), jv = to_unit_float(std::uint32_t(h >> 32));
      std::uint32_t cy = spec.div_k.quot(cell), cx = cell - cy * spec.k;
      return {detail::unit(spec.div_k.over(cx + double(ju))),
              detail::unit(spec.div_m.over(cy + double(jv)))};
    }
    case ir::SamplerKind::Sobol: {
      // owen_scramble(x, s) = reverse(lk(reverse(x), s)); written out so that
      // reversals that cancel are not computed (dimension 0 is reverse(i)).
      std::uint32_t i = detail::owen_scramble(index, std::uint32_t(pixel_key));
      std::uint32_t x = detail::reverse_bits(detail::lk_permutation(i, dk.seed_u));
      std::uint32_t y =
          detail::reverse_bits(detail::lk_permutation(detail::reversed_sobol1(i), dk.seed_v));
      return {to_unit_float(x), to_unit_float(y)};
    }
  }
  return {};
}

// A 1-D draw with its dim_key1.
[[gnu::always_inline]] inline float sample1(const SamplerSpec& spec, const DimKey& dk,
                                            std::uint32_t index) {
  if (spec.kind != ir::SamplerKind::Stratified) {
    // sobol's u needs neither the v scramble nor the second Sobol' dimension.
    if (spec.kind == ir::SamplerKind::Sobol) {
      std::uint32_t i = detail::owen_scramble(index, std::uint32_t(dk.key));
      return to_unit_float(detail::reverse_bits(detail::lk_permutation(i, dk.seed_u)));
    }
    return sample2(spec, dk, index).u;
  }
  // 1-D jitter over spp strata, the sample-to-stratum map a hashed permutation.
  const std::uint64_t pixel_key = dk.key;
  std::uint32_t cell = index < spec.n
                           ? permute(index, spec.div_n, spec.n_mask, std::uint32_t(pixel_key))
                           : std::uint32_t(hash_combine(pixel_key, index) % spec.n);
  float j = to_unit_float(std::uint32_t(hash_combine(pixel_key ^ 0x5bd1e995u, index)));
  return detail::unit(spec.div_n.over(cell + double(j)));
}

[[gnu::always_inline]] inline Sample2 sample2(const SamplerSpec& spec, std::uint64_t pixel,
                                              std::uint32_t index, std::uint32_t dim) {
  return sample2(spec, dim_key(spec, pixel, dim), index);
}
[[gnu::always_inline]] inline float sample1(const SamplerSpec& spec, std::uint64_t pixel,
                                            std::uint32_t index, std::uint32_t dim) {
  return sample1(spec, dim_key1(spec, pixel, dim), index);
}

// One sobol dimension pair of up to kLanes pixels, as arrays of their DimKeys'
// seeds: sobol2_lanes draws one sample index for all of them at once (plain loops
// would stay scalar, as GCC turns the bit reversal into a scalar bswap). Each lane
// draws exactly what sample2(spec, its key, index) does
// (tests/runtime/test_sampler.cpp).
struct SobolLanes {
  static constexpr std::uint32_t kLanes = 16;
  alignas(16) std::uint32_t index_seed[kLanes] = {}, seed_u[kLanes] = {}, seed_v[kLanes] = {};
  void set(std::uint32_t lane, const DimKey& k) {
    index_seed[lane] = std::uint32_t(k.key), seed_u[lane] = k.seed_u, seed_v[lane] = k.seed_v;
  }
};

// u[0, n), v[0, n), in the widest SIMD path this CPU has (sampler_lanes.cpp);
// every path draws the same numbers. Both arrays need room for kLanes floats: a
// path may write all of them (lanes from n on are unspecified), since a masked
// store would keep the caller's loads of single lanes from being forwarded.
void sobol2_lanes(const SobolLanes& k, std::uint32_t n, std::uint32_t index, float* u, float* v);
// The paths this build and CPU offer, best (the one sobol2_lanes uses) first, and
// one of them by name (false if it is not offered): for tests and benchmarks.
std::vector<std::string> sobol2_lanes_paths();
bool sobol2_lanes_with(const std::string& path, const SobolLanes& k, std::uint32_t n,
                       std::uint32_t index, float* u, float* v);
// A path's function itself (null if it is not offered), so that a benchmark looks
// the name up once and not per call, as the renderer does.
using Sobol2LanesFn = void (*)(const SobolLanes&, std::uint32_t, std::uint32_t, float*, float*);
Sobol2LanesFn sobol2_lanes_path(const std::string& path);

// One stratified dimension (2-D or 1-D) of up to kLanes pixels, as their DimKeys'
// keys (dim_key for stratified2_lanes, dim_key1 for stratified1_lanes). Each lane
// draws exactly what sample2 / sample1 draw with its key (test_sampler.cpp).
struct StrataLanes {
  static constexpr std::uint32_t kLanes = 16;
  alignas(64) std::uint64_t key[kLanes] = {};
  void set(std::uint32_t lane, const DimKey& k) { key[lane] = k.key; }
};
// u[0, n) (and v[0, n)) of a stratified spec at one sample index, in the widest
// SIMD path this CPU has; room for kLanes floats each, as for sobol2_lanes.
void stratified2_lanes(const SamplerSpec& spec, const StrataLanes& k, std::uint32_t n,
                       std::uint32_t index, float* u, float* v);
void stratified1_lanes(const SamplerSpec& spec, const StrataLanes& k, std::uint32_t n,
                       std::uint32_t index, float* u);
// count (at most kMaxStrataDims) 2-D dimensions of the same lanes at once: k[c]
// into u[c], v[c], the numbers of stratified2_lanes on each. Faster than one by
// one where the grid is not a power of two: each dimension's permutation walks a
// chain of dependent products, and the chains interleave.
inline constexpr std::uint32_t kMaxStrataDims = 4;
void stratified2_lanes(const SamplerSpec& spec, const StrataLanes* const* k, std::uint32_t count,
                       std::uint32_t n, std::uint32_t index, float* const* u, float* const* v);
// The paths, best first, and one by name (v null: the 1-D draw), for tests and
// benchmarks. A path's function draws `count` dimensions as the overload above
// (v null: 1-D draws).
std::vector<std::string> stratified_lanes_paths();
bool stratified_lanes_with(const std::string& path, const SamplerSpec& spec, const StrataLanes& k,
                           std::uint32_t n, std::uint32_t index, float* u, float* v);
using StratifiedLanesFn = void (*)(const SamplerSpec&, const StrataLanes* const*, std::uint32_t,
                                   std::uint32_t, std::uint32_t, float* const*, float* const*);
StratifiedLanesFn stratified_lanes_path(const std::string& path);

// A packet's lanes of per-lane sampler keys (cell_keys_lanes).
inline constexpr std::uint32_t kHashLanes = 16;
// The keys a packet's lanes draw a light cell's jitter with (whitted_light.hpp),
// three hash_combines in one pass: lane i's node dimension of `cell`
// (kDimFirstFree + the low 31 bits of hash_combine(node_keys[i], cell)), the
// pixel's key of it (hash_combine(pixels[i], dim)), and with `indices` (the
// independent sampler) that key combined with indices[i]. kHashLanes lanes.
void cell_keys_lanes(const std::uint64_t* node_keys, std::uint64_t cell,
                     const std::uint64_t* pixels, const std::uint64_t* indices, std::uint64_t* out);
std::vector<std::string> cell_keys_lanes_paths();
bool cell_keys_lanes_with(const std::string& path, const std::uint64_t* node_keys,
                          std::uint64_t cell, const std::uint64_t* pixels,
                          const std::uint64_t* indices, std::uint64_t* out);

// A pixel's keys of the dimensions its ray trees draw, remembered across its
// samples: a ray tree's per-node dimensions (an area light's cells at the first
// hit, a glossy lobe) are the same for every sample of a pixel that reaches the
// same node, so most draws find their key here. Direct-mapped on the dimension;
// the tag tells a 2-D key from a 1-D one. Purely a cache: a draw gives the same
// number with or without it.
struct DimCache {
  static constexpr std::uint32_t kSlots = 16;
  std::uint64_t tag[kSlots] = {};  // 0: empty; else dim | (1 or 2) << 32
  DimKey key[kSlots];
  // Empties the cache: only the tags (a fresh cache was a 384-byte `rep stos` per
  // pixel of a packet, 2 % of a diffuse render).
  void reset() {
    for (std::uint64_t& t : tag) t = 0;
  }
  template <bool one_d>
  [[gnu::always_inline]] const DimKey& get(const SamplerSpec& spec, std::uint64_t pixel,
                                           std::uint32_t dim) {
    const std::uint64_t t = dim | (std::uint64_t(one_d ? 2 : 1) << 32);
    const std::uint32_t slot = (dim ^ (dim >> 7)) & (kSlots - 1);
    if (tag[slot] != t) {
      tag[slot] = t;
      key[slot] = one_d ? dim_key1(spec, pixel, dim) : dim_key(spec, pixel, dim);
    }
    return key[slot];
  }
};

inline Sample2 sample2(const SamplerSpec& spec, std::uint32_t px, std::uint32_t py,
                       std::uint32_t index, std::uint32_t dim) {
  return sample2(spec, pixel_hash(spec, px, py), index, dim);
}
inline float sample1(const SamplerSpec& spec, std::uint32_t px, std::uint32_t py,
                     std::uint32_t index, std::uint32_t dim) {
  return sample1(spec, pixel_hash(spec, px, py), index, dim);
}

std::string to_string(const SamplerSpec& s);
std::string to_string(Sample2 s);

}  // namespace snell::rt
