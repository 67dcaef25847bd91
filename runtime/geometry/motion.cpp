#include "runtime/geometry/motion.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

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

// The most a motion turns over the shutter, in degrees: the sum of its rotation
// steps' angles (a composition of turns turns at most by their sum; frames and
// pivots change no angle).
double turn_degrees(const ir::Motion& m) {
  double deg = 0;
  auto add = [&](const std::vector<ir::TransformOp>& ops) {
    for (const ir::TransformOp& op : ops)
      if (op.kind == ir::TransformOp::Kind::Rotate)
        deg += std::fabs(op.value.x) + std::fabs(op.value.y) + std::fabs(op.value.z);
  };
  add(m.ops);
  for (const ir::MotionBlock& b : m.nested) add(b.ops);
  return deg;
}

namespace {

// `tolerance` × the size of `verts` where s stands at shutter open (× 1 for a point).
double size_tolerance(const ir::Shape& s, const std::vector<Vec3>& verts, Vec3 origin,
                      double tolerance) {
  ir::Transform t0 = rel_at(s, origin, 0);
  Box3 box;
  for (const Vec3& v : verts) box.grow(t0.point(v));
  double size =
      ir::length(Vec3(box.hi[0] - box.lo[0], box.hi[1] - box.lo[1], box.hi[2] - box.lo[2]));
  return tolerance * (size > 0 ? size : 1);
}

}  // namespace

unsigned first_segments(const ir::Motion& m) {
  const double deg = turn_degrees(m);
  unsigned segs = 1;
  while (segs < 128 && deg > 90.0 * segs) segs *= 2;
  return segs;
}

unsigned motion_segments(const ir::Shape& s, const std::vector<Vec3>& verts, Vec3 origin,
                         double tolerance) {
  if (verts.empty()) return 1;
  std::vector<Vec3> probe;
  std::size_t stride = std::max<std::size_t>(1, verts.size() / 64);
  for (std::size_t i = 0; i < verts.size(); i += stride) probe.push_back(verts[i]);
  const double tol = size_tolerance(s, verts, origin, tolerance);
  unsigned segs = first_segments(s.motion());
  for (; segs < 128; segs *= 2) {
    double err = 0;
    for (unsigned i = 0; i < segs; ++i) {
      ir::Transform a = rel_at(s, origin, double(i) / segs);
      ir::Transform b = rel_at(s, origin, double(i + 1) / segs);
      for (double f : {0.25, 0.5, 0.75}) {
        ir::Transform m = rel_at(s, origin, (i + f) / segs);
        for (const Vec3& v : probe)
          err = ir::max_num(err, ir::length(m.point(v) - (a.point(v) * (1 - f) + b.point(v) * f)));
      }
    }
    if (!(err > tol)) break;
  }
  return segs;
}

std::optional<QuatPlacement> quat_placement(const ir::Mat4& m, Vec3 centre) {
  Vec3 l[3];
  for (int c = 0; c < 3; ++c) l[c] = Vec3(m(0, c), m(1, c), m(2, c));
  QuatPlacement p;
  Vec3 r[3];
  double scale = 0;
  for (int c = 0; c < 3; ++c) {
    if (!is_finite(l[c])) return std::nullopt;
    scale = ir::max_num(scale, length(l[c]));
  }
  for (int c = 0; c < 3; ++c) {
    Vec3 v = l[c];
    for (int k = 0; k < c; ++k) {
      p.u[k][c] = dot(r[k], l[c]);
      v = v - r[k] * p.u[k][c];
    }
    p.u[c][c] = length(v);
    // A column (nearly) in the span of the others: no rotation to speak of.
    if (!(p.u[c][c] > 1e-9 * scale)) return std::nullopt;
    r[c] = v / p.u[c][c];
  }
  if (dot(cross(r[0], r[1]), r[2]) < 0) r[2] = -r[2], p.u[2][2] = -p.u[2][2];
  // The rotation's quaternion (Shepperd: from the largest of the four squares).
  const double m00 = r[0].x, m11 = r[1].y, m22 = r[2].z;
  const double m10 = r[0].y, m20 = r[0].z, m01 = r[1].x, m21 = r[1].z, m02 = r[2].x, m12 = r[2].y;
  const double tr = m00 + m11 + m22;
  double* q = p.q;
  if (tr >= m00 && tr >= m11 && tr >= m22) {
    double s = std::sqrt(1 + tr) * 2;
    q[0] = s / 4, q[1] = (m21 - m12) / s, q[2] = (m02 - m20) / s, q[3] = (m10 - m01) / s;
  } else if (m00 >= m11 && m00 >= m22) {
    double s = std::sqrt(1 + m00 - m11 - m22) * 2;
    q[0] = (m21 - m12) / s, q[1] = s / 4, q[2] = (m01 + m10) / s, q[3] = (m02 + m20) / s;
  } else if (m11 >= m22) {
    double s = std::sqrt(1 + m11 - m00 - m22) * 2;
    q[0] = (m02 - m20) / s, q[1] = (m01 + m10) / s, q[2] = s / 4, q[3] = (m12 + m21) / s;
  } else {
    double s = std::sqrt(1 + m22 - m00 - m11) * 2;
    q[0] = (m10 - m01) / s, q[1] = (m02 + m20) / s, q[2] = (m12 + m21) / s, q[3] = s / 4;
  }
  // About the centre: R·(U·p − U·c) + m·c.
  Vec3 uc(0, 0, 0);
  for (int i = 0; i < 3; ++i)
    for (int j = i; j < 3; ++j) uc[i] += p.u[i][j] * centre[j];
  p.shift = -uc;
  p.translation = xform_point(m, centre);
  return p;
}

ir::Mat4 quat_matrix(const QuatPlacement& p) {
  const double w = p.q[0], x = p.q[1], y = p.q[2], z = p.q[3];
  const double n = w * w + x * x + y * y + z * z;
  const double s = n > 0 ? 2 / n : 0;
  const double r[3][3] = {{1 - s * (y * y + z * z), s * (x * y - w * z), s * (x * z + w * y)},
                          {s * (x * y + w * z), 1 - s * (x * x + z * z), s * (y * z - w * x)},
                          {s * (x * z - w * y), s * (y * z + w * x), 1 - s * (x * x + y * y)}};
  ir::Mat4 m;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      double a = 0;
      for (int k = 0; k <= j; ++k) a += r[i][k] * p.u[k][j];
      m(i, j) = a;
    }
    m(i, 3) = r[i][0] * p.shift.x + r[i][1] * p.shift.y + r[i][2] * p.shift.z + p.translation[i];
  }
  return m;
}

QuatPlacement quat_between(const QuatPlacement& a, const QuatPlacement& b, double f) {
  QuatPlacement p;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) p.u[i][j] = a.u[i][j] + (b.u[i][j] - a.u[i][j]) * f;
  p.shift = a.shift + (b.shift - a.shift) * f;
  p.translation = a.translation + (b.translation - a.translation) * f;
  double c = 0, q1[4];
  for (int k = 0; k < 4; ++k) c += a.q[k] * b.q[k];
  const double sign = c < 0 ? -1 : 1;  // the shorter arc, as Embree takes it
  for (int k = 0; k < 4; ++k) q1[k] = sign * b.q[k];
  c = ir::min_num(1.0, std::fabs(c));
  const double theta = std::acos(c);
  double wa = 1 - f, wb = f;
  if (theta > 1e-9)
    wa = std::sin((1 - f) * theta) / std::sin(theta), wb = std::sin(f * theta) / std::sin(theta);
  for (int k = 0; k < 4; ++k) p.q[k] = wa * a.q[k] + wb * q1[k];
  return p;
}

std::vector<QuatPlacement> quat_motion_steps(const ir::Shape& s, const std::vector<Vec3>& corners,
                                             Vec3 centre, Vec3 origin, double tolerance) {
  const double tol = size_tolerance(s, corners, origin, tolerance);
  std::vector<QuatPlacement> steps;
  for (unsigned segs = first_segments(s.motion());; segs *= 2) {
    steps.clear();
    for (unsigned i = 0; i <= segs; ++i) {
      std::optional<QuatPlacement> p =
          quat_placement(rel_at(s, origin, double(i) / segs).m, centre);
      if (!p) return {};
      steps.push_back(*p);
    }
    if (segs == 128) return steps;
    bool close = true;
    for (unsigned i = 0; i < segs && close; ++i) {
      double c = 0;
      for (int k = 0; k < 4; ++k) c += steps[i].q[k] * steps[i + 1].q[k];
      // cos of half the turn: under 90° a step, far from the half turn's tie.
      if (std::fabs(c) < std::sqrt(0.5)) close = false;
      for (double f : {0.25, 0.5, 0.75}) {
        if (!close) break;
        ir::Mat4 exact = rel_at(s, origin, (i + f) / segs).m;
        ir::Mat4 between = quat_matrix(quat_between(steps[i], steps[i + 1], f));
        for (const Vec3& v : corners)
          if (!(ir::length(xform_point(exact, v) - xform_point(between, v)) <= tol)) close = false;
      }
    }
    if (close) return steps;
  }
}

}  // namespace snell::rt::geom
