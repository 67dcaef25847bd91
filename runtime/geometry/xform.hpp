// Double-precision transform helpers of the geometry kinds (no Embree types).
#pragma once

#include <cmath>

#include "runtime/ir/math.hpp"

namespace snell::rt::geom {

using ir::Vec3;

inline Vec3 xform_point(const ir::Mat4& m, Vec3 p) {
  return {m(0, 0) * p.x + m(0, 1) * p.y + m(0, 2) * p.z + m(0, 3),
          m(1, 0) * p.x + m(1, 1) * p.y + m(1, 2) * p.z + m(1, 3),
          m(2, 0) * p.x + m(2, 1) * p.y + m(2, 2) * p.z + m(2, 3)};
}
inline Vec3 xform_vector(const ir::Mat4& m, Vec3 v) {
  return {m(0, 0) * v.x + m(0, 1) * v.y + m(0, 2) * v.z,
          m(1, 0) * v.x + m(1, 1) * v.y + m(1, 2) * v.z,
          m(2, 0) * v.x + m(2, 1) * v.y + m(2, 2) * v.z};
}
// Normal to world: inverse transpose of world_from_object = transpose of object_from_world.
inline Vec3 xform_normal_by_inverse(const ir::Mat4& inv, Vec3 n) {
  return {inv(0, 0) * n.x + inv(1, 0) * n.y + inv(2, 0) * n.z,
          inv(0, 1) * n.x + inv(1, 1) * n.y + inv(2, 1) * n.z,
          inv(0, 2) * n.x + inv(1, 2) * n.y + inv(2, 2) * n.z};
}
inline double det3(const ir::Mat4& m) {
  return m(0, 0) * (m(1, 1) * m(2, 2) - m(1, 2) * m(2, 1)) -
         m(0, 1) * (m(1, 0) * m(2, 2) - m(1, 2) * m(2, 0)) +
         m(0, 2) * (m(1, 0) * m(2, 1) - m(1, 1) * m(2, 0));
}

// A camera-relative box in double, grown point by point.
struct Box3 {
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  void grow(Vec3 p) {
    for (int k = 0; k < 3; ++k) lo[k] = ir::min_num(lo[k], p[k]), hi[k] = ir::max_num(hi[k], p[k]);
  }
};

}  // namespace snell::rt::geom
