// Solid-angle sampling of rectangular area lights (light_sampling "solid_angle",
// spherical_rect.hpp) against closed forms: the solid angle of a rectangle, the
// irradiance it gives a point below it, and the same mean as area sampling with
// far less spread near a large light.
#include <catch2/catch.hpp>
#include <cmath>

#include "runtime/shading/lights.hpp"
#include "runtime/shading/spherical_rect.hpp"

using namespace snell;
using namespace snell::rt;

namespace {

// Irradiance / radiance at a point h below the corner of a parallel X × Y rectangle
// (π times the point-to-rectangle form factor; Howell's catalogue, C-11).
double corner_irradiance(double X, double Y, double h) {
  double A = X / h, B = Y / h;
  return 0.5 * (A / std::sqrt(1 + A * A) * std::atan(B / std::sqrt(1 + A * A)) +
                B / std::sqrt(1 + B * B) * std::atan(A / std::sqrt(1 + B * B)));
}

// A one-sided a × b light facing down at height h, centred over the origin, with
// the given sampling.
AreaLightF light(double a, double b, double h, bool solid_angle) {
  AreaLightF l;
  l.corner = {float(-a / 2), float(h), float(-b / 2)};
  l.e1 = {0, 0, float(b)};  // cross(e1, e2) points down: the light faces the floor
  l.e2 = {float(a), 0, 0};
  l.n = {0, -1, 0};
  l.area = float(a * b);
  l.radiance = Color(1);
  l.solid_angle = solid_angle;
  l.corner_d = ir::Vec3(-a / 2, h, -b / 2);
  l.ux = ir::Vec3(0, 0, 1);
  l.uy = ir::Vec3(1, 0, 0);
  l.lx = b;
  l.ly = a;
  return l;
}

struct Moments {
  double mean = 0, stddev = 0;
};

// g over an n × n grid of jitters (cell midpoints), at point p with normal up.
Moments moments(const AreaLightF& l, Vec3f p, int n) {
  double sum = 0, sum2 = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      LightSample s;
      float u = (i + 0.5f) / n, v = (j + 0.5f) / n;
      double g = l.sample_li(p, p, {0, 1, 0}, 0, 0, 0, u, v, 1e-4f, s) ? s.g : 0.0;
      sum += g;
      sum2 += g * g;
    }
  double m = sum / (n * n);
  return {m, std::sqrt(std::fmax(0.0, sum2 / (n * n) - m * m))};
}

}  // namespace

TEST_CASE("a spherical rectangle's solid angle is the closed form's", "[lights]") {
  // On the axis of an a × b rectangle at distance d: 4 asin(ab / sqrt((a²+4d²)(b²+4d²))).
  for (double d : {0.01, 0.3, 1.0, 10.0, 1000.0}) {
    double a = 2, b = 0.5;
    SphericalRect sr;
    REQUIRE(sr.init(ir::Vec3(-a / 2, -b / 2, d), ir::Vec3(1, 0, 0), a, ir::Vec3(0, 1, 0), b,
                    ir::Vec3(0, 0, 0)));
    double want = 4 * std::asin(a * b / std::sqrt((a * a + 4 * d * d) * (b * b + 4 * d * d)));
    INFO("d = " << d);
    CHECK(sr.solid_angle == Approx(want).epsilon(1e-9));
  }
  SphericalRect in_plane;
  CHECK_FALSE(in_plane.init(ir::Vec3(-1, 0, 0), ir::Vec3(1, 0, 0), 2, ir::Vec3(0, 1, 0), 2,
                            ir::Vec3(5, 5, 0)));
}

TEST_CASE("solid-angle samples lie on the rectangle, uniform in solid angle", "[lights]") {
  SphericalRect sr;
  REQUIRE(sr.init(ir::Vec3(0.3, -0.2, 0.5), ir::Vec3(1, 0, 0), 1.5, ir::Vec3(0, 1, 0), 0.7,
                  ir::Vec3(0, 0, 0)));
  // Each of 4 × 4 equal (u, v) cells maps to a piece of the rectangle subtending
  // S / 16: the solid angle of the piece, by the closed form of its corners'
  // spherical rectangle.
  int n = 4;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      ir::Vec3 q = sr.sample((i + 0.5) / n, (j + 0.5) / n);
      CHECK(q.z == Approx(0.5).margin(1e-12));
      CHECK(q.x >= 0.3 - 1e-12);
      CHECK(q.x <= 1.8 + 1e-12);
      CHECK(q.y >= -0.2 - 1e-12);
      CHECK(q.y <= 0.5 + 1e-12);
    }
  // Columns: u in [0, 1/n) covers x in [x0, x(u = 1/n)], a rectangle whose solid
  // angle is S / n.
  for (int i = 1; i < n; ++i) {
    double xu = sr.sample(double(i) / n, 0.5).x;
    SphericalRect part;
    REQUIRE(part.init(ir::Vec3(0.3, -0.2, 0.5), ir::Vec3(1, 0, 0), xu - 0.3, ir::Vec3(0, 1, 0), 0.7,
                      ir::Vec3(0, 0, 0)));
    CHECK(part.solid_angle == Approx(sr.solid_angle * i / n).epsilon(1e-9));
  }
}

TEST_CASE("both light samplings give a point the closed-form irradiance", "[lights]") {
  // A 2 × 1 light at heights from far (area sampling is near-perfect) to very
  // near (area sampling's 1/d² spreads widely). The point sits under the centre,
  // so the closed form is 4 corner pieces of 1 × 0.5.
  for (double h : {5.0, 1.0, 0.2, 0.05}) {
    double want = 4 * corner_irradiance(1.0, 0.5, h);
    Moments area = moments(light(2, 1, h, false), {0, 0, 0}, 256);
    Moments solid = moments(light(2, 1, h, true), {0, 0, 0}, 256);
    INFO("h = " << h << ": area " << area.mean << " ± " << area.stddev << ", solid angle "
                << solid.mean << " ± " << solid.stddev << ", want " << want);
    // Midpoint quadrature over 256² jitters of smooth integrands: within 0.5 %.
    CHECK(area.mean == Approx(want).epsilon(5e-3));
    CHECK(solid.mean == Approx(want).epsilon(5e-3));
    // Per-sample spread: solid angle sampling leaves only cosθ_surface to vary.
    CHECK(solid.stddev <= area.stddev * 1.0001);
    if (h <= 0.2) CHECK(solid.stddev < 0.5 * area.stddev);
  }
}

TEST_CASE("a one-sided light gives nothing behind it under solid-angle sampling", "[lights]") {
  AreaLightF l = light(2, 1, 1, true);
  LightSample s;
  // Above the light (it faces down): behind it.
  CHECK_FALSE(l.sample_li({0, 2, 0}, {0, 2, 0}, {0, -1, 0}, 0, 0, 0, 0.5f, 0.5f, 1e-4f, s));
  l.two_sided = true;
  CHECK(l.sample_li({0, 2, 0}, {0, 2, 0}, {0, -1, 0}, 0, 0, 0, 0.5f, 0.5f, 1e-4f, s));
  CHECK(s.g > 0);
}

TEST_CASE("light_sampling solid_angle applies to rectangles only", "[lights]") {
  ir::Scene scene;
  ir::AreaLight rect;
  rect.corner = ir::Vec3(-1, 3, -1);
  rect.edge1 = ir::Vec3(2, 0, 0);
  rect.edge2 = ir::Vec3(0, 0, 2);
  ir::AreaLight skewed = rect;
  skewed.edge2 = ir::Vec3(0.5, 0, 2);
  scene.area_lights = {rect, skewed};
  Lights area(scene, ir::Vec3(0, 0, 0));
  CHECK_FALSE(area.areas[0].solid_angle);
  scene.settings.light_sampling = ir::LightSampling::SolidAngle;
  Lights solid(scene, ir::Vec3(0, 1, 0));
  CHECK(solid.areas[0].solid_angle);
  CHECK_FALSE(solid.areas[1].solid_angle);
  // The double-precision corner is camera-relative, like the float one.
  CHECK(solid.areas[0].corner_d.y == 2.0);
}

// light_sampling "adaptive": solid angle for a cell the point is near (within
// kNearCell cell diagonals of its centre), area for one far away; both unbiased.
TEST_CASE("adaptive light sampling takes solid angle near the light, area far", "[lights]") {
  ir::Scene scene;
  ir::AreaLight rect;
  rect.corner = ir::Vec3(-1, 1, -0.5);
  rect.edge1 = ir::Vec3(2, 0, 0);  // cross(edge1, edge2) = -y: faces down
  rect.edge2 = ir::Vec3(0, 0, 1);
  rect.radiance = ir::Vec3(1, 1, 1);
  scene.area_lights = {rect};
  scene.settings.light_sampling = ir::LightSampling::Adaptive;
  for (double h : {20.0, 0.2}) {
    scene.area_lights[0].corner.y = h;
    AreaLightF adaptive = Lights(scene, ir::Vec3(0, 0, 0)).areas[0];
    REQUIRE(adaptive.solid_angle);
    // The 2 × 1 cell's diagonal is √5: near below 4√5 = 8.9.
    CHECK(adaptive.near_cell2 == Approx(16 * 5.0f));
    CHECK(adaptive.near({0, 0, 0}, 0, 0) == (h < 8));
    Moments m = moments(adaptive, {0, 0, 0}, 256);
    AreaLightF as_area = adaptive, as_solid = adaptive;
    as_area.solid_angle = false;
    as_solid.near_cell2 = 0;  // solid angle everywhere
    Moments area = moments(as_area, {0, 0, 0}, 256), solid = moments(as_solid, {0, 0, 0}, 256);
    INFO("h = " << h);
    CHECK(m.mean == Approx(4 * corner_irradiance(1.0, 0.5, h)).epsilon(5e-3));
    // The very samples of the mode it picks.
    const Moments& same = h < 8 ? solid : area;
    CHECK(m.mean == same.mean);
    CHECK(m.stddev == same.stddev);
    if (h < 8) CHECK(m.stddev < 0.5 * area.stddev);
  }
}
