// Lowering of the IR kinds (runtime/ir/kinds.def): a shape, material or pattern
// block becomes its kind struct, each field taken from the property of the same
// name (properties.def), then the kind's own hook, if it has one, checks what
// involves several properties or the file system. A kind without special needs
// has no code here at all.
#include <array>
#include <cmath>
#include <tuple>

#include "compiler/ir_binding.hpp"
#include "compiler/lower.hpp"

namespace snell::compile {

using lang::DiagKind;

namespace {

// For each field of T, the id of its block's property of that name, or -1
// (computed once per kind).
template <class T>
auto field_prop_ids() {
  constexpr std::size_t n = std::tuple_size_v<decltype(T::fields())>;
  std::array<std::int32_t, n> ids{};
  const BlockInfo* block = find_block(ir::KindName<T>::value);
  std::size_t i = 0;
  const T kind{};
  ir::for_each_field(kind, [&](const char* name, const auto&) {
    const PropInfo* p = block ? find_prop(*block, name) : nullptr;
    ids[i++] = p ? p->id : -1;
  });
  return ids;
}

template <class T>
void bind_fields(T& kind, const std::vector<EvaluatedProp>& props) {
  [[maybe_unused]] static const auto ids = field_prop_ids<T>();
  std::size_t i = 0;
  ir::for_each_field(kind, [&](const char*, auto& f) {
    std::int32_t id = ids[i++];
    if (id < 0) return;
    if (const EvaluatedProp* p = find_evaluated(props, PropId(id))) assign(f, p->value);
  });
}

// The kinds' hooks: true to keep the item. The template is every kind without one.
template <class T>
bool finish_kind(T&, LowerContext&) {
  return true;
}

// dot(p, n) = d with n normalised: the plane is the same set of points.
bool finish_kind(ir::Plane& p, LowerContext&) {
  double len = ir::length(p.normal);
  p.normal = p.normal / len;
  p.distance = p.distance / len;
  return true;
}

bool finish_kind(ir::Box& b, LowerContext& cx) {
  if (b.min.x <= b.max.x && b.min.y <= b.max.y && b.min.z <= b.max.z) return true;
  cx.diags
      .report(DiagKind::InvalidValue, cx.get(PropId::box_max)->value_span,
              "a box's 'max' must be >= its 'min' in every component")
      .note(cx.get(PropId::box_min)->value_span, "min is " + ir::to_string(b.min));
  return false;
}

bool finish_kind(ir::Triangle& t, LowerContext& cx) {
  if (ir::length(ir::cross(t.b - t.a, t.c - t.a)) != 0) return true;
  cx.diags.report(DiagKind::DegenerateGeometry, cx.keyword,
                  "this triangle has no area (its corners are collinear); it is left out");
  return false;
}

bool finish_kind(ir::Mesh& m, LowerContext& cx) {
  const EvaluatedProp* f = cx.get(PropId::mesh_file);
  return cx.builder.load_mesh(f->value.str(), f->value_span, m.mesh);
}

template <class T>
bool lower_into(ir::ShapeGeom& out, LowerContext& cx) {
  T kind;
  bind_fields(kind, cx.props);
  if (!finish_kind(kind, cx)) return false;
  out = kind;
  return true;
}

using ShapeFn = bool (*)(ir::ShapeGeom&, LowerContext&);
constexpr ShapeFn kShapes[] = {
#define SNELL_SHAPE(name, Type) &lower_into<ir::Type>,
#include "runtime/ir/kinds.def"
};

template <class T>
Value make_material(const std::vector<EvaluatedProp>& props) {
  T kind;
  bind_fields(kind, props);
  return Value::of_material(ir::Material(kind));
}
template <class T>
Value make_pattern(const std::vector<EvaluatedProp>& props) {
  ir::Texture t;
  T kind;
  bind_fields(kind, props);
  t.pattern = kind;
  return Value::of_pattern(t);
}
using MakeFn = Value (*)(const std::vector<EvaluatedProp>&);
constexpr MakeFn kMaterials[] = {
#define SNELL_MATERIAL(name, Type) &make_material<ir::Type>,
#include "runtime/ir/kinds.def"
};
constexpr MakeFn kPatterns[] = {
#define SNELL_PATTERN(name, Type) &make_pattern<ir::Type>,
#include "runtime/ir/kinds.def"
};

}  // namespace

bool lower_shape(const BlockInfo& block, LowerContext& cx, ir::ShapeGeom& out) {
  return kShapes[block.shape_kind](out, cx);
}

Value make_constructor_value(const BlockInfo& block, const std::vector<EvaluatedProp>& props) {
  if (block.material_kind >= 0) return kMaterials[block.material_kind](props);
  if (block.pattern_kind >= 0) return kPatterns[block.pattern_kind](props);
  return Value::error();
}

}  // namespace snell::compile
