// Cylinders and cones (§11): one local surface, the truncated cone, for both kinds
// (a cylinder is the cone of equal radii), in the frame whose origin is `base` and
// whose +z runs to `cap`; intersected in double (local_set.hpp: the sets). No
// Embree types.
#pragma once

#include <cmath>

#include "runtime/geometry/local_set.hpp"
#include "runtime/ir/ir.hpp"

namespace snell::rt::geom {

// The points with ρ = hypot(x, y) <= r(z) = r0 + (r1 − r0)·z/h and 0 <= z <= h,
// closed by its end discs unless open (then only the side: ρ = r(z)).
class TruncatedCone {
 public:
  explicit TruncatedCone(const ir::Cylinder& c)
      : TruncatedCone(c.base, c.radius, c.cap, c.radius, c.open) {}
  explicit TruncatedCone(const ir::Cone& c)
      : TruncatedCone(c.base, c.base_radius, c.cap, c.cap_radius, c.open) {}

  ir::Transform object_from_local;
  bool intersect(Vec3 o, Vec3 d, double tnear, double tfar, double& t, Vec3& n) const;
  // A stretch of the ray inside the closed solid: [e, x] in t, with the outward
  // normals (any length) at its ends, a cap's or the side's.
  struct Piece {
    double e, x;
    Vec3 n_e, n_x;
  };
  // The closed solid's pieces along o + t·d (local space), from one solve: at most
  // two (the solid is convex, so one where the arithmetic is exact), in order, the
  // same ends as the hits intersect() finds one by one; [lo, hi] only places the
  // ray's clipped start (conditioning), the pieces are not cut to it.
  int solid_spans(Vec3 o, Vec3 d, double lo, double hi, Piece* out) const;
  Vec3 project(Vec3 p) const;
  template <class F>
  void corners(F&& f) const {
    for (int i = 0; i < 4; ++i) {
      double su = i & 1 ? 1 : -1, sv = i & 2 ? 1 : -1;
      f(Vec3{su * r0_, sv * r0_, 0}), f(Vec3{su * r1_, sv * r1_, h_});
    }
  }

 private:
  TruncatedCone(Vec3 base, double r0, Vec3 cap, double r1, bool open);
  Vec3 side_normal(Vec3 p) const;
  // The side's quadric g(s) = a s² + 2 b s + c along os + s·d, os = o + ts·d the
  // ray's start clipped to the bounding ball, and its roots s0 <= s1 when real.
  struct Quadric {
    double ts, a, b, c, s0, s1;
    Vec3 os;
    bool roots;
  };
  bool along(Vec3 o, Vec3 d, double& lo, double& hi, Quadric& q) const;
  int pieces(const Quadric& q, Vec3 d, Piece* out) const;
  double h_ = 1, r0_ = 1, r1_ = 1, k_ = 0;  // k: dr/dz
  double ball_ = 1;                         // the bounding ball's radius about (0, 0, h/2), padded
  bool open_ = false;
};

}  // namespace snell::rt::geom
