// The shading-function compiler's internals (§15), shared by its two halves:
// shading_function.cpp (expressions, calls, builtins) and shading_statements.cpp
// (statements, the function, code generation). The compiler is symbolic
// evaluation of a user function's body: every expression becomes either a
// constant Value (folded with the evaluator's arithmetic and builtins) or a node
// of a value graph over the inputs p and n; equal nodes are shared (a repeated
// subexpression is computed once), `if` on a run-time condition becomes a select,
// calls are inlined. Code generation then walks back from the result (what it
// does not reach is dropped) and gives each node a slot, reusing slots after
// their last use.
//
// A tail recursion on run-time values (a function that calls itself only as
// `return f(...)`, called with a run-time argument) is not inlined: its body is
// compiled by a compiler of its own into a loop body (ir::Program::loops) whose
// inputs are the parameters, and the call becomes a Loop node. In that body a
// `return f(args)` is an outcome that is not done and carries args as the next
// inputs; every outcome carries (done, value, next) and merges by selects.
#pragma once

#include <deque>
#include <optional>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "compiler/shading_function.hpp"

namespace snell::compile {
namespace shading {

using Op = ir::ProgramOp;

enum class BKind { Map, Dot, Cross, Length, Normalize, Random, Noise, Fbm, Turb, Cells };
struct BuiltinRow {
  std::string_view name;
  BKind kind;
  Op s, v;  // Map: the scalar and vector forms; others: the 3-vector and 2-vector forms
};
// The native op(s) of builtin `id` (builtins.def), or null.
const BuiltinRow* builtin_row(int id);

inline bool runtime_type(Type t) {
  return t == Type::Number || t == Type::Bool || t == Type::Vec2 || t == Type::Vec3;
}
inline bool is_vec(Type t) {
  return t == Type::Vec2 || t == Type::Vec3;
}

// Whether `def` (a block-bodied fn) calls itself, by its name, and only as
// `return NAME(...)` with no such call in the arguments (shading_loops.cpp). A
// recursion on run-time values of such a function runs as a loop.
bool tail_recursive(const lang::Stmt& def);

// A node of the value graph.
struct Node {
  enum Kind : std::uint8_t { Input, Const, Comp, Apply, Loop } kind;
  Node(Kind k, Type t) : kind(k), type(t) {}
  Type type;
  Op op = Op::AddS;
  int arg[3] = {-1, -1, -1};
  // Input: 0 the point, 1 the normal (a loop body's: its parameters); Comp: the
  // component; Loop: the loop (its body and arguments in the compiler's tables)
  int index = 0;
  Value value;  // Const
};

struct Scope;

// What an expression compiles to.
struct SVal {
  enum Kind : std::uint8_t { Error, None, Const, Graph, LocalFn } kind = None;
  SVal() = default;
  explicit SVal(Kind kd) : kind(kd) {}
  Value k;                          // Const: any value (functions too)
  int node = -1;                    // Graph
  Type type = Type::None;           // Const, Graph
  const lang::Stmt* def = nullptr;  // LocalFn: a `fn` inside the shading function
  Scope* scope = nullptr;           // LocalFn: where it was defined

  static SVal error() { return SVal(Error); }
  static SVal constant(Value v) {
    SVal s(Const);
    s.type = v.type;
    s.k = std::move(v);
    return s;
  }
  bool is_error() const { return kind == Error; }
  bool is_const() const { return kind == Const; }
};

// A scope of the function being compiled. A function body's scope has no parent
// but the defining Env (evaluator closures) or the scope of its `fn` (LocalFn).
struct Scope {
  Scope* parent = nullptr;
  std::shared_ptr<Env> env;
  std::vector<std::pair<std::int32_t, SVal>> vars;
};

// The effect of a statement list on the function's return: it returned `val` when
// `cond` (a bool: constant true, constant false = fell through, or a run-time bool).
// In a loop body, `done` (a bool) is false where the outcome is a tail call, whose
// arguments are `next` (one per parameter; None, or missing, where it does not
// matter, as `val` is None for a tail call).
struct Outcome {
  SVal cond = SVal::constant(Value::boolean(false));
  SVal val;
  lang::Span at;  // the return that gave val
  SVal done;
  std::vector<SVal> next;
};

inline bool const_false(const SVal& c) {
  return c.is_const() && c.k.type == Type::Bool && !c.k.truth();
}
inline bool const_true(const SVal& c) {
  return c.is_const() && c.k.type == Type::Bool && c.k.truth();
}

}  // namespace shading

class ShadingCompiler {
  using Node = shading::Node;
  using SVal = shading::SVal;
  using Scope = shading::Scope;
  using Outcome = shading::Outcome;
  using Op = ir::ProgramOp;
  using Span = lang::Span;
  using Expr = lang::Expr;
  using Stmt = lang::Stmt;
  using DiagKind = lang::DiagKind;

 public:
  ShadingCompiler(Evaluator& ev, Span use_span) : ev_(ev), use_(use_span) {}

  bool run(const Value& fn, Span fn_span, ir::Program& out);
  static std::int32_t intern(Evaluator& ev, const std::string& name) { return ev.intern(name); }

 private:
  // ---- diagnostics
  // Reports an error; its own notes follow, then (at the next error or at the end)
  // the calls it was inlined through and the use.
  lang::DiagBuilder& error(DiagKind kind, Span at, std::string msg) {
    flush();
    failed_ = true;
    pending_.emplace(ev_.error(kind, at, std::move(msg)));
    context_.clear();
    Span last = at;
    for (std::size_t i = calls_.size(); i-- > 1 && context_.size() < 4;) {
      const Span& cs = calls_[i].span;
      if (cs.file == last.file && cs.begin == last.begin && cs.end == last.end)
        continue;  // a recursion: one note for its calls
      last = calls_[i].span;
      context_.push_back({calls_[i].span, "in the call of '" + calls_[i].name + "' here"});
    }
    return *pending_;
  }

 public:
  void flush() {
    if (!pending_) return;
    for (auto& [span, text] : context_) pending_->note(span, text);
    pending_->note(use_, "in the shading function used here");
    pending_.reset();
  }

 private:
  // `of_type`: the value's type is what is wrong (a string, a material, a pattern),
  // so the note says which types there are; other limits (recursion, unrolling,
  // mixed return types) are said by the message alone.
  SVal unsupported(Span at, const std::string& msg, bool of_type = false) {
    auto& d = error(DiagKind::UnsupportedInShadingFunction, at, msg);
    if (of_type) d.note("a shading function computes with numbers, bools and vectors only");
    return SVal::error();
  }
  SVal impure(Span at, const std::string& what) {
    error(DiagKind::ImpureShadingFunction, at,
          "a shading function must not create scene items, and this " + what + " would");
    return SVal::error();
  }
  // An object value creates nothing by itself (§13), but has no place in a
  // function that computes numbers: said so, under the same kind.
  SVal object_value(Span at, const std::string& what) {
    error(DiagKind::ImpureShadingFunction, at,
          what +
              " is an object value; a shading function works on numbers, bools and "
              "vectors and places no objects");
    return SVal::error();
  }
  bool work(Span at) {
    if (++work_ <= kMaxCompileWork) return true;
    if (work_ == kMaxCompileWork + 1)
      unsupported(at, "this shading function takes more than " + std::to_string(kMaxCompileWork) +
                          " steps to compile (recursion or loops unrolled too far?)");
    return false;
  }

  // ---- the graph
  int add(Node n) {
    std::string key(reinterpret_cast<const char*>(&n.kind), 1);
    key += static_cast<char>(n.type);
    key += static_cast<char>(n.op);
    key.append(reinterpret_cast<const char*>(n.arg), sizeof n.arg);
    key.append(reinterpret_cast<const char*>(&n.index), sizeof n.index);
    if (n.kind == Node::Const) {
      double c[4] = {n.value.n, n.value.v.x, n.value.v.y, n.value.v.z};
      key.append(reinterpret_cast<const char*>(c), sizeof c);
    }
    auto [it, fresh] = cse_.try_emplace(key, static_cast<int>(nodes_.size()));
    if (fresh) nodes_.push_back(std::move(n));
    return it->second;
  }
  SVal graph(int id) {
    SVal s(SVal::Graph);
    s.node = id;
    s.type = nodes_[id].type;
    return s;
  }
  int mat(const SVal& v) {
    if (v.kind == SVal::Graph) return v.node;
    Node n(Node::Const, v.k.type);
    n.value = v.k;
    return add(std::move(n));
  }
  SVal apply(Op op, Type t, const SVal& a, const SVal* b = nullptr, const SVal* c = nullptr) {
    Node n(Node::Apply, t);
    n.op = op;
    n.arg[0] = mat(a);
    if (b) n.arg[1] = mat(*b);
    if (c) n.arg[2] = mat(*c);
    return graph(add(std::move(n)));
  }
  // A number promoted to a vector of type `t`.
  SVal splat(const SVal& s, Type t) {
    if (s.type == t) return s;
    if (s.is_const())
      return SVal::constant(t == Type::Vec2 ? Value::vec2(s.k.n, s.k.n)
                                            : Value::vec3(ir::Vec3(s.k.n)));
    return apply(Op::Splat, t, s);
  }
  SVal select(const SVal& c, const SVal& a, const SVal& b, Span at);
  SVal logic_or(const SVal& a, const SVal& b, Span at) {
    return select(a, SVal::constant(Value::boolean(true)), b, at);
  }

  // ---- expressions and statements
  SVal expr(const Expr& e, Scope* s);
  SVal name(const Expr& e, Scope* s);
  SVal vector(const Expr& e, Scope* s);
  SVal unary(const Expr& e, Scope* s);
  SVal binary(const Expr& e, Scope* s);
  SVal fold_binary(const Expr& e, const Value& a, const Value& b);
  SVal component(const Expr& e, Scope* s);
  SVal call(const Expr& e, Scope* s);
  SVal call_with(SVal callee, const Expr& e, Scope* s);
  SVal loop_call(const Closure& fn, std::vector<SVal>& args, const Expr& call);
  Outcome tail_call(const Stmt& ret, const Expr& call, std::vector<SVal> args);
  void merge_loop(Outcome& r, const SVal& c, const Outcome& a, const Outcome& b);
  SVal call_builtin_fn(int id, const Expr& e, std::vector<SVal>& args);
  SVal inline_call(const Stmt& def, Scope* body_scope, const std::vector<std::int32_t>& params,
                   std::vector<SVal>& args, const Expr& call, const std::string& fname);
  Outcome block(const std::vector<lang::StmtPtr>& stmts, Scope* s);
  Outcome stmt(const Stmt& st, Scope* s);
  Outcome if_stmt(const Stmt& st, std::size_t branch, Scope* s);
  Outcome for_stmt(const Stmt& st, Scope* s);
  Outcome seq(const Outcome& a, const Outcome& b);
  Scope* scope(Scope* parent, std::shared_ptr<Env> env = nullptr) {
    scopes_.push_back({parent, std::move(env), {}});
    return &scopes_.back();
  }
  void define(Scope* s, std::int32_t sym, SVal v, Span at);

  // roots[0] is the result; a loop body's are then done and the next inputs.
  bool codegen(const std::vector<SVal>& roots, Span fn_span, ir::Program& out);

  Evaluator& ev_;
  Span use_;
  std::optional<lang::DiagBuilder> pending_;
  std::vector<std::pair<Span, std::string>> context_;
  bool failed_ = false;
  int work_ = 0;
  int unrolled_ = 0;
  std::vector<Node> nodes_;
  std::unordered_map<std::string, int> cse_;
  std::deque<Scope> scopes_;
  struct Call {
    const Stmt* def;
    Span span;
    std::string name;
  };
  std::vector<Call> calls_;  // the inlined calls in progress, outermost first
  // Loops: the bodies this program runs, each Loop node's argument nodes; in a
  // loop body's compiler, the function it is and how deep bodies nest here, and
  // each input's first slot.
  std::vector<ir::Program> loops_;
  std::vector<std::vector<int>> loop_args_;
  const Stmt* loop_def_ = nullptr;
  int loop_depth_ = 0;
  std::vector<int> input_slot_{ir::kPointSlot, ir::kNormalSlot};
  std::vector<Type> loop_types_;  // a loop body's parameters' types
  std::size_t loop_calls_ = 0;    // calls_.size() directly in a loop body
};

}  // namespace snell::compile
