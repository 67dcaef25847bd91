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

Transform Motion::at(double u) const {
  auto about_pivot = [&](const Transform& step) {
    return has_pivot ? Transform::translate(pivot) * step * Transform::translate(-pivot) : step;
  };
  Transform t;
  for (const TransformOp& op : ops) {
    switch (op.kind) {
      case TransformOp::Kind::Translate:
        t = Transform::translate(op.value * u) * t;
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

}  // namespace snell::ir
