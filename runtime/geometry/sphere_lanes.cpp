#include "runtime/geometry/sphere_lanes.hpp"

#include "runtime/geometry/sphere.hpp"
#include "runtime/simd_paths.hpp"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define SNELL_HAVE_AVX512_PATH 1
#endif

namespace snell::rt::geom {

namespace {

#ifdef SNELL_HAVE_AVX512_PATH

// The whole section for AVX-512, so its small helpers inline into eight().
#pragma GCC push_options
#pragma GCC target("avx512f,avx512vl")
// GCC 12's AVX-512 headers warn falsely on their own masked builtins
// (-Wmaybe-uninitialized, GCC PR 105593: _mm512_sqrt_pd, _mm512_andnot_si512).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

// Plain vector arithmetic (GCC's operators on __m512d are the packed IEEE ops), and
// conversions by __builtin_convertvector.
using F32x8 = float __attribute__((vector_size(32)));
using F64x8 = double __attribute__((vector_size(64)));
inline __m512d widen(const float* p) {
  F32x8 f;
  __builtin_memcpy(&f, p, sizeof f);
  return __m512d(__builtin_convertvector(f, F64x8));
}
inline __m256 narrow(__m512d d) {
  return __m256(__builtin_convertvector(F64x8(d), F32x8));
}
inline __m512d dot3(__m512d ax, __m512d ay, __m512d az, __m512d bx, __m512d by, __m512d bz) {
  return (ax * bx + ay * by) + az * bz;
}

// Eight lanes starting at `off`. Each line is one operation of sphere_roots or
// hit_similar_sphere, in their order (a dot product is (x·x + y·y) + z·z, as
// ir::dot).
std::uint32_t eight(ir::Vec3 c, double r, double scale, const RayLanes& R, std::uint32_t off,
                    HitLanes* out, std::uint32_t& undecided) {
  __m256i valid = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(R.valid + off));
  __mmask8 m = _mm256_cmpneq_epi32_mask(valid, _mm256_setzero_si256());
  if (!m) return 0;
  const __m512d ox = widen(R.ox + off), oy = widen(R.oy + off), oz = widen(R.oz + off);
  const __m512d dx = widen(R.dx + off), dy = widen(R.dy + off), dz = widen(R.dz + off);
  const __m256 tnear_f = _mm256_loadu_ps(R.tnear + off), tfar_f = _mm256_loadu_ps(R.tfar + off);
  const __m512d tnear = widen(R.tnear + off), tfar = widen(R.tfar + off);
  const __m512d cx = _mm512_set1_pd(c.x), cy = _mm512_set1_pd(c.y), cz = _mm512_set1_pd(c.z);
  const __m512d rv = _mm512_set1_pd(r);
  // sphere_roots(o, d, c, r)
  const __m512d fx = ox - cx, fy = oy - cy, fz = oz - cz;
  const __m512d a = dot3(dx, dy, dz, dx, dy, dz);
  const __m512d b = dot3(fx, fy, fz, dx, dy, dz);
  const __m512d ba = b / a;
  const __m512d vx = fx - dx * ba, vy = fy - dy * ba, vz = fz - dz * ba;
  const __m512d lv = _mm512_sqrt_pd(dot3(vx, vy, vz, vx, vy, vz));
  const __m512d disc = (rv + lv) * (rv - lv);
  m &= _mm512_cmp_pd_mask(disc, _mm512_setzero_pd(), _CMP_GE_OQ);
  if (!m) return 0;
  const __m512d cc = dot3(fx, fy, fz, fx, fy, fz) - _mm512_set1_pd(r * r);
  const __m512d s = _mm512_sqrt_pd(a * disc);
  const __m512i sign = _mm512_set1_epi64(std::int64_t(0x8000000000000000ull));
  // copysign(s, b) and -b: sign-bit operations, exact as the scalar ones.
  const __m512d s_b =
      _mm512_castsi512_pd(_mm512_or_si512(_mm512_andnot_si512(sign, _mm512_castpd_si512(s)),
                                          _mm512_and_si512(sign, _mm512_castpd_si512(b))));
  const __m512d neg_b = _mm512_castsi512_pd(_mm512_xor_si512(sign, _mm512_castpd_si512(b)));
  const __m512d q = neg_b - s_b;
  const __mmask8 q0 = m & _mm512_cmp_pd_mask(q, _mm512_setzero_pd(), _CMP_EQ_OQ);
  undecided |= std::uint32_t(q0) << off;
  m &= ~q0;
  const __m512d t0 = cc / q, t1 = q / a;
  const __mmask8 swap = _mm512_cmp_pd_mask(t0, t1, _CMP_GT_OQ);
  const __m512d lo = _mm512_mask_blend_pd(swap, t0, t1), hi = _mm512_mask_blend_pd(swap, t1, t0);
  // hit_similar_sphere: the nearer root past tnear, inside (tnear, tfar) in double
  // and again after rounding to float.
  const __m512d t = _mm512_mask_blend_pd(_mm512_cmp_pd_mask(lo, tnear, _CMP_GT_OQ), hi, lo);
  m &= _mm512_cmp_pd_mask(t, tnear, _CMP_GT_OQ) & _mm512_cmp_pd_mask(t, tfar, _CMP_LT_OQ);
  const __m256 tf = narrow(t);
  m &= _mm256_cmp_ps_mask(tf, tnear_f, _CMP_GT_OQ) & _mm256_cmp_ps_mask(tf, tfar_f, _CMP_LT_OQ);
  if (!m || !out) return std::uint32_t(m) << off;
  // n = (o + d·t - c) · normal_scale(r), not unit (hit_similar_sphere)
  const __m512d sc = _mm512_set1_pd(scale);
  const __m512d nx = (ox + dx * t - cx) * sc, ny = (oy + dy * t - cy) * sc,
                nz = (oz + dz * t - cz) * sc;
  _mm256_storeu_ps(out->t + off, tf);
  _mm256_storeu_ps(out->nx + off, narrow(nx));
  _mm256_storeu_ps(out->ny + off, narrow(ny));
  _mm256_storeu_ps(out->nz + off, narrow(nz));
  return std::uint32_t(m) << off;
}

std::uint32_t sphere_lanes_avx512(ir::Vec3 c, double r, const RayLanes& rays, HitLanes* out,
                                  std::uint32_t& undecided) {
  std::uint32_t hits = 0;
  const double scale = out ? normal_scale(r) : 0;
  for (std::uint32_t off = 0; off < rays.n && off < 16; off += 8)
    hits |= eight(c, r, scale, rays, off, out, undecided);
  return hits;
}

#pragma GCC diagnostic pop
#pragma GCC pop_options

bool avx512_supported() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl");
}

// AVX2: eight() as two halves of four doubles in step, masks as bits (movemask).
// The halves share eight()'s early returns and its stores (all eight lanes of t and
// n once any of them hits), so both paths leave the same HitLanes.
#pragma GCC push_options
#pragma GCC target("avx2,fma")

#include "runtime/geometry/lanes_avx2.hpp"  // inside the region: takes its target

inline F64x4 dot3(F64x4 ax, F64x4 ay, F64x4 az, F64x4 bx, F64x4 by, F64x4 bz) {
  return (ax * bx + ay * by) + az * bz;
}

// Eight lanes starting at `off`, as eight(): the same operations in the same order,
// each half's mask in its own four bits of m.
std::uint32_t eight_avx2(ir::Vec3 c, double r, double scale, const RayLanes& R, std::uint32_t off,
                         HitLanes* out, std::uint32_t& undecided) {
  std::uint32_t m = 0;
  for (int h = 0; h < 2; ++h) {
    I32x4 valid;
    __builtin_memcpy(&valid, R.valid + off + 4 * h, sizeof valid);
    m |= bits4(valid != 0) << 4 * h;
  }
  if (!m) return 0;
  const F64x4 cx = splat4(c.x), cy = splat4(c.y), cz = splat4(c.z), rv = splat4(r);
  F64x4 ox[2], oy[2], oz[2], dx[2], dy[2], dz[2], fx[2], fy[2], fz[2], a[2], b[2], disc[2];
  for (int h = 0; h < 2; ++h) {
    const std::uint32_t at = off + 4 * h;
    ox[h] = widen4(R.ox + at), oy[h] = widen4(R.oy + at), oz[h] = widen4(R.oz + at);
    dx[h] = widen4(R.dx + at), dy[h] = widen4(R.dy + at), dz[h] = widen4(R.dz + at);
    // sphere_roots(o, d, c, r)
    fx[h] = ox[h] - cx, fy[h] = oy[h] - cy, fz[h] = oz[h] - cz;
    a[h] = dot3(dx[h], dy[h], dz[h], dx[h], dy[h], dz[h]);
    b[h] = dot3(fx[h], fy[h], fz[h], dx[h], dy[h], dz[h]);
    const F64x4 ba = b[h] / a[h];
    const F64x4 vx = fx[h] - dx[h] * ba, vy = fy[h] - dy[h] * ba, vz = fz[h] - dz[h] * ba;
    const F64x4 lv = F64x4(_mm256_sqrt_pd(__m256d(dot3(vx, vy, vz, vx, vy, vz))));
    disc[h] = (rv + lv) * (rv - lv);
    m &= ~(bits4(!(disc[h] >= 0)) << 4 * h);
  }
  if (!m) return 0;
  const F64x4 rr = splat4(r * r);
  constexpr std::int64_t kSign = std::int64_t(0x8000000000000000ull);
  F64x4 t[2];
  F32x4 tf[2];
  for (int h = 0; h < 2; ++h) {
    const std::uint32_t at = off + 4 * h;
    const F64x4 cc = dot3(fx[h], fy[h], fz[h], fx[h], fy[h], fz[h]) - rr;
    const F64x4 s = F64x4(_mm256_sqrt_pd(__m256d(a[h] * disc[h])));
    // copysign(s, b) and -b: sign-bit operations, exact as the scalar ones.
    const F64x4 s_b = F64x4((I64x4(s) & ~kSign) | (I64x4(b[h]) & kSign));
    const F64x4 neg_b = F64x4(I64x4(b[h]) ^ kSign);
    const F64x4 q = neg_b - s_b;
    const std::uint32_t q0 = (m >> 4 * h) & 15 & bits4(q == 0);
    undecided |= q0 << at;
    m &= ~(q0 << 4 * h);
    const F64x4 t0 = cc / q, t1 = q / a[h];
    const I64x4 swap = t0 > t1;
    const F64x4 lo = swap ? t1 : t0, hi = swap ? t0 : t1;
    // hit_similar_sphere: the nearer root past tnear, inside (tnear, tfar) in double
    // and again after rounding to float.
    const F64x4 tnear = widen4(R.tnear + at), tfar = widen4(R.tfar + at);
    t[h] = lo > tnear ? lo : hi;
    m &= ~(bits4(!((t[h] > tnear) & (t[h] < tfar))) << 4 * h);
    F32x4 tnear_f, tfar_f;
    __builtin_memcpy(&tnear_f, R.tnear + at, sizeof tnear_f);
    __builtin_memcpy(&tfar_f, R.tfar + at, sizeof tfar_f);
    tf[h] = narrow4(t[h]);
    m &= ~(bits4(!((tf[h] > tnear_f) & (tf[h] < tfar_f))) << 4 * h);
  }
  if (!m || !out) return m << off;
  // n = (o + d·t - c) · normal_scale(r), not unit (hit_similar_sphere)
  const F64x4 sc = splat4(scale);
  for (int h = 0; h < 2; ++h) {
    const std::uint32_t at = off + 4 * h;
    const F32x4 nx = narrow4((ox[h] + dx[h] * t[h] - cx) * sc);
    const F32x4 ny = narrow4((oy[h] + dy[h] * t[h] - cy) * sc);
    const F32x4 nz = narrow4((oz[h] + dz[h] * t[h] - cz) * sc);
    __builtin_memcpy(out->t + at, &tf[h], sizeof tf[h]);
    __builtin_memcpy(out->nx + at, &nx, sizeof nx);
    __builtin_memcpy(out->ny + at, &ny, sizeof ny);
    __builtin_memcpy(out->nz + at, &nz, sizeof nz);
  }
  return m << off;
}

std::uint32_t sphere_lanes_avx2(ir::Vec3 c, double r, const RayLanes& rays, HitLanes* out,
                                std::uint32_t& undecided) {
  std::uint32_t hits = 0;
  const double scale = out ? normal_scale(r) : 0;
  for (std::uint32_t off = 0; off < rays.n && off < 16; off += 8)
    hits |= eight_avx2(c, r, scale, rays, off, out, undecided);
  return hits;
}

#pragma GCC pop_options

#endif  // SNELL_HAVE_AVX512_PATH

const SimdPaths<SphereLanesFn>& available() {
#ifdef SNELL_HAVE_AVX512_PATH
  static const auto paths = simd_paths<SphereLanesFn>(avx512_supported(), sphere_lanes_avx512,
                                                      cpu_has_avx2(), sphere_lanes_avx2, nullptr);
#else
  static const auto paths = simd_paths<SphereLanesFn>(false, nullptr, nullptr);
#endif
  return paths;
}

}  // namespace

SphereLanesFn sphere_lanes() {
  static const SphereLanesFn best = best_path(available());
  return best;
}

std::vector<std::pair<std::string, SphereLanesFn>> sphere_lanes_paths() {
  return available();
}

}  // namespace snell::rt::geom
