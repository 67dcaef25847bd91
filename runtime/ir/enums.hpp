// The enums of the settings and the kind enums of shapes, materials and patterns,
// all generated from kinds.def: enumerators, spellings, parsing. Nothing here is
// written per enum by hand.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

namespace snell::ir {

// Spellings and name of each enum: EnumInfo<E>::spellings[i] spells enumerator i.
template <class E>
struct EnumInfo;

#define SNELL_ENUMERATOR(spelling, Enumerator) Enumerator,
#define SNELL_SPELLING(spelling, Enumerator) #spelling,
#define SNELL_ENUM(Type, VALUES)                                              \
  enum class Type : std::uint8_t { VALUES(SNELL_ENUMERATOR) };                \
  template <>                                                                 \
  struct EnumInfo<Type> {                                                     \
    static constexpr std::string_view name = #Type;                           \
    static constexpr std::string_view spellings[] = {VALUES(SNELL_SPELLING)}; \
  };
#include "runtime/ir/kinds.def"

// The kinds: ShapeKind::Sphere ... in kinds.def order, spelled as the language's
// block and constructor names.
#define SNELL_KIND_ENUMERATOR(name, Type) Type,
#define SNELL_KIND_SPELLING(name, Type) #name,
enum class ShapeKind : std::uint8_t {
#define SNELL_SHAPE SNELL_KIND_ENUMERATOR
#define SNELL_COMPOSITE SNELL_KIND_ENUMERATOR
#include "runtime/ir/kinds.def"
};
template <>
struct EnumInfo<ShapeKind> {
  static constexpr std::string_view name = "ShapeKind";
  static constexpr std::string_view spellings[] = {
#define SNELL_SHAPE SNELL_KIND_SPELLING
#define SNELL_COMPOSITE SNELL_KIND_SPELLING
#include "runtime/ir/kinds.def"
  };
};
enum class MaterialKind : std::uint8_t {
#define SNELL_MATERIAL SNELL_KIND_ENUMERATOR
#include "runtime/ir/kinds.def"
};
template <>
struct EnumInfo<MaterialKind> {
  static constexpr std::string_view name = "MaterialKind";
  static constexpr std::string_view spellings[] = {
#define SNELL_MATERIAL SNELL_KIND_SPELLING
#include "runtime/ir/kinds.def"
  };
};
enum class PatternKind : std::uint8_t {
#define SNELL_PATTERN SNELL_KIND_ENUMERATOR
#include "runtime/ir/kinds.def"
};
template <>
struct EnumInfo<PatternKind> {
  static constexpr std::string_view name = "PatternKind";
  static constexpr std::string_view spellings[] = {
#define SNELL_PATTERN SNELL_KIND_SPELLING
#include "runtime/ir/kinds.def"
  };
};
#undef SNELL_KIND_ENUMERATOR
#undef SNELL_KIND_SPELLING
#undef SNELL_ENUMERATOR
#undef SNELL_SPELLING

template <class E>
constexpr std::span<const std::string_view> spellings() {
  return EnumInfo<E>::spellings;
}
template <class E>
constexpr std::string_view spelling(E e) {
  auto s = spellings<E>();
  return std::size_t(e) < s.size() ? s[std::size_t(e)] : std::string_view("?");
}
// The enumerator spelled `s`; false when none is.
template <class E>
constexpr bool parse_enum(std::string_view s, E& out) {
  auto all = spellings<E>();
  for (std::size_t i = 0; i < all.size(); ++i)
    if (all[i] == s) {
      out = E(i);
      return true;
    }
  return false;
}
// "\"a\", \"b\" or \"c\"": the spellings as a user reads them in an error.
template <class E>
std::string spellings_text() {
  std::string s;
  auto all = spellings<E>();
  for (std::size_t i = 0; i < all.size(); ++i) {
    if (i) s += i + 1 == all.size() ? " or " : ", ";
    s += "\"" + std::string(all[i]) + "\"";
  }
  return s;
}

inline std::string to_string(SamplerKind v) {
  return std::string(spelling(v));
}
inline std::string to_string(FresnelMode v) {
  return std::string(spelling(v));
}
inline std::string to_string(Branching v) {
  return std::string(spelling(v));
}
inline std::string to_string(Termination v) {
  return std::string(spelling(v));
}
inline std::string to_string(LightSampling v) {
  return std::string(spelling(v));
}
inline std::string to_string(GlossySampling v) {
  return std::string(spelling(v));
}
inline std::string to_string(IntegratorKind v) {
  return std::string(spelling(v));
}
inline std::string to_string(ShapeKind v) {
  return std::string(spelling(v));
}
inline std::string to_string(MaterialKind v) {
  return std::string(spelling(v));
}
inline std::string to_string(PatternKind v) {
  return std::string(spelling(v));
}

}  // namespace snell::ir
