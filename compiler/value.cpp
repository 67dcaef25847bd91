#include "compiler/value.hpp"

#include <atomic>
#include <charconv>
#include <cmath>

#include "compiler/object_value.hpp"

namespace snell::compile {

namespace {
std::atomic<std::int64_t> g_live_string_bytes{0};
}  // namespace

LiveString::LiveString(std::string t) : text(std::move(t)) {
  g_live_string_bytes.fetch_add(std::int64_t(text.size()), std::memory_order_relaxed);
}
LiveString::~LiveString() {
  g_live_string_bytes.fetch_sub(std::int64_t(text.size()), std::memory_order_relaxed);
}
std::int64_t live_string_bytes() {
  return g_live_string_bytes.load(std::memory_order_relaxed);
}

std::string_view type_name(Type t) {
  switch (t) {
    case Type::None:
      return "nothing";
    case Type::Error:
      return "error";
    case Type::Number:
      return "number";
    case Type::Bool:
      return "bool";
    case Type::String:
      return "string";
    case Type::Vec2:
      return "2-vector";
    case Type::Vec3:
      return "3-vector";
    case Type::Material:
      return "material";
    case Type::Pattern:
      return "pattern";
    case Type::Function:
      return "function";
    case Type::Object:
      return "object";
  }
  return "?";
}

std::string a_type(Type t) {
  if (t == Type::None) return "nothing";
  std::string_view n = type_name(t);
  return (n.front() == 'e' || n.front() == 'o' ? "an " : "a ") + std::string(n);
}

namespace {
std::string num(double x) {
  if (x == 0) return "0";
  char buf[32];
  auto r = std::to_chars(buf, buf + sizeof buf, x);
  return std::string(buf, r.ptr);
}
}  // namespace

std::string to_string(const Value& v) {
  switch (v.type) {
    case Type::None:
      return "nothing";
    case Type::Error:
      return "<error>";
    case Type::Number:
      return num(v.n);
    case Type::Bool:
      return v.n != 0 ? "true" : "false";
    case Type::String:
      return "\"" + v.str() + "\"";
    case Type::Vec2:
      return "<" + num(v.v.x) + ", " + num(v.v.y) + ">";
    case Type::Vec3:
      return "<" + num(v.v.x) + ", " + num(v.v.y) + ", " + num(v.v.z) + ">";
    case Type::Material:
      return ir::to_string(v.mat());
    case Type::Pattern:
      return ir::to_string(v.pat());
    case Type::Function:
      return "fn " + v.func().name;
    case Type::Object:
      return std::string(v.object()->keyword_name()) + " { ... }";
  }
  return "?";
}

}  // namespace snell::compile
