// Discs (§11): the annulus hole <= ρ <= radius of the plane z = 0 of the frame
// whose origin is `center` and whose +z is `normal`, intersected in double
// (local_set.hpp: the sets). One-sided geometry with no inside: its normal is
// always `normal`, whichever side a ray comes from (§11). No Embree types.
#pragma once

#include <algorithm>
#include <cmath>

#include "runtime/geometry/local_set.hpp"
#include "runtime/ir/ir.hpp"

namespace snell::rt::geom {

class DiscSurface {
 public:
  explicit DiscSurface(const ir::Disc& g)
      : object_from_local(ir::axis_frame(g.center, ir::normalize(g.normal))),
        r_(g.radius),
        hole_(g.hole) {}

  ir::Transform object_from_local;
  // The plane's t from the local origin's height (exact to rounding: the origin is
  // moved off the disc along its normal by a spawned ray's offset, so the sign of
  // o.z decides the side), then the ring test on the point.
  bool intersect(Vec3 o, Vec3 d, double tnear, double tfar, double& t_out, Vec3& n) const {
    if (d.z == 0) return false;
    double t = -o.z / d.z;
    if (!(t > tnear && t < tfar)) return false;
    double x = o.x + d.x * t, y = o.y + d.y * t;
    double rho = ir::hypot_fast(x, y);
    if (!(rho <= r_ && rho >= hole_)) return false;
    t_out = t, n = {0, 0, 1};
    return true;
  }
  // Onto the plane, the radius clamped to the ring.
  Vec3 project(Vec3 p) const {
    double rho = ir::hypot_fast(p.x, p.y);
    double s = rho > 0 ? std::clamp(rho, hole_, r_) / rho : 1;
    return {p.x * s, p.y * s, 0};
  }
  template <class F>
  void corners(F&& f) const {
    for (int i = 0; i < 4; ++i) f(Vec3{i & 1 ? r_ : -r_, i & 2 ? r_ : -r_, 0});
  }

 private:
  double r_ = 1, hole_ = 0;
};

}  // namespace snell::rt::geom
