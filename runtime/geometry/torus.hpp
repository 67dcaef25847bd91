// Tori (§11): centred at the origin around the y axis, intersected in double in
// object space (local_set.hpp: the sets) by a quartic solved robustly (torus.cpp:
// how). No Embree types.
#pragma once

#include "runtime/geometry/local_set.hpp"
#include "runtime/ir/ir.hpp"

namespace snell::rt::geom {

// The real roots of c[0] + c[1]·x + ... + c[n]·x^n (n <= 4, c[n] != 0) in (lo, hi],
// ascending, into `roots`; returns how many. Each root is bracketed between the
// polynomial's critical points (the roots of its derivative, found the same way),
// so none is missed where the polynomial changes sign, and is then found by
// Newton's method safeguarded by bisection.
int polynomial_roots(const double* c, int n, double lo, double hi, double* roots);

class TorusSurface {
 public:
  explicit TorusSurface(const ir::Torus& g) : big_(g.major), small_(g.minor) {}

  ir::Transform object_from_local;  // the identity: the torus is placed by transforms
  bool intersect(Vec3 o, Vec3 d, double tnear, double tfar, double& t, Vec3& n) const;
  // The nearest point: along the ray from the tube's centre circle through p.
  Vec3 project(Vec3 p) const;
  template <class F>
  void corners(F&& f) const {
    double a = big_ + small_, b = small_;
    for (int i = 0; i < 8; ++i) f(Vec3{i & 1 ? a : -a, i & 2 ? b : -b, i & 4 ? a : -a});
  }

 private:
  double big_ = 1, small_ = 0.25;  // major R, minor r
};

}  // namespace snell::rt::geom
