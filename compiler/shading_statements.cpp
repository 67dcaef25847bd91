// The shading-function compiler, statements (let, fn, return, if, for: their
// effect on the return value as an Outcome), the function as a whole, and code
// generation. See shading_compiler.hpp for the design.

#include "compiler/arith.hpp"
#include "compiler/builtins.hpp"
#include "compiler/shading_compiler.hpp"

namespace snell::compile {

using lang::DiagKind;
using lang::Expr;
using lang::ExprKind;
using lang::Span;
using lang::Stmt;
using lang::StmtKind;
using lang::TokenKind;
using Op = ir::ProgramOp;
using namespace shading;

// ---------------------------------------------------------------------------
// Statements

void ShadingCompiler::define(Scope* s, std::int32_t sym, SVal v, Span at) {
  for (const auto& [name, value] : s->vars)
    if (name == sym) {
      error(DiagKind::Redefinition, at,
            "'" + ev_.symbol_names_[sym] + "' is already defined in this scope");
      return;
    }
  s->vars.push_back({sym, std::move(v)});
}

// A loop body's done flag and next inputs of `c ? a : b`.
void ShadingCompiler::merge_loop(Outcome& r, const SVal& c, const Outcome& a, const Outcome& b) {
  if (!loop_def_) return;
  r.done = select(c, a.done, b.done, r.at);
  r.next.resize(std::max(a.next.size(), b.next.size()));
  for (std::size_t k = 0; k < r.next.size(); ++k)
    r.next[k] = select(c, k < a.next.size() ? a.next[k] : SVal{},
                       k < b.next.size() ? b.next[k] : SVal{}, r.at);
}

Outcome ShadingCompiler::seq(const Outcome& a, const Outcome& b) {
  if (const_false(a.cond)) return b;
  if (const_false(b.cond)) return a;
  Outcome r;
  r.cond = logic_or(a.cond, b.cond, a.at);
  r.val = select(a.cond, a.val, b.val, b.at);
  r.at = a.at;
  merge_loop(r, a.cond, a, b);
  return r;
}

Outcome ShadingCompiler::block(const std::vector<lang::StmtPtr>& stmts, Scope* s) {
  Outcome acc;
  for (const lang::StmtPtr& st : stmts) {
    if (const_true(acc.cond) || acc.cond.is_error() || work_ > kMaxCompileWork) break;
    acc = seq(acc, stmt(*st, s));
  }
  return acc;
}

Outcome ShadingCompiler::stmt(const Stmt& st, Scope* s) {
  Outcome none;
  switch (st.kind) {
    case StmtKind::Let: {
      SVal v = expr(*st.exprs[0], s);
      if (v.kind == SVal::None) {
        error(DiagKind::MissingReturn, st.exprs[0]->span,
              "this call returns nothing to bind to '" + st.name + "'");
        v = SVal::error();
      }
      define(s, ev_.symbol_of(st), std::move(v), st.name_span);
      return none;
    }
    case StmtKind::Fn: {
      SVal f(SVal::LocalFn);
      f.def = &st;
      f.scope = s;
      f.type = Type::Function;
      define(s, ev_.symbol_of(st), f, st.name_span);
      return none;
    }
    case StmtKind::Return: {
      Outcome r;
      r.cond = SVal::constant(Value::boolean(true));
      r.at = st.span;
      if (loop_def_) r.done = SVal::constant(Value::boolean(true));
      if (st.exprs.empty()) return r;
      const Expr& e = *st.exprs[0];
      if (loop_def_ && calls_.size() == loop_calls_ && e.kind == ExprKind::Call) {
        // `return f(...)` directly in f's loop body: the next run's inputs.
        SVal callee = expr(*e.args[0], s);
        if (callee.is_const() && callee.type == Type::Function && callee.k.func().builtin < 0 &&
            callee.k.func().def == loop_def_) {
          std::vector<SVal> args;
          bool bad = false;
          for (std::size_t i = 1; i < e.args.size(); ++i) {
            args.push_back(expr(*e.args[i], s));
            bad |= args.back().is_error() || args.back().kind == SVal::None;
          }
          if (bad) {
            r.cond = SVal::error();
            return r;
          }
          return tail_call(st, e, std::move(args));
        }
        r.val = call_with(callee, e, s);
      } else {
        r.val = expr(e, s);
      }
      if (r.val.is_error()) r.cond = SVal::error();
      return r;
    }
    case StmtKind::For:
      return for_stmt(st, s);
    case StmtKind::If:
      return if_stmt(st, 0, s);
    case StmtKind::Import:
      unsupported(st.span, "a shading function cannot import files");
      return none;
    case StmtKind::ExprStmt: {
      const Expr& e = *st.exprs[0];
      if (e.kind == ExprKind::Call) {
        call(e, s);  // run for its errors (an impure callee); the value is dropped
      } else if (e.kind != ExprKind::Error) {
        SVal v = expr(e, s);
        if (!v.is_error())
          error(DiagKind::ValueAsStatement, e.span,
                "this " + std::string(type_name(v.type)) +
                    " is computed and thrown away; only a call can stand as a statement");
      }
      return none;
    }
    case StmtKind::Item:
      impure(st.name_span, "'" + st.name + "' block");
      return none;
    case StmtKind::Background:
      impure(st.name_span.end > st.name_span.begin ? st.name_span : st.span, "background");
      return none;
    case StmtKind::Error:
      return none;
  }
  return none;
}

Outcome ShadingCompiler::if_stmt(const Stmt& st, std::size_t i, Scope* s) {
  if (i == st.branches.size()) {
    if (!st.has_else) return {};
    return block(st.else_body, scope(s));
  }
  SVal c = expr(*st.exprs[i], s);
  Outcome bad;
  bad.cond = SVal::error();
  if (c.is_error()) return bad;
  if (c.type != Type::Bool) {
    error(DiagKind::TypeMismatch, st.exprs[i]->span,
          "a condition must be a bool, not " + a_type(c.type))
        .note("there is no truthiness: write a comparison such as 'x != 0'");
    return bad;
  }
  if (c.is_const()) return c.k.truth() ? block(st.branches[i], scope(s)) : if_stmt(st, i + 1, s);
  Outcome yes = block(st.branches[i], scope(s));
  Outcome no = if_stmt(st, i + 1, s);
  Outcome r;
  r.cond = select(c, yes.cond, no.cond, st.span);
  r.val = select(c, yes.val, no.val, const_false(yes.cond) ? no.at : yes.at);
  r.at = const_false(yes.cond) ? no.at : yes.at;
  merge_loop(r, c, yes, no);
  return r;
}

Outcome ShadingCompiler::for_stmt(const Stmt& st, Scope* s) {
  Outcome bad;
  bad.cond = SVal::error();
  SVal b[3];
  for (std::size_t i = 0; i < 3; ++i) {
    if (i == 2 && st.exprs.size() < 3) {
      b[2] = SVal::constant(Value::number(1));
      continue;
    }
    b[i] = expr(*st.exprs[i], s);
    if (b[i].is_error()) return bad;
    if (b[i].type != Type::Number) {
      error(DiagKind::TypeMismatch, st.exprs[i]->span,
            std::string(i == 2 ? "the step" : "a loop bound") + " must be a number, not " +
                a_type(b[i].type));
      return bad;
    }
    if (!b[i].is_const()) {
      unsupported(st.exprs[i]->span,
                  "a loop in a shading function needs constant bounds and step (it is "
                  "unrolled); this one depends on the point");
      return bad;
    }
  }
  double from = b[0].k.n, to = b[1].k.n, by = b[2].k.n;
  if (by == 0) {
    error(DiagKind::ZeroStep, st.exprs[2]->span, "a for loop's step must not be 0");
    return bad;
  }
  std::int32_t sym = ev_.symbol_of(st);
  Outcome acc;
  for (std::uint64_t k = 0;; ++k) {
    double x = from + static_cast<double>(k) * by;  // as the evaluator counts
    if (by > 0 ? !(x < to) : !(x > to)) break;
    if (const_true(acc.cond) || acc.cond.is_error() || work_ > kMaxCompileWork) break;
    if (++unrolled_ > kMaxUnroll) {
      unsupported(st.span, "a shading function unrolls at most " + std::to_string(kMaxUnroll) +
                               " loop iterations");
      return bad;
    }
    Scope* body = scope(s);
    body->vars.push_back({sym, SVal::constant(Value::number(x))});
    acc = seq(acc, block(st.body, body));
  }
  return acc;
}

// ---------------------------------------------------------------------------
// The function and code generation

bool ShadingCompiler::run(const Value& fn, Span fn_span, ir::Program& out) {
  if (fn.type != Type::Function) {
    error(DiagKind::InvalidValue, fn_span,
          "a shading function must be a function, not " + a_type(fn.type));
    return false;
  }
  const Closure& c = fn.func();
  if (c.builtin >= 0 || !c.def) {
    error(DiagKind::InvalidValue, fn_span,
          "'" + c.name + "' is a builtin; write 'fn f(p) = " + c.name + "(...);' around it");
    return false;
  }
  std::size_t n = c.def->params.size();
  if (n != 1 && n != 2) {
    error(DiagKind::InvalidValue, fn_span,
          "a shading function takes the point, or the point and the normal; '" + c.name +
              "' takes " + std::to_string(n) + " parameters")
        .note(c.def->name_span, "defined here");
    return false;
  }
  std::vector<SVal> args;
  for (int i = 0; i < static_cast<int>(n); ++i) {
    Node in(Node::Input, Type::Vec3);
    in.index = i;
    args.push_back(graph(add(std::move(in))));
  }
  // The use stands for the call: it is what the notes point at.
  Expr use;
  use.span = use_;
  SVal r = tail_recursive(*c.def)
               ? loop_call(c, args, use)
               : inline_call(*c.def, scope(nullptr, c.env), c.params, args, use, c.name);
  if (failed_) return false;
  if (r.kind == SVal::None) {
    error(DiagKind::MissingReturn, c.def->name_span, "'" + c.name + "' returns no value");
    return false;
  }
  if (r.type != Type::Number) {
    error(DiagKind::InvalidValue, fn_span,
          "a shading function must return a number, and '" + c.name + "' returns " + a_type(r.type))
        .note(c.def->name_span, "defined here");
    return false;
  }
  out.first_constant = ir::kFirstConstantSlot;
  return codegen({r}, c.def->name_span, out);
}

bool ShadingCompiler::codegen(const std::vector<SVal>& roots, Span fn_span, ir::Program& out) {
  const std::uint8_t first_constant = out.first_constant;
  const std::uint16_t depth0 = out.depth0;
  out = {};
  out.first_constant = first_constant;
  out.depth0 = depth0;
  std::vector<int> root_ids;
  for (const SVal& r : roots) root_ids.push_back(mat(r));
  const int root = root_ids[0];
  // Live nodes: what the roots reach (ids are topological: args come first).
  std::vector<char> live(nodes_.size(), 0);
  for (int r : root_ids) live[r] = 1;
  auto operands = [&](int id, auto&& f) {
    for (int a : nodes_[id].arg)
      if (a >= 0) f(a);
    if (nodes_[id].kind == Node::Loop)
      for (int a : loop_args_[nodes_[id].index]) f(a);
  };
  for (int i = static_cast<int>(nodes_.size()) - 1; i >= 0; --i)
    if (live[i]) operands(i, [&](int a) { live[a] = 1; });
  std::vector<int> slot(nodes_.size(), -1);
  auto width = [&](int id) { return is_vec(nodes_[id].type) ? 3 : 1; };
  int next = first_constant;
  auto too_big = [&](const std::string& what) {
    error(DiagKind::UnsupportedInShadingFunction, fn_span,
          "this shading function is too big for a program: " + what);
    return false;
  };
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    if (!live[i]) continue;
    const Node& nd = nodes_[i];
    if (nd.kind == Node::Input) {
      slot[i] = input_slot_[nd.index];
      if (!loop_def_) (nd.index == 0 ? out.reads_point : out.reads_normal) = true;
    } else if (nd.kind == Node::Const) {
      slot[i] = next;
      if (is_vec(nd.type))
        for (int k = 0; k < 3; ++k) out.constants.push_back(nd.value.v[k]);
      else
        out.constants.push_back(nd.value.n);
      next += width(static_cast<int>(i));
    }
  }
  if (next > ir::kMaxSlots) return too_big("more than " + std::to_string(ir::kMaxSlots) + " slots");
  // Last use of each node's slot (a component's use is its vector's).
  auto owner = [&](int id) { return nodes_[id].kind == Node::Comp ? nodes_[id].arg[0] : id; };
  auto computed = [&](int id) {
    return nodes_[id].kind == Node::Apply || nodes_[id].kind == Node::Loop;
  };
  std::vector<int> last(nodes_.size(), -1);
  for (std::size_t i = 0; i < nodes_.size(); ++i)
    if (live[i] && computed(static_cast<int>(i)))
      operands(static_cast<int>(i), [&](int a) { last[owner(a)] = static_cast<int>(i); });
  for (int r : root_ids) last[owner(r)] = static_cast<int>(nodes_.size());
  std::vector<int> free1, free3;
  auto take = [&](int w) {
    std::vector<int>& pool = w == 3 ? free3 : free1;
    if (!pool.empty()) {
      int t = pool.back();
      pool.pop_back();
      return t;
    }
    next += w;
    return next - w;
  };
  auto emit = [&](Op op, int dst, int a, int b = -1, int c = -1) {
    ir::Instr in;
    in.op = op;
    in.dst = static_cast<std::uint8_t>(dst);
    if (a >= 0) in.a = static_cast<std::uint8_t>(a);
    if (b >= 0) in.b = static_cast<std::uint8_t>(b);
    if (c >= 0) in.c = static_cast<std::uint8_t>(c);
    out.code.push_back(in);
  };
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    if (!live[i]) continue;
    const Node& nd = nodes_[i];
    if (nd.kind == Node::Comp) {
      slot[i] = slot[nd.arg[0]] + nd.index;
      continue;
    }
    if (!computed(static_cast<int>(i))) continue;
    // The destination is taken before the operands are freed, so an instruction
    // never writes a slot it reads.
    slot[i] = take(width(static_cast<int>(i)));
    if (nd.kind == Node::Loop) {
      // The arguments copied into consecutive slots, the body's inputs.
      const std::vector<int>& args = loop_args_[nd.index];
      int w = 0;
      for (int a : args) w += width(a);
      const int block = next;
      next += w;
      if (next <= ir::kMaxSlots) {
        int at = block;
        for (int a : args) {
          emit(width(a) == 3 ? Op::MovV : Op::MovS, at, slot[a]);
          at += width(a);
        }
        emit(is_vec(nd.type) ? Op::LoopV : Op::LoopS, slot[i], nd.index, block);
        for (int at2 = block, k = 0; k < static_cast<int>(args.size()); at2 += width(args[k]), ++k)
          (width(args[k]) == 3 ? free3 : free1).push_back(at2);
      }
    } else {
      emit(nd.op, slot[i], nd.arg[0] >= 0 ? slot[nd.arg[0]] : -1,
           nd.arg[1] >= 0 ? slot[nd.arg[1]] : -1, nd.arg[2] >= 0 ? slot[nd.arg[2]] : -1);
    }
    if (next > ir::kMaxSlots)
      return too_big("more than " + std::to_string(ir::kMaxSlots) + " slots");
    if (out.code.size() > static_cast<std::size_t>(ir::kMaxCode))
      return too_big("more than " + std::to_string(ir::kMaxCode) + " instructions");
    operands(static_cast<int>(i), [&](int a) {
      int o = owner(a);
      if (last[o] != static_cast<int>(i) || !computed(o)) return;
      last[o] = -2;  // freed once, even when read twice by this instruction
      (width(o) == 3 ? free3 : free1).push_back(slot[o]);
    });
  }
  out.slots = static_cast<std::uint16_t>(next);
  out.result = static_cast<std::uint8_t>(slot[root]);
  if (loop_def_) {
    // A body: done, then each parameter's next value into its input slots.
    out.done = static_cast<std::uint8_t>(slot[root_ids[1]]);
    out.next.assign(first_constant, 0);
    for (std::size_t k = 0; k + 2 < root_ids.size(); ++k)
      for (int c = 0; c < width(root_ids[k + 2]); ++c)
        out.next[input_slot_[k] + c] = static_cast<std::uint8_t>(slot[root_ids[k + 2]] + c);
  }
  out.loops = std::move(loops_);
  return true;
}

}  // namespace snell::compile
