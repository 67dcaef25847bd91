// Four-lane double helpers of the geometry kernels' AVX2 paths (plane_lanes,
// sphere_lanes). Include it inside a `#pragma GCC target("avx2,fma")` region, in the
// kernel's own (anonymous) namespace, after <immintrin.h> and <cstdint>: its
// functions take that region's target (outside one their intrinsics do not
// compile) and stay private to the file.
#pragma once

using F64x4 = double __attribute__((vector_size(32)));
using I64x4 = std::int64_t __attribute__((vector_size(32)));
using F32x4 = float __attribute__((vector_size(16)));
using I32x4 = std::int32_t __attribute__((vector_size(16)));

inline F64x4 widen4(const float* p) {
  return F64x4(_mm256_cvtps_pd(_mm_loadu_ps(p)));
}
inline F32x4 narrow4(F64x4 d) {
  return F32x4(_mm256_cvtpd_ps(__m256d(d)));
}
inline F64x4 splat4(double x) {  // a broadcast: keeps -0, which 0 + x would not
  return F64x4(_mm256_set1_pd(x));
}
// A compare's lanes as bits.
inline std::uint32_t bits4(I64x4 m) {
  return std::uint32_t(_mm256_movemask_pd(__m256d(m)));
}
inline std::uint32_t bits4(I32x4 m) {
  return std::uint32_t(_mm_movemask_ps(__m128(m)));
}
inline F64x4 abs4(F64x4 x) {  // the sign bit cleared, as _mm512_abs_pd
  return F64x4(I64x4(x) & 0x7fffffffffffffffll);
}
inline F64x4 max4(F64x4 a, F64x4 b) {  // vmaxpd: b where either is NaN, as _mm512_max_pd
  return F64x4(_mm256_max_pd(__m256d(a), __m256d(b)));
}
