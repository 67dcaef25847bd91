#include "runtime/ir/ir.hpp"

namespace snell::ir {

namespace {
bool ops_move(const std::vector<TransformOp>& ops) {
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
}  // namespace

bool Motion::moves() const {
  if (ops_move(ops)) return true;
  for (const MotionBlock& b : nested)
    if (ops_move(b.ops)) return true;
  return false;
}

Motion nest_motion(const Motion& outer, const Transform& world_from_frame, const Motion& own) {
  Motion m = outer;
  if (own.empty()) return m;
  // Acting in the world's frame, with nothing around it that moves: the plain
  // block, computed as a top-level object's (bit for bit).
  if (m.empty() && !m.has_pivot && world_from_frame.is_identity()) return own;
  if (!own.ops.empty()) m.nested.push_back({world_from_frame, own.ops, own.has_pivot, own.pivot});
  for (const MotionBlock& b : own.nested)
    m.nested.push_back({world_from_frame * b.world_from_frame, b.ops, b.has_pivot, b.pivot});
  return m;
}

bool moves(const Shape& s, const Scene& scene) {
  if (s.motion().moves()) return true;
  const Csg* csg = s.as<Csg>();
  return csg && any_csg_leaf(scene, csg->node, [&](std::uint32_t part) {
           return scene.parts[part].motion().moves();
         });
}

namespace {
// One block's transform at u as a chain of T: Transform, or InverseTransform for
// its inverse alone; `make` turns each step's Transform into a T. One body, so the
// two agree bit for bit.
template <class T, class Make>
T block_at(const std::vector<TransformOp>& ops, bool has_pivot, Vec3 pivot, double u, Make make) {
  auto about_pivot = [&](const Transform& step) {
    return has_pivot
               ? make(Transform::translate(pivot)) * make(step) * make(Transform::translate(-pivot))
               : make(step);
  };
  T t;
  for (const TransformOp& op : ops) {
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

template <class T, class Make>
T motion_at(const Motion& mo, double u, Make make) {
  T t = block_at<T>(mo.ops, mo.has_pivot, mo.pivot, u, make);
  for (const MotionBlock& b : mo.nested) {
    T step = block_at<T>(b.ops, b.has_pivot, b.pivot, u, make);
    // A frame that is the world's (a union without transforms) needs no carrying.
    if (!b.world_from_frame.is_identity())
      step = make(b.world_from_frame) * step * make(b.world_from_frame.inverse());
    t = t * step;
  }
  return t;
}
}  // namespace

namespace {
bool same_ops(const std::vector<TransformOp>& a, const std::vector<TransformOp>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i].kind != b[i].kind || !(a[i].value == b[i].value)) return false;
  return true;
}
}  // namespace

bool same_motion(const Motion& a, const Motion& b) {
  if (!same_ops(a.ops, b.ops) || a.has_pivot != b.has_pivot || !(a.pivot == b.pivot) ||
      a.nested.size() != b.nested.size())
    return false;
  for (std::size_t i = 0; i < a.nested.size(); ++i) {
    const MotionBlock &x = a.nested[i], &y = b.nested[i];
    if (!(x.world_from_frame.m == y.world_from_frame.m) || !same_ops(x.ops, y.ops) ||
        x.has_pivot != y.has_pivot || !(x.pivot == y.pivot))
      return false;
  }
  return true;
}

Transform Motion::at(double u) const {
  return motion_at<Transform>(*this, u, [](const Transform& x) { return x; });
}

InverseTransform Motion::inverse_at(double u) const {
  return motion_at<InverseTransform>(*this, u, InverseTransform::of);
}

}  // namespace snell::ir
