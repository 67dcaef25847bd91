#include "runtime/ray_packet.hpp"

#include <cstddef>
#include <cstdint>

#include "runtime/simd_paths.hpp"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define SNELL_HAVE_AVX512_PATH 1
#endif

namespace snell::rt {

namespace {

// The gathers read a Ray as nine floats in this order.
static_assert(sizeof(Ray) == 9 * sizeof(float));
static_assert(offsetof(Ray, org) == 0 && offsetof(Ray, dir) == 12 && offsetof(Ray, tmax) == 24 &&
              offsetof(Ray, time) == 28 && offsetof(Ray, tnear) == 32);

void store_rays16_generic(const Ray* rays, std::size_t n, RTCRay16& p) {
  for (std::size_t k = 0; k < 16; ++k) {
    const Ray& r = rays[k < n ? k : 0];
    p.org_x[k] = r.org.x, p.org_y[k] = r.org.y, p.org_z[k] = r.org.z;
    p.dir_x[k] = r.dir.x, p.dir_y[k] = r.dir.y, p.dir_z[k] = r.dir.z;
    p.tnear[k] = r.tnear, p.tfar[k] = r.tmax, p.time[k] = r.time;
    p.mask[k] = ~0u, p.id[k] = 0, p.flags[k] = 0;
  }
}

#ifdef SNELL_HAVE_AVX512_PATH

#pragma GCC push_options
#pragma GCC target("avx512f")
void store_rays16_avx512(const Ray* rays, std::size_t n, RTCRay16& p) {
  const __m512i lane = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  const __mmask16 live = __mmask16((1u << n) - 1);
  // Lane k reads ray k's floats at 9k (ray 0's past n).
  const __m512i at = _mm512_maskz_mullo_epi32(live, lane, _mm512_set1_epi32(9));
  const float* f = &rays[0].org.x;
#define SNELL_GATHER(out, offset)                                                                 \
  _mm512_storeu_ps(out, _mm512_mask_i32gather_ps(_mm512_setzero_ps(), __mmask16(0xffff),          \
                                                 _mm512_add_epi32(at, _mm512_set1_epi32(offset)), \
                                                 f, sizeof(float)))
  SNELL_GATHER(p.org_x, 0), SNELL_GATHER(p.org_y, 1), SNELL_GATHER(p.org_z, 2);
  SNELL_GATHER(p.dir_x, 3), SNELL_GATHER(p.dir_y, 4), SNELL_GATHER(p.dir_z, 5);
  SNELL_GATHER(p.tfar, 6), SNELL_GATHER(p.time, 7), SNELL_GATHER(p.tnear, 8);
#undef SNELL_GATHER
  _mm512_storeu_si512(p.mask, _mm512_set1_epi32(-1));
  _mm512_storeu_si512(p.id, _mm512_setzero_si512());
  _mm512_storeu_si512(p.flags, _mm512_setzero_si512());
}

#pragma GCC pop_options

bool avx512_supported() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx512f");
}

// AVX2: no gathers (Zen 3's cost more than the scalar copies), but each ray's
// first eight floats in one load and an 8x8 transposition; tnear, the ninth, one
// by one.
#pragma GCC push_options
#pragma GCC target("avx2,fma")
void store_rays16_avx2(const Ray* rays, std::size_t n, RTCRay16& p) {
  for (std::size_t h = 0; h < 16; h += 8) {
    const Ray* r[8];
    for (std::size_t k = 0; k < 8; ++k) r[k] = &rays[h + k < n ? h + k : 0];
    __m256 a[8];
    for (std::size_t k = 0; k < 8; ++k) a[k] = _mm256_loadu_ps(&r[k]->org.x);
    // Pairs of rays interleaved, then quads, then the 128-bit halves: u_k holds
    // field k of rays 0-3 and field k + 4 of the same rays (u_{k+4}: rays 4-7).
    const __m256 t0 = _mm256_unpacklo_ps(a[0], a[1]), t1 = _mm256_unpackhi_ps(a[0], a[1]);
    const __m256 t2 = _mm256_unpacklo_ps(a[2], a[3]), t3 = _mm256_unpackhi_ps(a[2], a[3]);
    const __m256 t4 = _mm256_unpacklo_ps(a[4], a[5]), t5 = _mm256_unpackhi_ps(a[4], a[5]);
    const __m256 t6 = _mm256_unpacklo_ps(a[6], a[7]), t7 = _mm256_unpackhi_ps(a[6], a[7]);
    const __m256 u0 = _mm256_shuffle_ps(t0, t2, 0x44), u1 = _mm256_shuffle_ps(t0, t2, 0xee);
    const __m256 u2 = _mm256_shuffle_ps(t1, t3, 0x44), u3 = _mm256_shuffle_ps(t1, t3, 0xee);
    const __m256 u4 = _mm256_shuffle_ps(t4, t6, 0x44), u5 = _mm256_shuffle_ps(t4, t6, 0xee);
    const __m256 u6 = _mm256_shuffle_ps(t5, t7, 0x44), u7 = _mm256_shuffle_ps(t5, t7, 0xee);
    _mm256_storeu_ps(p.org_x + h, _mm256_permute2f128_ps(u0, u4, 0x20));
    _mm256_storeu_ps(p.org_y + h, _mm256_permute2f128_ps(u1, u5, 0x20));
    _mm256_storeu_ps(p.org_z + h, _mm256_permute2f128_ps(u2, u6, 0x20));
    _mm256_storeu_ps(p.dir_x + h, _mm256_permute2f128_ps(u3, u7, 0x20));
    _mm256_storeu_ps(p.dir_y + h, _mm256_permute2f128_ps(u0, u4, 0x31));
    _mm256_storeu_ps(p.dir_z + h, _mm256_permute2f128_ps(u1, u5, 0x31));
    _mm256_storeu_ps(p.tfar + h, _mm256_permute2f128_ps(u2, u6, 0x31));
    _mm256_storeu_ps(p.time + h, _mm256_permute2f128_ps(u3, u7, 0x31));
    _mm256_storeu_ps(p.tnear + h,
                     _mm256_setr_ps(r[0]->tnear, r[1]->tnear, r[2]->tnear, r[3]->tnear, r[4]->tnear,
                                    r[5]->tnear, r[6]->tnear, r[7]->tnear));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(p.mask + h), _mm256_set1_epi32(-1));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(p.id + h), _mm256_setzero_si256());
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(p.flags + h), _mm256_setzero_si256());
  }
}
#pragma GCC pop_options

#endif  // SNELL_HAVE_AVX512_PATH

const SimdPaths<StoreRays16Fn>& available() {
#ifdef SNELL_HAVE_AVX512_PATH
  static const auto paths =
      simd_paths<StoreRays16Fn>(avx512_supported(), store_rays16_avx512, cpu_has_avx2(),
                                store_rays16_avx2, store_rays16_generic);
#else
  static const auto paths = simd_paths<StoreRays16Fn>(false, nullptr, store_rays16_generic);
#endif
  return paths;
}

}  // namespace

StoreRays16Fn store_rays16() {
  static const StoreRays16Fn best = best_path(available());
  return best;
}

std::vector<std::pair<std::string, StoreRays16Fn>> store_rays16_paths() {
  return available();
}

}  // namespace snell::rt
