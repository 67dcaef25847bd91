// The abstract syntax tree of a .scn file. Plain data: the parser builds it, the
// compiler's evaluator walks it, ast_dump prints it. Every node carries the span of
// the source text it came from.
//
// The parser is generic about scene items: `sphere { ... }` is a BlockStmt with
// kind "sphere" and a list of properties; whether "sphere" names a scene item and
// which properties it takes is the compiler's business (so misspellings get "did
// you mean" notes from the property tables, not parse errors).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "language/source.hpp"
#include "language/token.hpp"

namespace snell::lang {

struct Expr;
struct Stmt;
struct Block;
using ExprPtr = std::unique_ptr<Expr>;
using StmtPtr = std::unique_ptr<Stmt>;
using BlockPtr = std::unique_ptr<Block>;

// One `name value` pair of a block. Exactly one of value / block is set:
// `radius 1` has a value; `motion { translate <1,0,0> }` has a nested block.
struct Property {
  std::string name;
  Span name_span;
  ExprPtr value;
  BlockPtr block;
  mutable std::int32_t prop = -1;  // the compiler's property id once resolved (a cache)
};

// `{ name value name value ... }`, the body of a scene item, of a named material
// constructor (`dielectric { ior 1.5 }`), of `checker { ... }` or of `motion { ... }`.
struct Block {
  Span span;  // from '{' to '}'
  std::vector<Property> properties;
};

enum class ExprKind {
  Number,       // number
  Bool,         // boolean
  String,       // text
  Name,         // text: a reference to a variable or function
  Vector,       // args: 2 or 3 components (the parser accepts any count >= 1; the
                //       compiler rejects other than 2 or 3 with BadVectorArity)
  Unary,        // op (Minus or Bang), args[0]
  Binary,       // op, args[0] lhs, args[1] rhs
  Call,         // args[0] callee, args[1..] arguments
  Component,    // text "x", "y" or "z"; args[0] the vector
  Constructor,  // text: constructor name (diffuse, mirror, glossy, dielectric, glazed,
                //       checker); positional form: args[0]; named form: block
  Error,        // placeholder after a syntax error; the compiler skips it silently
};

struct Expr {
  ExprKind kind = ExprKind::Error;
  Span span;
  double number = 0;
  bool boolean = false;
  std::string text;
  TokenKind op = TokenKind::Error;
  std::vector<ExprPtr> args;
  BlockPtr block;
  mutable std::int32_t symbol = -1;  // Name: the compiler's interned id (a cache)
  // Set by the compiler once this node's numeric fast path has failed (a cache: it
  // then always takes the general path; see Evaluator::eval_number).
  mutable bool not_numeric = false;
};

enum class StmtKind {
  Let,         // name, exprs[0] value
  Fn,          // name, params; expression form: exprs[0]; block form: body
  Return,      // exprs[0]
  For,         // name (the loop variable), exprs[0] from, exprs[1] to, exprs[2] step
               // (absent when not written), body
  If,          // exprs[i] the condition of branch i, branches[i] its body; else_body
               // set when there is a final `else { }` (has_else)
  Import,      // name: the path string as written
  ExprStmt,    // exprs[0], a call used as a statement
  Item,        // name: block keyword (sphere, camera, settings, ...); block
  Background,  // exprs[0]
  Error,       // placeholder after a syntax error
};

struct Stmt {
  StmtKind kind = StmtKind::Error;
  Span span;
  std::string name;
  Span name_span;
  std::vector<std::string> params;
  std::vector<Span> param_spans;
  std::vector<ExprPtr> exprs;
  std::vector<StmtPtr> body;
  std::vector<std::vector<StmtPtr>> branches;
  std::vector<StmtPtr> else_body;
  bool has_else = false;
  BlockPtr block;
  mutable std::int32_t symbol = -1;  // Let/Fn/For: the compiler's interned id (a cache)
};

struct Program {
  FileId file = 0;
  std::vector<StmtPtr> statements;
  // The parsed file, set by parse(): dump_ast prints line:col from it. Owned by the
  // SourceManager, which outlives every Program parsed from it.
  const SourceFile* source = nullptr;
};

// The names the parser treats as constructors in operand position (see parser.hpp).
bool is_constructor_name(std::string_view name);

// A stable, indented, human-readable dump; tests/lang compares against it.
std::string dump_ast(const Program& program);

}  // namespace snell::lang
