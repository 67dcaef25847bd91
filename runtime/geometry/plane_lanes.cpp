#include "runtime/geometry/plane_lanes.hpp"

#include "runtime/geometry/plane.hpp"  // kMaxPlaneHit
#include "runtime/simd_paths.hpp"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define SNELL_HAVE_AVX512_PATH 1
#endif

namespace snell::rt::geom {

namespace {

#ifdef SNELL_HAVE_AVX512_PATH

#pragma GCC push_options
#pragma GCC target("avx512f,avx512vl")
// GCC 12's AVX-512 headers warn falsely on their own masked builtins
// (-Wmaybe-uninitialized, GCC PR 105593: _mm512_abs_pd).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

using F32x8 = float __attribute__((vector_size(32)));
using F64x8 = double __attribute__((vector_size(64)));
inline F64x8 widen(const float* p) {
  F32x8 f;
  __builtin_memcpy(&f, p, sizeof f);
  return __builtin_convertvector(f, F64x8);
}
inline F64x8 abs8(F64x8 x) {
  return F64x8(_mm512_abs_pd(__m512d(x)));
}

// Eight lanes: the lanes of m whose ray o + t·d meets the plane dot(n, x) = pd at
// a t in (tnear, tmax + tie / |n·d|), that t in `t`. Each line is one operation of
// hit_plane, in its order (a dot product is x·x + y·y + z·z, as ir::dot): with
// tnear >= 0 a ray leaving the plane (or starting on it) is turned away; t must be
// positive in float too; the hit point lies within kMaxPlaneHit (finite there, as
// t, o and d are, so fmax is max). kTie: a tie window (nearest-hit queries; for
// shadow rays it is 0, and tmax + 0 / |n·d| is tmax).
template <bool kTie>
__mmask8 meets(ir::Vec3 n, double pd, F64x8 ox, F64x8 oy, F64x8 oz, F64x8 dx, F64x8 dy, F64x8 dz,
               F64x8 tnear, F64x8 tmax, F64x8 tie, __mmask8 m, F64x8& t) {
  const F64x8 denom = n.x * dx + n.y * dy + n.z * dz;
  const F64x8 num = pd - (n.x * ox + n.y * oy + n.z * oz);
  const __m512d zero = _mm512_setzero_pd();
  const __mmask8 leaves = _mm512_cmp_pd_mask(__m512d(tnear), zero, _CMP_GE_OQ) &
                          (_mm512_cmp_pd_mask(__m512d(num), zero, _CMP_EQ_OQ) |
                           (_mm512_cmp_pd_mask(__m512d(num), zero, _CMP_GT_OQ) &
                            _mm512_cmp_pd_mask(__m512d(denom), zero, _CMP_LT_OQ)) |
                           (_mm512_cmp_pd_mask(__m512d(num), zero, _CMP_LT_OQ) &
                            _mm512_cmp_pd_mask(__m512d(denom), zero, _CMP_GT_OQ)));
  m &= __mmask8(~(leaves | _mm512_cmp_pd_mask(__m512d(denom), zero, _CMP_EQ_OQ)));
  if (!m) return 0;
  t = num / denom;
  F64x8 limit = tmax;
  if constexpr (kTie) limit = tmax + tie / abs8(denom);
  m &= _mm512_cmp_pd_mask(__m512d(t), __m512d(tnear), _CMP_GT_OQ) &
       _mm512_cmp_pd_mask(__m512d(t), __m512d(limit), _CMP_LT_OQ);
  const __m256 tf = __m256(__builtin_convertvector(t, F32x8));
  m &= _mm256_cmp_ps_mask(tf, _mm256_setzero_ps(), _CMP_GT_OQ);
  if (!m) return 0;
  const F64x8 qx = ox + dx * t, qy = oy + dy * t, qz = oz + dz * t;
  const F64x8 far =
      F64x8(_mm512_max_pd(__m512d(abs8(qx)), _mm512_max_pd(__m512d(abs8(qy)), __m512d(abs8(qz)))));
  return m & _mm512_cmp_pd_mask(__m512d(far), _mm512_set1_pd(kMaxPlaneHit), _CMP_LE_OQ);
}

// Eight shadow rays from `off`: tnear 0, tmax kAreaShadowEnd, no tie.
std::uint32_t eight(ir::Vec3 n, double pd, const ShadowLanes16& r, std::uint32_t off,
                    std::uint32_t live) {
  const __mmask8 m = __mmask8(live >> off);
  if (!m) return 0;
  F64x8 t;
  return std::uint32_t(meets<false>(n, pd, widen(r.ox + off), widen(r.oy + off), widen(r.oz + off),
                                    widen(r.dx + off), widen(r.dy + off), widen(r.dz + off),
                                    F64x8{}, F64x8{} + double(kAreaShadowEnd), F64x8{}, m, t))
         << off;
}

// Eight rays of the nearest-hit test from `off`, with their tnear, tmax[i] and
// tie[i]; a hit sets tmax[i] to its t and tie[i] to 0.
std::uint32_t eight_hit(ir::Vec3 n, double pd, const PlaneRayLanes& r, std::uint32_t off,
                        std::uint32_t live, double* tmax_io, double* tie_io) {
  const __mmask8 live8 = __mmask8(live >> off);
  if (!live8) return 0;
  F64x8 tmax, tie, t;
  __builtin_memcpy(&tmax, tmax_io + off, sizeof tmax);
  __builtin_memcpy(&tie, tie_io + off, sizeof tie);
  const __mmask8 m =
      meets<true>(n, pd, widen(r.ox + off), widen(r.oy + off), widen(r.oz + off), widen(r.dx + off),
                  widen(r.dy + off), widen(r.dz + off), widen(r.tnear + off), tmax, tie, live8, t);
  if (!m) return 0;
  _mm512_storeu_pd(tmax_io + off, _mm512_mask_blend_pd(m, __m512d(tmax), __m512d(t)));
  _mm512_storeu_pd(tie_io + off, _mm512_mask_blend_pd(m, __m512d(tie), _mm512_setzero_pd()));
  return std::uint32_t(m) << off;
}

std::uint32_t plane_hit_lanes_avx512(ir::Vec3 n, double d, const PlaneRayLanes& rays,
                                     std::uint32_t live, double* tmax, double* tie) {
  return eight_hit(n, d, rays, 0, live, tmax, tie) | eight_hit(n, d, rays, 8, live, tmax, tie);
}

std::uint32_t plane_lanes_avx512(ir::Vec3 n, double d, const ShadowLanes16& rays,
                                 std::uint32_t live) {
  return eight(n, d, rays, 0, live) | eight(n, d, rays, 8, live);
}

#pragma GCC diagnostic pop
#pragma GCC pop_options

bool avx512_supported() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl");
}

// AVX2: the same operations on four doubles at a time, masks as bits (movemask).
#pragma GCC push_options
#pragma GCC target("avx2,fma")

#include "runtime/geometry/lanes_avx2.hpp"  // inside the region: takes its target

// meets() on four lanes, m and the result as bits.
template <bool kTie>
std::uint32_t meets4(ir::Vec3 n, double pd, F64x4 ox, F64x4 oy, F64x4 oz, F64x4 dx, F64x4 dy,
                     F64x4 dz, F64x4 tnear, F64x4 tmax, F64x4 tie, std::uint32_t m, F64x4& t) {
  const F64x4 denom = n.x * dx + n.y * dy + n.z * dz;
  const F64x4 num = pd - (n.x * ox + n.y * oy + n.z * oz);
  const I64x4 leaves =
      (tnear >= 0) & ((num == 0) | ((num > 0) & (denom < 0)) | ((num < 0) & (denom > 0)));
  m &= ~bits4(leaves | (denom == 0));
  if (!m) return 0;
  t = num / denom;
  F64x4 limit = tmax;
  if constexpr (kTie) limit = tmax + tie / abs4(denom);
  m &= bits4((t > tnear) & (t < limit));
  const F32x4 tf = __builtin_convertvector(t, F32x4);
  m &= bits4(tf > 0.0f);
  if (!m) return 0;
  const F64x4 qx = ox + dx * t, qy = oy + dy * t, qz = oz + dz * t;
  const F64x4 far = max4(abs4(qx), max4(abs4(qy), abs4(qz)));
  return m & bits4(far <= kMaxPlaneHit);
}

std::uint32_t plane_lanes_avx2(ir::Vec3 n, double d, const ShadowLanes16& r, std::uint32_t live) {
  std::uint32_t hits = 0;
  for (std::uint32_t off = 0; off < 16; off += 4) {
    const std::uint32_t m = (live >> off) & 15;
    if (!m) continue;
    F64x4 t;
    hits |= meets4<false>(n, d, widen4(r.ox + off), widen4(r.oy + off), widen4(r.oz + off),
                          widen4(r.dx + off), widen4(r.dy + off), widen4(r.dz + off), F64x4{},
                          F64x4{} + double(kAreaShadowEnd), F64x4{}, m, t)
            << off;
  }
  return hits;
}

std::uint32_t plane_hit_lanes_avx2(ir::Vec3 n, double d, const PlaneRayLanes& r, std::uint32_t live,
                                   double* tmax_io, double* tie_io) {
  std::uint32_t hits = 0;
  for (std::uint32_t off = 0; off < 16; off += 4) {
    const std::uint32_t live4 = (live >> off) & 15;
    if (!live4) continue;
    F64x4 tmax, tie, t;
    __builtin_memcpy(&tmax, tmax_io + off, sizeof tmax);
    __builtin_memcpy(&tie, tie_io + off, sizeof tie);
    const std::uint32_t m = meets4<true>(
        n, d, widen4(r.ox + off), widen4(r.oy + off), widen4(r.oz + off), widen4(r.dx + off),
        widen4(r.dy + off), widen4(r.dz + off), widen4(r.tnear + off), tmax, tie, live4, t);
    if (!m) continue;
    const I64x4 hit = (I64x4{1, 2, 4, 8} & std::int64_t(m)) != 0;
    tmax = hit ? t : tmax;
    tie = hit ? F64x4{} : tie;
    __builtin_memcpy(tmax_io + off, &tmax, sizeof tmax);
    __builtin_memcpy(tie_io + off, &tie, sizeof tie);
    hits |= m << off;
  }
  return hits;
}

#pragma GCC pop_options

#endif  // SNELL_HAVE_AVX512_PATH

const SimdPaths<PlaneLanesFn>& available() {
#ifdef SNELL_HAVE_AVX512_PATH
  static const auto paths = simd_paths<PlaneLanesFn>(avx512_supported(), plane_lanes_avx512,
                                                     cpu_has_avx2(), plane_lanes_avx2, nullptr);
#else
  static const auto paths = simd_paths<PlaneLanesFn>(false, nullptr, nullptr);
#endif
  return paths;
}

const SimdPaths<PlaneHitLanesFn>& hit_available() {
#ifdef SNELL_HAVE_AVX512_PATH
  static const auto paths = simd_paths<PlaneHitLanesFn>(
      avx512_supported(), plane_hit_lanes_avx512, cpu_has_avx2(), plane_hit_lanes_avx2, nullptr);
#else
  static const auto paths = simd_paths<PlaneHitLanesFn>(false, nullptr, nullptr);
#endif
  return paths;
}

}  // namespace

PlaneHitLanesFn plane_hit_lanes() {
  static const PlaneHitLanesFn best = best_path(hit_available());
  return best;
}

std::vector<std::pair<std::string, PlaneHitLanesFn>> plane_hit_lanes_paths() {
  return hit_available();
}

PlaneLanesFn plane_lanes() {
  static const PlaneLanesFn best = best_path(available());
  return best;
}

std::vector<std::pair<std::string, PlaneLanesFn>> plane_lanes_paths() {
  return available();
}

}  // namespace snell::rt::geom
