// Lowering of the IR kinds (runtime/ir/kinds.def): a shape, material or pattern
// block becomes its kind struct, each field taken from the property of the same
// name (properties.def), then the kind's own hook, if it has one, checks what
// involves several properties or the file system. A kind without special needs
// has no code here at all.
#include <array>
#include <cmath>
#include <tuple>
#include <type_traits>

#include "compiler/ir_binding.hpp"
#include "compiler/lower.hpp"
#include "runtime/ir/dump.hpp"

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
  if (!cx.judged({PropId::box_min, PropId::box_max})) return true;
  if (b.min.x <= b.max.x && b.min.y <= b.max.y && b.min.z <= b.max.z) return true;
  cx.diags
      .report(DiagKind::InvalidValue, cx.get(PropId::box_max)->value_span,
              "a box's 'max' must be >= its 'min' in every component")
      .note(cx.get(PropId::box_min)->value_span, "min is " + ir::to_string(b.min));
  return false;
}

bool finish_kind(ir::Triangle& t, LowerContext& cx) {
  if (!cx.judged({PropId::triangle_a, PropId::triangle_b, PropId::triangle_c})) return true;
  if (ir::length(ir::cross(t.b - t.a, t.c - t.a)) != 0) return true;
  cx.diags.report(DiagKind::DegenerateGeometry, cx.keyword,
                  "this triangle has no area (its corners are collinear); it is left out");
  return false;
}

// §11's constraints that involve two properties: an error at the second one, with
// a note at the first.
lang::Span value_span(const LowerContext& cx, PropId id) {
  const EvaluatedProp* p = cx.get(id);
  return p ? p->value_span : cx.keyword;
}
bool distinct_ends(ir::Vec3 base, ir::Vec3 cap, const char* what, PropId base_id, PropId cap_id,
                   LowerContext& cx) {
  if (base != cap || !cx.judged({base_id, cap_id})) return true;
  cx.diags
      .report(DiagKind::InvalidValue, value_span(cx, cap_id),
              std::string("a ") + what + "'s 'cap' must differ from its 'base' (they set its axis)")
      .note(value_span(cx, base_id), "base is " + ir::to_string(base));
  return false;
}

bool finish_kind(ir::Cylinder& c, LowerContext& cx) {
  return distinct_ends(c.base, c.cap, "cylinder", PropId::cylinder_base, PropId::cylinder_cap, cx);
}

bool finish_kind(ir::Cone& c, LowerContext& cx) {
  bool ok = distinct_ends(c.base, c.cap, "cone", PropId::cone_base, PropId::cone_cap, cx);
  if (c.base_radius == 0 && c.cap_radius == 0 &&
      cx.judged({PropId::cone_base_radius, PropId::cone_cap_radius})) {
    cx.diags
        .report(DiagKind::InvalidValue, value_span(cx, PropId::cone_cap_radius),
                "a cone's 'base_radius' and 'cap_radius' cannot both be 0")
        .note(value_span(cx, PropId::cone_base_radius), "base_radius is 0");
    ok = false;
  }
  return ok;
}

// The normal is normalised (the same disc); the hole must leave a ring.
bool finish_kind(ir::Disc& d, LowerContext& cx) {
  ir::Vec3 n = d.normal;
  double m = std::fmax(std::fabs(n.x), std::fmax(std::fabs(n.y), std::fabs(n.z)));
  d.normal = ir::normalize(n / m);  // scaled first: <1e-200, 0, 0> is a direction too
  if (d.hole < d.radius || !cx.judged({PropId::disc_hole, PropId::disc_radius})) return true;
  cx.diags
      .report(DiagKind::InvalidValue, value_span(cx, PropId::disc_hole),
              "a disc's 'hole' must be < its 'radius'")
      .note(value_span(cx, PropId::disc_radius), "radius is " + ir::num(d.radius));
  return false;
}

bool finish_kind(ir::Torus& t, LowerContext& cx) {
  if (t.minor < t.major || !cx.judged({PropId::torus_minor, PropId::torus_major})) return true;
  cx.diags
      .report(DiagKind::InvalidValue, value_span(cx, PropId::torus_minor),
              "a torus's 'minor' must be < its 'major' (major > minor > 0)")
      .note(value_span(cx, PropId::torus_major), "major is " + ir::num(t.major));
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
Value make_material(const std::vector<EvaluatedProp>& props, lang::DiagnosticEngine&) {
  T kind;
  bind_fields(kind, props);
  ir::Material m(kind);
  // §16 `bump <P, A>`, common to every material (its parts: properties.def `bump`).
  for (const EvaluatedProp& p : props)
    if (p.info->name == "bump" && p.nested.size() == 2) {
      m.bump.pattern = p.nested[0].value.pat();
      m.bump.amount = p.nested[1].value.n;
    }
  return Value::of_material(m);
}

}  // namespace

bool color_map_of(const EvaluatedProp& p, lang::DiagnosticEngine& diags,
                  std::vector<ir::ColorStop>& map) {
  bool ok = true;
  const EvaluatedProp* prev = nullptr;
  for (const EvaluatedProp& stop : p.nested) {
    if (stop.nested.size() != 2) continue;  // its error is reported
    ir::ColorStop s{stop.nested[0].value.n, stop.nested[1].value.v};
    if (!map.empty() && s.at < map.back().at) {
      diags
          .report(DiagKind::InvalidValue, stop.nested[0].value_span,
                  "a colour map's stops must be in non-decreasing order: " + ir::num(s.at) +
                      " comes after " + ir::num(map.back().at))
          .note(prev->nested[0].value_span, "the stop before it");
      ok = false;
    }
    map.push_back(s);
    prev = &stop;
  }
  if (p.written == 0) {
    diags.report(DiagKind::InvalidValue, p.value_span,
                 "a colour map needs at least one 'stop <at, color>'");
    ok = false;
  }
  return ok && !map.empty();  // a map whose stops all failed said so already
}

namespace {

// §15's properties common to every pattern (properties.def SNELL_PATTERN_PROPS),
// found by name: each pattern block has its own rows of them.
bool common_pattern_props(ir::Texture& t, const std::vector<EvaluatedProp>& props,
                          lang::DiagnosticEngine& diags) {
  bool ok = true;
  t.world_from_pattern = object_transforms(props);
  for (const EvaluatedProp& p : props) {
    std::string_view name = p.info->name;
    if (name == "turbulence") {
      t.turbulence = p.value.n;
    } else if (name == "octaves") {
      t.octaves = static_cast<std::uint32_t>(p.value.n);
    } else if (name == "space") {
      ir::parse_enum(p.value.str(), t.space);
    } else if (name == "color_map") {
      ok &= color_map_of(p, diags, t.color_map);
    }
  }
  return ok;
}

template <class T>
Value make_pattern(const std::vector<EvaluatedProp>& props, lang::DiagnosticEngine& diags) {
  ir::Texture t;
  T kind;
  bind_fields(kind, props);
  t.pattern = kind;
  if constexpr (!std::is_same_v<T, ir::Constant>)
    if (!common_pattern_props(t, props, diags)) return Value::error();
  return Value::of_pattern(t);
}
using MakeFn = Value (*)(const std::vector<EvaluatedProp>&, lang::DiagnosticEngine&);
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

void check_shape_rest(const BlockInfo& block, SceneBuilder& builder, lang::Span keyword,
                      const std::vector<EvaluatedProp>& props,
                      const std::bitset<kPropCount>& failed, lang::DiagnosticEngine& diags) {
  if (block.shape_kind < 0) return;
  LowerContext cx{builder, keyword, props, diags, &failed};
  if (block.shape_kind == static_cast<int>(ir::ShapeKind::Mesh)) {
    // Its file is read (once; a missing or malformed one is an error at `file`).
    if (const EvaluatedProp* f = cx.get(PropId::mesh_file); f && cx.judged({PropId::mesh_file})) {
      ir::Mesh unused;
      builder.load_mesh(f->value.str(), f->value_span, unused.mesh);
    }
    return;
  }
  ir::ShapeGeom unused;
  lower_shape(block, cx, unused);
}

Value make_constructor_value(const BlockInfo& block, const std::vector<EvaluatedProp>& props,
                             lang::DiagnosticEngine& diags) {
  if (block.material_kind >= 0) return kMaterials[block.material_kind](props, diags);
  if (block.pattern_kind >= 0) return kPatterns[block.pattern_kind](props, diags);
  return Value::error();
}

}  // namespace snell::compile
