#include "runtime/shading/area_lanes.hpp"

#include "runtime/shading/lights.hpp"
#include "runtime/simd_paths.hpp"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define SNELL_HAVE_AVX512_PATH 1
#endif

namespace snell::rt {

namespace {

#ifdef SNELL_HAVE_AVX512_PATH

#pragma GCC push_options
#pragma GCC target("avx512f")
// GCC 12's AVX-512 headers warn falsely on their own masked builtins
// (-Wmaybe-uninitialized, GCC PR 105593: _mm512_cvttps_epi32).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

inline __m512 load(const float* p) {
  return _mm512_load_ps(p);
}
inline __m512 splat(float x) {
  return _mm512_set1_ps(x);
}
inline __mmask16 gt(__m512 a, __m512 b) {
  return _mm512_cmp_ps_mask(a, b, _CMP_GT_OQ);
}
// dot(a, b) as Vec3f's: (x·x + y·y) + z·z.
inline __m512 dot3(__m512 ax, __m512 ay, __m512 az, __m512 bx, __m512 by, __m512 bz) {
  return (ax * bx + ay * by) + az * bz;
}
inline __m512 dot3(Vec3f a, __m512 bx, __m512 by, __m512 bz) {
  return (splat(a.x) * bx + splat(a.y) * by) + splat(a.z) * bz;
}
// offset_coord (vec.hpp) of 16 coordinates p along the normal's component n.
inline __m512 offset_coord(__m512 p, __m512 n, float scale) {
  const float origin = scale * (1.0f / 32.0f);
  const float float_scale = scale * (1.0f / 65536.0f);
  const __m512 near = p + splat(float_scale) * n;
  const __m512i of = _mm512_cvttps_epi32(splat(256.0f) * n);
  const __m512i neg_of = _mm512_sub_epi32(_mm512_setzero_si512(), of);
  const __mmask16 below = _mm512_cmp_ps_mask(p, _mm512_setzero_ps(), _CMP_LT_OQ);
  const __m512i step = _mm512_mask_blend_epi32(below, of, neg_of);
  const __m512 far = _mm512_castsi512_ps(_mm512_add_epi32(_mm512_castps_si512(p), step));
  const __mmask16 small = _mm512_cmp_ps_mask(_mm512_abs_ps(p), splat(origin), _CMP_LT_OQ);
  return _mm512_mask_blend_ps(small, far, near);
}

// Each line is one operation of sample_li_area and shadow_to, in their order.
std::uint32_t area_lanes_avx512(const AreaCell& cell, const PointLanes& P, const float* ju,
                                const float* jv, std::uint32_t lanes, ShadowLanes& out) {
  const AreaLightF& l = *cell.light;
  __mmask16 m = __mmask16(lanes);
  const __m512 u = (splat(float(cell.iu)) + _mm512_loadu_ps(ju)) / splat(float(l.nu));
  const __m512 v = (splat(float(cell.iv)) + _mm512_loadu_ps(jv)) / splat(float(l.nv));
  // q = corner + e1 * u + e2 * v
  const __m512 qx = (splat(l.corner.x) + splat(l.e1.x) * u) + splat(l.e2.x) * v;
  const __m512 qy = (splat(l.corner.y) + splat(l.e1.y) * u) + splat(l.e2.y) * v;
  const __m512 qz = (splat(l.corner.z) + splat(l.e1.z) * u) + splat(l.e2.z) * v;
  const __m512 tx = qx - load(P.px), ty = qy - load(P.py), tz = qz - load(P.pz);
  const __m512 nx = load(P.nx), ny = load(P.ny), nz = load(P.nz);
  const __m512 d2 = dot3(tx, ty, tz, tx, ty, tz);
  const __m512 cos_s = dot3(nx, ny, nz, tx, ty, tz);
  // -dot(n, to): negation is exact, so its sign tests are dot's.
  const __m512 cos_l = _mm512_castsi512_ps(
      _mm512_xor_si512(_mm512_castps_si512(dot3(l.n, tx, ty, tz)), _mm512_set1_epi32(INT32_MIN)));
  const __m512 ox = load(P.ox), oy = load(P.oy), oz = load(P.oz);
  const __m512 zero = _mm512_setzero_ps();
  m &= gt(cos_s, zero) & gt(d2, zero) & gt(dot3(nx, ny, nz, qx - ox, qy - oy, qz - oz), zero);
  const __mmask16 front = gt(cos_l, zero);
  if (!l.two_sided) m &= front;
  if (!m) return 0;
  // side = cos_l > 0 ? n : -n; the target is the sample moved off the light.
  const __m512 sx = _mm512_mask_blend_ps(front, splat(-l.n.x), splat(l.n.x));
  const __m512 sy = _mm512_mask_blend_ps(front, splat(-l.n.y), splat(l.n.y));
  const __m512 sz = _mm512_mask_blend_ps(front, splat(-l.n.z), splat(l.n.z));
  const float scale = near_scale(cell.scale, l.reach);
  _mm512_store_ps(out.dx, offset_coord(qx, sx, scale) - ox);
  _mm512_store_ps(out.dy, offset_coord(qy, sy, scale) - oy);
  _mm512_store_ps(out.dz, offset_coord(qz, sz, scale) - oz);
  const float inv_n = 1.0f / float(l.nu * l.nv);
  _mm512_store_ps(out.g,
                  ((cos_s * _mm512_abs_ps(cos_l)) / (d2 * d2)) * splat(l.area) * splat(inv_n));
  _mm512_store_ps(out.tx, tx);
  _mm512_store_ps(out.ty, ty);
  _mm512_store_ps(out.tz, tz);
  return m;
}

#pragma GCC diagnostic pop
#pragma GCC pop_options

bool avx512_supported() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx512f");
}

#endif  // SNELL_HAVE_AVX512_PATH

const SimdPaths<AreaLanesFn>& available() {
#ifdef SNELL_HAVE_AVX512_PATH
  static const auto paths = simd_paths<AreaLanesFn>(avx512_supported(), area_lanes_avx512, nullptr);
#else
  static const auto paths = simd_paths<AreaLanesFn>(false, nullptr, nullptr);
#endif
  return paths;
}

}  // namespace

AreaLanesFn area_lanes() {
  static const AreaLanesFn best = best_path(available());
  return best;
}

std::vector<std::pair<std::string, AreaLanesFn>> area_lanes_paths() {
  return available();
}

}  // namespace snell::rt
