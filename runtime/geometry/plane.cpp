#include "runtime/geometry/plane.hpp"

#include <cmath>

#include "runtime/geometry/motion.hpp"
#include "runtime/geometry/sphere.hpp"

namespace snell::rt::geom {

using ir::Vec3;

void PlaneSet::add(const ir::Shape& s, const ir::Plane& g, std::uint32_t index, Vec3 origin,
                   bool moving) {
  const ir::Transform& xf = s.world_from_object();
  Vec3 p0 = xf.point(g.normal * g.distance) - origin;
  Vec3 n = ir::normalize(xf.normal(g.normal));
  planes_.push_back({n, ir::dot(n, p0), index, moving ? &s : nullptr, moving ? &g : nullptr});
  any_moving_ = any_moving_ || moving;
  origin_ = origin;
}

// Planes in double from the float ray; the float origin was already offset by the
// caller, so the sign of (d - n·o) is reliable. A moving plane is placed at the
// ray's time first.
bool PlaneSet::hit_plane(const PlaneData& p, const Ray& r, double tmax, double tie, double& t,
                         Vec3& n_out, Vec3* point) const {
  Vec3 o(r.org.x, r.org.y, r.org.z), d(r.dir.x, r.dir.y, r.dir.z);
  Vec3 n = p.n;
  double pd = p.d;
  if (p.moving) {
    ir::Transform xf = rel_at(*p.moving, origin_, shutter_fraction(r.time));
    Vec3 p0 = xf.point(p.plane->normal * p.plane->distance);
    n = ir::normalize(xf.normal(p.plane->normal));
    pd = ir::dot(n, p0);
  }
  n_out = n;
  double denom = ir::dot(n, d);
  double num = pd - ir::dot(n, o);
  // A ray leaving the plane (num and denom of opposite signs, or num 0) has t <= 0,
  // which the test below rejects anyway (tnear >= 0): turned away before the
  // division, as every shadow ray leaving the floor upwards is. NaN goes on and
  // fails below.
  if (r.tnear >= 0 && (num == 0 || (num > 0 && denom < 0) || (num < 0 && denom > 0))) return false;
  if (denom == 0) return false;
  t = num / denom;
  double tnear = r.tnear;
  if (!((t > tnear) && (t < tmax + tie / std::fabs(denom)) && (static_cast<float>(t) > 0)))
    return false;
  // A grazing hit can land arbitrarily far away; past kMaxPlaneHit the ray is taken
  // to escape, so no ray Embree is given starts beyond its range (FLT_LARGE, 1.8e18).
  Vec3 q = o + d * t;
  if (!(ir::max_num(std::fabs(q.x), ir::max_num(std::fabs(q.y), std::fabs(q.z))) <= kMaxPlaneHit))
    return false;
  // The hit point, projected onto the plane in double (o + t·d is off it by ulps of t).
  if (point) *point = q - n * (ir::dot(n, q) - pd);
  return true;
}

void PlaneSet::write_hit(const PlaneData& p, double t, Vec3 n, Vec3 q, Hit& hit) {
  hit.t = static_cast<float>(t);
  hit.ng = to_float(n.x, n.y, n.z);
  // Off the plane only by its rounding to float; the plane is re-tested in
  // double from the float origin, so a few ulps clear it (as for spheres).
  hit.p = to_float(q.x, q.y, q.z);
  hit.offset = float(kSurfaceOffsetUlps * 0x1p-24 * double(max_abs(hit.p)));
  hit.kind = Hit::Kind::Shape;
  hit.index = p.shape;
}

bool PlaneSet::intersect_planes(const Ray& r, double& tmax, double tie, Hit& hit) const {
  bool found = false;
  for (const PlaneData& p : planes_) {
    double t;
    Vec3 n, q;
    if (!hit_plane(p, r, tmax, tie, t, n, &q)) continue;
    tmax = t;
    tie = 0;  // between planes, the nearer t
    found = true;
    write_hit(p, t, n, q, hit);
  }
  return found;
}

bool PlaneSet::intersect_lanes(const PlaneRayLanes& rays, std::uint32_t live, double* tmax,
                               double* tie, std::uint32_t* which, std::uint32_t& hit_lanes) const {
  const PlaneHitLanesFn lanes = plane_hit_lanes();
  hit_lanes = 0;
  if (!lanes || any_moving_) return false;
  for (std::uint32_t i = 0; i < planes_.size(); ++i) {
    const std::uint32_t hit = lanes(planes_[i].n, planes_[i].d, rays, live, tmax, tie);
    for (std::uint32_t bits = hit; bits; bits &= bits - 1) which[__builtin_ctz(bits)] = i;
    hit_lanes |= hit;
  }
  return true;
}

void PlaneSet::plane_hit(std::uint32_t which, const Ray& r, double t, Hit& hit) const {
  const PlaneData& p = planes_[which];
  const Vec3 o(r.org.x, r.org.y, r.org.z), d(r.dir.x, r.dir.y, r.dir.z);
  // As hit_plane places it: o + t·d projected onto the plane in double.
  const Vec3 q = o + d * t;
  write_hit(p, t, p.n, q - p.n * (ir::dot(p.n, q) - p.d), hit);
}

bool PlaneSet::occluded_planes(const Ray& r) const {
  for (const PlaneData& p : planes_) {
    double t;
    Vec3 n;
    if (hit_plane(p, r, r.tmax, 0, t, n, nullptr)) return true;
  }
  return false;
}

std::uint32_t PlaneSet::occluded_lanes(const ShadowLanes16& in, std::uint32_t live) const {
  return occluded_lanes(in, live, plane_lanes());
}

std::uint32_t PlaneSet::occluded_lanes(const ShadowLanes16& in, std::uint32_t live,
                                       PlaneLanesFn lanes) const {
  std::uint32_t blocked = 0;
  for (const PlaneData& p : planes_) {
    const std::uint32_t todo = live & ~blocked;
    if (!todo) break;
    if (lanes && !p.moving) {
      blocked |= lanes(p.n, p.d, in, todo);
      continue;
    }
    for (std::uint32_t bits = todo; bits; bits &= bits - 1) {
      const unsigned k = unsigned(__builtin_ctz(bits));
      const Ray r = in.ray(k);
      double t;
      Vec3 n;
      if (hit_plane(p, r, r.tmax, 0, t, n, nullptr)) blocked |= 1u << k;
    }
  }
  return blocked;
}

}  // namespace snell::rt::geom
