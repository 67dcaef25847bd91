#include "compiler/properties.hpp"

#include <fmt/format.h>

#include <cmath>
#include <deque>
#include <memory>
#include <span>
#include <string_view>
#include <vector>

#include "compiler/ir_binding.hpp"
#include "language/diagnostics.hpp"
#include "runtime/pattern/noise.hpp"

namespace snell::compile {

const PropInfo* const* detail::prop_index = nullptr;

namespace {

struct Registry {
  std::deque<PropInfo> props;
  std::deque<BlockInfo> blocks;
  std::vector<const PropInfo*> by_id;

  Registry() {
#define SNELL_BLOCK(name, kind) blocks.push_back({#name, BlockKind::kind, {}, false});
#define SNELL_PROP(block, name, type, check, flags, def) \
  add(#block, #name, PropType::type, Check::check, static_cast<unsigned>(flags), def);
#define SNELL_SETTING(name, type, check, def) \
  add("settings", #name, PropType::type, Check::check, 0, def);
#include "compiler/properties.def"
    for (std::size_t i = 0; i < props.size(); ++i) {
      props[i].id = static_cast<std::int32_t>(i);
      by_id.push_back(&props[i]);
    }
    detail::prop_index = by_id.data();
    for (const PropInfo& p : props)
      for (BlockInfo& b : blocks)
        if (b.name == p.block) (p.named_only() ? b.named : b.props).push_back(&p);
    // The kinds of runtime/ir/kinds.def: their blocks, and the IR defaults of
    // their properties (and of the settings).
    int index = 0;
#define SNELL_SHAPE(name, Type) bind_kind<ir::Type>(#name, index++, &BlockInfo::shape_kind);
#include "runtime/ir/kinds.def"
    index = 0;
#define SNELL_MATERIAL(name, Type) bind_kind<ir::Type>(#name, index++, &BlockInfo::material_kind);
#include "runtime/ir/kinds.def"
    index = 0;
#define SNELL_PATTERN(name, Type) bind_kind<ir::Type>(#name, index++, &BlockInfo::pattern_kind);
#include "runtime/ir/kinds.def"
    const ir::Settings settings;
    BlockInfo& sb = block("settings");
    ir::for_each_field(
        settings, [&](const char* field, const auto& v) { ir_default(sb, field, to_value(v)); });
    ir_default(sb, "resolution", Value::vec2(settings.width, settings.height));
    const ir::Camera camera;
    BlockInfo& cb = block("camera");
    ir::for_each_field(
        camera, [&](const char* field, const auto& v) { ir_default(cb, field, to_value(v)); });
    ir_default(cb, "shutter", Value::vec2(camera.shutter_open, camera.shutter_close));
    const ir::PointLight point;
    ir::for_each_field(point, [&](const char* field, const auto& v) {
      ir_default(block("point_light"), field, to_value(v));
    });
    const ir::AreaLight area;
    ir::for_each_field(area, [&](const char* field, const auto& v) {
      ir_default(block("area_light"), field, to_value(v));
    });
    ir_default(block("area_light"), "samples", Value::vec2(area.samples_u, area.samples_v));
    const auto ops = ir::spellings<ir::CsgOp>();
    for (std::size_t i = 0; i < ops.size(); ++i)
      for (BlockInfo& b : blocks)
        if (b.name == ops[i]) b.csg_op = static_cast<int>(i);
    for (BlockInfo& b : blocks) b.is_object = b.shape_kind >= 0 || b.csg_op >= 0;
  }

  void add(std::string_view block, std::string_view name, PropType type, Check check,
           unsigned flags, Value def) {
    props.push_back({block, name, type, check, flags, std::move(def)});
  }
  void add(std::string_view block, std::string_view name, PropType type, Check check,
           unsigned flags, FromIR) {
    add(block, name, type, check, flags, Value::none());
    props.back().default_from_ir = true;
  }
  BlockInfo& block(std::string_view name) {
    for (BlockInfo& b : blocks)
      if (b.name == name) return b;
    static BlockInfo none{"", BlockKind::Nested, {}, false};  // a kind without a block:
    return none;                                              // the registry test reports it
  }
  // Fills the default of `block`'s property `field` when its row says IR. A Named
  // property's default is only shown (hovers, docs): it is never added to a block
  // that leaves it out, where the IR struct's own field already holds it.
  void ir_default(BlockInfo& b, std::string_view field, const Value& v) {
    for (const auto* list : {&b.props, &b.named})
      for (const PropInfo* p : *list)
        if (p->name == field && p->default_from_ir) const_cast<PropInfo*>(p)->default_value = v;
  }
  template <class T>
  void bind_kind(std::string_view name, int index, int BlockInfo::*slot) {
    BlockInfo& b = block(name);
    b.*slot = index;
    const T kind{};
    ir::for_each_field(
        kind, [&](const char* field, const auto& v) { ir_default(b, field, to_value(v)); });
  }
};

const Registry& registry() {
  static const Registry r;
  return r;
}

const BlockInfo& object_block() {
  static const BlockInfo* b = find_block("object");
  return *b;
}

bool is_integer(double x) {
  return std::isfinite(x) && std::floor(x) == x;
}

bool range_ok(Check c, double x) {
  switch (c) {
    case Check::Any:
    case Check::Shutter:
    case Check::NonZero:
      return true;
    case Check::Positive:
      return x > 0;
    case Check::NonNegative:
      return x >= 0 && x <= kMaxMagnitude;
    case Check::Length:
      return x >= 0;
    case Check::AtLeast1:
    case Check::Pixels:
      return x >= 1;
    case Check::Fov:
      return x > 0 && x < 180;
    case Check::Ior:
      return x > 0;
    case Check::Octaves:
      return x >= 1 && x <= pattern::kMaxOctaves;
  }
  return true;
}

std::string check_range(Check c, double x) {
  if (range_ok(c, x)) return {};
  switch (c) {
    case Check::Positive:
      return "must be > 0";
    case Check::Length:
      return "must be >= 0";
    case Check::NonNegative:
      return x < 0 ? "must be >= 0"
                   : "must be at most 1e30 (the renderer's colours and weights are single "
                     "precision)";
    case Check::AtLeast1:
    case Check::Pixels:
      return "must be >= 1";
    case Check::Fov:
      return "must be in (0, 180) degrees";
    case Check::Ior:
      return "must be > 0";
    case Check::Octaves:
      return "must be in 1.." + std::to_string(pattern::kMaxOctaves);
    default:
      return {};
  }
}

std::string range_words(Check c) {
  switch (c) {
    case Check::Positive:
      return " > 0";
    case Check::NonNegative:
    case Check::Length:
      return " >= 0";
    case Check::AtLeast1:
      return " >= 1";
    case Check::Pixels:
      return " >= 1, at most 268435456 pixels in all";
    case Check::Fov:
      return " in (0, 180)";
    case Check::Ior:
      return " > 0";
    case Check::NonZero:
      return ", not zero";
    case Check::Shutter:
      return " <open, close> with open <= close";
    case Check::Octaves:
      return " in 1.." + std::to_string(pattern::kMaxOctaves);
    case Check::Any:
      return "";
  }
  return "";
}

}  // namespace

const BlockInfo* find_block(std::string_view name) {
  for (const BlockInfo& b : registry().blocks)
    if (b.name == name) return &b;
  return nullptr;
}

const PropInfo* find_prop(const BlockInfo& block, std::string_view name) {
  for (const PropInfo* p : block.props)
    if (p->name == name) return p;
  for (const PropInfo* p : block.named)
    if (p->name == name) return p;
  if (block.is_object) return find_prop(object_block(), name);
  return nullptr;
}

std::vector<std::string_view> prop_names(const BlockInfo& block) {
  std::vector<std::string_view> out;
  for (const PropInfo* p : block.props) out.push_back(p->name);
  for (const PropInfo* p : block.named) out.push_back(p->name);
  if (block.is_object)
    for (const PropInfo* p : object_block().props) out.push_back(p->name);
  return out;
}

std::vector<std::string_view> block_names(BlockKind kind) {
  std::vector<std::string_view> out;
  for (const BlockInfo& b : registry().blocks)
    if (b.kind == kind) out.push_back(b.name);
  return out;
}

bool is_enum(PropType t) {
  switch (t) {
#define SNELL_ENUM(Type, VALUES) case PropType::Type:
#include "runtime/ir/kinds.def"
    return true;
    default:
      return false;
  }
}

std::string describe(const PropInfo& p) {
  std::string r = range_words(p.check);
  switch (p.type) {
    case PropType::Number:
      return "a number" + r;
    case PropType::Integer:
      return "an integer" + r;
    case PropType::Vec2:
      return "a 2-vector" + r;
    case PropType::IntVec2:
      return "a 2-vector of integers" + r;
    case PropType::Vec3:
      return "a 3-vector (or a number for all components)" + r;
    case PropType::Bool:
      return "true or false";
    case PropType::String:
      return "a string";
#define SNELL_ENUM(Type, VALUES) \
  case PropType::Type:           \
    return ir::spellings_text<ir::Type>();
#include "runtime/ir/kinds.def"
    case PropType::Material:
      return "a material (diffuse, mirror, glossy, dielectric, glazed)";
    case PropType::Color:
      return "a colour (a 3-vector or a number)" + r;
    case PropType::ColorOrPattern:
      return "a colour (a 3-vector or a number) or a pattern" + r;
    case PropType::Translate:
    case PropType::Rotate:
      return "a 3-vector (or a number for all components)";
    case PropType::Scale:
      return "a number or a 3-vector, with no zero component";
    case PropType::Block:
      return "a block { ... }";
    case PropType::Pattern:
      return "a pattern (checker { ... }, gradient { ... }, ...)";
    case PropType::Function:
      return "a function (the name of an fn)";
    case PropType::Pair: {
      std::string parts;
      if (const BlockInfo* b = find_block(p.name))
        for (const PropInfo* q : b->props)
          parts += (parts.empty() ? "" : ", ") + std::string(q->name);
      return "a pair <" + parts + ">";
    }
  }
  return "?";
}

// "'sampler' takes "independent", "stratified" or "sobol", not "sobel"; did you
// mean "sobol"?": a string setting's refusal, with its near miss where it has one.
static std::string enum_refused(const PropInfo& p, const std::string& got,
                                std::span<const std::string_view> spellings) {
  std::string msg = "'" + std::string(p.name) + "' takes " + describe(p) + ", not \"" + got + "\"";
  const std::string guess =
      lang::closest_match(got, std::vector<std::string_view>(spellings.begin(), spellings.end()));
  if (!guess.empty()) msg += "; did you mean \"" + guess + "\"?";
  return msg;
}

std::string check_value(const PropInfo& p, Value& v, bool* integral) {
  if (integral) *integral = false;
  auto wrong = [&]() {
    return "'" + std::string(p.name) + "' takes " + describe(p) + ", not " + a_type(v.type);
  };
  auto check_components = [&](int dims) -> std::string {
    for (int i = 0; i < dims; ++i) {
      std::string e = check_range(p.check, v.v[i]);
      if (!e.empty()) return "'" + std::string(p.name) + "' " + e + " in every component";
    }
    return {};
  };
  switch (p.type) {
    case PropType::Number:
    case PropType::Integer: {
      if (v.type != Type::Number) return wrong();
      if (p.type == PropType::Integer && !is_integer(v.n)) {
        if (integral) *integral = true;
        return "'" + std::string(p.name) + "' must be an integer, not " + to_string(v);
      }
      if (p.type == PropType::Integer && std::fabs(v.n) > 4294967295.0)
        return "'" + std::string(p.name) + "' must be at most 4294967295, not " + to_string(v);
      std::string e = check_range(p.check, v.n);
      return e.empty() ? "" : "'" + std::string(p.name) + "' " + e;
    }
    case PropType::Vec2:
    case PropType::IntVec2: {
      if (v.type == Type::Number) v = Value::vec2(v.n, v.n);
      if (v.type != Type::Vec2) return wrong();
      if (p.type == PropType::IntVec2) {
        if (!is_integer(v.v.x) || !is_integer(v.v.y)) {
          if (integral) *integral = true;
          return "'" + std::string(p.name) + "' must have integer components, not " + to_string(v);
        }
        if (std::fabs(v.v.x) > 1e9 || std::fabs(v.v.y) > 1e9)
          return "'" + std::string(p.name) + "' must have components of at most 1e9, not " +
                 to_string(v);
      }
      if (p.check == Check::Shutter && !(v.v.x <= v.v.y)) return "'shutter' needs open <= close";
      if (std::string e = check_components(2); !e.empty()) return e;
      if (p.check == Check::Pixels && v.v.x * v.v.y > kMaxPixels)
        return fmt::format(
            "'{}' is at most 268435456 pixels in all (e.g. 16384x16384), not {}x{} = {} pixels",
            p.name, v.v.x, v.v.y, v.v.x * v.v.y);
      return {};
    }
    case PropType::Vec3:
    case PropType::Color:
    case PropType::Translate:
    case PropType::Rotate: {
      if (v.type == Type::Number) v = Value::vec3(ir::Vec3(v.n));
      if (v.type != Type::Vec3) return wrong();
      if (p.check == Check::NonZero && v.v == ir::Vec3{})
        return "'" + std::string(p.name) + "' must not be the zero vector";
      return check_components(3);
    }
    case PropType::Scale: {
      if (v.type == Type::Number) v = Value::vec3(ir::Vec3(v.n));
      if (v.type != Type::Vec3) return wrong();
      if (v.v.x == 0 || v.v.y == 0 || v.v.z == 0)
        return "'scale' must not have a zero component (the object would vanish)";
      return {};
    }
    case PropType::ColorOrPattern: {
      if (v.type == Type::Pattern) return {};
      if (v.type == Type::Number) v = Value::vec3(ir::Vec3(v.n));
      if (v.type != Type::Vec3) return wrong();
      return check_components(3);
    }
    case PropType::Bool:
      return v.type == Type::Bool ? "" : wrong();
    case PropType::String:
      return v.type == Type::String ? "" : wrong();
#define SNELL_ENUM(Enum, VALUES)                                                                 \
  case PropType::Enum: {                                                                         \
    ir::Enum e;                                                                                  \
    if (v.type != Type::String) return wrong();                                                  \
    if (!ir::parse_enum(v.str(), e)) return enum_refused(p, v.str(), ir::spellings<ir::Enum>()); \
    return {};                                                                                   \
  }
#include "runtime/ir/kinds.def"
    case PropType::Material:
      return v.type == Type::Material ? "" : wrong();
    case PropType::Pattern:
      return v.type == Type::Pattern ? "" : wrong();
    case PropType::Function:
      return v.type == Type::Function ? "" : wrong();
    case PropType::Block:
      return wrong();  // blocks are written `motion { ... }`
    case PropType::Pair:
      return wrong();  // taken apart by the evaluator (eval_pair)
  }
  return {};
}

bool value_ok(const PropInfo& p, Value& v) {
  auto components_ok = [&](const ir::Vec3& c, int dims) {
    for (int i = 0; i < dims; ++i)
      if (!range_ok(p.check, c[i])) return false;
    return true;
  };
  switch (p.type) {
    case PropType::Number:
      return v.type == Type::Number && range_ok(p.check, v.n);
    case PropType::Vec3:
    case PropType::Color:
    case PropType::Translate:
    case PropType::Rotate:
    case PropType::ColorOrPattern: {
      if (p.type == PropType::ColorOrPattern && v.type == Type::Pattern) return true;
      ir::Vec3 c;
      if (v.type == Type::Number)
        c = ir::Vec3(v.n);
      else if (v.type == Type::Vec3)
        c = v.v;
      else
        return false;
      if (p.check == Check::NonZero && p.type != PropType::ColorOrPattern && c == ir::Vec3{})
        return false;
      if (!components_ok(c, 3)) return false;
      if (v.type == Type::Number) v = Value::vec3(c);
      return true;
    }
    case PropType::Material:
      return v.type == Type::Material;
    case PropType::Bool:
      return v.type == Type::Bool;
    default: {  // the rarer kinds: decide through the full check on a copy
      Value copy = v;
      if (!check_value(p, copy).empty()) return false;
      v = std::move(copy);
      return true;
    }
  }
}

}  // namespace snell::compile
