// Solids' ray intervals (runtime/geometry/intervals.hpp), the seam CSG composes:
// along random rays, a point is inside the solid exactly when its t lies in one of
// the spans, away from the boundary (within 1e-9 of the scene's size a point's
// side is a matter of rounding).
#include <catch2/catch.hpp>
#include <cmath>
#include <functional>
#include <iostream>
#include <random>

#include "runtime/geometry/intervals.hpp"

using namespace snell;
using ir::Vec3;
using rt::geom::Spans;

namespace {

bool in_spans(const Spans& s, double t, double eps, bool& near_edge) {
  near_edge = false;
  bool in = false;
  for (int i = 0; i < s.count; ++i) {
    if (std::fabs(t - s.span[i].t_in) < eps || std::fabs(t - s.span[i].t_out) < eps)
      near_edge = true;
    if (t > s.span[i].t_in && t < s.span[i].t_out) in = true;
  }
  return in;
}

// `inside(p)` against the spans along 2000 rays through the solid's box [-3, 3]³;
// `margin(p)`: the distance to the boundary below which a sample is not judged.
template <class K>
void check_solid(const K& kind, std::function<bool(Vec3)> inside,
                 std::function<double(Vec3)> margin) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  long judged = 0, wrong = 0, spans_seen = 0;
  for (int r = 0; r < 2000; ++r) {
    Vec3 o(3 * u(rng), 3 * u(rng), 3 * u(rng));
    Vec3 d(u(rng), u(rng), u(rng));
    if (r % 10 == 0) d = Vec3(0, 0, 1);  // axis-aligned rays too
    Spans s = rt::geom::solid_intervals(kind, o, d, -10.0, 10.0);
    spans_seen += s.count;
    for (int i = 0; i + 1 < s.count; ++i) REQUIRE(s.span[i].t_out <= s.span[i + 1].t_in);
    for (int k = 0; k <= 400; ++k) {
      double t = -10 + 20.0 * k / 400;
      Vec3 p = o + d * t;
      if (margin(p) < 1e-6) continue;
      bool edge;
      bool in = in_spans(s, t, 1e-9, edge);
      if (edge) continue;
      ++judged;
      if (in != inside(p)) {
        ++wrong;
        if (wrong < 3) {
          std::string sp;
          for (int q = 0; q < s.count; ++q)
            sp += " [" + std::to_string(s.span[q].t_in) + ", " + std::to_string(s.span[q].t_out) +
                  "]";
          std::cerr << ("ray " + std::to_string(r) + " o " + ir::to_string(o) + " d " +
                        ir::to_string(d))
                    << " t " << t << " in " << in << " spans" << sp << "\n";
        }
      }
    }
  }
  INFO("judged " << judged << " spans " << spans_seen);
  CHECK(judged > 100000);
  CHECK(spans_seen > 200);
  CHECK(wrong == 0);
}

double torus_sdf(Vec3 p, double R, double r) {
  return std::hypot(std::hypot(p.x, p.z) - R, p.y) - r;
}

}  // namespace

TEST_CASE("solid intervals: sphere, box, plane half-space", "[intervals]") {
  ir::Sphere s{{0.3, -0.2, 0.1}, 1.4};
  check_solid(
      s, [&](Vec3 p) { return ir::length(p - s.center) < s.radius; },
      [&](Vec3 p) { return std::fabs(ir::length(p - s.center) - s.radius); });
  ir::Box b{{-1, -0.5, -2}, {1.5, 0.7, 0.4}};
  auto box_margin = [&](Vec3 p) {
    double m = INFINITY;
    for (int k = 0; k < 3; ++k)
      m = std::fmin(m, std::fmin(std::fabs(p[k] - b.min[k]), std::fabs(p[k] - b.max[k])));
    return m;
  };
  check_solid(
      b,
      [&](Vec3 p) {
        return p.x > b.min.x && p.x < b.max.x && p.y > b.min.y && p.y < b.max.y && p.z > b.min.z &&
               p.z < b.max.z;
      },
      box_margin);
  ir::Plane pl{ir::normalize(Vec3(1, 2, -0.5)), 0.3};
  check_solid(
      pl, [&](Vec3 p) { return ir::dot(pl.normal, p) < pl.distance; },
      [&](Vec3 p) { return std::fabs(ir::dot(pl.normal, p) - pl.distance); });
}

TEST_CASE("solid intervals: closed cylinder and cone, torus, open shapes have none",
          "[intervals]") {
  auto axial = [](Vec3 base, Vec3 cap, double r0, double r1) {
    Vec3 a = cap - base;
    double h = ir::length(a);
    Vec3 ax = a / h;
    auto rho_z = [=](Vec3 p, double& rho, double& z) {
      z = ir::dot(p - base, ax);
      rho = ir::length((p - base) - ax * z);
    };
    auto inside = [=](Vec3 p) {
      double rho, z;
      rho_z(p, rho, z);
      return z > 0 && z < h && rho < r0 + (r1 - r0) * z / h;
    };
    auto margin = [=](Vec3 p) {
      double rho, z;
      rho_z(p, rho, z);
      double slope = (r1 - r0) / h;
      double side = std::fabs(rho - (r0 + slope * z)) / std::sqrt(1 + slope * slope);
      return std::fmin(side, std::fmin(std::fabs(z), std::fabs(z - h)));
    };
    return std::pair{std::function<bool(Vec3)>(inside), std::function<double(Vec3)>(margin)};
  };
  ir::Cylinder c{{0.2, -1, 0.3}, {-0.4, 1.5, 0.1}, 0.8, false};
  auto [ci, cm] = axial(c.base, c.cap, c.radius, c.radius);
  check_solid(c, ci, cm);
  ir::Cone k{{0, -1.2, 0}, 1.3, {0.3, 1.4, -0.2}, 0.2, false};
  auto [ki, km] = axial(k.base, k.cap, k.base_radius, k.cap_radius);
  check_solid(k, ki, km);
  ir::Torus t{1.6, 0.5};
  check_solid(
      t, [&](Vec3 p) { return torus_sdf(p, t.major, t.minor) < 0; },
      [&](Vec3 p) { return std::fabs(torus_sdf(p, t.major, t.minor)); });

  ir::Cylinder open = c;
  open.open = true;
  CHECK(rt::geom::solid_intervals(open, {0, -5, 0}, {0, 1, 0}, -10, 10).count == 0);
  ir::Shape s;
  s.geom = open;
  CHECK_FALSE(rt::geom::has_inside(s));
  s.geom = ir::Triangle{};
  CHECK_FALSE(rt::geom::has_inside(s));
  s.geom = t;
  CHECK(rt::geom::has_inside(s));
}

TEST_CASE("a closed cone's spans from one solve are what walking its surface finds",
          "[intervals][cone]") {
  // cone_spans solves the quadric once; walk_surface, kept for the torus, finds
  // each crossing with a solve of its own from just past the last. Same spans to
  // rounding, the same outward normals at their ends (the cap's at a pointed
  // cone's tip, where the side's vanishes), over frusta, cylinders and pointed
  // cones in any frame, from rays outside and inside, along the axis and across.
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  long spans = 0, clipped_in = 0;
  for (int shape = 0; shape < 60; ++shape) {
    ir::Cone c;
    c.base = Vec3(u(rng), u(rng), u(rng));
    c.cap = c.base + Vec3(u(rng), 2 + u(rng), u(rng));
    c.base_radius = shape % 3 == 0 ? 0.0 : 0.2 + 0.8 * std::fabs(u(rng));
    c.cap_radius = shape % 3 == 1 ? c.base_radius : std::fabs(u(rng));
    const rt::geom::TruncatedCone l(c);
    for (int r = 0; r < 400; ++r) {
      Vec3 o(3 * u(rng), 3 * u(rng), 3 * u(rng));
      Vec3 d(u(rng), u(rng), u(rng));
      if (r % 10 == 0) d = c.cap - c.base;         // along the axis
      if (r % 7 == 0) o = (c.base + c.cap) * 0.5;  // from inside
      const Spans one = rt::geom::cone_spans(l, o, d, -10.0, 10.0);
      const Spans walked = rt::geom::walk_surface(l, o, d, -10.0, 10.0);
      REQUIRE(one.count == walked.count);
      for (int i = 0; i < one.count; ++i) {
        const rt::geom::Span &a = one.span[i], &b = walked.span[i];
        const double tol = 1e-12 * (1 + std::fabs(b.t_in) + std::fabs(b.t_out));
        CHECK(std::fabs(a.t_in - b.t_in) <= tol);
        CHECK(std::fabs(a.t_out - b.t_out) <= tol);
        // A clipped end has no surface (and walk_surface no normal) there.
        if (b.t_in > -10) {
          INFO("shape " << shape << " ray " << r);
          CHECK(ir::dot(ir::normalize(a.n_in), ir::normalize(b.n_in)) > 1 - 1e-9);
          CHECK(ir::dot(a.n_in, d) < 0);
        } else {
          ++clipped_in;
        }
        if (b.t_out < 10) {
          CHECK(ir::dot(ir::normalize(a.n_out), ir::normalize(b.n_out)) > 1 - 1e-9);
          CHECK(ir::dot(a.n_out, d) > 0);
        }
        ++spans;
      }
    }
  }
  INFO(spans << " spans, " << clipped_in << " starting inside");
  CHECK(spans > 4000);
}
