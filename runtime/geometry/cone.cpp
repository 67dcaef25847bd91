#include "runtime/geometry/cone.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace snell::rt::geom {

TruncatedCone::TruncatedCone(Vec3 base, double r0, Vec3 cap, double r1, bool open)
    : h_(ir::length(cap - base)), r0_(r0), r1_(r1), open_(open) {
  object_from_local = ir::axis_frame(base, (cap - base) / h_);
  k_ = (r1 - r0) / h_;
  // Once here: hypot is slow, and intersect was computing it on every call.
  ball_ = std::hypot(0.5 * h_, ir::max_num(r0_, r1_)) * (1 + 1e-9);
}

// The gradient of ρ² − r(z)²: outward, and along the axis at the apex of a cone.
Vec3 TruncatedCone::side_normal(Vec3 p) const {
  Vec3 n(p.x, p.y, -k_ * (r0_ + k_ * p.z));
  if (n.x == 0 && n.y == 0 && n.z == 0) return {0, 0, k_ > 0 ? -1.0 : 1.0};
  return n;
}

// The solid is the slab 0 <= z <= h cut by the quadric g = ρ² − r(z)² <= 0 (within
// the slab r(z) >= 0, so this is ρ <= r(z), a convex set): along the ray, g <= 0 is
// one interval or two (a ray crossing both nappes of the double cone), each cut by
// the slab's interval. The hits are the ends of those pieces, so a closed shape
// is watertight at its rims by construction: a ray never slips between the side and
// a cap. Open: the roots of g with 0 <= z <= h. The ray is first clipped to the
// shape's bounding ball and its origin moved there (clip_to_ball: conditioning).
bool TruncatedCone::along(Vec3 o, Vec3 d, double& lo, double& hi, Quadric& q) const {
  if (!clip_to_ball(o, d, {0, 0, 0.5 * h_}, ball_, lo, hi)) return false;
  q.ts = lo;
  q.os = o + d * q.ts;
  const Vec3 os = q.os;
  // g(s) = a s² + 2 b s + c along os + s·d.
  double rz = r0_ + k_ * os.z, kd = k_ * d.z;
  q.a = d.x * d.x + d.y * d.y - kd * kd;
  q.b = os.x * d.x + os.y * d.y - rz * kd;
  double ro = ir::hypot_fast(os.x, os.y);
  q.c = (ro - rz) * (ro + rz);
  double disc = q.b * q.b - q.a * q.c;
  q.s0 = 0, q.s1 = 0;
  q.roots = false;
  if (q.a != 0 && disc >= 0) {
    double r = -(q.b + std::copysign(std::sqrt(disc), q.b));
    if (r != 0) q.s0 = q.c / r, q.s1 = r / q.a;
    if (q.s0 > q.s1) std::swap(q.s0, q.s1);
    q.roots = true;
  }
  return true;
}

int TruncatedCone::pieces(const Quadric& q, Vec3 d, Piece* out) const {
  const Vec3 os = q.os;
  const double a = q.a, b = q.b, c = q.c, s0 = q.s0, s1 = q.s1;
  // The intervals where g <= 0, in order.
  const double inf = INFINITY;
  std::pair<double, double> in[2];
  int m = 0;
  if (a > 0) {
    if (q.roots) in[m++] = {s0, s1};
  } else if (a < 0) {
    if (!q.roots)
      in[m++] = {-inf, inf};
    else
      in[m++] = {-inf, s0}, in[m++] = {s1, inf};
  } else if (b != 0) {
    double s = -c / (2 * b);
    in[m++] = b > 0 ? std::pair{-inf, s} : std::pair{s, inf};
  } else if (c <= 0) {
    in[m++] = {-inf, inf};
  }
  // The slab's interval, and the caps it enters and leaves by.
  double z_in = -inf, z_out = inf;
  if (d.z != 0) {
    z_in = -os.z / d.z, z_out = (h_ - os.z) / d.z;
    if (z_in > z_out) std::swap(z_in, z_out);
  } else if (!(os.z >= 0 && os.z <= h_)) {
    return 0;
  }
  const Vec3 cap_in(0, 0, d.z > 0 ? -1.0 : 1.0), cap_out = -cap_in;
  int n = 0;
  for (int i = 0; i < m; ++i) {
    double e = ir::max_num(in[i].first, z_in), x = ir::min_num(in[i].second, z_out);
    if (!(e <= x)) continue;
    out[n++] = {e, x, z_in >= in[i].first ? cap_in : side_normal(os + d * e),
                z_out <= in[i].second ? cap_out : side_normal(os + d * x)};
  }
  return n;
}

bool TruncatedCone::intersect(Vec3 o, Vec3 d, double tnear, double tfar, double& t_out,
                              Vec3& n_out) const {
  double lo = tnear, hi = tfar;
  Quadric q;
  if (!along(o, d, lo, hi, q)) return false;
  const double ts = q.ts;
  auto accept = [&](double s, Vec3 n) {
    double t = ts + s;
    if (!(t > tnear && t < tfar && t <= hi)) return false;
    t_out = t, n_out = n;
    return true;
  };
  if (open_) {
    double cand[2];
    int m = 0;
    if (q.roots)
      cand[m++] = q.s0, cand[m++] = q.s1;
    else if (q.a == 0 && q.b != 0)
      cand[m++] = -q.c / (2 * q.b);
    for (int i = 0; i < m; ++i) {
      double z = q.os.z + d.z * cand[i];
      if (z >= 0 && z <= h_ && accept(cand[i], side_normal(q.os + d * cand[i]))) return true;
    }
    return false;
  }
  Piece p[2];
  const int n = pieces(q, d, p);
  for (int i = 0; i < n; ++i) {
    if (accept(p[i].e, p[i].n_e)) return true;
    if (accept(p[i].x, p[i].n_x)) return true;
  }
  return false;
}

int TruncatedCone::solid_spans(Vec3 o, Vec3 d, double lo, double hi, Piece* out) const {
  Quadric q;
  if (!along(o, d, lo, hi, q)) return 0;
  const int n = pieces(q, d, out);
  for (int i = 0; i < n; ++i) out[i].e += q.ts, out[i].x += q.ts;
  return n;
}

// The nearest point of the side (the generator segment (r0, 0)..(r1, h) in the
// half-plane of p's azimuth) or, when closed, of an end disc.
Vec3 TruncatedCone::project(Vec3 p) const {
  double rho = ir::hypot_fast(p.x, p.y);
  double er = r1_ - r0_;
  double lam = std::clamp(((rho - r0_) * er + p.z * h_) / (er * er + h_ * h_), 0.0, 1.0);
  double pr = r0_ + lam * er, pz = lam * h_;
  double best = ir::hypot_fast(rho - pr, p.z - pz);
  if (!open_) {
    double br = ir::min_num(rho, r0_), cr = ir::min_num(rho, r1_);
    if (double db = ir::hypot_fast(rho - br, p.z); db < best) best = db, pr = br, pz = 0;
    if (double dc = ir::hypot_fast(rho - cr, p.z - h_); dc < best) best = dc, pr = cr, pz = h_;
  }
  double s = rho > 0 ? pr / rho : 0;
  return {p.x * s, p.y * s, pz};
}

}  // namespace snell::rt::geom
