// The shading-function compiler, tail recursion: a function that calls itself
// only as `return f(...)`, called on run-time values, runs as a loop instead of
// being inlined (which could not end: its recursion ends on run-time values). See
// shading_compiler.hpp for the design and runtime/ir/program.hpp for the machine.
//
// Limits: the parameters must be numbers, bools or vectors, and keep their types
// from run to run; the function must return on some path and call itself only
// directly in its body (not from a helper it calls); bodies nest at most
// ir::kMaxLoopNesting deep. At render time a loop whose calls would nest deeper
// than §4's 10 000 (ir::kMaxCallDepth, counting the calls around it as the
// evaluator does) or that runs out of the evaluation's work (ir::kMaxWork) gives
// NaN (so the hit's value is 0, counted in --stats).

#include "compiler/shading_compiler.hpp"

namespace snell::compile {

static_assert(kMaxCallDepth == ir::kMaxCallDepth, "the evaluator's and the loops' §4 bound");

using lang::DiagKind;
using lang::Expr;
using lang::ExprKind;
using lang::Stmt;
using lang::StmtKind;
using namespace shading;

namespace shading {
namespace {

bool calls_name(const Expr& e, const std::string& self) {
  if (e.kind == ExprKind::Call && !e.args.empty() && e.args[0]->kind == ExprKind::Name &&
      e.args[0]->text == self)
    return true;
  for (const lang::ExprPtr& a : e.args)
    if (a && calls_name(*a, self)) return true;
  return false;
}

bool mentions(const std::vector<lang::StmtPtr>& stmts, const std::string& self);
bool mentions(const Stmt& st, const std::string& self) {
  for (const lang::ExprPtr& e : st.exprs)
    if (e && calls_name(*e, self)) return true;
  if (mentions(st.body, self) || mentions(st.else_body, self)) return true;
  for (const auto& b : st.branches)
    if (mentions(b, self)) return true;
  return false;
}
bool mentions(const std::vector<lang::StmtPtr>& stmts, const std::string& self) {
  for (const lang::StmtPtr& st : stmts)
    if (st && mentions(*st, self)) return true;
  return false;
}

// False when `self` is called other than as `return self(...)`; `tails` counts
// those returns.
bool tails_only(const std::vector<lang::StmtPtr>& stmts, const std::string& self, int& tails) {
  for (const lang::StmtPtr& p : stmts) {
    if (!p) continue;
    const Stmt& st = *p;
    switch (st.kind) {
      case StmtKind::Return: {
        if (st.exprs.empty() || !st.exprs[0]) break;
        const Expr& e = *st.exprs[0];
        if (e.kind == ExprKind::Call && !e.args.empty() && e.args[0]->kind == ExprKind::Name &&
            e.args[0]->text == self) {
          ++tails;
          for (std::size_t i = 1; i < e.args.size(); ++i)
            if (calls_name(*e.args[i], self)) return false;
        } else if (calls_name(e, self)) {
          return false;
        }
        break;
      }
      case StmtKind::If:
        for (const lang::ExprPtr& c : st.exprs)
          if (c && calls_name(*c, self)) return false;
        for (const auto& b : st.branches)
          if (!tails_only(b, self, tails)) return false;
        if (!tails_only(st.else_body, self, tails)) return false;
        break;
      case StmtKind::For:
        for (const lang::ExprPtr& c : st.exprs)
          if (c && calls_name(*c, self)) return false;
        if (!tails_only(st.body, self, tails)) return false;
        break;
      default:
        if (mentions(st, self)) return false;
    }
  }
  return true;
}

}  // namespace

bool tail_recursive(const Stmt& def) {
  if (!def.exprs.empty()) return false;  // `fn f(x) = EXPR;`: no return statements
  int tails = 0;
  return tails_only(def.body, def.name, tails) && tails > 0;
}

}  // namespace shading

SVal ShadingCompiler::loop_call(const Closure& fn, std::vector<SVal>& args, const Expr& call) {
  const Stmt& def = *fn.def;
  if (loop_depth_ >= ir::kMaxLoopNesting)
    return unsupported(call.span, "tail recursions run as loops nested more than " +
                                      std::to_string(ir::kMaxLoopNesting) + " deep here");
  for (std::size_t k = 0; k < args.size(); ++k)
    if (!runtime_type(args[k].type))
      return unsupported(call.span, "'" + fn.name +
                                        "' calls itself on run-time values, so it runs "
                                        "as a loop, and its parameter '" +
                                        def.params[k] + "' is " + a_type(args[k].type) +
                                        " here: a loop carries numbers, bools and vectors");
  flush();  // this compiler's error first, then the body's
  ShadingCompiler body(ev_, use_);
  body.calls_ = calls_;
  body.calls_.push_back({&def, call.span, fn.name});
  body.loop_calls_ = body.calls_.size();
  body.loop_def_ = &def;
  body.loop_depth_ = loop_depth_ + 1;
  body.work_ = work_;
  body.unrolled_ = unrolled_;
  body.input_slot_.clear();
  Scope* sc = body.scope(nullptr, fn.env);
  int inputs = 0;
  for (std::size_t k = 0; k < args.size(); ++k) {
    Node in(Node::Input, args[k].type);
    in.index = static_cast<int>(k);
    sc->vars.push_back({fn.params[k], body.graph(body.add(std::move(in)))});
    body.input_slot_.push_back(inputs);
    body.loop_types_.push_back(args[k].type);
    inputs += is_vec(args[k].type) ? 3 : 1;
  }
  Outcome o = body.block(def.body, sc);
  ir::Program prog;
  if (!body.failed_ && !o.cond.is_error()) {
    if (!const_true(o.cond)) {
      body.unsupported(def.name_span, "'" + fn.name +
                                          "' returns a value on some run-time paths and none on "
                                          "others; give every path a 'return'");
    } else if (o.val.kind == SVal::None || const_false(o.done)) {
      body.unsupported(def.name_span, "'" + fn.name + "' never returns: every path calls it again");
    } else if (!runtime_type(o.val.type)) {
      body.unsupported(def.name_span, "'" + fn.name + "' returns " + a_type(o.val.type) +
                                          "; a loop returns a number, a bool or a vector");
    } else {
      std::vector<SVal> roots{o.val, o.done};
      for (std::size_t k = 0; k < args.size(); ++k) {
        SVal n = k < o.next.size() ? o.next[k] : SVal{};
        roots.push_back(n.kind == SVal::None ? sc->vars[k].second : n);
      }
      prog.first_constant = static_cast<std::uint8_t>(inputs);
      // The calls between the frame that starts the loop and its first run: the
      // helpers inlined since (the shading function's own at the top, where no
      // loop's frame is).
      prog.depth0 = static_cast<std::uint16_t>(calls_.size() - loop_calls_ + 1);
      body.codegen(roots, def.name_span, prog);
    }
  }
  body.flush();
  work_ = body.work_;
  unrolled_ = body.unrolled_;
  if (body.failed_ || o.cond.is_error()) {
    failed_ = true;
    return SVal::error();
  }
  std::vector<int> arg_nodes;
  for (const SVal& a : args) arg_nodes.push_back(mat(a));
  loops_.push_back(std::move(prog));
  loop_args_.push_back(std::move(arg_nodes));
  Node n(Node::Loop, o.val.type);
  n.index = static_cast<int>(loops_.size() - 1);
  return graph(add(std::move(n)));
}

Outcome ShadingCompiler::tail_call(const Stmt& ret, const Expr& call, std::vector<SVal> args) {
  Outcome r;
  r.at = ret.span;
  if (args.size() != loop_types_.size()) {
    error(DiagKind::WrongArgumentCount, call.span,
          "'" + loop_def_->name + "' takes " + std::to_string(loop_types_.size()) + " argument" +
              (loop_types_.size() == 1 ? "" : "s") + ", not " + std::to_string(args.size()))
        .note(loop_def_->name_span, "defined here");
    r.cond = SVal::error();
    return r;
  }
  for (std::size_t k = 0; k < args.size(); ++k)
    if (args[k].type != loop_types_[k]) {
      unsupported(call.args[k + 1]->span,
                  "'" + loop_def_->name + "' runs as a loop, and here passes " +
                      a_type(args[k].type) + " as '" + loop_def_->params[k] + "', which began as " +
                      a_type(loop_types_[k]) + "; a loop's parameters keep their types");
      r.cond = SVal::error();
      return r;
    }
  r.cond = SVal::constant(Value::boolean(true));
  r.done = SVal::constant(Value::boolean(false));
  r.next = std::move(args);
  return r;
}

}  // namespace snell::compile
