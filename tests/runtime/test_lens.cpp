// Depth of field (§6): the thin lens. Aperture 0 is the pinhole bit for bit; every
// lens ray meets the pinhole ray on the focal plane; an edge at depth z blurs over a
// disk of diameter aperture·|z − zf|/z on the focal plane (robustness.md §3.8 #10).
#include <catch2/catch.hpp>
#include <random>

#include "runtime/camera.hpp"
#include "tests/runtime/effects_util.hpp"

using namespace snell;
using namespace snell::test;

TEST_CASE("aperture 0 gives the pinhole ray bit for bit", "[lens]") {
  ir::Camera c;
  c.look_at = {0.3, -0.2, 1};
  c.fov = 50;
  rt::Camera cam(c, 64, 48);
  CHECK_FALSE(cam.has_lens());
  for (double fx : {0.0, 13.25, 63.9})
    for (float lu : {0.0f, 0.3f, 0.99f}) {
      rt::Ray a = cam.generate(fx, 20.5), b = cam.generate(fx, 20.5, lu, 1 - lu);
      CHECK((a.dir.x == b.dir.x && a.dir.y == b.dir.y && a.dir.z == b.dir.z));
      CHECK((b.org.x == 0 && b.org.y == 0 && b.org.z == 0));
    }
}

TEST_CASE("every lens ray reaches the pinhole ray's point on the focal plane", "[lens][property]") {
  ir::Camera c;
  c.look_at = {0.2, 0.1, 1};
  c.fov = 60;
  c.aperture = 0.4;
  c.focal_distance = 7;
  rt::Camera lens(c, 100, 80), pin(
                                   [&] {
                                     ir::Camera p = c;
                                     p.aperture = 0;
                                     return p;
                                   }(),
                                   100, 80);
  rt::Vec3f fwd = rt::normalize(rt::to_float(0.2, 0.1, 1));
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u01(0, 0.99999994f);
  double worst = 0;
  for (int i = 0; i < 20000; ++i) {
    double fx = 100 * double(u01(rng)), fy = 80 * double(u01(rng));
    rt::Ray p = pin.generate(fx, fy), l = lens.generate(fx, fy, u01(rng), u01(rng));
    // Intersect both with the plane dot(x, fwd) = 7.
    rt::Vec3f a = p.org + p.dir * ((7 - rt::dot(p.org, fwd)) / rt::dot(p.dir, fwd));
    rt::Vec3f b = l.org + l.dir * ((7 - rt::dot(l.org, fwd)) / rt::dot(l.dir, fwd));
    worst = std::fmax(worst, rt::length(a - b) / rt::length(a));
    REQUIRE(rt::length(l.org) <= 0.2f * 1.000001f);
  }
  CHECK(worst < 1e-5);
}

TEST_CASE("lens rays stay finite and unit at the extremes of fov and focal distance",
          "[lens][robust]") {
  // |focus|² overflows float when a wide fov meets a far focal plane (fov 179.99999°:
  // film corners 1.1e7 wide per unit; focal distance 1e14), and org / focal when the
  // lens is far larger than the focal distance (below): the direction is scaled
  // before it is normalised. Embree asserts on a non-finite ray; Snell never makes one.
  ir::Camera c;
  c.fov = 179.99999;
  c.aperture = 1e10;
  c.focal_distance = 1e14;
  rt::Camera cam(c, 16, 16);
  for (double fx : {0.0, 8.0, 15.999})
    for (double fy : {0.0, 15.999})
      for (float lu : {0.0f, 0.5f, 0.99999994f}) {
        rt::Ray r = cam.generate(fx, fy, lu, 1 - lu);
        INFO(rt::to_string(r));
        REQUIRE(rt::is_finite(r.dir));
        CHECK(rt::length(r.dir) == Approx(1).margin(1e-6));
      }
}

TEST_CASE("lens rays stay finite and unit when the lens dwarfs the focal distance",
          "[lens][robust]") {
  // Valid input: any aperture up to the scene's range, any focal distance > 0.
  for (double aperture : {1.0, 2e12})
    for (double focal : {1e-3, 1e-20, 1e-300}) {
      ir::Camera c;
      c.fov = 90;
      c.aperture = aperture;
      c.focal_distance = focal;
      rt::Camera cam(c, 16, 16);
      for (double fx : {0.0, 8.0, 15.999})
        for (float lu : {0.0f, 0.25f, 0.5f, 0.99999994f}) {
          rt::Ray r = cam.generate(fx, 7.5, lu, lu == 0.25f ? 0.5f : 1 - lu);
          INFO(aperture << " " << focal << " " << rt::to_string(r));
          REQUIRE(rt::is_finite(r.dir));
          REQUIRE(rt::is_finite(r.org));
          CHECK(rt::length(r.dir) == Approx(1).margin(1e-6));
        }
    }
}

namespace {
// A black half-plane (image left) at depth z before a white background, seen by a lens of
// diameter 0.1 focused at 5, on one row of 201 pixels spanning x in [-0.1, 0.1] on
// the focal plane.
ir::Scene edge_scene(double z, std::uint32_t spp) {
  ir::Scene s = base_scene(201, 1, spp);
  s.settings.sampler = ir::SamplerKind::Sobol;
  s.background = ir::Vec3{1, 1, 1};
  // The image right is cross(forward, up) = -x: world x > 0 is the image left.
  s.shapes.push_back(box({0, -10, z}, {10, 10, z + 0.001}, add_material(s, diffuse({0, 0, 0}))));
  look(s, {0, 0, 0}, {0, 0, 5}, 2 * std::atan(0.1 / 5) * 180 / 3.14159265358979323846);
  s.camera.aperture = 0.1;
  s.camera.focal_distance = 5;
  return s;
}
// Expected pixel: the disk-coverage profile averaged over the pixel's footprint.
double expected_edge(std::uint32_t x, double coc_diameter) {
  double sum = 0;
  const int n = 64;
  for (int k = 0; k < n; ++k) {
    double xf = ((x + (k + 0.5) / n) / 201.0 * 2 - 1) * 0.1;
    double rho = coc_diameter / 2;
    sum += rho > 0 ? disk_fraction_right_of(xf / rho) : (xf > 0 ? 1 : 0);
  }
  return sum / n;
}
}  // namespace

TEST_CASE("thin-lens circle of confusion is A |z - zf| / z", "[lens][scene]") {
  for (double z : {10.0, 2.5}) {
    double coc = 0.1 * std::fabs(z - 5) / z;  // 0.05 at z = 10, 0.1 at z = 2.5
    rt::RenderResult r = render_with(edge_scene(z, 1024));
    CHECK(r.stats.lens_samples == 201u * 1024u);
    double worst = 0;
    for (std::uint32_t x = 0; x < 201; ++x)
      worst = std::fmax(worst, std::fabs(r.image.at(x, 0)[0] - expected_edge(x, coc)));
    INFO("z " << z << " circle of confusion " << coc << " worst pixel error " << worst);
    CHECK(worst < 0.02);
    // A circle twice or half as wide fails the same check: the test sees the size.
    double other = 0;
    for (std::uint32_t x = 0; x < 201; ++x)
      other = std::fmax(other, std::fabs(r.image.at(x, 0)[0] - expected_edge(x, coc * 1.5)));
    CHECK(other > 0.05);
  }
}

TEST_CASE("an edge on the focal plane stays sharp", "[lens][scene]") {
  rt::RenderResult r = render_with(edge_scene(5, 256));
  int grey = 0;
  for (std::uint32_t x = 0; x < 201; ++x) {
    float v = r.image.at(x, 0)[0];
    if (v > 0.001f && v < 0.999f) ++grey;
  }
  CHECK(grey <= 1);
  CHECK(r.image.at(100, 0)[0] == Approx(0.5).margin(0.05));
}

TEST_CASE("a block of camera rays is the rays made one by one, bit for bit", "[lens][packets]") {
  // The packet loop makes 16 rays at once (vectorised), the one-ray loop (--pixel,
  // --stats) one: the picture must not depend on which.
  for (double aperture : {0.0, 0.4}) {
    ir::Camera c;
    c.look_at = {0.3, -0.2, 1};
    c.fov = 70;
    c.aperture = aperture;
    c.focal_distance = 3.5;
    rt::Camera cam(c, 400, 300);
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u01(0, 0.99999994f);
    std::uint64_t differ = 0;
    for (int round = 0; round < 500; ++round) {
      constexpr std::uint32_t n = rt::Camera::kMaxBlock;
      double fx[n], fy[n];
      float lu[n], lv[n];
      for (std::uint32_t i = 0; i < n; ++i) {
        fx[i] = 400 * double(u01(rng)), fy[i] = 300 * double(u01(rng));
        lu[i] = u01(rng), lv[i] = u01(rng);
      }
      lu[0] = lv[0] = 0.5f;  // the lens centre (the 0/0 of the concentric map)
      std::uint32_t count = 1 + std::uint32_t(round) % n;
      rt::Ray block[n];
      cam.generate_block(count, fx, fy, lu, lv, block);
      for (std::uint32_t i = 0; i < count; ++i) {
        rt::Ray one = cam.generate(fx[i], fy[i], lu[i], lv[i]);
        differ += one.dir.x != block[i].dir.x || one.dir.y != block[i].dir.y ||
                  one.dir.z != block[i].dir.z || one.org.x != block[i].org.x ||
                  one.org.y != block[i].org.y || one.org.z != block[i].org.z;
        REQUIRE(rt::is_finite(block[i].dir));
      }
    }
    CHECK(differ == 0);
  }
}

TEST_CASE("the concentric map's polynomial sine and cosine are float-accurate", "[lens]") {
  // cos_quarter / sin_quarter replace libm on |t| <= π/4; against double libm they
  // must be within 2 float ulps of 1 (the map's error is then far below any
  // visible blur), and the map must stay inside the unit disk.
  double worst = 0;
  for (int i = 0; i <= 20000; ++i) {
    float t = float(-0.785398163397448 + 1.570796326794896 * i / 20000.0);
    worst = std::fmax(worst, std::fabs(rt::cos_quarter(t) - std::cos(double(t))));
    worst = std::fmax(worst, std::fabs(rt::sin_quarter(t) - std::sin(double(t))));
  }
  CHECK(worst < 2.4e-7);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u01(0, 0.99999994f);
  for (int i = 0; i < 100000; ++i) {
    float x, y;
    rt::concentric_disk(u01(rng), u01(rng), x, y);
    REQUIRE(x * x + y * y <= 1.000001f);
  }
  float x = 1, y = 1;
  rt::concentric_disk(0.5f, 0.5f, x, y);
  CHECK((x == 0 && y == 0));
}
