// §15 shading functions: a user `fn` named by `pattern { function f }` compiled to
// an ir::Program (runtime/ir/program.hpp) that the renderer interprets at each hit.
//
// What is accepted: a function of the point (one parameter, a 3-vector) or of the
// point and the normal (two), in either form (`fn f(p) = EXPR;` or a block with
// `return`). Its body may use numbers, bools and vectors; `let`; `if`/`else`
// (a condition on run-time values computes both arms and selects, one on constants
// keeps only the branch taken); `for` loops whose bounds are constants (unrolled,
// at most kMaxUnroll iterations in all); nested `fn`s; calls of other user
// functions (inlined, recursive ones too: a recursion on constants folds away, one
// on run-time values unrolls, and must end on constants within kMaxInlineDepth
// calls); a tail recursion on run-time values (`return f(...)` its only
// self-call) runs as a loop instead (shading_loops.cpp); every builtin of §3 and
// §15. Captured names of the defining scope
// are constants. Everything computable from constants is folded with the
// evaluator's own arithmetic and builtins (so a folded error, such as a
// non-finite value, is reported as the evaluator would); what the result does not
// depend on is dropped, and the program records whether it reads the normal.
//
// Errors: ImpureShadingFunction at a scene item, object or background the
// function would make; UnsupportedInShadingFunction at a string, material,
// pattern, import, loop with run-time bounds, recursion that is not a tail call
// and does not end on constants within kMaxInlineDepth calls, a loop whose
// parameters change type or that never returns, or a function too big for the
// program's limits; the usual kinds (TypeMismatch,
// WrongArgumentCount, ...) for type errors; InvalidValue for other arities and a
// result that is not a number. Each has a note at the use.
#pragma once

#include <memory>
#include <string>

#include "compiler/evaluator.hpp"
#include "compiler/value.hpp"
#include "language/source.hpp"
#include "runtime/ir/program.hpp"

namespace snell::compile {

inline constexpr int kMaxUnroll = 4096;            // loop iterations unrolled per function
inline constexpr int kMaxInlineDepth = 256;        // nested inlined calls
inline constexpr int kMaxCompileWork = 1'000'000;  // expressions compiled per function

// Compiles `fn` (a Function value: the evaluated `function` property) into `out`.
// `fn_span` is the property's value, `use_span` the `pattern` block (notes point
// there). False after reporting errors through the evaluator's diagnostics.
bool compile_shading_function(Evaluator& ev, const Value& fn, lang::Span fn_span,
                              lang::Span use_span, ir::Program& out);

// The value bound to `name` in `env` or a scope around it, or null (for tests and
// tools that pick a function out of a file's top-level scope).
const Value* find_value(Evaluator& ev, const Env& env, const std::string& name);

// The operation(s) the compiler uses for builtin `id` (builtins.def) on a scalar
// and on a vector: for tests that every builtin has a native op.
struct BuiltinOps {
  ir::ProgramOp scalar, vector;
  bool found = false;
};
BuiltinOps builtin_ops(int id);

}  // namespace snell::compile
