// Hard cases on the runtime's pure functions (robustness.md §1): Fresnel and
// refraction for any input (#10, #11, #12), Schlick's domain (#16), the glass→water
// interface (#17, unit part), Beer's special values (#22), orthonormal bases (#25),
// sample values at 0 and just below 1 (#31), 8-bit conversion of non-finite values
// (#38) and FTZ/DAZ independence (#39). Tests in tests/runtime that already cover a
// case are listed in docs/hardcases.md and not repeated here.
#include <pmmintrin.h>
#include <xmmintrin.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "runtime/camera.hpp"
#include "runtime/color.hpp"
#include "runtime/sampler.hpp"
#include "runtime/shading/fresnel.hpp"
#include "runtime/vec.hpp"
#include "tests/runtime/scene_util.hpp"

using namespace snell;
using namespace snell::rt;
using ir::FresnelMode;

namespace {
using test::kPi;
double deg(double d) {
  return d * kPi / 180.0;
}
// log-uniform in [lo, hi]
double log_uniform(std::mt19937_64& rng, double lo, double hi) {
  std::uniform_real_distribution<double> u(std::log(lo), std::log(hi));
  return std::exp(u(rng));
}
}  // namespace

TEST_CASE("hc10 Fresnel is finite and in 0..1 for cos just outside -1..1 and eta 1e-3..1e3",
          "[hardcase][fresnel][property]") {
  // 2e6 samples, cos uniform in [-1-4ulp, 1+4ulp] (an unnormalised direction's cos),
  // eta log-uniform in [1e-3, 1e3]; both Fresnel modes. R == 1 exactly whenever
  // sin²θt ≥ 1 (TIR), with the incident side chosen by the sign of cos.
  std::mt19937_64 rng(10);
  const double lim = 1 + 4 * std::numeric_limits<double>::epsilon();
  std::uniform_real_distribution<double> ucos(-lim, lim);
  long bad = 0, tir = 0;
  for (int i = 0; i < 2000000; ++i) {
    double c = ucos(rng), eta = log_uniform(rng, 1e-3, 1e3);
    for (auto mode : {FresnelMode::Exact, FresnelMode::Schlick}) {
      double R = fresnel_dielectric(c, eta, mode);
      if (!(R >= 0 && R <= 1)) ++bad;  // also catches NaN
      double e = c < 0 ? 1 / eta : eta, ca = std::fmin(std::fabs(c), 1.0);
      if ((1 - ca * ca) / (e * e) >= 1) {
        ++tir;
        if (R != 1) ++bad;
      }
    }
  }
  CHECK(bad == 0);
  CHECK(tir > 100000);
  CHECK(fresnel_dielectric(1, 1.5, FresnelMode::Exact) == Approx(0.04).margin(1e-6));
  CHECK(fresnel_dielectric(-1, 1.5, FresnelMode::Exact) == Approx(0.04).margin(1e-6));
  CHECK(fresnel_dielectric(lim, 1.5, FresnelMode::Exact) == Approx(0.04).margin(1e-6));
  CHECK(fresnel_dielectric(-lim, 1.5, FresnelMode::Schlick) == Approx(0.04).margin(1e-6));
}

TEST_CASE("hc11 which side and which eta: theta_t and reciprocity", "[hardcase][fresnel]") {
  // The R tables for both sides are in tests/runtime/test_fresnel.cpp; here θt at
  // 45° for η 1.5 (28.1255°, §3.1) and reciprocity Fr(cosθi, η) = Fr(-cosθt, η):
  // the same interface crossed backwards reflects the same fraction.
  Interface f = make_interface(std::cos(deg(45)), 1.5);
  CHECK(std::acos(f.cos_t) * 180 / kPi == Approx(28.1255).margin(1e-4));
  CHECK(fresnel_exact(f) == Approx(0.05023991).margin(1e-8));
  CHECK(fresnel_dielectric(std::cos(deg(60)), 1.5, FresnelMode::Exact) ==
        Approx(0.08918671).margin(1e-8));
  CHECK(fresnel_dielectric(std::cos(deg(60)), 1 / 1.5, FresnelMode::Exact) == 1.0);
  for (double eta : {1.5, 1.33, 1 / 1.5, 2.42})
    for (int th = 0; th < 90; ++th) {
      Interface g = make_interface(std::cos(deg(th)), eta);
      if (g.tir) continue;
      INFO("eta " << eta << " theta " << th);
      CHECK(fresnel_dielectric(-g.cos_t, eta, FresnelMode::Exact) ==
            Approx(fresnel_exact(g)).margin(1e-6));
    }
}

TEST_CASE("hc12 refraction fails exactly when Fresnel says TIR, over 2e6 inputs",
          "[hardcase][fresnel][property]") {
  // One Interface value carries the TIR test that both the reflectance and the
  // refracted direction use; this checks the agreement over 2e6 random (cos, η),
  // and that a refracted direction always exists (finite, unit, through the surface)
  // when there is no TIR. R == 1 without TIR happens only at cos = 0 exactly (grazing
  // incidence onto the denser side), which a continuous draw never produces.
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> u(0, 1);
  long disagree = 0, not_unit = 0, wrong_side = 0, tir = 0;
  for (int i = 0; i < 2000000; ++i) {
    double c = u(rng), eta = log_uniform(rng, 1e-3, 1e3);
    Interface f = make_interface(c, eta);
    double R = fresnel_exact(f);
    if (f.tir != (R == 1)) ++disagree;
    if (f.tir) {
      ++tir;
      continue;
    }
    double s = std::sqrt(1 - c * c);
    Vec3d t = refract({s, -c, 0}, {0, 1, 0}, f);
    double len = std::sqrt(t.x * t.x + t.y * t.y + t.z * t.z);
    if (!(std::fabs(len - 1) < 1e-9)) ++not_unit;
    if (!(t.y < 0)) ++wrong_side;
  }
  CHECK(disagree == 0);
  CHECK(not_unit == 0);
  CHECK(wrong_side == 0);
  CHECK(tir > 100000);
}

TEST_CASE("hc16 Schlick stays within R0..1 for cos in 0..1 on both sides", "[hardcase][fresnel]") {
  // The maximum-error oracle (0.035693 / 0.059924) is in tests/runtime/test_fresnel.cpp.
  for (double eta : {1.5, 1.33, 1 / 1.5, 1 / 1.33, 2.42}) {
    double r0 = (eta - 1) / (eta + 1);
    r0 *= r0;
    for (int i = 0; i <= 10000; ++i) {
      double c = i / 10000.0;
      double R = fresnel_schlick(make_interface(c, eta));
      INFO("eta " << eta << " cos " << c);
      REQUIRE(R >= r0 - 1e-15);
      REQUIRE(R <= 1);
    }
    // A negative cos (a caller bug) is clamped to 0, never 7.33 (§3.9).
    CHECK(fresnel_schlick(make_interface(-0.5, eta)) <= 1);
  }
}

TEST_CASE("hc17 the glass-to-water interface: eta 0.88667, R0 and critical angle",
          "[hardcase][fresnel]") {
  // Only the interface values: Snell has no nested media (docs/hardcases.md #17).
  double eta = 1.33 / 1.5;
  CHECK(eta == Approx(0.88667).margin(1e-5));
  CHECK(fresnel_exact(make_interface(1, eta)) == Approx(0.00360849).margin(1e-8));
  double crit = std::asin(eta) * 180 / kPi;
  CHECK(crit == Approx(62.4573).margin(1e-4));
  CHECK_FALSE(make_interface(std::cos(deg(crit - 1e-3)), eta).tir);
  CHECK(make_interface(std::cos(deg(crit + 1e-3)), eta).tir);
}

TEST_CASE("hc22 Beer special values: infinities, zeros and independent channels",
          "[hardcase][beer]") {
  // tests/runtime/test_fresnel.cpp has the table and T(0,∞) = T(∞,0) = 1,
  // T(1,∞) = T(1e30,1e10) = 0; the rest of §1 #22:
  CHECK(beer(INFINITY, 1) == 0.0);
  CHECK(beer(INFINITY, INFINITY) == 0.0);
  CHECK(beer(0, 0) == 1.0);
  CHECK(beer(1e-300, 1e-300) == 1.0);
  CHECK(beer(std::numeric_limits<double>::denorm_min(), INFINITY) == 0.0);
  // Channels are independent: one infinite channel does not touch the others.
  const double sig[3] = {0.5, 1, INFINITY};
  const double want[3] = {0.60653066, 0.36787944, 0};
  for (int k = 0; k < 3; ++k) CHECK(beer(sig[k], 1) == Approx(want[k]).margin(1e-8));
  // "Colour at distance" (σ = -ln c / d_ref) is not a language feature; its value
  // for c = 0.5, d_ref = 1 is the σ that halves light over one unit:
  CHECK(beer(0.69314718, 1) == Approx(0.5).margin(1e-8));
}

TEST_CASE("hc25 orthonormal basis on the axes, Duff's bad vector and 1e6 random normals",
          "[hardcase][onb]") {
  // Error metric of §1 #25: mean of (|a|-1)², (|b|-1)², (|n|-1)² and the three dot²,
  // computed in double from the float basis. Bound 1e-10: float rounding gives ~1e-14.
  auto metric = [](Vec3f n) {
    Vec3f a, b;
    orthonormal_basis(n, a, b);
    auto len = [](Vec3f v) {
      return std::sqrt(double(v.x) * v.x + double(v.y) * v.y + double(v.z) * v.z);
    };
    auto d = [](Vec3f p, Vec3f q) {
      return double(p.x) * q.x + double(p.y) * q.y + double(p.z) * q.z;
    };
    double e = 0;
    for (double l : {len(a), len(b), len(n)}) e += (l - 1) * (l - 1);
    for (double x : {d(a, b), d(a, n), d(b, n)}) e += x * x;
    return e / 6;
  };
  const Vec3f axes[] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (Vec3f n : axes) {
    Vec3f a, b;
    orthonormal_basis(n, a, b);
    INFO("n " << to_string(n) << " a " << to_string(a) << " b " << to_string(b));
    CHECK(metric(n) < 1e-10);
    CHECK((is_finite(a) && is_finite(b)));
  }
  CHECK(metric({0.00038527316f, 0.00038460016f, -0.99999988079f}) < 1e-10);
  std::mt19937_64 rng(25);
  std::normal_distribution<double> g;
  double worst = 0;
  for (int i = 0; i < 1000000; ++i) {
    double x = g(rng), y = g(rng), z = g(rng), l = std::sqrt(x * x + y * y + z * z);
    if (i % 2) z = -std::fabs(z), x *= 1e-4, y *= 1e-4, l = std::sqrt(x * x + y * y + z * z);
    worst = std::fmax(worst, metric(to_float(x / l, y / l, z / l)));
  }
  CHECK(worst < 1e-10);
}

TEST_CASE("hc31 sample values: exactly 0 is possible, 1 never, even from the top 128 integers",
          "[hardcase][sampler]") {
  // float(u32)·2^-32 rounds to 1.0f for the 128 largest integers (§1 #31); the
  // 24-bit conversion never does. Exhaustive over those 128, then the ends.
  for (std::uint32_t k = 0xFFFFFF80u; k != 0; ++k) REQUIRE(to_unit_float(k) < 1.0f);
  CHECK(to_unit_float(0xFFFFFFFFu) == 1.0f - 0x1p-24f);  // OneMinusEpsilon
  CHECK(to_unit_float(0) == 0.0f);
  CHECK(to_unit_float(0xFFu) == 0.0f);
  // Camera rays at the extreme film positions of a pixel (u = 0 and the largest
  // u < 1) are finite and unit length.
  ir::Camera cam;
  cam.location = {0, 0, 0};
  cam.look_at = {0, 0, 1};
  PinholeCamera pc(cam, 7, 5);
  for (float u : {0.0f, 0.5f, 1.0f - 0x1p-24f})
    for (float v : {0.0f, 0.5f, 1.0f - 0x1p-24f})
      for (std::uint32_t px : {0u, 6u}) {
        Ray r = pc.generate(px + double(u), 4 + double(v));
        REQUIRE(is_finite(r.dir));
        REQUIRE(std::fabs(length(r.dir) - 1) < 1e-6f);
      }
  // Every sampler kind, many seeds and large dimensions: values in [0, 1).
  for (auto kind :
       {ir::SamplerKind::Independent, ir::SamplerKind::Stratified, ir::SamplerKind::Sobol})
    for (std::uint64_t seed : {0ull, 1ull, 0xFFFFFFFFFFFFFFFFull})
      for (std::uint32_t spp : {1u, 3u, 256u})
        for (std::uint32_t i = 0; i < spp; i += 1 + spp / 16)
          for (std::uint32_t dim : {0u, 1u, 2u, 0x7FFFFFFFu, 0xFFFFFFFFu}) {
            Sample2 s = sample2({kind, seed, spp}, 0xFFFFFFFFu, 3, i, dim);
            REQUIRE((s.u >= 0.0f && s.u < 1.0f && s.v >= 0.0f && s.v < 1.0f));
          }
}

TEST_CASE("hc38 8-bit conversion of non-finite and out-of-range values", "[hardcase][color]") {
  // quantize8 is the writer's last step; the OCIO table of finite values is in
  // tests/runtime/test_color.cpp. NaN → 0, ±∞ and huge values clamp.
  CHECK(quantize8(std::numeric_limits<float>::quiet_NaN()) == 0);
  CHECK(quantize8(-std::numeric_limits<float>::quiet_NaN()) == 0);
  CHECK(quantize8(INFINITY) == 255);
  CHECK(quantize8(-INFINITY) == 0);
  CHECK(quantize8(1e30f) == 255);
  CHECK(quantize8(-1e30f) == 0);
  CHECK(quantize8(1.0f) == 255);
  CHECK(quantize8(0.0f) == 0);
  CHECK(quantize8(-0.0f) == 0);
}

TEST_CASE("hc39 Fresnel, Beer and sampler values are the same with FTZ/DAZ on and off",
          "[hardcase][fp]") {
  // The renderer turns FTZ/DAZ on in every worker (Embree's advice); the pure
  // functions must not care for normal-range inputs. Double-precision Fresnel and
  // Beer are untouched by the SSE flags' float paths only if nothing denormal comes
  // up; the comparison is exact, stricter than §1's 1e-6.
  auto table = [] {
    std::vector<double> v;
    for (int i = 0; i <= 200; ++i) {
      double c = i / 200.0;
      for (double eta : {1.5, 1 / 1.5, 1.33, 2.42}) {
        v.push_back(fresnel_exact(make_interface(c, eta)));
        v.push_back(fresnel_schlick(make_interface(c, eta)));
      }
      v.push_back(beer(0.5 + c, 3 * c));
      Sample2 s = sample2({ir::SamplerKind::Sobol, 5, 16}, i, 2, i % 16, i);
      v.push_back(s.u);
      v.push_back(s.v);
      Vec3f a, b;
      orthonormal_basis(normalize(Vec3f(c, 1 - c, -0.5f)), a, b);
      v.insert(v.end(), {a.x, a.y, a.z, b.x, b.y, b.z});
    }
    return v;
  };
  unsigned int saved = _mm_getcsr();
  _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_OFF);
  _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_OFF);
  std::vector<double> off = table();
  _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
  _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
  std::vector<double> on = table();
  _mm_setcsr(saved);
  REQUIRE(off.size() == on.size());
  for (std::size_t i = 0; i < off.size(); ++i) {
    INFO("entry " << i);
    CHECK(on[i] == off[i]);
  }
}
