// The shading-function compiler, expressions: names, operators, components,
// calls (inlined) and builtins (native ops), folded where the operands are
// constants. See shading_compiler.hpp for the design.

#include "compiler/arith.hpp"
#include "compiler/builtins.hpp"
#include "compiler/shading_compiler.hpp"
#include "compiler/stack_guard.hpp"

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

namespace shading {
namespace {
constexpr BuiltinRow kBuiltinOps[] = {
    {"sin", BKind::Map, Op::SinS, Op::SinV},
    {"cos", BKind::Map, Op::CosS, Op::CosV},
    {"tan", BKind::Map, Op::TanS, Op::TanV},
    {"asin", BKind::Map, Op::AsinS, Op::AsinV},
    {"acos", BKind::Map, Op::AcosS, Op::AcosV},
    {"atan", BKind::Map, Op::AtanS, Op::AtanV},
    {"atan2", BKind::Map, Op::Atan2S, Op::Atan2V},
    {"sqrt", BKind::Map, Op::SqrtS, Op::SqrtV},
    {"pow", BKind::Map, Op::PowS, Op::PowV},
    {"exp", BKind::Map, Op::ExpS, Op::ExpV},
    {"log", BKind::Map, Op::LogS, Op::LogV},
    {"abs", BKind::Map, Op::AbsS, Op::AbsV},
    {"floor", BKind::Map, Op::FloorS, Op::FloorV},
    {"ceil", BKind::Map, Op::CeilS, Op::CeilV},
    {"round", BKind::Map, Op::RoundS, Op::RoundV},
    {"min", BKind::Map, Op::MinS, Op::MinV},
    {"max", BKind::Map, Op::MaxS, Op::MaxV},
    {"clamp", BKind::Map, Op::ClampS, Op::ClampV},
    {"mix", BKind::Map, Op::MixS, Op::MixV},
    {"dot", BKind::Dot, Op::Dot3, Op::Dot2},
    {"cross", BKind::Cross, Op::Cross, Op::Cross},
    {"length", BKind::Length, Op::Len3, Op::Len2},
    {"normalize", BKind::Normalize, Op::Norm3, Op::Norm2},
    {"random", BKind::Random, Op::Random, Op::Random},
    {"noise", BKind::Noise, Op::Noise, Op::Noise},
    {"fbm", BKind::Fbm, Op::Fbm, Op::Fbm},
    {"turbulence", BKind::Turb, Op::Turb, Op::Turb},
    {"cells", BKind::Cells, Op::Cells, Op::Cells},
};

}  // namespace

const BuiltinRow* builtin_row(int id) {
  for (const BuiltinRow& r : kBuiltinOps)
    if (r.name == builtin_info(id).name) return &r;
  return nullptr;
}
}  // namespace shading

// ---------------------------------------------------------------------------
// Expressions

SVal ShadingCompiler::expr(const Expr& e, Scope* s) {
  if (!work(e.span)) return SVal::error();
  switch (e.kind) {
    case ExprKind::Number:
      return SVal::constant(Value::number(e.number));
    case ExprKind::Bool:
      return SVal::constant(Value::boolean(e.boolean));
    case ExprKind::String:
      return unsupported(e.span, "a string cannot be used in a shading function", true);
    case ExprKind::Name:
      return name(e, s);
    case ExprKind::Vector:
      return vector(e, s);
    case ExprKind::Unary:
      return unary(e, s);
    case ExprKind::Binary:
      return binary(e, s);
    case ExprKind::Call: {
      SVal v = call(e, s);
      if (v.kind == SVal::None) {
        error(DiagKind::MissingReturn, e.span, "this call returns no value")
            .note("a block-form function returns a value only through 'return EXPR;'");
        return SVal::error();
      }
      return v;
    }
    case ExprKind::Component:
      return component(e, s);
    case ExprKind::Constructor:
      return unsupported(e.span,
                         "'" + e.text +
                             "' makes a material or a pattern, which a shading "
                             "function cannot compute",
                         true);
    case ExprKind::Object:
      return object_value(e.span, "this '" + e.text + "'");
    case ExprKind::Error:
      return SVal::error();
  }
  return SVal::error();
}

SVal ShadingCompiler::name(const Expr& e, Scope* s) {
  std::int32_t sym = ev_.symbol_of(e);
  const Value* found = nullptr;
  for (Scope* sc = s; sc && !found; sc = sc->parent) {
    for (auto it = sc->vars.rbegin(); it != sc->vars.rend(); ++it)
      if (it->first == sym) return it->second;
    if (sc->env) {
      for (const Env* en = sc->env.get(); en && !found; en = en->parent.get())
        if (const Binding* b = en->find_local(sym)) found = &b->value;
      break;
    }
  }
  if (!found) {
    if (int id = find_builtin(e.text); id >= 0) return SVal::constant(ev_.builtin_value(id));
    error(DiagKind::UndefinedName, e.span, "'" + e.text + "' is not defined");
    return SVal::error();
  }
  if (found->is_error()) return SVal::error();
  switch (found->type) {
    case Type::String:
    case Type::Material:
    case Type::Pattern:
      return unsupported(
          e.span,
          "'" + e.text + "' is " + a_type(found->type) + ", which a shading function cannot use",
          true);
    case Type::Object:
      return object_value(e.span, "'" + e.text + "'");
    default:
      return SVal::constant(*found);
  }
}

SVal ShadingCompiler::vector(const Expr& e, Scope* s) {
  std::vector<SVal> c;
  bool bad = false, all_const = true;
  for (const lang::ExprPtr& a : e.args) {
    c.push_back(expr(*a, s));
    SVal& v = c.back();
    if (v.is_error()) {
      bad = true;
    } else if (v.type != Type::Number && v.type != Type::Bool) {
      error(DiagKind::TypeMismatch, a->span,
            "a vector's components must be numbers, not " + a_type(v.type));
      bad = true;
    }
    all_const &= v.is_const();
  }
  if (e.args.size() < 2 || e.args.size() > 3) {
    error(DiagKind::BadVectorArity, e.span,
          "a vector has 2 or 3 components, not " + std::to_string(e.args.size()));
    return SVal::error();
  }
  if (bad) return SVal::error();
  if (all_const)
    return SVal::constant(c.size() == 2 ? Value::vec2(c[0].k.n, c[1].k.n)
                                        : Value::vec3({c[0].k.n, c[1].k.n, c[2].k.n}));
  // A bool component is 1 or 0, as in the evaluator (§3's `<(a > b), 1, 2>`): a
  // number node, so the component read back (`.x`) is a number too.
  const SVal one = SVal::constant(Value::number(1)), zero = SVal::constant(Value::number(0));
  for (SVal& v : c)
    if (v.type == Type::Bool) v = apply(Op::SelS, Type::Number, v, &one, &zero);
  // A 2-vector's z slot is don't-care: its y goes there.
  Type t = c.size() == 2 ? Type::Vec2 : Type::Vec3;
  return apply(Op::MakeV, t, c[0], &c[1], &c[c.size() - 1]);
}

SVal ShadingCompiler::unary(const Expr& e, Scope* s) {
  SVal v = expr(*e.args[0], s);
  if (v.is_error()) return v;
  if (e.op == TokenKind::Bang) {
    if (v.type != Type::Bool) {
      error(DiagKind::TypeMismatch, e.args[0]->span, "'!' needs a bool, not " + a_type(v.type));
      return SVal::error();
    }
    if (v.is_const()) return SVal::constant(Value::boolean(!v.k.truth()));
    return apply(Op::Not, Type::Bool, v);
  }
  if (v.type != Type::Number && !is_vec(v.type)) {
    error(DiagKind::TypeMismatch, e.args[0]->span,
          "'-' needs a number or a vector, not " + a_type(v.type));
    return SVal::error();
  }
  if (v.is_const()) {
    Value r = v.k;
    if (r.type == Type::Number)
      r.n = -r.n;
    else
      r.v = -r.v;
    return SVal::constant(r);
  }
  return apply(v.type == Type::Number ? Op::NegS : Op::NegV, v.type, v);
}

// Two constants, by the rules of Evaluator::eval_binary (the same arithmetic).
SVal ShadingCompiler::fold_binary(const Expr& e, const Value& a, const Value& b) {
  TokenKind op = e.op;
  if (is_arith(op)) {
    if (a.type == Type::Number && b.type == Type::Number) {
      // A non-finite constant is kept, not refused (§15: a non-finite result at
      // a hit gives 0 there); it may sit on a path few points take.
      return SVal::constant(Value::number(arith(op, a.n, b.n)));
    }
    Value r = a.is_vector() ? a : b;
    bool an = a.type == Type::Number, bn = b.type == Type::Number;
    for (int i = 0; i < r.dims(); ++i) r.v[i] = arith(op, an ? a.n : a.v[i], bn ? b.n : b.v[i]);
    return SVal::constant(r);
  }
  switch (op) {
    case TokenKind::Less:
      return SVal::constant(Value::boolean(a.n < b.n));
    case TokenKind::LessEqual:
      return SVal::constant(Value::boolean(a.n <= b.n));
    case TokenKind::Greater:
      return SVal::constant(Value::boolean(a.n > b.n));
    case TokenKind::GreaterEqual:
      return SVal::constant(Value::boolean(a.n >= b.n));
    case TokenKind::EqualEqual:
    case TokenKind::BangEqual: {
      bool eq = a.is_vector() ? a.v == b.v : a.n == b.n;
      return SVal::constant(Value::boolean((op == TokenKind::EqualEqual) == eq));
    }
    default:
      return SVal::error();
  }
}

SVal ShadingCompiler::binary(const Expr& e, Scope* s) {
  TokenKind op = e.op;
  auto spelling = [op] { return std::string(lang::token_spelling(op)); };
  if (op == TokenKind::AmpAmp || op == TokenKind::PipePipe) {
    bool is_and = op == TokenKind::AmpAmp;
    SVal a = expr(*e.args[0], s);
    if (a.is_error()) return a;
    if (a.type != Type::Bool) {
      error(DiagKind::TypeMismatch, e.args[0]->span,
            "'" + spelling() + "' needs bools, not " + a_type(a.type));
      return SVal::error();
    }
    if (a.is_const() && is_and != a.k.truth()) return a;  // short circuit, as evaluated
    SVal b = expr(*e.args[1], s);
    if (b.is_error()) return b;
    if (b.type != Type::Bool) {
      error(DiagKind::TypeMismatch, e.args[1]->span,
            "'" + spelling() + "' needs bools, not " + a_type(b.type));
      return SVal::error();
    }
    if (a.is_const()) return b;
    // Both sides are pure, so `a && false` is false whatever a is.
    if (b.is_const()) return is_and == b.k.truth() ? a : b;
    return apply(is_and ? Op::And : Op::Or, Type::Bool, a, &b);
  }
  SVal a = expr(*e.args[0], s);
  SVal b = expr(*e.args[1], s);
  if (a.is_error() || b.is_error()) return SVal::error();
  auto mismatch = [&](const char* what) {
    error(DiagKind::TypeMismatch, e.span,
          "'" + spelling() + "' " + what + ", not " + a_type(a.type) + " and " + a_type(b.type))
        .note(e.args[0]->span, "left operand: " + std::string(type_name(a.type)))
        .note(e.args[1]->span, "right operand: " + std::string(type_name(b.type)));
    return SVal::error();
  };
  if (a.type == Type::Function || b.type == Type::Function)
    return mismatch("needs numbers, bools or vectors");
  bool both_const = a.is_const() && b.is_const();
  if (is_arith(op)) {
    bool an = a.type == Type::Number, bn = b.type == Type::Number;
    if ((!an && !is_vec(a.type)) || (!bn && !is_vec(b.type)))
      return mismatch("needs numbers or vectors");
    if (is_vec(a.type) && is_vec(b.type) && a.type != b.type)
      return mismatch("needs vectors of one size");
    if (both_const) return fold_binary(e, a.k, b.k);
    static constexpr struct {
      TokenKind tok;
      Op s, v;
    } kOps[] = {{TokenKind::Plus, Op::AddS, Op::AddV},
                {TokenKind::Minus, Op::SubS, Op::SubV},
                {TokenKind::Star, Op::MulS, Op::MulV},
                {TokenKind::Slash, Op::DivS, Op::DivV},
                {TokenKind::Percent, Op::ModS, Op::ModV}};
    Op os = Op::AddS, ov = Op::AddV;
    for (const auto& r : kOps)
      if (r.tok == op) os = r.s, ov = r.v;
    if (an && bn) return apply(os, Type::Number, a, &b);
    Type t = an ? b.type : a.type;
    SVal x = splat(a, t), y = splat(b, t);
    return apply(ov, t, x, &y);
  }
  switch (op) {
    case TokenKind::Less:
    case TokenKind::LessEqual:
    case TokenKind::Greater:
    case TokenKind::GreaterEqual: {
      if (a.type != Type::Number || b.type != Type::Number) return mismatch("compares numbers");
      if (both_const) return fold_binary(e, a.k, b.k);
      Op o = op == TokenKind::Less        ? Op::Lt
             : op == TokenKind::LessEqual ? Op::Le
             : op == TokenKind::Greater   ? Op::Gt
                                          : Op::Ge;
      return apply(o, Type::Bool, a, &b);
    }
    case TokenKind::EqualEqual:
    case TokenKind::BangEqual: {
      bool same =
          (a.type == Type::Number || a.type == Type::Bool || is_vec(a.type)) && a.type == b.type;
      if (!same) return mismatch("compares two numbers, bools, strings or vectors of one size");
      if (both_const) return fold_binary(e, a.k, b.k);
      bool eq = op == TokenKind::EqualEqual;
      if (!is_vec(a.type)) return apply(eq ? Op::EqS : Op::NeS, Type::Bool, a, &b);
      SVal r = apply(a.type == Type::Vec3 ? Op::Eq3 : Op::Eq2, Type::Bool, a, &b);
      return eq ? r : apply(Op::Not, Type::Bool, r);
    }
    default:
      return SVal::error();
  }
}

SVal ShadingCompiler::component(const Expr& e, Scope* s) {
  SVal v = expr(*e.args[0], s);
  if (v.is_error()) return v;
  int idx = e.text == "x" ? 0 : e.text == "y" ? 1 : e.text == "z" ? 2 : -1;
  if (!is_vec(v.type)) {
    error(DiagKind::TypeMismatch, e.args[0]->span,
          "'." + e.text + "' needs a vector, not " + a_type(v.type));
    return SVal::error();
  }
  int dims = v.type == Type::Vec2 ? 2 : 3;
  if (idx < 0 || idx >= dims) {
    error(DiagKind::BadComponent, e.span, a_type(v.type) + " has no component '" + e.text + "'");
    return SVal::error();
  }
  if (v.is_const()) return SVal::constant(Value::number(v.k.v[idx]));
  // A component of a vector made from components is that component's own node.
  const Node& n = nodes_[v.node];
  if (n.kind == Node::Apply && n.op == Op::MakeV) return graph(n.arg[idx]);
  Node c(Node::Comp, Type::Number);
  c.arg[0] = v.node;
  c.index = idx;
  return graph(add(std::move(c)));
}

SVal ShadingCompiler::call(const Expr& e, Scope* s) {
  return call_with(expr(*e.args[0], s), e, s);
}

SVal ShadingCompiler::call_with(SVal callee, const Expr& e, Scope* s) {
  std::vector<SVal> args;
  bool bad = callee.is_error();
  for (std::size_t i = 1; i < e.args.size(); ++i) {
    args.push_back(expr(*e.args[i], s));
    bad |= args.back().is_error();
    if (args.back().kind == SVal::None) {
      error(DiagKind::MissingReturn, e.args[i]->span, "this argument has no value");
      bad = true;
    }
  }
  if (callee.is_error()) return callee;
  if (callee.kind != SVal::LocalFn && callee.type != Type::Function) {
    error(DiagKind::NotCallable, e.args[0]->span, a_type(callee.type) + " cannot be called");
    return SVal::error();
  }
  const Closure* fn = callee.kind == SVal::Const ? &callee.k.func() : nullptr;
  const Stmt* def = fn ? fn->def : callee.def;
  std::string fname = fn ? fn->name : callee.def->name;
  int arity = fn && fn->builtin >= 0 ? builtin_info(fn->builtin).arity
                                     : static_cast<int>(def->params.size());
  if (static_cast<int>(args.size()) != arity) {
    auto d = error(DiagKind::WrongArgumentCount, e.span,
                   "'" + fname + "' takes " + std::to_string(arity) + " argument" +
                       (arity == 1 ? "" : "s") + ", not " + std::to_string(args.size()));
    if (fn && fn->builtin >= 0)
      d.note(std::string(builtin_info(fn->builtin).signature));
    else
      d.note(def->name_span, "defined here");
    return SVal::error();
  }
  if (bad) return SVal::error();
  if (fn && fn->builtin >= 0) return call_builtin_fn(fn->builtin, e, args);
  if (fn && tail_recursive(*def)) {
    bool all_const = true, inside = false;
    for (const SVal& a : args) all_const &= a.is_const();
    for (const Call& c : calls_) inside = inside || c.def == def;
    if (!all_const && !inside) return loop_call(*fn, args, e);
  }
  std::vector<std::int32_t> params;
  Scope* body;
  if (fn) {
    params = fn->params;
    body = scope(nullptr, fn->env);
  } else {
    for (const std::string& p : def->params) params.push_back(ev_.intern(p));
    body = scope(callee.scope);
  }
  return inline_call(*def, body, params, args, e, fname);
}

SVal ShadingCompiler::inline_call(const Stmt& def, Scope* body,
                                  const std::vector<std::int32_t>& params, std::vector<SVal>& args,
                                  const Expr& call, const std::string& fname) {
  // A recursion is unrolled like any call: on run-time values too, as long as it
  // ends on constants within the depth limit (an escape-time fractal counting its
  // iterations; every level is computed and the returns select the first taken).
  if (&def == loop_def_)
    return unsupported(call.span, "'" + fname + "' calls itself here other than as 'return " +
                                      fname +
                                      "(...)' directly in its body; a tail recursion on run-time "
                                      "values runs as a loop, and this call cannot");
  // A call on constants alone folds to a constant (it adds no instructions), so
  // it may nest as deep as the evaluator's calls (§4: 10 000), the stack
  // permitting: a `fn s(n)` summing 1..300 was refused at 256.
  bool all_const = true;
  for (const SVal& a : args) all_const = all_const && a.is_const();
  const int limit = all_const ? kMaxCallDepth : kMaxInlineDepth;
  const bool deep = static_cast<int>(calls_.size()) >= kMaxInlineDepth;
  if (deep && all_const && static_cast<int>(calls_.size()) < limit &&
      stack_low(stack_floor(std::size_t(4) << 20))) {
    return unsupported(call.span, "calls on constants are nested " + std::to_string(calls_.size()) +
                                      " deep here: more than the compiler's stack holds");
  }
  if (static_cast<int>(calls_.size()) >= limit) {
    bool recursive = false;
    for (const Call& c : calls_) recursive = recursive || c.def == &def;
    if (recursive)
      return unsupported(call.span,
                         "'" + fname + "' calls itself more than " + std::to_string(limit) +
                             " deep here; a shading function's recursion is unrolled when it is "
                             "compiled, so it must end on constants within that many calls (a "
                             "counter such as 'i + 1' up to a limit)");
    return unsupported(call.span, "calls are nested more than " + std::to_string(limit) +
                                      " deep here in a shading function");
  }
  for (std::size_t i = 0; i < args.size(); ++i) body->vars.push_back({params[i], args[i]});
  calls_.push_back({&def, call.span, fname});
  SVal r;
  if (!def.exprs.empty()) {
    r = expr(*def.exprs[0], body);
  } else {
    Outcome o = block(def.body, body);
    if (const_true(o.cond)) {
      r = o.val;
    } else if (!const_false(o.cond) && !o.cond.is_error()) {
      r = unsupported(def.name_span, "'" + fname +
                                         "' returns a value on some run-time paths and none on "
                                         "others; give every path a 'return'");
    } else if (o.cond.is_error()) {
      r = SVal::error();
    }
  }
  calls_.pop_back();
  return r;
}

SVal ShadingCompiler::call_builtin_fn(int id, const Expr& e, std::vector<SVal>& args) {
  const BuiltinInfo& info = builtin_info(id);
  auto fail = [&](int arg, const std::string& msg, DiagKind kind = DiagKind::TypeMismatch) {
    error(kind, arg >= 0 ? e.args[arg + 1]->span : e.span,
          "'" + std::string(info.name) + "' " + msg)
        .note(std::string(info.signature));
    return SVal::error();
  };
  bool all_const = true;
  for (const SVal& a : args) all_const &= a.is_const();
  if (all_const) {
    std::vector<Value> v;
    for (const SVal& a : args) v.push_back(a.k);
    BuiltinError err;
    Value r = call_builtin(id, v.data(), err);
    if (r.is_error()) return fail(err.arg, err.message, err.kind);
    return SVal::constant(r);  // non-finite kept, as fold_binary keeps it
  }
  const BuiltinRow* row = builtin_row(id);
  if (!row) return unsupported(e.span, "'" + std::string(info.name) + "' has no native op");
  auto want_vec = [&](int i) {
    if (is_vec(args[i].type)) return true;
    fail(i, "expects a vector, got " + a_type(args[i].type));
    return false;
  };
  auto want_vec3 = [&](int i) {
    if (args[i].type == Type::Vec3) return true;
    fail(i, "expects a 3-vector (a point), got " + a_type(args[i].type));
    return false;
  };
  switch (row->kind) {
    case BKind::Map: {
      Type t = Type::Number;
      for (std::size_t i = 0; i < args.size(); ++i) {
        Type ti = args[i].type;
        if (ti != Type::Number && !is_vec(ti))
          return fail(static_cast<int>(i), "expects a number or a vector, got " + a_type(ti));
        if (ti == Type::Number) continue;
        if (t != Type::Number && t != ti)
          return fail(static_cast<int>(i), "mixes a 2-vector and a 3-vector");
        t = ti;
      }
      for (SVal& a : args) a = splat(a, t);
      Op o = t == Type::Number ? row->s : row->v;
      return apply(o, t, args[0], args.size() > 1 ? &args[1] : nullptr,
                   args.size() > 2 ? &args[2] : nullptr);
    }
    case BKind::Dot:
      if (!want_vec(0) || !want_vec(1)) return SVal::error();
      if (args[0].type != args[1].type)
        return fail(1, "dot of " + a_type(args[0].type) + " and " + a_type(args[1].type));
      return apply(args[0].type == Type::Vec3 ? row->s : row->v, Type::Number, args[0], &args[1]);
    case BKind::Cross:
      if (!want_vec3(0) || !want_vec3(1)) return SVal::error();
      return apply(Op::Cross, Type::Vec3, args[0], &args[1]);
    case BKind::Length:
      if (!want_vec(0)) return SVal::error();
      return apply(args[0].type == Type::Vec3 ? row->s : row->v, Type::Number, args[0]);
    case BKind::Normalize:
      if (!want_vec(0)) return SVal::error();
      return apply(args[0].type == Type::Vec3 ? row->s : row->v, args[0].type, args[0]);
    case BKind::Random:
      if (args[0].type != Type::Number)
        return fail(0, "expects a number, got " + a_type(args[0].type));
      return apply(Op::Random, Type::Number, args[0]);
    case BKind::Noise:
    case BKind::Cells:
      if (!want_vec3(0)) return SVal::error();
      return apply(row->s, Type::Number, args[0]);
    case BKind::Fbm:
    case BKind::Turb: {
      bool p_ok = want_vec3(0);
      if (args[1].is_const()) {
        BuiltinError err;
        if (!octaves_ok(args[1].k, 1, err)) return fail(err.arg, err.message, err.kind);
      } else if (args[1].type != Type::Number) {
        return fail(1, "expects a number of octaves, got " + a_type(args[1].type));
      }
      if (!p_ok) return SVal::error();
      return apply(row->s, Type::Number, args[0], &args[1]);
    }
  }
  return SVal::error();
}

// c ? a : b, folded where the condition or the arms allow.
SVal ShadingCompiler::select(const SVal& c, const SVal& a, const SVal& b, Span at) {
  if (c.is_error() || a.is_error() || b.is_error()) return SVal::error();
  if (c.is_const()) return c.k.truth() ? a : b;
  if (a.kind == SVal::None) return b;
  if (b.kind == SVal::None) return a;
  if (a.type != b.type || !runtime_type(a.type))
    return unsupported(at, "this returns " + a_type(a.type) + " on one run-time path and " +
                               a_type(b.type) + " on another");
  if (a.is_const() && b.is_const() && a.type == Type::Bool) {
    if (a.k.truth() == b.k.truth()) return a;
    return a.k.truth() ? c : apply(Op::Not, Type::Bool, c);
  }
  if (a.kind == b.kind && a.kind == SVal::Graph && a.node == b.node) return a;
  if (a.is_const() && b.is_const() && a.k.n == b.k.n && a.k.v == b.k.v) return a;
  return apply(is_vec(a.type) ? Op::SelV : Op::SelS, a.type, c, &a, &b);
}

bool compile_shading_function(Evaluator& ev, const Value& fn, Span fn_span, Span use_span,
                              ir::Program& out) {
  ShadingCompiler c(ev, use_span);
  bool ok = c.run(fn, fn_span, out);
  c.flush();
  return ok;
}

const Value* find_value(Evaluator& ev, const Env& env, const std::string& name) {
  std::int32_t sym = ShadingCompiler::intern(ev, name);
  for (const Env* e = &env; e; e = e->parent.get())
    if (const Binding* b = e->find_local(sym)) return &b->value;
  return nullptr;
}

BuiltinOps builtin_ops(int id) {
  const BuiltinRow* r = builtin_row(id);
  if (!r) return {};
  return {r->s, r->v, true};
}

}  // namespace snell::compile
