// The abstract syntax tree of a .scn file. Plain data: the parser builds it, the
// compiler's evaluator walks it, ast_dump prints it. Every node carries the span of
// the source text it came from.
//
// The parser is generic about scene items: `sphere { ... }` is a BlockStmt with
// kind "sphere" and a list of properties; whether "sphere" names a scene item and
// which properties it takes is the compiler's business (so misspellings get "did
// you mean" notes from the property tables, not parse errors).
#pragma once

#include <algorithm>
#include <cstdint>
#include <memory>
#include <new>
#include <string>
#include <vector>

#include "language/source.hpp"
#include "language/token.hpp"

namespace snell::lang {

struct Expr;
struct Stmt;
struct Block;

// Destroys an Expr (its text, children and block) but leaves its memory to the
// ExprArena it came from.
struct ExprDelete {
  void operator()(Expr* e) const noexcept;
};
using ExprPtr = std::unique_ptr<Expr, ExprDelete>;
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
// A CSG block's body (§12) also holds statements, in order; an instance's
// (`object { EXPR ... }`, §13) starts with the expression it places.
struct Block {
  Span span;  // from '{' to '}'
  std::vector<Property> properties;
  std::vector<StmtPtr> statements;  // CSG blocks
  ExprPtr subject;                  // `object { EXPR ... }`
  // Comma-separated values before the first property, POV-Ray's habit
  // (`cylinder { <0,0,0>, <0,1,0>, 0.5 }`): kept so the compiler can show the named
  // form with these values; the language has no positional blocks (§5).
  std::vector<ExprPtr> positional;
  // A syntax error inside the body (a value where a property name belongs): the
  // properties it made unreadable are not reported missing too (§10: independent
  // errors only; `box { 3 }` is the parse error alone).
  bool broken = false;
};

enum class ExprKind : std::uint8_t {
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
  Object,       // text: an object block's keyword (sphere, union, object, ...); block:
                //       its body (§13: an object value)
  Error,        // placeholder after a syntax error; the compiler skips it silently
};

// The children of an Expr: an array allocated once with its exact length. Lists
// never change after parsing, and Expr is the commonest node (millions in a big
// scene), so this is 16 bytes in the node where a vector took 24, with no spare
// capacity behind it.
class ExprList {
 public:
  ExprList() = default;
  ExprList(ExprList&&) noexcept = default;
  ExprList& operator=(ExprList&&) noexcept = default;
  // Moves the elements of [first, last) in.
  template <typename It>
  ExprList(It first, It last) : size_(static_cast<std::uint32_t>(last - first)) {
    if (size_ == 0) return;
    items_ = std::make_unique<ExprPtr[]>(size_);
    for (std::uint32_t i = 0; i < size_; ++i, ++first) items_[i] = std::move(*first);
  }
  static ExprList of(ExprPtr a) { return ExprList(&a, &a + 1); }
  static ExprList of(ExprPtr a, ExprPtr b) {
    ExprPtr two[2] = {std::move(a), std::move(b)};
    return ExprList(two, two + 2);
  }

  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  ExprPtr& operator[](std::size_t i) { return items_[i]; }
  const ExprPtr& operator[](std::size_t i) const { return items_[i]; }
  ExprPtr* begin() { return items_.get(); }
  ExprPtr* end() { return items_.get() + size_; }
  const ExprPtr* begin() const { return items_.get(); }
  const ExprPtr* end() const { return items_.get() + size_; }

 private:
  std::unique_ptr<ExprPtr[]> items_;
  std::uint32_t size_ = 0;
};

// Fields are ordered so the small ones share one word (sizeof 88: a 96-byte heap
// block where the first layout took 128).
struct Expr {
  ExprKind kind = ExprKind::Error;
  TokenKind op = TokenKind::Error;
  bool boolean = false;
  // Set by the compiler once this node's numeric fast path has failed (a cache: it
  // then always takes the general path; see Evaluator::eval_number).
  mutable bool not_numeric = false;
  mutable std::int32_t symbol = -1;  // Name: the compiler's interned id (a cache)
  Span span;
  // The compiler's compiled form of this numeric expression (a cache; -1 none yet,
  // -2 part of an enclosing one; see compiler/evaluator_number.cpp).
  mutable std::int32_t code = -1;
  double number = 0;
  std::string text;
  ExprList args;
  BlockPtr block;
};

// Storage for a Program's Expr nodes, in chunks that die with the Program rather
// than one heap block per node: a 50 MB scene has about five million of them,
// and handing them back to malloc one by one took over a second. Destroying an
// ExprPtr still runs ~Expr, so a node's own lists and text are freed as before.
class ExprArena {
 public:
  ExprArena() = default;
  ExprArena(const ExprArena&) = delete;
  ExprArena& operator=(const ExprArena&) = delete;
  ExprPtr make() {
    if (next_ == end_) grow();
    return ExprPtr(new (next_++) Expr());
  }

 private:
  struct alignas(Expr) Slot {
    unsigned char bytes[sizeof(Expr)];
  };
  void grow() {
    // 256 nodes at first (small files stay small), doubling up to 16384 (1.4 MiB).
    std::size_t n = chunks_.empty() ? 256 : std::min<std::size_t>(16384, 2 * last_size_);
    chunks_.push_back(std::make_unique_for_overwrite<Slot[]>(n));
    next_ = chunks_.back().get();
    end_ = next_ + n;
    last_size_ = n;
  }
  std::vector<std::unique_ptr<Slot[]>> chunks_;
  Slot* next_ = nullptr;
  Slot* end_ = nullptr;
  std::size_t last_size_ = 0;
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

inline void ExprDelete::operator()(Expr* e) const noexcept {
  e->~Expr();
}

struct Program {
  FileId file = 0;
  std::vector<StmtPtr> statements;
  // The parsed file, set by parse(): dump_ast prints line:col from it. Owned by the
  // SourceManager, which outlives every Program parsed from it.
  const SourceFile* source = nullptr;
  // Every name in a statement a syntax error broke (from its start to where the
  // parser picked up again): one of them found undefined is not reported, since
  // the broken statement may be what defined it (§10: independent errors only).
  std::vector<std::string> unsure_names;
  // Where the Expr nodes live. Declared after `statements` so that a move
  // assignment replaces the old nodes before their arena; the destructor clears
  // `statements` first for the same reason.
  std::unique_ptr<ExprArena> arena;

  Program() = default;
  Program(Program&&) noexcept = default;
  Program& operator=(Program&&) noexcept = default;
  ~Program() { statements.clear(); }
};

// The names the parser treats as constructors in operand position (see parser.hpp).
bool is_constructor_name(std::string_view name);
// A constructor written only as `NAME { ... }` (constructors.def).
bool is_block_only_constructor(std::string_view name);
// Every constructor name (constructors.def), for "did you mean" notes.
std::vector<std::string_view> constructor_names();
// groups.def: CSG blocks, the instance block, the object properties, and the
// statement blocks.
bool is_group_name(std::string_view name);
bool is_instance_name(std::string_view name);
bool is_object_property(std::string_view name);
bool is_item_name(std::string_view name);

// A stable, indented, human-readable dump; tests/lang compares against it.
std::string dump_ast(const Program& program);

}  // namespace snell::lang
