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

// AVX2: the same operations on eight floats at a time, masks as bits (movemask).
#pragma GCC push_options
#pragma GCC target("avx2,fma")

using F32x8 = float __attribute__((vector_size(32)));
using I32x8 = std::int32_t __attribute__((vector_size(32)));
inline F32x8 load8(const float* p) {
  F32x8 x;
  __builtin_memcpy(&x, p, sizeof x);
  return x;
}
inline void store8(float* p, F32x8 x) {
  __builtin_memcpy(p, &x, sizeof x);
}
inline F32x8 splat8(float x) {  // a broadcast: keeps -0, which 0 + x would not
  return F32x8(_mm256_set1_ps(x));
}
inline std::uint32_t bits8(I32x8 m) {
  return std::uint32_t(_mm256_movemask_ps(__m256(m)));
}
inline F32x8 abs8(F32x8 x) {  // the sign bit cleared, as _mm512_abs_ps
  return F32x8(I32x8(x) & 0x7fffffff);
}
inline F32x8 dot3(F32x8 ax, F32x8 ay, F32x8 az, F32x8 bx, F32x8 by, F32x8 bz) {
  return (ax * bx + ay * by) + az * bz;
}
inline F32x8 dot3(Vec3f a, F32x8 bx, F32x8 by, F32x8 bz) {
  return (a.x * bx + a.y * by) + a.z * bz;
}
inline F32x8 offset_coord8(F32x8 p, F32x8 n, float scale) {
  const float origin = scale * (1.0f / 32.0f);
  const float float_scale = scale * (1.0f / 65536.0f);
  const F32x8 near = p + float_scale * n;
  // cvttps2dq, as the scalar conversion (out of range: INT32_MIN, never reached).
  const I32x8 of = I32x8(_mm256_cvttps_epi32(__m256(256.0f * n)));
  const I32x8 step = p < F32x8{} ? -of : of;
  const F32x8 far = F32x8(I32x8(p) + step);
  return abs8(p) < origin ? near : far;
}

std::uint32_t area_lanes_avx2(const AreaCell& cell, const PointLanes& P, const float* ju,
                              const float* jv, std::uint32_t lanes, ShadowLanes& out) {
  const AreaLightF& l = *cell.light;
  const float scale = near_scale(cell.scale, l.reach);
  const float inv_n = 1.0f / float(l.nu * l.nv);
  std::uint32_t lit = 0;
  for (std::uint32_t h = 0; h < 16; h += 8) {
    std::uint32_t m = (lanes >> h) & 255;
    if (!m) continue;
    const F32x8 u = (float(cell.iu) + load8(ju + h)) / float(l.nu);
    const F32x8 v = (float(cell.iv) + load8(jv + h)) / float(l.nv);
    const F32x8 qx = (l.corner.x + l.e1.x * u) + l.e2.x * v;
    const F32x8 qy = (l.corner.y + l.e1.y * u) + l.e2.y * v;
    const F32x8 qz = (l.corner.z + l.e1.z * u) + l.e2.z * v;
    const F32x8 tx = qx - load8(P.px + h), ty = qy - load8(P.py + h), tz = qz - load8(P.pz + h);
    const F32x8 nx = load8(P.nx + h), ny = load8(P.ny + h), nz = load8(P.nz + h);
    const F32x8 d2 = dot3(tx, ty, tz, tx, ty, tz);
    const F32x8 cos_s = dot3(nx, ny, nz, tx, ty, tz);
    const F32x8 cos_l = F32x8(I32x8(dot3(l.n, tx, ty, tz)) ^ INT32_MIN);  // exact negation
    const F32x8 ox = load8(P.ox + h), oy = load8(P.oy + h), oz = load8(P.oz + h);
    const F32x8 zero{};
    m &= bits8((cos_s > zero) & (d2 > zero) & (dot3(nx, ny, nz, qx - ox, qy - oy, qz - oz) > zero));
    const I32x8 front = cos_l > zero;
    if (!l.two_sided) m &= bits8(front);
    if (!m) continue;
    const F32x8 sx = front ? splat8(l.n.x) : splat8(-l.n.x);
    const F32x8 sy = front ? splat8(l.n.y) : splat8(-l.n.y);
    const F32x8 sz = front ? splat8(l.n.z) : splat8(-l.n.z);
    store8(out.dx + h, offset_coord8(qx, sx, scale) - ox);
    store8(out.dy + h, offset_coord8(qy, sy, scale) - oy);
    store8(out.dz + h, offset_coord8(qz, sz, scale) - oz);
    store8(out.g + h, ((cos_s * abs8(cos_l)) / (d2 * d2)) * l.area * inv_n);
    store8(out.tx + h, tx);
    store8(out.ty + h, ty);
    store8(out.tz + h, tz);
    lit |= m << h;
  }
  return lit;
}

#pragma GCC pop_options

#endif  // SNELL_HAVE_AVX512_PATH

const SimdPaths<AreaLanesFn>& available() {
#ifdef SNELL_HAVE_AVX512_PATH
  static const auto paths = simd_paths<AreaLanesFn>(avx512_supported(), area_lanes_avx512,
                                                    cpu_has_avx2(), area_lanes_avx2, nullptr);
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
