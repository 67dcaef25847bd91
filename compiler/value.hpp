// Run-time values of the .scn interpreter (§3): number, bool, string, 2- and
// 3-vectors, material, pattern, function. `Error` is a poison value: an operation
// on it yields Error without a new diagnostic, so one mistake reports once.
#pragma once

#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "runtime/ir/ir.hpp"

namespace snell::lang {
struct Stmt;
}

namespace snell::compile {

enum class Type : std::uint8_t {
  None,
  Error,
  Number,
  Bool,
  String,
  Vec2,
  Vec3,
  Material,
  Pattern,
  Function,
  Object  // §13: an object block written as a value
};

std::string_view type_name(Type t);
// The type with its article, as a message says it: "a number", "an object", "nothing".
std::string a_type(Type t);

struct Env;
struct ObjectNode;  // object_value.hpp

// A string value's text, counted while it lives: the bytes of every string value
// alive in the process (live_string_bytes), which concatenation keeps below a
// cap, so a recursion holding long strings in each frame stops with an error
// instead of taking the machine's memory.
struct LiveString {
  std::string text;
  explicit LiveString(std::string t);
  ~LiveString();
  LiveString(const LiveString&) = delete;
  LiveString& operator=(const LiveString&) = delete;
};
std::int64_t live_string_bytes();

// A user function (closure over its defining scope) or a builtin.
struct Closure {
  const lang::Stmt* def = nullptr;   // the `fn` statement; null for builtins
  std::shared_ptr<Env> env;          // the scope it was defined in
  int builtin = -1;                  // index into the builtin table
  std::vector<std::int32_t> params;  // interned parameter names
  std::string name;
};

struct Value {
  Type type = Type::None;
  double n = 0;  // Number; Bool as 0/1
  ir::Vec3 v;    // Vec2 uses x, y (z is 0)
  // String, Material, Pattern, Function: one shared payload keeps Value small
  // (it is copied on every variable read).
  std::shared_ptr<const void> obj;

  const std::string& str() const { return static_cast<const LiveString*>(obj.get())->text; }
  const ir::Material& mat() const { return *static_cast<const ir::Material*>(obj.get()); }
  const ir::Texture& pat() const { return *static_cast<const ir::Texture*>(obj.get()); }
  const Closure& func() const { return *static_cast<const Closure*>(obj.get()); }
  std::shared_ptr<const ObjectNode> object() const {
    return std::static_pointer_cast<const ObjectNode>(obj);
  }

  static Value none() { return {}; }
  static Value error() {
    Value r;
    r.type = Type::Error;
    return r;
  }
  static Value number(double x) {
    Value r;
    r.type = Type::Number;
    r.n = x;
    return r;
  }
  static Value boolean(bool b) {
    Value r;
    r.type = Type::Bool;
    r.n = b ? 1 : 0;
    return r;
  }
  static Value vec2(double x, double y) {
    Value r;
    r.type = Type::Vec2;
    r.v = {x, y, 0};
    return r;
  }
  static Value vec3(ir::Vec3 v3) {
    Value r;
    r.type = Type::Vec3;
    r.v = v3;
    return r;
  }
  static Value string(std::string text) {
    Value r;
    r.type = Type::String;
    r.obj = std::make_shared<const LiveString>(std::move(text));
    return r;
  }
  static Value of_material(ir::Material m) {
    Value r;
    r.type = Type::Material;
    r.obj = std::make_shared<const ir::Material>(std::move(m));
    return r;
  }
  static Value of_pattern(ir::Texture t) {
    Value r;
    r.type = Type::Pattern;
    r.obj = std::make_shared<const ir::Texture>(t);
    return r;
  }
  static Value of_object(std::shared_ptr<const ObjectNode> node) {
    Value r;
    r.type = Type::Object;
    r.obj = std::move(node);
    return r;
  }
  static Value of_function(std::shared_ptr<const Closure> c) {
    Value r;
    r.type = Type::Function;
    r.obj = std::move(c);
    return r;
  }

  bool is_error() const { return type == Type::Error; }
  bool is_vector() const { return type == Type::Vec2 || type == Type::Vec3; }
  int dims() const { return type == Type::Vec2 ? 2 : type == Type::Vec3 ? 3 : 1; }
  bool truth() const { return n != 0; }
  // True when every numeric component is finite (non-numeric values: true).
  bool finite() const {
    switch (type) {
      case Type::Number:
        return std::isfinite(n);
      case Type::Vec2:
        return std::isfinite(v.x) && std::isfinite(v.y);
      case Type::Vec3:
        return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
      default:
        return true;
    }
  }
};

// Readable text of a value, as the language would write it (used in messages).
std::string to_string(const Value& v);

}  // namespace snell::compile
