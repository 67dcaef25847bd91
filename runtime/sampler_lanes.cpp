// sobol2_lanes: a sobol dimension pair of up to 16 pixels at one sample index, in
// the widest integer SIMD the CPU has, chosen once at start-up; stratified2_lanes
// and stratified1_lanes likewise for the stratified sampler (below). Every path computes
// the same integers as the scalar sample2 (only integer operations, then an exact
// int-to-float conversion and a multiplication by 2^-24), so the image does not
// depend on which one runs: tests/runtime/test_sampler.cpp checks each path
// available on the machine against the scalar draws.
//
// - avx512: AVX-512 (F, BW) with GFNI, 16 lanes at once. A bit reversal is one
//   GF(2) affine transform per byte (gf2p8affineqb with the anti-diagonal matrix)
//   and a byte shuffle; Sobol' dimension 1 is eight 16-entry tables, one per
//   nibble of the index, each a single vpermd from a register. x86-64 only.
// cell_keys_lanes: a light cell's sampler keys of sixteen lanes at once (three
// hash_combines each), in 64-bit lane products where the CPU has AVX-512 DQ.
//
// - avx2: AVX2 with FMA, eight lanes at once (sampler_lanes_avx2.cpp): nibble
//   lookups reverse the bits, and Sobol' dimension 1 gathers from the byte tables;
//   the 64-bit hashes of the stratified draws and cell_keys_lanes in 32x32-bit
//   products, four lanes at once.
// - generic: GCC/clang vector types, four lanes at a time (SSE2 on x86-64, NEON
//   on ARM), with scalar lookups of the byte tables.
#include <cstring>
#include <string>
#include <vector>

#include "runtime/sampler.hpp"
#include "runtime/sampler_lanes_isa.hpp"
#include "runtime/simd_paths.hpp"

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

// The stratified draws of 16 pixels at one sample index (sample2 / sample1 with
// each lane's key). The scalar draw is a Kensler permutation of the index (which
// cycle-walks a lane-dependent number of rounds), a splitmix64 jitter hash and a
// division in double placing the jitter in its cell; in lanes the permutation
// walks until every lane is in range (a lane keeps its first value in range),
// the hashes are 64-bit lane products (vpmullq), the Lemire remainders and
// quotients are 64x32-bit products split in halves (a mask and a shift when the
// grid's sides are powers of two), and the divisions are vdivpd (exact products
// for powers of two): the same IEEE results on the same operands, so the same bits.
// generic: the scalar draws, lane by lane.
void stratified_one_generic(const SamplerSpec& spec, const StrataLanes& k, std::uint32_t n,
                            std::uint32_t index, float* u, float* v) {
  for (std::uint32_t l = 0; l < n; ++l) {
    if (v) {
      Sample2 s = sample2(spec, DimKey{k.key[l]}, index);
      u[l] = s.u, v[l] = s.v;
    } else {
      u[l] = sample1(spec, DimKey{k.key[l]}, index);
    }
  }
}
void stratified_lanes_generic(const SamplerSpec& spec, const StrataLanes* const* k,
                              std::uint32_t count, std::uint32_t n, std::uint32_t index,
                              float* const* u, float* const* v) {
  for (std::uint32_t c = 0; c < count; ++c)
    stratified_one_generic(spec, *k[c], n, index, u[c], v ? v[c] : nullptr);
}

#ifdef SNELL_HAVE_AVX512_PATH

#define SNELL_AVX512DQ_TARGET __attribute__((target("avx512f,avx512bw,avx512dq")))

using U64x8 = std::uint64_t __attribute__((vector_size(64)));
using F64x8 = double __attribute__((vector_size(64)));
using F32x8 = float __attribute__((vector_size(32)));
using U32x8 = std::uint32_t __attribute__((vector_size(32)));
using I32x8 = std::int32_t __attribute__((vector_size(32)));

SNELL_AVX512DQ_TARGET inline U64x8 hash64_8(U64x8 x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}
// (x · d) >> 64 for 64-bit x and 32-bit d, exactly: the halves of x times d.
SNELL_AVX512DQ_TARGET inline U64x8 mulhi64x32(U64x8 x, std::uint64_t d) {
  U64x8 lo = (x & 0xffffffffull) * d, hi = (x >> 32) * d;
  return (hi + (lo >> 32)) >> 32;
}
// Divisor32::rem and ::quot of 8 lanes (a mask and a shift for a power of two).
SNELL_AVX512DQ_TARGET inline U64x8 rem8(U64x8 a, const Divisor32& l) {
  if (l.pow2) return a & (l.d - 1);
  return mulhi64x32(a * l.magic, l.d);
}
SNELL_AVX512DQ_TARGET inline U64x8 quot8(U64x8 a, const Divisor32& l) {
  if (l.pow2) return a >> l.shift;
  // (magic · a) >> 64 with a < 2^32: the halves of magic times a.
  U64x8 lo = (l.magic & 0xffffffffull) * a, hi = (l.magic >> 32) * a;
  return (hi + (lo >> 32)) >> 32;
}
SNELL_AVX512DQ_TARGET inline U64x8 widen(U32x8 x) {
  return __builtin_convertvector(x, U64x8);
}
// detail::unit of d.over(c + double(j)): exact sum, one IEEE division (or the
// product that gives its bits), rounded to float, kept below 1.
SNELL_AVX512DQ_TARGET inline F32x8 place8(U64x8 c, F32x8 j, const Divisor32& d) {
  const F64x8 sum = __builtin_convertvector(c, F64x8) + __builtin_convertvector(j, F64x8);
  const F64x8 x = d.pow2 ? sum * d.inv : sum / double(d.d);
  F32x8 f = __builtin_convertvector(x, F32x8);
  return f < 1.0f ? f : F32x8{} + 0x1.fffffep-1f;
}
SNELL_AVX512DQ_TARGET inline F32x8 unit8(U64x8 bits) {
  return __builtin_convertvector(I32x8(__builtin_convertvector(bits, U32x8) >> 8), F32x8) *
         (1.0f / 16777216.0f);
}

// permute(index, l, w, p[c]) of 16 lanes of N key sets p[c]. Kensler's rounds
// are written again here, as lk16 is: the scalar code cannot be inlined into a
// function of another target; test_sampler.cpp holds the two to the same bits.
// A round is one dependent chain of ~40 cycles (seven products), so the N walks
// go in one loop, each round of one filling the others' latency; a chain that is
// done still runs its rounds (cheaper than a branch), keeping its first value in
// range.
// a ^ (b & c), (a ^ b) & c and a ^ b ^ c in one instruction each (vpternlogd).
SNELL_AVX512DQ_TARGET inline U32x16 xor_and(U32x16 a, U32x16 b, U32x16 c) {
  return U32x16(_mm512_ternarylogic_epi32(__m512i(a), __m512i(b), __m512i(c), 0x78));
}
SNELL_AVX512DQ_TARGET inline U32x16 and_of_xor(U32x16 a, U32x16 b, U32x16 c) {
  return U32x16(_mm512_ternarylogic_epi32(__m512i(a), __m512i(b), __m512i(c), 0x28));
}
SNELL_AVX512DQ_TARGET inline U32x16 xor3(U32x16 a, U32x16 b, U32x16 c) {
  return U32x16(_mm512_ternarylogic_epi32(__m512i(a), __m512i(b), __m512i(c), 0x96));
}

// A chain's key-dependent terms of Kensler's round, the same every round.
struct KenslerKey {
  U32x16 q, q16_q8, q16_4, q23, q23_1, mul;
};
SNELL_AVX512DQ_TARGET inline KenslerKey kensler_key(U32x16 q) {
  // x · (1 | q >> 27) · 0x6935fa69 is x times their product, mod 2^32.
  return {q, (q >> 16) ^ (q >> 8), q >> 20, q >> 23, q >> 24, (1 | q >> 27) * 0x6935fa69u};
}
// One of Kensler's rounds (permute(), sampler.hpp): the same bits, in fewer and
// shorter steps. (x & w) >> k is (x >> k) & (w >> k); a step x ^= (x & w) >> k
// after x ^= a is x ^ a ^ (((x >> k) ^ (a >> k)) & (w >> k)), two ternary logic
// operations on a shift; and the two products in a row are one.
SNELL_AVX512DQ_TARGET inline U32x16 kensler_round(U32x16 x, const KenslerKey& k, U32x16 w,
                                                  U32x16 w4, U32x16 w1, U32x16 w11, U32x16 w2,
                                                  U32x16 w5) {
  x = (x ^ k.q) * 0xe170893du;
  x = xor3(x, k.q16_q8, and_of_xor(x >> 4, k.q16_4, w4));  // ^ q>>16, ^ (x&w)>>4, ^ q>>8
  x *= 0x0929eb3fu;
  x = xor3(x, k.q23, and_of_xor(x >> 1, k.q23_1, w1));  // ^ q>>23, ^ (x&w)>>1
  x *= k.mul;
  x = xor_and(x, x >> 11, w11);
  x *= 0x74dcb303u;
  x = xor_and(x, x >> 2, w2);
  x *= 0x9e501cc3u;
  x = xor_and(x, x >> 2, w2);
  x *= 0xc860a3dfu;
  return xor_and(x & w, x >> 5, w5);  // x &= w, ^ x>>5
}

// permute(index, l, w, p[c]) of 16 lanes of N key sets p[c]. Kensler's rounds
// are written again here (kensler_round), as lk16 is: the scalar code cannot be
// inlined into a function of another target; test_sampler.cpp holds the two to
// the same bits. A round is one dependent chain of ~33 cycles (six products), so
// the N walks go in one loop, each round of one filling the others' latency; a
// chain that is done still runs its rounds (cheaper than a branch), keeping its
// first value in range.
template <int N>
SNELL_AVX512DQ_TARGET inline void permute16(std::uint32_t index, const Divisor32& l,
                                            std::uint32_t w, const U32x16* p, U32x16* out) {
  U32x16 i[N];
  KenslerKey key[N];
  __mmask16 todo[N];
  for (int c = 0; c < N; ++c) i[c] = U32x16{} + index, out[c] = U32x16{}, todo[c] = 0xffff;
  if (l.d <= 1) return;
  for (int c = 0; c < N; ++c) key[c] = kensler_key(p[c]);
  const U32x16 wv = U32x16{} + w, w4 = wv >> 4, w1 = wv >> 1, w11 = wv >> 11, w2 = wv >> 2,
               w5 = wv >> 5;
  for (;;) {
    __mmask16 any = 0;
    for (int c = 0; c < N; ++c) {
      const U32x16 x = kensler_round(i[c], key[c], wv, w4, w1, w11, w2, w5);
      i[c] = x;
      __mmask16 in = _mm512_cmplt_epu32_mask(__m512i(x), _mm512_set1_epi32(int(l.d))) & todo[c];
      out[c] = U32x16(_mm512_mask_mov_epi32(__m512i(out[c]), in, __m512i(x)));
      todo[c] &= __mmask16(~in);
      any |= todo[c];
    }
    if (!any) return;
  }
}

// The draws of N dimensions (key sets k[c]) at one sample index.
template <int N>
SNELL_AVX512DQ_TARGET void stratified_n_avx512(const SamplerSpec& spec, const StrataLanes* const* k,
                                               std::uint32_t index, float* const* u,
                                               float* const* v) {
  const Divisor32& div = v ? spec.div_cells : spec.div_n;
  U64x8 key[N][2];
  U32x16 p[N];
  for (int c = 0; c < N; ++c) {
    std::memcpy(key[c], k[c]->key, 128);
    p[c] = __builtin_shufflevector(__builtin_convertvector(key[c][0], U32x8),
                                   __builtin_convertvector(key[c][1], U32x8), 0, 1, 2, 3, 4, 5, 6,
                                   7, 8, 9, 10, 11, 12, 13, 14, 15);
  }
  // hash_combine(key ^ 0x5bd1e995, index): the index's hash is the same in every
  // lane. The jitter hashes go first: they do not depend on the permutation, so
  // they fill the latency of its rounds instead of waiting behind its loop.
  const std::uint64_t hb = hash64(index) + 0x9e3779b97f4a7c15ull;
  U64x8 jit[N][2];
  for (int c = 0; c < N; ++c)
    for (int h = 0; h < 2; ++h) {
      U64x8 a = key[c][h] ^ 0x5bd1e995u;
      jit[c][h] = hash64_8(a ^ (hb + (a << 6) + (a >> 2)));
    }
  U32x16 perm[N];
  permute16<N>(index, div, v ? spec.cells_mask : spec.n_mask, p, perm);
  for (int c = 0; c < N; ++c)
    for (int h = 0; h < 2; ++h) {
      U64x8 cell;
      if (div.d <= 1) {
        cell = U64x8{};
      } else {
        U32x8 half;
        std::memcpy(&half, reinterpret_cast<const std::uint32_t*>(&perm[c]) + 8 * h, 32);
        U32x8 ph;
        std::memcpy(&ph, reinterpret_cast<const std::uint32_t*>(&p[c]) + 8 * h, 32);
        cell = rem8(widen(half + ph), div);  // the u32 sum wraps, as in permute
      }
      F32x8 ju = unit8(jit[c][h]);
      if (v) {
        F32x8 jv = unit8(jit[c][h] >> 32);
        U64x8 cy = quot8(cell, spec.div_k), cx = cell - cy * spec.k;
        F32x8 fu = place8(cx, ju, spec.div_k), fv = place8(cy, jv, spec.div_m);
        std::memcpy(u[c] + 8 * h, &fu, 32);
        std::memcpy(v[c] + 8 * h, &fv, 32);
      } else {
        F32x8 fu = place8(cell, ju, spec.div_n);
        std::memcpy(u[c] + 8 * h, &fu, 32);
      }
    }
}

SNELL_AVX512DQ_TARGET void stratified_lanes_avx512(const SamplerSpec& spec,
                                                   const StrataLanes* const* k, std::uint32_t count,
                                                   std::uint32_t n, std::uint32_t index,
                                                   float* const* u, float* const* v) {
  static_assert(StrataLanes::kLanes == 16 && kMaxStrataDims == 4);
  const std::uint32_t cells = v ? spec.cells : spec.n;
  if (index >= cells) {  // past the grid (not drawn by a render): the scalar draws
    stratified_lanes_generic(spec, k, count, n, index, u, v);
    return;
  }
  // All 16 lanes are drawn and stored: the caller has room for them.
  switch (count) {
    case 1:
      return stratified_n_avx512<1>(spec, k, index, u, v);
    case 2:
      return stratified_n_avx512<2>(spec, k, index, u, v);
    case 3:
      return stratified_n_avx512<3>(spec, k, index, u, v);
    case 4:
      return stratified_n_avx512<4>(spec, k, index, u, v);
    default:
      return;
  }
}

// hash_combine(x, c) of 8 lanes with one c: its hash64(c) term once.
SNELL_AVX512DQ_TARGET inline U64x8 hash_combine_8(U64x8 x, std::uint64_t hashed_c) {
  return hash64_8(x ^ (hashed_c + 0x9e3779b97f4a7c15ull + (x << 6) + (x >> 2)));
}
SNELL_AVX512DQ_TARGET inline U64x8 hash_combine_8(U64x8 x, U64x8 y) {
  return hash64_8(x ^ (hash64_8(y) + 0x9e3779b97f4a7c15ull + (x << 6) + (x >> 2)));
}

SNELL_AVX512DQ_TARGET void cell_keys_lanes_avx512(const std::uint64_t* node_keys,
                                                  std::uint64_t cell, const std::uint64_t* pixels,
                                                  const std::uint64_t* indices,
                                                  std::uint64_t* out) {
  const std::uint64_t hashed_cell = hash64(cell);
  for (int h = 0; h < 2; ++h) {
    U64x8 x, p;
    std::memcpy(&x, node_keys + 8 * h, 64);
    std::memcpy(&p, pixels + 8 * h, 64);
    const U64x8 dim =
        (hash_combine_8(x, hashed_cell) & 0x7fffffffull) + std::uint64_t(kDimFirstFree);
    U64x8 k = hash_combine_8(p, dim);
    if (indices) {
      U64x8 i;
      std::memcpy(&i, indices + 8 * h, 64);
      k = hash_combine_8(k, i);
    }
    std::memcpy(out + 8 * h, &k, 64);
  }
}

bool avx512dq_supported() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
         __builtin_cpu_supports("avx512dq");
}

#endif  // SNELL_HAVE_AVX512_PATH

using StrataFn = StratifiedLanesFn;
const SimdPaths<StrataFn>& strata_available() {
#ifdef SNELL_HAVE_AVX512_PATH
  static const auto paths =
      simd_paths<StrataFn>(avx512dq_supported(), stratified_lanes_avx512, cpu_has_avx2(),
                           lanes::stratified_lanes_avx2, stratified_lanes_generic);
#else
  static const auto paths = simd_paths<StrataFn>(false, nullptr, stratified_lanes_generic);
#endif
  return paths;
}
const StrataFn g_stratified_lanes = best_path(strata_available());

void cell_keys_lanes_generic(const std::uint64_t* node_keys, std::uint64_t cell,
                             const std::uint64_t* pixels, const std::uint64_t* indices,
                             std::uint64_t* out) {
  for (std::uint32_t i = 0; i < kHashLanes; ++i) {
    const std::uint32_t dim =
        kDimFirstFree + std::uint32_t(hash_combine(node_keys[i], cell) & 0x7fffffffu);
    out[i] = hash_combine(pixels[i], dim);
    if (indices) out[i] = hash_combine(out[i], indices[i]);
  }
}
using CellKeysFn = void (*)(const std::uint64_t*, std::uint64_t, const std::uint64_t*,
                            const std::uint64_t*, std::uint64_t*);
const SimdPaths<CellKeysFn>& cell_keys_available() {
#ifdef SNELL_HAVE_AVX512_PATH
  static const auto paths =
      simd_paths<CellKeysFn>(avx512dq_supported(), cell_keys_lanes_avx512, cpu_has_avx2(),
                             lanes::cell_keys_lanes_avx2, cell_keys_lanes_generic);
#else
  static const auto paths = simd_paths<CellKeysFn>(false, nullptr, cell_keys_lanes_generic);
#endif
  return paths;
}
const CellKeysFn g_cell_keys_lanes = best_path(cell_keys_available());

using LanesFn = Sobol2LanesFn;
const SimdPaths<LanesFn>& available() {
#ifdef SNELL_HAVE_AVX512_PATH
  static const auto paths =
      simd_paths<LanesFn>(avx512_supported(), sobol2_lanes_avx512, cpu_has_avx2(),
                          lanes::sobol2_lanes_avx2, sobol2_lanes_generic);
#else
  static const auto paths = simd_paths<LanesFn>(false, nullptr, sobol2_lanes_generic);
#endif
  return paths;
}
const LanesFn g_sobol2_lanes = best_path(available());

}  // namespace

void lanes::stratified_lanes_scalar(const SamplerSpec& spec, const StrataLanes* const* k,
                                    std::uint32_t count, std::uint32_t n, std::uint32_t index,
                                    float* const* u, float* const* v) {
  stratified_lanes_generic(spec, k, count, n, index, u, v);
}

void sobol2_lanes(const SobolLanes& k, std::uint32_t n, std::uint32_t index, float* u, float* v) {
  g_sobol2_lanes(k, n, index, u, v);
}

std::vector<std::string> sobol2_lanes_paths() {
  return path_names(available());
}

Sobol2LanesFn sobol2_lanes_path(const std::string& path) {
  return path_named(available(), path);
}

bool sobol2_lanes_with(const std::string& path, const SobolLanes& k, std::uint32_t n,
                       std::uint32_t index, float* u, float* v) {
  const LanesFn p = sobol2_lanes_path(path);
  if (p) p(k, n, index, u, v);
  return p != nullptr;
}

void stratified2_lanes(const SamplerSpec& spec, const StrataLanes& k, std::uint32_t n,
                       std::uint32_t index, float* u, float* v) {
  const StrataLanes* ks = &k;
  g_stratified_lanes(spec, &ks, 1, n, index, &u, &v);
}
void stratified1_lanes(const SamplerSpec& spec, const StrataLanes& k, std::uint32_t n,
                       std::uint32_t index, float* u) {
  const StrataLanes* ks = &k;
  g_stratified_lanes(spec, &ks, 1, n, index, &u, nullptr);
}
void stratified2_lanes(const SamplerSpec& spec, const StrataLanes* const* k, std::uint32_t count,
                       std::uint32_t n, std::uint32_t index, float* const* u, float* const* v) {
  g_stratified_lanes(spec, k, count, n, index, u, v);
}
std::vector<std::string> stratified_lanes_paths() {
  return path_names(strata_available());
}

StratifiedLanesFn stratified_lanes_path(const std::string& path) {
  return path_named(strata_available(), path);
}

bool stratified_lanes_with(const std::string& path, const SamplerSpec& spec, const StrataLanes& k,
                           std::uint32_t n, std::uint32_t index, float* u, float* v) {
  const StrataFn p = stratified_lanes_path(path);
  const StrataLanes* ks = &k;
  if (p) p(spec, &ks, 1, n, index, &u, v ? &v : nullptr);
  return p != nullptr;
}

void cell_keys_lanes(const std::uint64_t* node_keys, std::uint64_t cell,
                     const std::uint64_t* pixels, const std::uint64_t* indices,
                     std::uint64_t* out) {
  g_cell_keys_lanes(node_keys, cell, pixels, indices, out);
}
std::vector<std::string> cell_keys_lanes_paths() {
  return path_names(cell_keys_available());
}
bool cell_keys_lanes_with(const std::string& path, const std::uint64_t* node_keys,
                          std::uint64_t cell, const std::uint64_t* pixels,
                          const std::uint64_t* indices, std::uint64_t* out) {
  const CellKeysFn p = path_named(cell_keys_available(), path);
  if (p) p(node_keys, cell, pixels, indices, out);
  return p != nullptr;
}

}  // namespace snell::rt
