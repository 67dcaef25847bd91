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

#endif  // SNELL_HAVE_AVX512_PATH

const SimdPaths<StoreRays16Fn>& available() {
#ifdef SNELL_HAVE_AVX512_PATH
  static const auto paths =
      simd_paths<StoreRays16Fn>(avx512_supported(), store_rays16_avx512, store_rays16_generic);
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
