// Fresnel, Schlick, refraction and Beer: exact values from robustness.md §3.1–3.4.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "runtime/shading/fresnel.hpp"

using namespace snell::rt;
using snell::ir::FresnelMode;

namespace {
double deg(double d) {
  return d * 3.14159265358979323846 / 180.0;
}
double cosd(int th) {
  return th == 90 ? 0.0 : std::cos(deg(th));
}
struct Row {
  int th;
  double out, in;
};
}  // namespace

TEST_CASE("exact Fresnel matches the reference table, eta 1.5, both directions", "[fresnel]") {
  // robustness.md §3.1: R_out = fr(cos, 1.5), R_in = fr(cos, 1/1.5).
  const Row rows[] = {
      {0, 0.04000000, 0.04000000},  {10, 0.04001549, 0.04008296}, {20, 0.04026623, 0.04172852},
      {30, 0.04152263, 0.05519017}, {40, 0.04573364, 0.24529120}, {45, 0.05023991, 1.00000000},
      {50, 0.05766294, 1.00000000}, {60, 0.08918671, 1.00000000}, {70, 0.17104254, 1.00000000},
      {75, 0.25306056, 1.00000000}, {80, 0.38770435, 1.00000000}, {85, 0.61279965, 1.00000000},
      {89, 0.90418495, 1.00000000}, {90, 1.00000000, 1.00000000},
  };
  for (const Row& r : rows) {
    INFO("theta " << r.th);
    CHECK(fresnel_dielectric(cosd(r.th), 1.5, FresnelMode::Exact) == Approx(r.out).margin(1e-6));
    CHECK(fresnel_dielectric(-cosd(r.th), 1.5, FresnelMode::Exact) == Approx(r.in).margin(1e-6));
    CHECK(fresnel_exact(make_interface(cosd(r.th), 1 / 1.5)) == Approx(r.in).margin(1e-6));
  }
}

TEST_CASE("exact Fresnel matches the reference table, eta 1.33", "[fresnel]") {
  const Row rows[] = {
      {0, 0.02005931, 0.02005931},  {20, 0.02023971, 0.02072333}, {30, 0.02111246, 0.02508987},
      {45, 0.02752138, 0.13418672}, {60, 0.05912560, 1.0},        {75, 0.21142660, 1.0},
      {85, 0.58272824, 1.0},        {89, 0.89604651, 1.0},
  };
  for (const Row& r : rows) {
    INFO("theta " << r.th);
    CHECK(fresnel_dielectric(cosd(r.th), 1.33, FresnelMode::Exact) == Approx(r.out).margin(1e-6));
    CHECK(fresnel_dielectric(-cosd(r.th), 1.33, FresnelMode::Exact) == Approx(r.in).margin(1e-6));
  }
}

TEST_CASE("Brewster angle: p-polarised reflectance vanishes", "[fresnel]") {
  CHECK(fresnel_exact(make_interface(std::cos(std::atan(1.5)), 1.5)) ==
        Approx(0.073964497).margin(1e-8));
  CHECK(fresnel_exact(make_interface(std::cos(std::atan(1.33)), 1.33)) ==
        Approx(0.038556285).margin(1e-8));
}

TEST_CASE("Schlick maximum error against exact, both sides", "[fresnel]") {
  // §3.2: 0.035693 (eta 1.5) and 0.059924 (1.33) on both sides when the cosine on
  // the less dense side is used; TIR gives exactly 1.
  for (auto [eta, expected] : {std::pair{1.5, 0.035693}, std::pair{1.33, 0.059924}}) {
    double worst_out = 0, worst_in = 0;
    for (int i = 0; i <= 100000; ++i) {
      double c = std::cos(deg(90.0 * i / 100000));
      for (int side = 0; side < 2; ++side) {
        double e = side ? 1 / eta : eta;
        Interface f = make_interface(c, e);
        double err = std::fabs(fresnel_schlick(f) - fresnel_exact(f));
        (side ? worst_in : worst_out) = std::fmax(side ? worst_in : worst_out, err);
        if (f.tir) REQUIRE(fresnel_schlick(f) == 1.0);
      }
    }
    CHECK(worst_out == Approx(expected).margin(2e-6));
    CHECK(worst_in == Approx(expected).margin(2e-6));
  }
}

TEST_CASE("ior 1 reflects nothing and refracts straight", "[fresnel]") {
  for (double c : {1.0, 0.7, 0.1, 1e-4}) {
    Interface f = make_interface(c, 1.0);
    CHECK_FALSE(f.tir);
    CHECK(fresnel_exact(f) == 0.0);
    CHECK(fresnel_schlick(f) == 0.0);
    double s = std::sqrt(1 - c * c);
    Vec3d d{s, -c, 0};
    Vec3d t = refract(d, {0, 1, 0}, f);
    CHECK(t.x == d.x);
    CHECK(t.y == d.y);
  }
}

TEST_CASE("refraction and Fresnel agree on TIR and Snell's law holds", "[fresnel][property]") {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  int tir_count = 0;
  for (int i = 0; i < 200000; ++i) {
    double eta = std::exp(std::log(1e-3) + u(rng) * (std::log(1e3) - std::log(1e-3)));
    double c = u(rng);
    Interface f = make_interface(c, eta);
    double R = fresnel_exact(f), Rs = fresnel_schlick(f);
    REQUIRE(R >= 0);
    REQUIRE(R <= 1);
    REQUIRE(Rs >= 0);
    REQUIRE(Rs <= 1);
    bool geometric_tir = (1 - c * c) / (eta * eta) >= 1;
    REQUIRE(f.tir == geometric_tir);
    REQUIRE((R == 1) >= f.tir);
    if (f.tir) {
      ++tir_count;
      continue;
    }
    double s = std::sqrt(1 - c * c);
    Vec3d t = refract({s, -c, 0}, {0, 1, 0}, f);
    double len = std::sqrt(t.x * t.x + t.y * t.y + t.z * t.z);
    REQUIRE(len == Approx(1).margin(1e-9));
    REQUIRE(t.y <= 0);                                         // goes through
    REQUIRE(eta * t.x == Approx(s).margin(1e-9 * (1 + eta)));  // n_t sinθt = n_i sinθi
  }
  CHECK(tir_count > 0);
}

TEST_CASE("Beer transmittance table and special values", "[beer]") {
  // §3.4: sigma = (0.5, 1, 2).
  const double sig[3] = {0.5, 1, 2};
  const double table[][4] = {
      {0, 1, 1, 1},
      {0.1, 0.951229425, 0.904837418, 0.818730753},
      {0.5, 0.778800783, 0.60653066, 0.367879441},
      {1, 0.60653066, 0.367879441, 0.135335283},
      {2, 0.367879441, 0.135335283, 0.0183156389},
      {5, 0.0820849986, 0.006737947, 4.53999298e-05},
      {10, 0.006737947, 4.53999298e-05, 2.06115362e-09},
  };
  for (const auto& row : table)
    for (int k = 0; k < 3; ++k) CHECK(beer(sig[k], row[0]) == Approx(row[k + 1]).epsilon(1e-8));
  CHECK(beer(0.5, 100) == Approx(1.92874985e-22).epsilon(1e-8));
  CHECK(beer(0, INFINITY) == 1.0);
  CHECK(beer(INFINITY, 0) == 1.0);
  CHECK(beer(1, INFINITY) == 0.0);
  CHECK(beer(1e30, 1e10) == 0.0);
}
