// How language values and IR fields meet: a field's default as a Value (the
// registry's IR defaults) and a checked Value stored into a field (lowering).
// One overload per field type; kinds and settings bind by field name
// (properties.def), so a new kind or setting needs no code here.
#pragma once

#include <cstdint>
#include <string>
#include <type_traits>

#include "compiler/value.hpp"
#include "runtime/ir/ir.hpp"

namespace snell::compile {

inline Value to_value(double v) {
  return Value::number(v);
}
inline Value to_value(std::uint32_t v) {
  return Value::number(v);
}
inline Value to_value(std::uint64_t v) {
  return Value::number(double(v));
}
inline Value to_value(bool v) {
  return Value::boolean(v);
}
inline Value to_value(ir::Vec3 v) {
  return Value::vec3(v);
}
inline Value to_value(const ir::Texture& t) {
  if (const auto* c = std::get_if<ir::Constant>(&t.pattern)) return Value::vec3(c->color);
  return Value::of_pattern(t);
}
template <class E>
requires std::is_enum_v<E> Value to_value(E e) {
  return Value::string(std::string(ir::spelling(e)));
}

// `v` has passed the property's check_value (its type and range are right).
inline void assign(double& f, const Value& v) {
  f = v.n;
}
inline void assign(std::uint32_t& f, const Value& v) {
  f = static_cast<std::uint32_t>(v.n);
}
inline void assign(std::uint64_t& f, const Value& v) {
  f = static_cast<std::uint64_t>(v.n);
}
inline void assign(bool& f, const Value& v) {
  f = v.truth();
}
inline void assign(ir::Vec3& f, const Value& v) {
  f = v.v;
}
inline void assign(ir::Texture& f, const Value& v) {
  f = v.type == Type::Pattern ? v.pat() : ir::Texture(v.v);
}
template <class E>
requires std::is_enum_v<E>
void assign(E& f, const Value& v) {
  ir::parse_enum(v.str(), f);
}

}  // namespace snell::compile
