// sobol2_lanes: a sobol dimension pair of up to 16 pixels at one sample index, in
// the widest integer SIMD the CPU has, chosen once at start-up. Every path computes
// the same integers as the scalar sample2 (only integer operations, then an exact
// int-to-float conversion and a multiplication by 2^-24), so the image does not
// depend on which one runs: tests/runtime/test_sampler.cpp checks each path
// available on the machine against the scalar draws.
//
// - avx512: AVX-512 (F, BW) with GFNI, 16 lanes at once. A bit reversal is one
//   GF(2) affine transform per byte (gf2p8affineqb with the anti-diagonal matrix)
//   and a byte shuffle; Sobol' dimension 1 is eight 16-entry tables, one per
//   nibble of the index, each a single vpermd from a register. x86-64 only.
// - generic: GCC/clang vector types, four lanes at a time (SSE2 on x86-64, NEON
//   on ARM), with scalar lookups of the byte tables.
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "runtime/sampler.hpp"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define SNELL_HAVE_AVX512_PATH 1
#endif

namespace snell::rt {

namespace {

using U32x4 = std::uint32_t __attribute__((vector_size(16)));
using I32x4 = std::int32_t __attribute__((vector_size(16)));
using F32x4 = float __attribute__((vector_size(16)));
// to_unit_float of four lanes.
inline F32x4 to_unit_float4(U32x4 bits) {
  return __builtin_convertvector(I32x4(bits >> 8), F32x4) * (1.0f / 16777216.0f);
}

void sobol2_lanes_generic(const SobolLanes& k, std::uint32_t n, std::uint32_t index, float* u,
                          float* v) {
  using namespace detail;
  for (std::uint32_t l = 0; l < n; l += 4) {
    U32x4 seed0, su, sv;
    __builtin_memcpy(&seed0, k.index_seed + l, 16);
    __builtin_memcpy(&su, k.seed_u + l, 16);
    __builtin_memcpy(&sv, k.seed_v + l, 16);
    const U32x4 idx = U32x4{} + index;
    // owen_scramble(index, seed0), then dimension 0 is reverse(i) scrambled.
    U32x4 i = reverse_bits(lk_permutation(reverse_bits(idx), seed0));
    F32x4 fu = to_unit_float4(reverse_bits(lk_permutation(i, su)));
    U32x4 s1 = {reversed_sobol1(i[0]), reversed_sobol1(i[1]), reversed_sobol1(i[2]),
                reversed_sobol1(i[3])};
    F32x4 fv = to_unit_float4(reverse_bits(lk_permutation(s1, sv)));
    __builtin_memcpy(u + l, &fu, 16);
    __builtin_memcpy(v + l, &fv, 16);
  }
}

#ifdef SNELL_HAVE_AVX512_PATH

// reversed_sobol1 by nibbles: t[j][x] is the reversed XOR of the direction numbers
// of x's set bits shifted to nibble j. Linear over XOR, so the XOR of the eight
// lookups is reversed_sobol1(i).
struct Sobol1Nibbles {
  alignas(64) std::uint32_t t[8][16] = {};
  constexpr Sobol1Nibbles() {
    for (int j = 0; j < 8; ++j)
      for (std::uint32_t x = 0; x < 16; ++x)  // x << 4j lies in byte j / 2
        t[j][x] = detail::kSobol1.t[j / 2][x << (4 * (j % 2))];
  }
};
constexpr Sobol1Nibbles kSobol1Nibbles{};

#define SNELL_AVX512_TARGET __attribute__((target("avx512f,avx512bw,gfni")))

// Lane arithmetic in vector types, intrinsics only for what they cannot say (GCC
// 12's headers warn falsely on their shifts and conversions, PR 105593).
using U32x16 = std::uint32_t __attribute__((vector_size(64)));
using I32x16 = std::int32_t __attribute__((vector_size(64)));
using F32x16 = float __attribute__((vector_size(64)));

SNELL_AVX512_TARGET inline U32x16 reverse16(U32x16 x) {
  // Bits within each byte (result bit i takes bit 7 - i: the anti-diagonal
  // matrix), then the bytes of each 32-bit lane.
  const __m512i bits = _mm512_set1_epi64(0x8040201008040201ll);
  const __m512i bytes = _mm512_set4_epi32(0x0c0d0e0f, 0x08090a0b, 0x04050607, 0x00010203);
  return U32x16(_mm512_shuffle_epi8(_mm512_gf2p8affine_epi64_epi8(__m512i(x), bits, 0), bytes));
}

SNELL_AVX512_TARGET inline U32x16 lk16(U32x16 x, U32x16 seed) {
  x += seed;
  for (std::uint32_t c : detail::kLkMultipliers) x ^= x * c;
  return x;
}

SNELL_AVX512_TARGET inline __m512 unit16(U32x16 bits) {
  return __m512(__builtin_convertvector(I32x16(bits >> 8), F32x16) * (1.0f / 16777216.0f));
}

SNELL_AVX512_TARGET void sobol2_lanes_avx512(const SobolLanes& k, std::uint32_t n,
                                             std::uint32_t index, float* u, float* v) {
  static_assert(SobolLanes::kLanes == 16);
  (void)n;  // all 16 lanes are drawn and stored: the caller has room for them
  U32x16 seed0, su, sv;
  std::memcpy(&seed0, k.index_seed, 64);
  std::memcpy(&su, k.seed_u, 64);
  std::memcpy(&sv, k.seed_v, 64);
  const U32x16 i = reverse16(lk16(reverse16(U32x16{} + index), seed0));
  _mm512_storeu_ps(u, unit16(reverse16(lk16(i, su))));
  U32x16 s1 = {};
  for (int j = 0; j < 8; ++j) {
    // vpermd reads only the low four bits of each index lane.
    U32x16 table;
    std::memcpy(&table, kSobol1Nibbles.t[j], 64);
    s1 ^= U32x16(_mm512_maskz_permutexvar_epi32(0xffff, __m512i(i >> (4 * j)), __m512i(table)));
  }
  _mm512_storeu_ps(v, unit16(reverse16(lk16(s1, sv))));
}

bool avx512_supported() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
         __builtin_cpu_supports("gfni");
}

#endif  // SNELL_HAVE_AVX512_PATH

using LanesFn = void (*)(const SobolLanes&, std::uint32_t, std::uint32_t, float*, float*);

struct LanesPath {
  const char* name;
  LanesFn fn;
};

// The paths this build has and this CPU runs, best first; SNELL_SIMD=generic
// forces the portable one (A/B measurements, and the tests of both paths).
const std::vector<LanesPath>& available() {
  static const std::vector<LanesPath> paths = [] {
    std::vector<LanesPath> p;
#ifdef SNELL_HAVE_AVX512_PATH
    const char* force = std::getenv("SNELL_SIMD");
    if (avx512_supported() && !(force && std::strcmp(force, "generic") == 0))
      p.push_back({"avx512", sobol2_lanes_avx512});
#endif
    p.push_back({"generic", sobol2_lanes_generic});
    return p;
  }();
  return paths;
}

const LanesFn g_sobol2_lanes = available().front().fn;

}  // namespace

void sobol2_lanes(const SobolLanes& k, std::uint32_t n, std::uint32_t index, float* u, float* v) {
  g_sobol2_lanes(k, n, index, u, v);
}

std::vector<std::string> sobol2_lanes_paths() {
  std::vector<std::string> names;
  for (const LanesPath& p : available()) names.push_back(p.name);
  return names;
}

bool sobol2_lanes_with(const std::string& path, const SobolLanes& k, std::uint32_t n,
                       std::uint32_t index, float* u, float* v) {
  for (const LanesPath& p : available())
    if (path == p.name) {
      p.fn(k, n, index, u, v);
      return true;
    }
  return false;
}

}  // namespace snell::rt
