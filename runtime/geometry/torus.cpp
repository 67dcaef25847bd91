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

// The root of g in [a, b], where g changes sign (g(a) = ga, g(b) of the other
// sign); g(x, slope) returns the value and sets the derivative: Newton's method,
// falling back to bisection whenever a step leaves the bracket or does not halve
// the error (Numerical Recipes' rtsafe).
template <class G>
double bracketed_root(G&& g, double a, double b, double ga) {
  double xl = a, xh = b;  // g(xl) < 0 < g(xh)
  if (ga > 0) std::swap(xl, xh);
  double x = 0.5 * (a + b), dx_old = std::fabs(b - a), dx = dx_old, df;
  double f = g(x, df);
  for (int it = 0; it < 200; ++it) {
    if (f == 0) return x;
    (f < 0 ? xl : xh) = x;
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
    if (std::fabs(dx) <= 0x1p-60 * ir::max_num(1.0, std::fabs(x))) return x;
    f = g(x, df);
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
      roots[count++] = bracketed_root(
          [&](double x, double& slope) {
            slope = horner(dc, n - 1, x);
            return horner(c, n, x);
          },
          a, b, fa);
    a = b, fa = fb;
  }
  return count;
}

// f(p) = (|p|² + R² − r²)² − 4R²(x² + z²) = 0 along the ray, in four steps:
//  1. clip the ray to the bounding ball |p| <= R + r and move its origin to where
//     the clipped ray starts (its entry, or tnear from inside): far from the torus
//     the quartic's coefficients would cancel catastrophically (robustness #5);
//  2. scale by 1/R and take the direction unit, so the quartic's coefficients are
//     O(1) for any size;
//  3. split the clipped interval at the quartic's critical points (the real roots
//     of its derivative, polynomial_roots on the cubic): f is monotonic between
//     them, so each piece holds at most one root;
//  4. f = q·Q with Q = (ρ + R)² + y² − r² > 0 and q of the sign of the signed
//     distance sd = hypot(hypot(x, z) − R, y) − r, so f and sd change sign at the
//     same points, and sd is accurate to ulps of R + r where the quartic, expanded
//     in powers of s, is only accurate to ulps of its largest term (a relative
//     error of ~1e-15·(R/r)² of r on a thin torus). The pieces whose ends have sd
//     of opposite signs hold the roots; each is found by Newton's method on sd,
//     safeguarded by bisection. A ray is missed only where sd does not change sign
//     at double precision: touching it by less than ~1e-16·(R + r).
// The first root past the origin is the hit.
bool TorusSurface::intersect(Vec3 o, Vec3 d, double tnear, double tfar, double& t_out,
                             Vec3& n_out) const {
  double lo = tnear, hi = tfar;
  if (!clip_to_ball(o, d, {0, 0, 0}, (big_ + small_) * (1 + 1e-9), lo, hi)) return false;
  const double len = ir::length(d), inv_r = 1 / big_, k = small_ * inv_r;
  const Vec3 u = d / len;
  const Vec3 p0 = (o + d * lo) * inv_r;
  const double smax = (hi - lo) * len * inv_r;
  // The quartic's derivative: 4s³ + 3c3·s² + 2c2·s + c1 (monic quartic in s).
  double alpha = ir::dot(p0, u), e = ir::dot(p0, p0) + (1 - k) * (1 + k);
  double c1 = 4 * alpha * e - 8 * (p0.x * u.x + p0.z * u.z);
  double c2 = 4 * alpha * alpha + 2 * e - 4 * (u.x * u.x + u.z * u.z);
  double c3 = 4 * alpha;
  const double deriv[4] = {c1, 2 * c2, 3 * c3, 4};
  double cuts[4];
  int m = polynomial_roots(deriv, 3, 0, smax, cuts);
  cuts[m++] = smax;
  auto distance = [&](double s, double& slope) {
    Vec3 p = p0 + u * s;
    double r = ir::hypot_fast(p.x, p.z), dr = r - 1, hh = ir::hypot_fast(dr, p.y);
    slope = r > 0 && hh > 0 ? (dr * (p.x * u.x + p.z * u.z) / r + p.y * u.y) / hh : 0;
    return hh - k;
  };
  double a = 0, slope, fa = distance(0, slope);
  for (int i = 0; i < m; ++i) {
    double b = cuts[i], fb = distance(b, slope), s = -1;
    if (fb == 0)
      s = b;
    else if ((fa < 0 && fb > 0) || (fa > 0 && fb < 0))
      s = bracketed_root(distance, a, b, fa);
    a = b, fa = fb;
    if (!(s > 0)) continue;
    double t = lo + s * big_ / len;
    if (!(t > tnear && t < tfar)) continue;
    Vec3 p = p0 + u * s;
    double r = ir::hypot_fast(p.x, p.z);
    if (!(r > 0)) continue;
    n_out = p - Vec3(p.x / r, 0, p.z / r);
    t_out = t;
    return true;
  }
  return false;
}

Vec3 TorusSurface::project(Vec3 p) const {
  double r = ir::hypot_fast(p.x, p.z);
  if (!(r > 0)) return p;
  Vec3 c(p.x * big_ / r, 0, p.z * big_ / r);
  Vec3 v = p - c;
  double l = ir::length(v);
  if (!(l > 0)) return p;
  return c + v * (small_ / l);
}

}  // namespace snell::rt::geom
