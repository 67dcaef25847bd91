#include "runtime/geometry/torus.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace snell::rt::geom {

namespace {

double horner(const double* c, int n, double x) {
  double v = c[n];
  for (int i = n - 1; i >= 0; --i) v = v * x + c[i];
  return v;
}

// The root of c (degree n, derivative dc) in [a, b], where it changes sign
// (fa·fb < 0): Newton's method, falling back to bisection whenever a step leaves
// the bracket or does not halve the error (Numerical Recipes' rtsafe).
double bracketed_root(const double* c, const double* dc, int n, double a, double b, double fa) {
  double xl = a, xh = b;  // c(xl) < 0 < c(xh)
  if (fa > 0) std::swap(xl, xh);
  double x = 0.5 * (a + b), dx_old = std::fabs(b - a), dx = dx_old;
  double f = horner(c, n, x), df = horner(dc, n - 1, x);
  for (int it = 0; it < 200; ++it) {
    if (((x - xh) * df - f) * ((x - xl) * df - f) > 0 ||
        std::fabs(2 * f) > std::fabs(dx_old * df)) {
      dx_old = dx;
      dx = 0.5 * (xh - xl);
      x = xl + dx;
      if (x == xl) return x;
    } else {
      dx_old = dx;
      dx = f / df;
      double before = x;
      x -= dx;
      if (x == before) return x;
    }
    if (std::fabs(dx) <= 0x1p-60 * std::fmax(1.0, std::fabs(x))) return x;
    f = horner(c, n, x), df = horner(dc, n - 1, x);
    if (f == 0) return x;
    (f < 0 ? xl : xh) = x;
  }
  return x;
}

}  // namespace

int polynomial_roots(const double* c, int n, double lo, double hi, double* roots) {
  if (n == 1) {
    double x = -c[0] / c[1];
    if (!(x > lo && x <= hi)) return 0;
    roots[0] = x;
    return 1;
  }
  if (n == 2) {  // the cancellation-free form
    double a = c[2], b = 0.5 * c[1], disc = b * b - a * c[0];
    if (disc < 0) return 0;
    double q = -(b + std::copysign(std::sqrt(disc), b));
    double r[2] = {q / a, q != 0 ? c[0] / q : 0.0};
    if (r[0] > r[1]) std::swap(r[0], r[1]);
    int m = 0;
    for (double x : r)
      if (x > lo && x <= hi) roots[m++] = x;
    return m;
  }
  double dc[4] = {};
  for (int i = 0; i < n; ++i) dc[i] = (i + 1) * c[i + 1];
  double crit[4] = {};
  int m = polynomial_roots(dc, n - 1, lo, hi, crit);
  int count = 0;
  double a = lo, fa = horner(c, n, lo);
  for (int i = 0; i <= m; ++i) {
    double b = i < m ? crit[i] : hi;
    double fb = horner(c, n, b);
    if (fb == 0)
      roots[count++] = b;
    else if ((fa < 0 && fb > 0) || (fa > 0 && fb < 0))
      roots[count++] = bracketed_root(c, dc, n, a, b, fa);
    a = b, fa = fb;
  }
  return count;
}

// f(p) = (|p|² + R² − r²)² − 4R²(x² + z²) = 0 along the ray, in four steps:
//  1. clip the ray to the bounding ball |p| <= R + r and move its origin to where
//     the clipped ray starts (its entry, or tnear from inside): far from the torus
//     the quartic's coefficients would cancel catastrophically (robustness #5);
//  2. scale by 1/R and take the direction unit, so the coefficients are O(1) for
//     any size and the constant term is computed from the factor that vanishes on
//     the surface, c0 = ((h − k)(h + k))·((ρ + 1)² + y² − k²), h = hypot(ρ − 1, y);
//  3. isolate the real roots on the clipped interval between the critical points
//     (polynomial_roots): a root is missed only where the quartic does not change
//     sign at double precision, i.e. a ray that touches the surface by less than
//     ~1e-15·R·(R/r) (in practice nothing a float ray can aim at);
//  4. polish each root by Newton's method on the signed distance
//     hypot(hypot(x, z) − R, y) − r (accurate to ulps of R + r, unlike the quartic
//     near its roots), keeping the step only if it is tiny; the first root past
//     the origin after polishing is the hit.
bool TorusSurface::intersect(Vec3 o, Vec3 d, double tnear, double tfar, double& t_out,
                             Vec3& n_out) const {
  double lo = tnear, hi = tfar;
  if (!clip_to_ball(o, d, {0, 0, 0}, (big_ + small_) * (1 + 1e-9), lo, hi)) return false;
  const double len = ir::length(d), inv_r = 1 / big_, k = small_ * inv_r;
  const Vec3 u = d / len;
  const Vec3 p0 = (o + d * lo) * inv_r;
  const double smax = (hi - lo) * len * inv_r;
  double alpha = ir::dot(p0, u), e = ir::dot(p0, p0) + (1 - k) * (1 + k);
  double rho = std::hypot(p0.x, p0.z), h = std::hypot(rho - 1, p0.y);
  double c[5];
  c[0] = ((h - k) * (h + k)) * ((rho + 1) * (rho + 1) + p0.y * p0.y - k * k);
  c[1] = 4 * alpha * e - 8 * (p0.x * u.x + p0.z * u.z);
  c[2] = 4 * alpha * alpha + 2 * e - 4 * (u.x * u.x + u.z * u.z);
  c[3] = 4 * alpha;
  c[4] = 1;
  double roots[4];
  int m = polynomial_roots(c, 4, 0, smax, roots);
  auto distance = [&](double s, double& slope) {
    Vec3 p = p0 + u * s;
    double r = std::hypot(p.x, p.z), dr = r - 1, hh = std::hypot(dr, p.y);
    slope = r > 0 && hh > 0 ? (dr * (p.x * u.x + p.z * u.z) / r + p.y * u.y) / hh : 0;
    return hh - k;
  };
  for (int i = 0; i < m; ++i) {
    double s = roots[i];
    for (int it = 0; it < 4; ++it) {
      double slope, v = distance(s, slope);
      if (v == 0 || slope == 0) break;
      double next = s - v / slope;
      if (!(std::fabs(next - s) <= 1e-9)) break;
      if (next == s) break;
      s = next;
    }
    if (!(s > 0)) continue;
    double t = lo + s * big_ / len;
    if (!(t > tnear && t < tfar)) continue;
    Vec3 p = p0 + u * s;
    double r = std::hypot(p.x, p.z);
    if (!(r > 0)) continue;
    n_out = p - Vec3(p.x / r, 0, p.z / r);
    t_out = t;
    return true;
  }
  return false;
}

Vec3 TorusSurface::project(Vec3 p) const {
  double r = std::hypot(p.x, p.z);
  if (!(r > 0)) return p;
  Vec3 c(p.x * big_ / r, 0, p.z * big_ / r);
  Vec3 v = p - c;
  double l = ir::length(v);
  if (!(l > 0)) return p;
  return c + v * (small_ / l);
}

}  // namespace snell::rt::geom
