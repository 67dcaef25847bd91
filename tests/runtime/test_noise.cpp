// §15's noise functions (runtime/pattern/noise.hpp): the reference values of
// Perlin's improved noise, the properties the spec asks for (range, lattice value,
// mean, continuity, determinism across threads) and inputs at the edges of double.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <thread>
#include <vector>

#include "runtime/pattern/noise.hpp"

using snell::ir::Vec3;
namespace pat = snell::pattern;
using Catch::Matchers::WithinAbs;

namespace {

// A reproducible stream of points in [-r, r]^3 (splitmix64).
struct Points {
  std::uint64_t s = 12345;
  double r;
  explicit Points(double radius) : r(radius) {}
  double next() {
    std::uint64_t z = (s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    z ^= z >> 31;
    return (double(z >> 11) * 0x1.0p-53 * 2 - 1) * r;
  }
  Vec3 point() {
    double x = next(), y = next();
    return {x, y, next()};
  }
};

}  // namespace

TEST_CASE("perlin: Perlin's reference implementation's values", "[noise]") {
  // From a line-by-line transcription of ImprovedNoise.java (2002) run in Python
  // (the first is also the value Perlin's page gives for its example).
  // The same operations in the same order: equal to a few ulps.
  CHECK_THAT(pat::perlin({3.14, 42, 7}), WithinAbs(0.13691995878400012, 1e-15));
  CHECK_THAT(pat::perlin({0.5, 0.25, 0.75}), WithinAbs(-0.40987873077392578, 1e-15));
  CHECK_THAT(pat::perlin({-1.3, 2.7, -12.45}), WithinAbs(0.61761096366423063, 1e-15));
  CHECK_THAT(pat::perlin({100.37, -200.81, 0.001}), WithinAbs(0.22751668926902321, 1e-15));
}

TEST_CASE("noise: 0.5 at every integer lattice point, at any magnitude", "[noise]") {
  for (double x : {-3.0, 0.0, 1.0, 17.0, 1e6, -1e15, 9007199254740992.0, 1e300})
    for (double y : {-2.0, 0.0, 5.0, 1e9})
      for (double z : {0.0, -7.0, 255.0, 256.0}) {
        CHECK(pat::perlin({x, y, z}) == 0);
        CHECK(pat::noise({x, y, z}) == 0.5);
      }
  CHECK(pat::fbm({0, 0, 0}, 6) == 0.5);  // every octave of the origin is a lattice point
}

TEST_CASE("noise: in range, mean 0.5 over space", "[noise]") {
  Points pts(200);
  double sum_n = 0, sum_f = 0, lo = 1, hi = 0, lo_c = 10, hi_c = 0;
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    Vec3 p = pts.point();
    double v = pat::noise(p), f = pat::fbm(p, 6), t = pat::turbulence(p, 6), c = pat::cells(p);
    REQUIRE(v >= 0);
    REQUIRE(v <= 1);
    REQUIRE(f >= 0);
    REQUIRE(f <= 1);
    REQUIRE(t >= 0);
    REQUIRE(t <= 1);
    lo = std::fmin(lo, v), hi = std::fmax(hi, v);
    lo_c = std::fmin(lo_c, c), hi_c = std::fmax(hi_c, c);
    sum_n += v, sum_f += f;
  }
  // Noise is odd about every lattice point, so its mean is exactly 0.5 over whole
  // periods; 2e5 samples of a variance < 0.05 give a standard error < 5e-4, and the
  // spec's bound 0.02 is 40 of those.
  CHECK_THAT(sum_n / n, WithinAbs(0.5, 0.02));
  CHECK_THAT(sum_f / n, WithinAbs(0.5, 0.02));
  // It uses its range: a remap that squashed it would fail here.
  CHECK(lo < 0.15);
  CHECK(hi > 0.85);
  // F1 of one feature point per unit cell: 0 near a feature point, never past √3.
  CHECK(lo_c < 0.05);
  CHECK(hi_c <= std::sqrt(3.0));
}

TEST_CASE("noise: continuous (Lipschitz) across cell boundaries", "[noise]") {
  Points pts(50);
  const double h = 1e-7;
  for (int i = 0; i < 20000; ++i) {
    Vec3 p = pts.point();
    // Put half the points right on a cell face, where a wrong fade or hash shows.
    if (i % 2) p.x = std::floor(p.x);
    for (Vec3 d : {Vec3{h, 0, 0}, Vec3{-h, 0, 0}, Vec3{0, h, 0}, Vec3{0, 0, -h}}) {
      // |∇perlin| <= 3·(15/8)·√3 < 10 (gradient lengths √2, fade slope 15/8), so a
      // step h changes it by < 10h; fbm's octaves sum to < 2·10h·lacunarity-weighted.
      CHECK(std::fabs(pat::perlin(p + d) - pat::perlin(p)) < 10 * h);
      CHECK(std::fabs(pat::fbm(p + d, 6) - pat::fbm(p, 6)) < 60 * h);
      // The distance to the nearest feature point moves by at most the step.
      CHECK(std::fabs(pat::cells(p + d) - pat::cells(p)) <= h * (1 + 1e-6));
    }
  }
}

TEST_CASE("noise: the same bits on every thread", "[noise]") {
  auto run = [](std::vector<double>& out) {
    Points pts(1000);
    for (double& v : out) {
      Vec3 p = pts.point();
      v = pat::fbm(p, 8) + pat::turbulence(p, 5) + pat::cells(p) + pat::vector_fbm(p, 4).y;
    }
  };
  std::vector<double> a(5000), b(5000), c(5000);
  run(a);
  std::thread t1([&] { run(b); }), t2([&] { run(c); });
  t1.join(), t2.join();
  CHECK(a == b);
  CHECK(a == c);
}

TEST_CASE("noise: non-finite and huge inputs give finite values", "[noise]") {
  for (double x : {double(INFINITY), -double(INFINITY), double(NAN), 1e308, -1e308, 4.5e15 + 0.5}) {
    Vec3 p{x, 0.3, 0.7};
    CHECK(std::isfinite(pat::noise(p)));
    CHECK(std::isfinite(pat::fbm(p, 32)));
    CHECK(std::isfinite(pat::cells(p)));
    CHECK(std::isfinite(pat::vector_fbm(p, 3).x));
  }
  // Octave counts are clamped, never loop for ever or index out of range.
  CHECK(std::isfinite(pat::fbm({0.3, 0.1, 0.2}, 1000000)));
  CHECK(std::isfinite(pat::fbm({0.3, 0.1, 0.2}, -5)));
}

TEST_CASE("fbm and turbulence: any gain gives a value in [0, 1]", "[noise]") {
  // The plain weighted sum, as the octave loop was before huge gains were scaled:
  // every ordinary gain must keep these bits.
  auto plain = [](Vec3 p, int octaves, double lac, double gain) {
    double sum = 0, norm = 0, amp = 1;
    for (int i = 0; i < octaves; ++i) {
      sum += amp * pat::perlin(p);
      norm += amp;
      amp *= gain;
      p = p * lac;
    }
    return std::clamp(0.5 + 0.5 * sum / norm, 0.0, 1.0);
  };
  for (int i = 0; i < 200; ++i) {
    Vec3 p{std::sin(i * 1.3) * 7, std::cos(i * 0.7) * 7, i * 0.031};
    for (double gain : {0.5, 0.9, 2.0, 1e3}) CHECK(pat::fbm(p, 8, 2, gain) == plain(p, 8, 2, gain));
    // 1e10 over 32 octaves reached 1e310: inf / inf was NaN. The sum is the last
    // octave's noise but for 1e-10 of the one before.
    const double huge = pat::fbm(p, 32, 1.01, 1e10);
    const double last = 0.5 + 0.5 * pat::perlin(p * std::pow(1.01, 31));
    CHECK_THAT(huge, WithinAbs(last, 1e-9));
    for (double gain : {1e100, 1e300, 1.7e308}) {
      const double v = pat::fbm(p, 32, 1.01, gain), t = pat::turbulence(p, 32, 1.01, gain);
      CHECK(v >= 0);
      CHECK(v <= 1);
      CHECK(t >= 0);
      CHECK(t <= 1);
    }
  }
}

TEST_CASE("perlin: period 256 across 2^31, where the lattice residue changes method", "[noise]") {
  // Below 2^31 a cell's residue mod 256 is the integer's low byte; beyond, fmod's.
  // Shifting by a multiple of 256 moves a point across without changing its cell
  // residue or its fraction (exact at these magnitudes), so the values are equal.
  Points pts(300);
  for (int i = 0; i < 2000; ++i) {
    Vec3 p = pts.point();
    p = {std::ldexp(std::round(std::ldexp(p.x, 10)), -10),
         std::ldexp(std::round(std::ldexp(p.y, 10)), -10),
         std::ldexp(std::round(std::ldexp(p.z, 10)), -10)};
    for (double shift : {0x1p32, -0x1p32, 0x1p31, -0x1p31 - 256}) {
      const Vec3 q = {p.x + shift, p.y - shift, p.z + shift};
      INFO(p.x << " " << p.y << " " << p.z << " shift " << shift);
      REQUIRE(pat::perlin(p) == pat::perlin(q));
    }
  }
}
