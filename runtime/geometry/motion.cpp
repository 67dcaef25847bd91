#include "runtime/geometry/motion.hpp"

#include <algorithm>
#include <cmath>

#include "runtime/geometry/xform.hpp"

namespace snell::rt::geom {

ir::Transform rel_at(const ir::Shape& s, Vec3 origin, double u) {
  return ir::Transform::translate(-origin) * (s.motion().at(u) * s.world_from_object());
}

ir::Mat4 rel_from_object_inverse_at(const ir::Shape& s, Vec3 origin, double u) {
  using ir::InverseTransform;
  return (InverseTransform::of(ir::Transform::translate(-origin)) *
          (s.motion().inverse_at(u) * InverseTransform::of(s.world_from_object())))
      .inv;
}

unsigned motion_segments(const ir::Shape& s, const std::vector<Vec3>& verts, Vec3 origin,
                         double tolerance) {
  if (verts.empty()) return 1;
  std::vector<Vec3> probe;
  std::size_t stride = std::max<std::size_t>(1, verts.size() / 64);
  for (std::size_t i = 0; i < verts.size(); i += stride) probe.push_back(verts[i]);
  ir::Transform t0 = rel_at(s, origin, 0);
  Box3 box;
  for (const Vec3& v : verts) box.grow(t0.point(v));
  double size =
      ir::length(Vec3(box.hi[0] - box.lo[0], box.hi[1] - box.lo[1], box.hi[2] - box.lo[2]));
  double tol = tolerance * (size > 0 ? size : 1);
  unsigned segs = 1;
  for (; segs < 128; segs *= 2) {
    double err = 0;
    for (unsigned i = 0; i < segs; ++i) {
      ir::Transform a = rel_at(s, origin, double(i) / segs);
      ir::Transform b = rel_at(s, origin, double(i + 1) / segs);
      ir::Transform m = rel_at(s, origin, (i + 0.5) / segs);
      for (const Vec3& v : probe)
        err = std::fmax(err, ir::length(m.point(v) - (a.point(v) + b.point(v)) * 0.5));
    }
    if (err <= tol) break;
  }
  return segs;
}

}  // namespace snell::rt::geom
