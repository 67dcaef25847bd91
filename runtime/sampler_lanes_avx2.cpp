// The AVX2 paths of sampler_lanes (x86-64-v3: AVX2 with FMA, the CPUs without
// AVX-512). The same integers as the scalar draws of sampler.hpp, so the same
// numbers: tests/runtime/test_sampler.cpp holds every path to them.
//
// AVX2 has no 64-bit lane product and no unsigned compare: a 64-bit product is
// three 32x32->64 ones (vpmuludq), and a compare flips the sign bits first. The
// 16 lanes go as two vectors of eight 32-bit lanes (Kensler's walk) or four of
// four 64-bit lanes (the hashes and the remainders).
#include "runtime/sampler_lanes_isa.hpp"

#if SNELL_HAVE_AVX2_PATH

#include <immintrin.h>

#include <cstring>

namespace snell::rt::lanes {

#pragma GCC push_options
#pragma GCC target("avx2,fma")

namespace {

using U32x8 = std::uint32_t __attribute__((vector_size(32)));
using I32x8 = std::int32_t __attribute__((vector_size(32)));
using U64x4 = std::uint64_t __attribute__((vector_size(32)));
using F64x4 = double __attribute__((vector_size(32)));
using F32x4 = float __attribute__((vector_size(16)));
using I32x4 = std::int32_t __attribute__((vector_size(16)));

// The low 32 bits of each lane of a times those of b, as 64-bit products.
inline U64x4 mul32(U64x4 a, U64x4 b) {
  return U64x4(_mm256_mul_epu32(__m256i(a), __m256i(b)));
}
// a · c mod 2^64.
inline U64x4 mul64(U64x4 a, std::uint64_t c) {
  const U64x4 cl = U64x4{} + (c & 0xffffffffull), ch = U64x4{} + (c >> 32);
  return mul32(a, cl) + ((mul32(a >> 32, cl) + mul32(a, ch)) << 32);
}
inline U64x4 hash64_4(U64x4 x) {
  x += 0x9e3779b97f4a7c15ull;
  x = mul64(x ^ (x >> 30), 0xbf58476d1ce4e5b9ull);
  x = mul64(x ^ (x >> 27), 0x94d049bb133111ebull);
  return x ^ (x >> 31);
}
// hash_combine(x, y) with y's hash64 given.
inline U64x4 combine4(U64x4 x, U64x4 hashed_y) {
  return hash64_4(x ^ (hashed_y + 0x9e3779b97f4a7c15ull + (x << 6) + (x >> 2)));
}
// Divisor32::rem and ::quot of lanes below 2^32 (a mask and a shift for a power
// of two), with the 64x32-bit products split in halves.
inline U64x4 rem4(U64x4 a, const Divisor32& l) {
  if (l.pow2) return a & std::uint64_t(l.d - 1);
  const U64x4 ml = U64x4{} + (l.magic & 0xffffffffull), mh = U64x4{} + (l.magic >> 32);
  const U64x4 t = mul32(a, ml) + (mul32(a, mh) << 32);  // magic · a mod 2^64
  const U64x4 d = U64x4{} + l.d;
  return (mul32(t >> 32, d) + (mul32(t, d) >> 32)) >> 32;
}
inline U64x4 quot4(U64x4 a, const Divisor32& l) {
  if (l.pow2) return a >> l.shift;
  const U64x4 ml = U64x4{} + (l.magic & 0xffffffffull), mh = U64x4{} + (l.magic >> 32);
  return (mul32(a, mh) + (mul32(a, ml) >> 32)) >> 32;
}
// The 32-bit halves of four 64-bit lanes: the low ones (hi = false) or the high.
inline I32x4 halves(U64x4 x, bool hi) {
  const __m256i pick =
      hi ? _mm256_setr_epi32(1, 3, 5, 7, 1, 3, 5, 7) : _mm256_setr_epi32(0, 2, 4, 6, 0, 2, 4, 6);
  return I32x4(_mm256_castsi256_si128(_mm256_permutevar8x32_epi32(__m256i(x), pick)));
}
// to_unit_float of four 32-bit integers.
inline F32x4 unit4(I32x4 bits) {
  return __builtin_convertvector(I32x4(__m128i(_mm_srli_epi32(__m128i(bits), 8))), F32x4) *
         (1.0f / 16777216.0f);
}
// detail::unit of d.over(c + double(j)) for c < 2^52 (exactly c in double, by
// the 2^52 exponent trick: AVX2 converts no unsigned 64-bit lanes), with the
// division's float from a product and two FMAs where Divisor32 allows.
inline F32x4 place4(U64x4 c, F32x4 j, const Divisor32& d) {
  const F64x4 two52 = F64x4{} + 0x1p52;
  const F64x4 cd = F64x4(c | 0x4330000000000000ull) - two52;
  const F64x4 sum = cd + __builtin_convertvector(j, F64x4);
  F64x4 x;
  if (d.pow2) {
    x = sum * d.inv;
  } else if (d.recip != 0) {  // the division's float, without one (Divisor32::recip)
    const __m256d r = _mm256_set1_pd(d.recip), q = __m256d(sum * d.recip);
    const __m256d rest = _mm256_fnmadd_pd(q, _mm256_set1_pd(double(d.d)), __m256d(sum));
    x = F64x4(_mm256_fmadd_pd(rest, r, q));
  } else {
    x = sum / double(d.d);
  }
  const F32x4 f = __builtin_convertvector(x, F32x4);
  return f < 1.0f ? f : F32x4{} + 0x1.fffffep-1f;
}

// permute(index, l, w, p) (sampler.hpp) of C chains of eight lanes, in one loop
// so that each chain's rounds fill the others' latency; a chain that is done
// still runs rounds (cheaper than a branch), keeping its first value in range.
template <int C>
void permute8(std::uint32_t index, const Divisor32& l, std::uint32_t w, const U32x8* p,
              U32x8* out) {
  U32x8 i[C], todo[C], mul[C];
  for (int c = 0; c < C; ++c) {
    i[c] = U32x8{} + index, out[c] = U32x8{}, todo[c] = U32x8{} + ~0u;
    mul[c] = (1 | p[c] >> 27) * 0x6935fa69u;
  }
  if (l.d <= 1) return;
  const U32x8 wv = U32x8{} + w;
  // x < d unsigned, as a signed compare of both with their sign bits flipped.
  const I32x8 d_flipped = I32x8(U32x8{} + (l.d ^ 0x80000000u));
  for (;;) {
    U32x8 left = U32x8{};
    for (int c = 0; c < C; ++c) {
      const U32x8 q = p[c];
      U32x8 x = i[c];
      x ^= q;
      x *= 0xe170893du;
      x ^= q >> 16;
      x ^= (x & wv) >> 4;
      x ^= q >> 8;
      x *= 0x0929eb3fu;
      x ^= q >> 23;
      x ^= (x & wv) >> 1;
      x *= mul[c];
      x ^= (x & wv) >> 11;
      x *= 0x74dcb303u;
      x ^= (x & wv) >> 2;
      x *= 0x9e501cc3u;
      x ^= (x & wv) >> 2;
      x *= 0xc860a3dfu;
      x &= wv;
      x ^= x >> 5;
      i[c] = x;
      const U32x8 in = U32x8(I32x8(x ^ 0x80000000u) < d_flipped) & todo[c];
      out[c] = in ? x : out[c];
      todo[c] &= ~in;
      left |= todo[c];
    }
    if (_mm256_testz_si256(__m256i(left), __m256i(left))) return;
  }
}

// The draws of N dimensions (key sets k[c]) at one sample index, as
// stratified_n_avx512 makes them.
template <int N>
void stratified_n(const SamplerSpec& spec, const StrataLanes* const* k, std::uint32_t index,
                  float* const* u, float* const* v) {
  const Divisor32& div = v ? spec.div_cells : spec.div_n;
  U64x4 key[N][4];
  U32x8 p[2 * N];
  for (int c = 0; c < N; ++c) {
    std::memcpy(key[c], k[c]->key, 128);
    for (int h = 0; h < 2; ++h) {
      const I32x4 lo = halves(key[c][2 * h], false), hi = halves(key[c][2 * h + 1], false);
      p[2 * c + h] = U32x8(_mm256_set_m128i(__m128i(hi), __m128i(lo)));
    }
  }
  // hash_combine(key ^ 0x5bd1e995, index), first: it does not wait on the walk.
  const std::uint64_t hb = hash64(index) + 0x9e3779b97f4a7c15ull;
  U64x4 jit[N][4];
  for (int c = 0; c < N; ++c)
    for (int q = 0; q < 4; ++q) {
      const U64x4 a = key[c][q] ^ 0x5bd1e995u;
      jit[c][q] = hash64_4(a ^ (hb + (a << 6) + (a >> 2)));
    }
  U32x8 perm[2 * N];
  permute8<2 * N>(index, div, v ? spec.cells_mask : spec.n_mask, p, perm);
  for (int c = 0; c < N; ++c)
    for (int q = 0; q < 4; ++q) {
      U64x4 cell = U64x4{};
      if (div.d > 1) {
        // perm + p in 32 bits (the sum wraps, as in permute), widened.
        const U32x8 sum = perm[2 * c + q / 2] + p[2 * c + q / 2];
        __m128i four;
        std::memcpy(&four, reinterpret_cast<const std::uint32_t*>(&sum) + 4 * (q % 2), 16);
        cell = rem4(U64x4(_mm256_cvtepu32_epi64(four)), div);
      }
      const F32x4 ju = unit4(halves(jit[c][q], false));
      if (v) {
        const F32x4 jv = unit4(halves(jit[c][q], true));
        const U64x4 cy = quot4(cell, spec.div_k), cx = cell - mul32(cy, U64x4{} + spec.k);
        const F32x4 fu = place4(cx, ju, spec.div_k), fv = place4(cy, jv, spec.div_m);
        std::memcpy(u[c] + 4 * q, &fu, 16);
        std::memcpy(v[c] + 4 * q, &fv, 16);
      } else {
        const F32x4 fu = place4(cell, ju, spec.div_n);
        std::memcpy(u[c] + 4 * q, &fu, 16);
      }
    }
}

// Bit reversal of eight 32-bit lanes: each byte's bits by two 16-entry nibble
// lookups (vpshufb), then the bytes of each lane.
inline U32x8 reverse8(U32x8 x) {
  const __m256i rev4 = _mm256_setr_epi8(0, 8, 4, 12, 2, 10, 6, 14, 1, 9, 5, 13, 3, 11, 7, 15, 0, 8,
                                        4, 12, 2, 10, 6, 14, 1, 9, 5, 13, 3, 11, 7, 15);
  const __m256i low = _mm256_set1_epi8(0x0f);
  const __m256i bytes = _mm256_setr_epi8(3, 2, 1, 0, 7, 6, 5, 4, 11, 10, 9, 8, 15, 14, 13, 12, 3, 2,
                                         1, 0, 7, 6, 5, 4, 11, 10, 9, 8, 15, 14, 13, 12);
  const __m256i lo = _mm256_and_si256(__m256i(x), low);
  const __m256i hi = _mm256_and_si256(_mm256_srli_epi16(__m256i(x), 4), low);
  const __m256i r = _mm256_or_si256(_mm256_slli_epi16(_mm256_shuffle_epi8(rev4, lo), 4),
                                    _mm256_shuffle_epi8(rev4, hi));
  return U32x8(_mm256_shuffle_epi8(r, bytes));
}
inline U32x8 lk8(U32x8 x, U32x8 seed) {
  x += seed;
  for (std::uint32_t c : detail::kLkMultipliers) x ^= x * c;
  return x;
}
inline __m256 unit8(U32x8 bits) {
  return _mm256_mul_ps(_mm256_cvtepi32_ps(__m256i(bits >> 8)), _mm256_set1_ps(1.0f / 16777216.0f));
}
// detail::reversed_sobol1 of eight lanes: its four byte tables, gathered.
inline U32x8 reversed_sobol1_8(U32x8 i) {
  __m256i s = _mm256_setzero_si256();
  for (int b = 0; b < 4; ++b) {
    const __m256i byte = __m256i((i >> (8 * b)) & 255u);
    const int* table = reinterpret_cast<const int*>(detail::kSobol1.t[b]);
    s = _mm256_xor_si256(s, _mm256_i32gather_epi32(table, byte, 4));
  }
  return U32x8(s);
}

}  // namespace

void sobol2_lanes_avx2(const SobolLanes& k, std::uint32_t n, std::uint32_t index, float* u,
                       float* v) {
  static_assert(SobolLanes::kLanes == 16);
  (void)n;  // all 16 lanes are drawn and stored: the caller has room for them
  const U32x8 idx = reverse8(U32x8{} + index);
  for (int h = 0; h < 16; h += 8) {
    U32x8 seed0, su, sv;
    std::memcpy(&seed0, k.index_seed + h, 32);
    std::memcpy(&su, k.seed_u + h, 32);
    std::memcpy(&sv, k.seed_v + h, 32);
    // owen_scramble(index, seed0); dimension 0 is reverse(i), dimension 1 the table's.
    const U32x8 i = reverse8(lk8(idx, seed0));
    _mm256_storeu_ps(u + h, unit8(reverse8(lk8(i, su))));
    _mm256_storeu_ps(v + h, unit8(reverse8(lk8(reversed_sobol1_8(i), sv))));
  }
}

void cell_keys_lanes_avx2(const std::uint64_t* node_keys, std::uint64_t cell,
                          const std::uint64_t* pixels, const std::uint64_t* indices,
                          std::uint64_t* out) {
  static_assert(kHashLanes == 16);
  const U64x4 hashed_cell = U64x4{} + hash64(cell);
  for (int q = 0; q < 16; q += 4) {
    U64x4 x, p;
    std::memcpy(&x, node_keys + q, 32);
    std::memcpy(&p, pixels + q, 32);
    const U64x4 dim = (combine4(x, hashed_cell) & 0x7fffffffull) + std::uint64_t(kDimFirstFree);
    U64x4 key = combine4(p, hash64_4(dim));
    if (indices) {
      U64x4 i;
      std::memcpy(&i, indices + q, 32);
      key = combine4(key, hash64_4(i));
    }
    std::memcpy(out + q, &key, 32);
  }
}

void stratified_lanes_avx2(const SamplerSpec& spec, const StrataLanes* const* k,
                           std::uint32_t count, std::uint32_t n, std::uint32_t index,
                           float* const* u, float* const* v) {
  static_assert(StrataLanes::kLanes == 16 && kMaxStrataDims == 4);
  const std::uint32_t cells = v ? spec.cells : spec.n;
  if (index >= cells) {  // past the grid (not drawn by a render): the scalar draws
    stratified_lanes_scalar(spec, k, count, n, index, u, v);
    return;
  }
  // All 16 lanes are drawn and stored: the caller has room for them.
  switch (count) {
    case 1:
      return stratified_n<1>(spec, k, index, u, v);
    case 2:
      return stratified_n<2>(spec, k, index, u, v);
    case 3:
      return stratified_n<3>(spec, k, index, u, v);
    case 4:
      return stratified_n<4>(spec, k, index, u, v);
    default:
      return;
  }
}

#pragma GCC pop_options

}  // namespace snell::rt::lanes

#endif  // SNELL_HAVE_AVX2_PATH
