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

#endif  // SNELL_HAVE_AVX512_PATH

const SimdPaths<SphereLanesFn>& available() {
#ifdef SNELL_HAVE_AVX512_PATH
  static const auto paths =
      simd_paths<SphereLanesFn>(avx512_supported(), sphere_lanes_avx512, nullptr);
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
