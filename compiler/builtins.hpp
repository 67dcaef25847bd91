// Built-in functions of §3, from builtins.def.
#pragma once

#include <string>
#include <string_view>

#include "compiler/value.hpp"
#include "language/diagnostics.hpp"

namespace snell::compile {

struct BuiltinInfo {
  std::string_view name;
  int arity;
  std::string_view signature;
};

int find_builtin(std::string_view name);  // -1 when `name` is no builtin
const BuiltinInfo& builtin_info(int id);
int builtin_count();
// builtin_info(id).arity, inline for the evaluator's fast path.
namespace detail {
extern const unsigned char kBuiltinArity[];
}
inline std::size_t builtin_arity(int id) {
  return detail::kBuiltinArity[id];
}

struct BuiltinError {
  int arg = -1;  // the offending argument, or -1 for the call as a whole
  std::string message;
  lang::DiagKind kind = lang::DiagKind::TypeMismatch;  // NotAnInteger, InvalidValue: octaves
};

// Applies builtin `id` to `args` (arity already checked). On a type error returns
// Value::error() and fills `err`. Results may be non-finite; the caller checks.
Value call_builtin(int id, const Value* args, BuiltinError& err);

// The same call when every argument is a number (args[0..arity-1]; unused ones 0):
// true with the result (possibly non-finite) for builtins that take numbers and give
// a number; false for dot, cross, length, normalize and the noise functions.
bool call_builtin_number(int id, const double* args, double& out);
// True when call_builtin_number handles `id` (all but dot, cross, length, normalize
// and the noise functions, which take a vector).
bool builtin_numeric(int id);

// random(n): the IEEE-754 bits of n (−0 taken as +0) through the SplitMix64
// finaliser, top 53 bits scaled by 2^−53. Pure integer arithmetic: the same value
// on every machine and compiler.
double random_hash(double n);

// The octave count of fbm/turbulence: an integer in 1..pattern::kMaxOctaves; false
// with `err` filled (for argument `arg`) otherwise. The shading-function compiler
// checks constant octaves with it too.
bool octaves_ok(const Value& v, int arg, BuiltinError& err);

}  // namespace snell::compile
