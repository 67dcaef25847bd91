// Property tables of every block (from properties.def) and the checks that turn
// an evaluated Value into what the block accepts (promotion, integers, ranges).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "compiler/value.hpp"
#include "runtime/ir/ir.hpp"

namespace snell::compile {

enum class BlockKind { Item, Constructor, Nested };

enum class PropType {
  Number,
  Integer,
  Vec2,
  IntVec2,
  Vec3,
  Bool,
  String,
// One type per settings enum of runtime/ir/kinds.def (SamplerKind, FresnelMode,
// ...): a string spelling one of its values.
#define SNELL_ENUM(Type, VALUES) Type,
#include "runtime/ir/kinds.def"
  Material,
  Color,
  ColorOrPattern,
  Translate,
  Rotate,
  Scale,
  Block,
  Pattern,   // a pattern value (§15: bump's)
  Function,  // a function value (§15: a shading function)
  // `NAME <a, b>`: two parts, checked as the properties of the Nested block NAME
  // (EvaluatedProp::nested holds them; §15 `stop <at, C>`, §16 `bump <P, A>`).
  Pair,
};

// Pixels: every component >= 1 and at most kMaxPixels in all (the image's
// float RGB film must fit in memory: 2^28 pixels is 3 GiB).
// The largest value a NonNegative property (colours, intensities, radiance, absorb,
// blur, aperture, min_weight) may take: the runtime's radiometric limit (the
// renderer works in float, 3.4e38; 1e30 leaves room for sums over lights and samples).
inline constexpr double kMaxMagnitude = ir::kMaxRadiometric;
// Length: >= 0 with no such limit (a cone's radii, a disc's hole): sizes are
// bounded by the scene's reach from the camera (ir::validate), not by radiometry.
enum class Check {
  Any,
  Positive,
  NonNegative,
  Length,
  AtLeast1,
  Fov,
  Ior,
  NonZero,
  Shutter,
  Pixels,
  Octaves
};
inline constexpr double kMaxPixels = 268435456.0;  // 2^28, e.g. 16384 x 16384

// Named: taken by name only, never a positional parameter (a constructor's
// positional form keeps the core's parameter list: `dielectric <ior, absorb>`).
// A Named property has no default and is not required.
inline constexpr unsigned Req = 1, Rep = 2, Obj = 4, Named = 8;

// The default column's `IR`: the default is the IR struct's own (the kind's
// struct in runtime/ir/shapes.hpp or materials.hpp, or ir::Settings), read when
// the registry is built, so every default is written once.
struct FromIR {};
inline constexpr FromIR IR{};

struct PropInfo {
  std::string_view block;
  std::string_view name;
  PropType type;
  Check check;
  unsigned flags;
  Value default_value;
  std::int32_t id = -1;          // position in the registry (prop_by_id); -1 for ad-hoc entries
  bool default_from_ir = false;  // the row said IR (default_value is filled from it)
  bool required() const { return flags & Req; }
  bool repeats() const { return flags & Rep; }
  bool named_only() const { return flags & Named; }
};

struct BlockInfo {
  std::string_view name;
  BlockKind kind;
  std::vector<const PropInfo*> props;  // own properties but the Named ones, in table order
  bool is_object = false;              // also takes the `object` properties
  // The IR kind the block makes (runtime/ir/kinds.def, matched by name when the
  // registry is built): an index of ir::ShapeGeom, ir::MaterialModel or
  // ir::PatternVariant, or -1.
  int shape_kind = -1, material_kind = -1, pattern_kind = -1;
  int csg_op = -1;                       // a CSG block (§12): its ir::CsgOp, matched by spelling
  std::vector<const PropInfo*> named{};  // own properties taken by name only (flag Named)
};

// True for the settings enums' property types.
bool is_enum(PropType t);

const BlockInfo* find_block(std::string_view name);
const PropInfo* find_prop(const BlockInfo& block, std::string_view name);
// Every property's id (its PropInfo::id), named BLOCK_NAME: sphere_center,
// object_material, ... Code that reads evaluated properties names them this way,
// so a misspelt name is a compile error and a lookup is an integer compare.
enum class PropId : std::int32_t {
#define SNELL_BLOCK(name, kind)
#define SNELL_PROP(block, name, type, check, flags, def) block##_##name,
#define SNELL_SETTING(name, type, check, def) settings_##name,
#include "compiler/properties.def"
  Count
};
inline constexpr int kPropCount = static_cast<int>(PropId::Count);
namespace detail {
extern const PropInfo* const* prop_index;  // set when the registry is built
}
// Only for ids taken from a PropInfo (so the registry exists).
inline const PropInfo& prop_by_id(std::int32_t id) {
  return *detail::prop_index[id];
}
// Every property name the block accepts (for "did you mean").
std::vector<std::string_view> prop_names(const BlockInfo& block);
// Every block name of a kind (for "did you mean").
std::vector<std::string_view> block_names(BlockKind kind);

// What a property accepts, in words: "an integer >= 1", "a colour or a pattern".
std::string describe(const PropInfo& prop);

// Converts `v` in place to the property's canonical type (a number becomes a
// vector where a vector is expected) and checks its range. Returns an error
// message naming what the property accepts, or an empty string.
// `integral` is set when the problem is a non-integral number (NotAnInteger).
std::string check_value(const PropInfo& prop, Value& v, bool* integral = nullptr);
// The same decision without building any text: true exactly when check_value would
// return "" (and then with the same conversion applied); false leaves `v` as it was,
// for check_value to explain. The per-item hot path of the evaluator.
bool value_ok(const PropInfo& prop, Value& v);

}  // namespace snell::compile
