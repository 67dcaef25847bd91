#include "runtime/ir/ir.hpp"

namespace snell::ir {

bool Motion::moves() const {
  for (const TransformOp& op : ops) {
    switch (op.kind) {
      case TransformOp::Kind::Translate:
      case TransformOp::Kind::Rotate:
        if (op.value != Vec3{}) return true;
        break;
      case TransformOp::Kind::Scale:
        if (op.value != Vec3{1, 1, 1}) return true;
        break;
    }
  }
  return false;
}

namespace {
// Motion::at as a chain of T: Transform, or InverseTransform for its inverse alone;
// `make` turns each step's Transform into a T. One body, so the two agree bit for bit.
template <class T, class Make>
T motion_at(const Motion& mo, double u, Make make) {
  auto about_pivot = [&](const Transform& step) {
    return mo.has_pivot ? make(Transform::translate(mo.pivot)) * make(step) *
                              make(Transform::translate(-mo.pivot))
                        : make(step);
  };
  T t;
  for (const TransformOp& op : mo.ops) {
    switch (op.kind) {
      case TransformOp::Kind::Translate:
        t = make(Transform::translate(op.value * u)) * t;
        break;
      case TransformOp::Kind::Rotate:
        t = about_pivot(Transform::rotate_xyz(op.value * u)) * t;
        break;
      case TransformOp::Kind::Scale:
        t = about_pivot(Transform::scale(Vec3{1, 1, 1} * (1 - u) + op.value * u)) * t;
        break;
    }
  }
  return t;
}
}  // namespace

Transform Motion::at(double u) const {
  return motion_at<Transform>(*this, u, [](const Transform& x) { return x; });
}

InverseTransform Motion::inverse_at(double u) const {
  return motion_at<InverseTransform>(*this, u, InverseTransform::of);
}

}  // namespace snell::ir
