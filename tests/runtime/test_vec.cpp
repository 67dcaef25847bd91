// #17: the inline fmax_f / next_up / next_down (vec.hpp) against libm's fmaxf and
// nextafterf, bit for bit, so replacing the calls changed no image: every pair of
// special values (±0, ±subnormals, ±FLT_MIN, ±1, ±FLT_MAX, ±inf, NaN) and a
// million random bit patterns (every exponent, NaNs among them). NaN results
// must be NaN; their payloads are not compared.
#include <catch2/catch.hpp>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "runtime/vec.hpp"

using namespace snell::rt;

namespace {

// Called through volatile pointers so the compiler neither folds nor inlines them.
float (*volatile libm_fmax)(float, float) = ::fmaxf;
float (*volatile libm_nextafter)(float, float) = ::nextafterf;

bool same(float a, float b) {
  if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b);
  return std::memcmp(&a, &b, 4) == 0;
}
std::uint32_t bits(float f) {
  std::uint32_t u;
  std::memcpy(&u, &f, 4);
  return u;
}
float from_bits(std::uint32_t u) {
  float f;
  std::memcpy(&f, &u, 4);
  return f;
}

std::vector<float> specials() {
  std::vector<float> v;
  for (float x : {0.0f, 0x1p-149f, 0x1p-148f, 0x1.fffffcp-127f, FLT_MIN, 0.5f, 1.0f, 1.5f,
                  16777216.0f, FLT_MAX, float(INFINITY)}) {
    v.push_back(x);
    v.push_back(-x);
  }
  v.push_back(std::nanf(""));
  v.push_back(-std::nanf(""));
  return v;
}

}  // namespace

TEST_CASE("fmax_f, next_up and next_down give libm's bits", "[vec]") {
  std::vector<float> xs = specials();
  std::mt19937 rng(17);
  for (int i = 0; i < 1000000; ++i) xs.push_back(from_bits(rng()));
  const std::vector<float> sp = specials();
  std::size_t checked = 0, nan_results = 0, signalling = 0;
  std::string first_mismatch;
  auto fail = [&](const char* what, float a, float b, float got, float want) {
    if (first_mismatch.empty())
      first_mismatch = std::string(what) + "(" + std::to_string(bits(a)) + ", " +
                       std::to_string(bits(b)) + "): " + std::to_string(bits(got)) + " not " +
                       std::to_string(bits(want));
  };
  auto pair = [&](float a, float b) {
    float want = libm_fmax(a, b), got = fmax_f(a, b);
    if (!same(got, want)) fail("fmax", a, b, got, want);
    nan_results += std::isnan(want);
    ++checked;
  };
  for (std::size_t i = 0; i < xs.size(); ++i) {
    float x = xs[i];
    signalling += is_signalling_nan(x);
    float up = libm_nextafter(x, INFINITY), down = libm_nextafter(x, -INFINITY);
    if (!same(next_up(x), up)) fail("next_up", x, INFINITY, next_up(x), up);
    if (!same(next_down(x), down)) fail("next_down", x, -INFINITY, next_down(x), down);
    // Pairs: each value against the next, and the specials against a sample of all.
    if (i + 1 < xs.size()) pair(x, xs[i + 1]);
    if (i % 16 == 0)
      for (float s : sp) pair(x, s), pair(s, x);
  }
  CHECK(first_mismatch == "");
  CHECK(checked > 1000000);
  CHECK(nan_results > 1000);  // the NaN rules were exercised,
  CHECK(signalling > 100);    // signalling NaNs among them
  // The signed zeros: maxss semantics, the second operand.
  CHECK(std::signbit(fmax_f(-0.0f, 0.0f)) == std::signbit(libm_fmax(-0.0f, 0.0f)));
  CHECK(std::signbit(fmax_f(0.0f, -0.0f)) == std::signbit(libm_fmax(0.0f, -0.0f)));
  CHECK(next_up(-0x1p-149f) == 0.0f);
  CHECK(next_up(FLT_MAX) == INFINITY);
  CHECK(next_down(-FLT_MAX) == -INFINITY);
}
