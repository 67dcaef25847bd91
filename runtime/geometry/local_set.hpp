// Shapes intersected in a local frame of their own (§11: cylinder, cone, disc,
// torus). A *local surface* type L does the geometry in that frame, in double; the
// two primitive sets here, one static and one moving, turn it into the user
// primitive-set interface of traits.hpp (transforms, bounds, the float/double seam,
// hit refinement), so a new kind of this family writes only its surface. No Embree
// types.
//
// A local surface L:
//   explicit L(const Kind&)            for each IR kind it serves
//   ir::Transform object_from_local    its frame in the kind's object space
//   bool intersect(Vec3 o, Vec3 d, double tnear, double tfar, double& t, Vec3& n) const
//        the nearest t in (tnear, tfar) of o + t·d (local space; d of any length)
//        and the outward normal there (any length)
//   Vec3 project(Vec3 p) const         the surface point nearest p (p within ulps of it)
//   void corners(F f) const            f(local point) for points whose hull holds it
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "runtime/geometry/motion.hpp"
#include "runtime/geometry/ray.hpp"
#include "runtime/geometry/sphere.hpp"
#include "runtime/geometry/xform.hpp"
#include "runtime/ir/ir.hpp"
#include "runtime/vec.hpp"

namespace snell::rt::geom {

// [lo, hi] ∩ the t where o + t·d is inside the ball (c, radius): false when empty.
// The shapes clip their rays to a ball around them and move the origin to where
// the clipped ray starts, so a ray from far away is solved with well-conditioned
// coefficients (robustness #5: the cancellation of b² - 4ac grows with the distance).
inline bool clip_to_ball(Vec3 o, Vec3 d, Vec3 c, double radius, double& lo, double& hi) {
  double t0, t1;
  if (!sphere_roots(o, d, c, radius, t0, t1)) return false;
  lo = ir::max_num(lo, t0), hi = ir::min_num(hi, t1);
  return lo <= hi;
}

// A camera-relative float ray against surface `l` placed by `local_from_rel`.
template <class L>
bool hit_local(const L& l, const ir::Mat4& local_from_rel, Vec3f of, Vec3f df, float tnear,
               float tfar, float& t_out, Vec3f& n_out) {
  Vec3 o = xform_point(local_from_rel, Vec3(of.x, of.y, of.z));
  Vec3 d = xform_vector(local_from_rel, Vec3(df.x, df.y, df.z));
  double t;
  Vec3 n;
  if (!l.intersect(o, d, tnear, tfar, t, n)) return false;
  t_out = static_cast<float>(t);
  if (!(t_out > tnear && t_out < tfar)) return false;
  Vec3 nw = ir::normalize(xform_normal_by_inverse(local_from_rel, n));
  if (!ir::is_finite(nw)) return false;
  n_out = to_float(nw.x, nw.y, nw.z);
  return true;
}

// The static shapes of one local surface type: one user primitive each.
template <class L>
class LocalSet {
 public:
  template <class Kind>
  void add(const ir::Shape& s, const Kind& g, std::uint32_t index, Vec3 origin) {
    L l(g);
    ir::Transform rel =
        ir::Transform::translate(-origin) * s.world_from_object() * l.object_from_local;
    double stretch = 0;  // the largest a local unit becomes
    for (int c = 0; c < 3; ++c)
      stretch = ir::max_num(stretch, ir::length(Vec3(rel.m(0, c), rel.m(1, c), rel.m(2, c))));
    prims_.push_back({l, rel.inv, rel.m, index, stretch});
  }
  std::size_t size() const { return prims_.size(); }
  std::uint32_t shape(unsigned prim) const { return prims_[prim].shape; }
  void bounds(unsigned prim, Box3& box) const {
    const Prim& p = prims_[prim];
    p.surface.corners([&](Vec3 c) { box.grow(xform_point(p.rel_from_local, c)); });
  }
  bool hit(unsigned prim, float, Vec3f o, Vec3f d, float tnear, float tfar, float& t,
           Vec3f& n) const {
    const Prim& p = prims_[prim];
    return hit_local(p.surface, p.local_from_rel, o, d, tnear, tfar, t, n);
  }
  // The hit point projected onto the surface in double, in its local frame, and
  // the bounded offset of spheres (kSurfaceOffsetUlps, sphere.cpp): o + t·d from
  // the float t is off the surface by ulps of t; the projection leaves only the
  // rounding of p to float, and the surface is re-tested in double from the spawned
  // float origin.
  void refine(unsigned prim, const Ray& r, float t, Hit& hit) const {
    const Prim& pr = prims_[prim];
    Vec3 p0(double(r.org.x) + double(r.dir.x) * t, double(r.org.y) + double(r.dir.y) * t,
            double(r.org.z) + double(r.dir.z) * t);
    const Vec3 q = pr.surface.project(xform_point(pr.local_from_rel, p0));
    Vec3 p = xform_point(pr.rel_from_local, q);
    if (!ir::is_finite(p)) {
      hit.p = r.org + r.dir * t, hit.offset = unbounded_offset(r, hit.p);
      return;
    }
    hit.p = to_float(p.x, p.y, p.z);
    hit.offset = float(kSurfaceOffsetUlps * 0x1p-24 * double(max_abs(hit.p)));
    // The projection itself is good to ulps of the local point, in double: only a
    // surface whose local coordinates dwarf the hit's distance from the camera
    // (a torus of major radius 1e11 seen from its tube) needs more than the above,
    // and it shadowed itself in speckles without it.
    const double local = ir::max_num(std::fabs(q.x), ir::max_num(std::fabs(q.y), std::fabs(q.z)));
    hit.offset = ir::max_num(hit.offset, float(kSurfaceOffsetUlps * 0x1p-52 * local * pr.stretch));
  }

 private:
  struct Prim {
    L surface;
    ir::Mat4 local_from_rel, rel_from_local;
    std::uint32_t shape = 0;
    double stretch = 1;  // rel_from_local's largest column length
  };
  std::vector<Prim> prims_;
};

// The shapes of one local surface type that move while the shutter is open: user
// geometry whose static bounds hold the whole sweep; the intersector places the
// shape at the ray's time (Motion::at, exact rotation), as MovingSphereSet does.
template <class L>
class MovingLocalSet {
 public:
  template <class Kind>
  void add(const ir::Shape& s, const Kind& g, std::uint32_t index, Vec3 origin) {
    prims_.push_back({&s, L(g), origin, index});
  }
  std::size_t size() const { return prims_.size(); }
  std::uint32_t shape(unsigned prim) const { return prims_[prim].index; }
  // The union of the boxes at kSteps + 1 times, grown by the largest distance a
  // corner moves between two neighbouring times (MovingSphereSet::bounds: why).
  void bounds(unsigned prim, Box3& box) const {
    const Moving& m = prims_[prim];
    swept_bounds([&](double u) { return rel_from_local(m, u); },
                 [&](auto&& f) { m.surface.corners(f); }, box);
  }
  bool hit(unsigned prim, float time, Vec3f o, Vec3f d, float tnear, float tfar, float& t,
           Vec3f& n) const {
    const Moving& m = prims_[prim];
    // The inverse alone: (rel_at(...) * object_from_local).inv to the bit, at half
    // the matrix products (a nested motion is several blocks).
    ir::Mat4 local_from_rel = (ir::InverseTransform{rel_from_object_inverse_at(
                                   *m.shape, m.origin, shutter_fraction(time))} *
                               ir::InverseTransform::of(m.surface.object_from_local))
                                  .inv;
    return hit_local(m.surface, local_from_rel, o, d, tnear, tfar, t, n);
  }
  // o + t·d with no bound of its own (unbounded_offset): the Wächter–Binder offset
  // covers its error.
  void refine(unsigned, const Ray& r, float t, Hit& hit) const {
    hit.p = r.org + r.dir * t, hit.offset = unbounded_offset(r, hit.p);
  }

 private:
  struct Moving {
    const ir::Shape* shape = nullptr;
    L surface;
    Vec3 origin;
    std::uint32_t index = 0;
  };
  static ir::Mat4 rel_from_local(const Moving& m, double u) {
    return (rel_at(*m.shape, m.origin, u) * m.surface.object_from_local).m;
  }
  std::vector<Moving> prims_;
};

}  // namespace snell::rt::geom
