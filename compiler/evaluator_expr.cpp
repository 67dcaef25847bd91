// Expression evaluation: operators, calls, vectors, components, constructors.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "compiler/arith.hpp"
#include "compiler/builtins.hpp"
#include "compiler/evaluator.hpp"
#include "compiler/povray_forms.hpp"
#include "compiler/properties.hpp"
#include "compiler/shading_function.hpp"

namespace snell::compile {

using lang::DiagKind;
using lang::Expr;
using lang::ExprKind;
using lang::Span;
using lang::TokenKind;

Value Evaluator::eval_standalone(const Expr& expr) {
  return eval(expr, std::make_shared<Env>());
}

namespace {
// One shared closure per builtin: reading `sqrt` allocates nothing.
const std::vector<Value>& builtin_values() {
  static const std::vector<Value> all = [] {
    std::vector<Value> v;
    for (int i = 0; i < builtin_count(); ++i) {
      auto c = std::make_shared<Closure>();
      c->builtin = i;
      c->name = std::string(builtin_info(i).name);
      v.push_back(Value::of_function(std::move(c)));
    }
    return v;
  }();
  return all;
}
}  // namespace

const Value& Evaluator::builtin_value(int id) {
  return builtin_values()[id];
}
const Closure& Evaluator::builtin_closure(int id) {
  return builtin_values()[id].func();
}

Value Evaluator::eval(const Expr& e, const std::shared_ptr<Env>& env) {
  if ((e.kind == ExprKind::Binary || e.kind == ExprKind::Call || e.kind == ExprKind::Unary) &&
      !e.not_numeric) {
    std::uint64_t saved = steps_;
    double r;
    if (fast_number(e, env.get(), r) && steps_ <= step_budget_ && !aborted_) [[likely]]
      return Value::number(r);
    steps_ = saved;
  }
  if (!step(e.span)) return Value::error();
  switch (e.kind) {
    case ExprKind::Number:
      return Value::number(e.number);
    case ExprKind::Bool:
      return Value::boolean(e.boolean);
    case ExprKind::String:
      if (e.text.size() > kMaxStringLength) {  // a literal is a string too
        error(DiagKind::StringTooLong, e.span,
              "this string is " + std::to_string(e.text.size()) +
                  " characters long; strings hold at most " + std::to_string(kMaxStringLength));
        return Value::error();
      }
      return Value::string(e.text);
    case ExprKind::Name:
      return eval_name(e, env);
    case ExprKind::Vector:
      return eval_vector(e, env);
    case ExprKind::Unary:
      return eval_unary(e, env);
    case ExprKind::Binary:
      return eval_binary(e, env);
    case ExprKind::Call: {
      Value v = eval_call(e, env, false);
      if (v.type == Type::None) {
        error(DiagKind::MissingReturn, e.span, "this call returns no value")
            .note("a block-form function returns a value only through 'return EXPR;'");
        return Value::error();
      }
      return v;
    }
    case ExprKind::Component:
      return eval_component(e, env);
    case ExprKind::Constructor:
      return eval_constructor(e, env);
    case ExprKind::Object:
      return eval_object_expr(e, env);
    case ExprKind::Error:
      return Value::error();
  }
  return Value::error();
}

Value Evaluator::eval_name(const Expr& e, const std::shared_ptr<Env>& env) {
  std::int32_t sym = symbol_of(e);
  for (const Env* s = env.get(); s; s = s->parent.get())
    if (const Binding* b = s->find_local(sym)) return b->value;
  if (int id = symbol_builtin_[sym]; id >= 0) return builtin_value(id);
  for (const Env* s = env.get(); s; s = s->parent.get())
    if (s->failed_import) return Value::error();  // reported at the import
  // A broken statement may have defined it: its syntax error is the report.
  if (unsure_names_.count(e.text)) return Value::error();
  const std::string message = "'" + e.text + "' is not defined";
  if (!undefined_at_.insert(std::uint64_t(e.span.file) << 32 | e.span.begin).second) {
    error(DiagKind::UndefinedName, e.span, message);
    return Value::error();
  }
  // A guess compares the name with every visible one: past kGuessWork names in
  // all (or once the errors are no longer kept) there are no more guesses, so a
  // file of 50 000 lets of undefined names is not quadratic in them.
  std::string guess;
  if (!diags_.limit_reached() && guess_work_ < kGuessWork) {
    std::vector<std::string_view> visible;
    for (const Env* s = env.get(); s; s = s->parent.get())
      for (const Binding& b : s->vars) visible.push_back(symbol_names_[b.symbol]);
    for (int i = 0; i < builtin_count(); ++i) visible.push_back(builtin_info(i).name);
    // A misspelt constructor (`material difuse 0.5`) reads as a name.
    for (std::string_view c : lang::constructor_names()) visible.push_back(c);
    guess_work_ += visible.size();
    guess = lang::closest_match(e.text, visible);
  }
  auto d = error(DiagKind::UndefinedName, e.span, message);
  if (const char* pov = povray_note(PovrayWordKind::Name, e.text))
    d.note(pov);
  else if (lang::is_constructor_name(e.text))
    // Only where no argument follows, or one starting with '-' (docs/language.md:
    // then it is an ordinary name, and `diffuse - c` a subtraction).
    d.note("'" + e.text + "' takes its argument after it ('" + e.text + " { ... }' or '" + e.text +
           " EXPR'); an argument that starts with '-' goes in parentheses: '" + e.text +
           " (-c + 1)'");
  else if (!guess.empty())
    d.note("did you mean '" + guess + "'?");
  else if (find_block(e.text))
    d.note("'" + e.text + "' is a block keyword; write '" + e.text + " { ... }'");
  return Value::error();
}

Value Evaluator::eval_vector(const Expr& e, const std::shared_ptr<Env>& env) {
  double c[3] = {0, 0, 0};
  bool bad = false;
  for (std::size_t i = 0; i < e.args.size(); ++i) {
    // Numeric components skip the Value (as eval() would, see eval_number).
    if (const Expr& a = *e.args[i]; !a.not_numeric && i < 3) {
      std::uint64_t saved = steps_;
      if (fast_number(a, env.get(), c[i]) && steps_ <= step_budget_ && !aborted_) [[likely]]
        continue;
      steps_ = saved;
    }
    Value v = eval(*e.args[i], env);
    if (v.is_error()) {
      bad = true;
    } else if (v.type != Type::Number && v.type != Type::Bool) {
      error(DiagKind::TypeMismatch, e.args[i]->span,
            "a vector's components must be numbers, not " + a_type(v.type));
      bad = true;
    } else if (i < 3) {
      // A bool component is 1 or 0: §3 writes `<(a > b), 1, 2>` as a vector, and POV-Ray
      // users expect a comparison to be a number there. Nowhere else is a bool a number.
      c[i] = v.n;
    }
  }
  // A component in error (reported already: the parser cut the vector short where
  // nesting ran too deep, or a name is undefined) says nothing sure about the
  // count: a 3000-deep vector gave a thousand arity errors after its one.
  if ((e.args.size() < 2 || e.args.size() > 3) && !bad) {
    error(DiagKind::BadVectorArity, e.span,
          "a vector has 2 or 3 components, not " + std::to_string(e.args.size()));
    return Value::error();
  }
  if (bad) return Value::error();
  return e.args.size() == 2 ? Value::vec2(c[0], c[1]) : Value::vec3({c[0], c[1], c[2]});
}

Value Evaluator::eval_unary(const Expr& e, const std::shared_ptr<Env>& env) {
  Value v = eval(*e.args[0], env);
  if (v.is_error()) return v;
  if (e.op == TokenKind::Bang) {
    if (v.type != Type::Bool) {
      error(DiagKind::TypeMismatch, e.args[0]->span, "'!' needs a bool, not " + a_type(v.type));
      return Value::error();
    }
    return Value::boolean(!v.truth());
  }
  if (v.type == Type::Number) return Value::number(-v.n);
  if (v.is_vector()) {
    v.v = -v.v;
    return v;
  }
  error(DiagKind::TypeMismatch, e.args[0]->span,
        "'-' needs a number or a vector, not " + a_type(v.type));
  return Value::error();
}

Value Evaluator::eval_binary(const Expr& e, const std::shared_ptr<Env>& env) {
  TokenKind op = e.op;
  auto spelling = [op] { return std::string(lang::token_spelling(op)); };
  if (op == TokenKind::AmpAmp || op == TokenKind::PipePipe) {
    Value a = eval(*e.args[0], env);
    if (a.is_error()) return a;
    if (a.type != Type::Bool) {
      error(DiagKind::TypeMismatch, e.args[0]->span,
            "'" + spelling() + "' needs bools, not " + a_type(a.type));
      return Value::error();
    }
    if ((op == TokenKind::AmpAmp) != a.truth()) return a;  // short circuit
    Value b = eval(*e.args[1], env);
    if (b.is_error()) return b;
    if (b.type != Type::Bool) {
      error(DiagKind::TypeMismatch, e.args[1]->span,
            "'" + spelling() + "' needs bools, not " + a_type(b.type));
      return Value::error();
    }
    return b;
  }
  Value a = eval(*e.args[0], env);
  Value b = eval(*e.args[1], env);
  if (a.type == Type::Number && b.type == Type::Number && is_arith(op)) [[likely]] {
    double r = arith(op, a.n, b.n);
    if (std::isfinite(r)) [[likely]]
      return Value::number(r);
  }
  if (a.is_error() || b.is_error()) return Value::error();
  auto mismatch = [&](const char* what) {
    error(DiagKind::TypeMismatch, e.span,
          "'" + spelling() + "' " + what + ", not " + a_type(a.type) + " and " + a_type(b.type))
        .note(e.args[0]->span, "left operand: " + std::string(type_name(a.type)))
        .note(e.args[1]->span, "right operand: " + std::string(type_name(b.type)));
    return Value::error();
  };
  if (is_arith(op)) {
    if (a.type == Type::String && b.type == Type::String && op == TokenKind::Plus) {
      // extension: string concatenation
      if (a.str().size() + b.str().size() > kMaxStringLength) {
        error(DiagKind::StringTooLong, e.span,
              "this string would be " + std::to_string(a.str().size() + b.str().size()) +
                  " characters long; strings hold at most " + std::to_string(kMaxStringLength));
        return Value::error();
      }
      if (!charge(e.span, (a.str().size() + b.str().size()) / kStringBytesPerStep))
        return Value::error();
      const std::int64_t live = live_string_bytes() + std::int64_t(a.str().size() + b.str().size());
      if (live > kMaxLiveStringBytes) {
        error(DiagKind::StringTooLong, e.span,
              "the strings in use would hold " + std::to_string(live) +
                  " bytes with this one; they hold at most " + std::to_string(kMaxLiveStringBytes) +
                  " in all")
            .note("long strings kept in each of many nested calls add up");
        aborted_ = true;
        return Value::error();
      }
      return Value::string(a.str() + b.str());
    }
    bool an = a.type == Type::Number, bn = b.type == Type::Number;
    if ((!an && !a.is_vector()) || (!bn && !b.is_vector()))
      return mismatch("needs numbers or vectors");
    if (an && bn) {
      Value r = Value::number(arith(op, a.n, b.n));
      return finite_ok(r, e) ? r : Value::error();
    }
    if (a.is_vector() && b.is_vector() && a.type != b.type)
      return mismatch("needs vectors of one size");
    Value r = a.is_vector() ? a : b;
    for (int i = 0; i < r.dims(); ++i) {
      double x = an ? a.n : a.v[i];
      double y = bn ? b.n : b.v[i];
      r.v[i] = arith(op, x, y);
    }
    return finite_ok(r, e) ? r : Value::error();
  }
  switch (op) {
    case TokenKind::Less:
    case TokenKind::LessEqual:
    case TokenKind::Greater:
    case TokenKind::GreaterEqual:
      if (a.type != Type::Number || b.type != Type::Number) return mismatch("compares numbers");
      if (op == TokenKind::Less) return Value::boolean(a.n < b.n);
      if (op == TokenKind::LessEqual) return Value::boolean(a.n <= b.n);
      if (op == TokenKind::Greater) return Value::boolean(a.n > b.n);
      return Value::boolean(a.n >= b.n);
    case TokenKind::EqualEqual:
    case TokenKind::BangEqual: {
      bool eq;
      if (a.type == Type::Number && b.type == Type::Number)
        eq = a.n == b.n;
      else if (a.type == Type::Bool && b.type == Type::Bool)
        eq = a.n == b.n;
      else if (a.type == Type::String && b.type == Type::String) {
        if (!charge(e.span, std::min(a.str().size(), b.str().size()) / kStringBytesPerStep))
          return Value::error();
        eq = a.str() == b.str();
      } else if (a.is_vector() && a.type == b.type)
        eq = a.v == b.v;
      else
        return mismatch("compares two numbers, bools, strings or vectors of one size");
      return Value::boolean(op == TokenKind::EqualEqual ? eq : !eq);
    }
    default:
      break;
  }
  return Value::error();
}

Value Evaluator::eval_component(const Expr& e, const std::shared_ptr<Env>& env) {
  Value v = eval(*e.args[0], env);
  if (v.is_error()) return v;
  int idx = e.text == "x" ? 0 : e.text == "y" ? 1 : e.text == "z" ? 2 : -1;
  if (!v.is_vector()) {
    error(DiagKind::TypeMismatch, e.args[0]->span,
          "'." + e.text + "' needs a vector, not " + a_type(v.type));
    return Value::error();
  }
  if (idx < 0 || idx >= v.dims()) {
    error(DiagKind::BadComponent, e.span, a_type(v.type) + " has no component '" + e.text + "'")
        .note(v.dims() == 2 ? "its components are .x and .y" : "its components are .x, .y and .z");
    return Value::error();
  }
  return Value::number(v.v[idx]);
}

Value Evaluator::eval_call(const Expr& e, const std::shared_ptr<Env>& env, bool as_statement) {
  // A called name is resolved in place: the closure is used where it is bound,
  // not copied (a copy costs two atomic reference-count updates per call).
  const Value* callee_ref = nullptr;
  Value callee_value;
  const Closure* builtin_fn = nullptr;
  if (const Expr& f = *e.args[0]; f.kind == ExprKind::Name) {
    if (!step(f.span)) return Value::error();
    std::int32_t sym = symbol_of(f);
    for (const Env* sc = env.get(); sc && !callee_ref; sc = sc->parent.get())
      if (const Binding* b = sc->find_local(sym)) callee_ref = &b->value;
    if (!callee_ref && symbol_builtin_[sym] >= 0)
      builtin_fn = &builtin_closure(symbol_builtin_[sym]);
  }
  if (!callee_ref && !builtin_fn) {
    callee_value = eval(*e.args[0], env);
    callee_ref = &callee_value;
  }
  if (builtin_fn) {
    callee_value.type = Type::Function;
    callee_ref = &callee_value;
  }
  const Value& callee = *callee_ref;
  // Argument lists come from a pool indexed by nesting, so a call allocates
  // nothing once the pool is warm (deque: growing it keeps references valid).
  if (args_pool_.size() <= args_depth_) args_pool_.emplace_back();
  std::vector<Value>& args = args_pool_[args_depth_++];
  args.clear();
  struct Release {
    std::size_t& depth;
    ~Release() { --depth; }
  } release{args_depth_};
  bool bad = callee.is_error();
  for (std::size_t i = 1; i < e.args.size(); ++i) {
    args.push_back(eval(*e.args[i], env));
    if (args.back().is_error()) bad = true;
    if (args.back().type == Type::None) {
      error(DiagKind::MissingReturn, e.args[i]->span, "this argument has no value");
      bad = true;
    }
  }
  if (callee.is_error()) return callee;
  if (callee.type != Type::Function) {
    error(DiagKind::NotCallable, e.args[0]->span, a_type(callee.type) + " cannot be called");
    return Value::error();
  }
  const Closure& fn = builtin_fn ? *builtin_fn : callee.func();
  int arity =
      fn.builtin >= 0 ? builtin_info(fn.builtin).arity : static_cast<int>(fn.def->params.size());
  if (static_cast<int>(args.size()) != arity) {
    auto d = error(DiagKind::WrongArgumentCount, e.span,
                   "'" + fn.name + "' takes " + std::to_string(arity) + " argument" +
                       (arity == 1 ? "" : "s") + ", not " + std::to_string(args.size()));
    if (fn.builtin >= 0)
      d.note(std::string(builtin_info(fn.builtin).signature));
    else
      d.note(fn.def->name_span, "defined here");
    return Value::error();
  }
  if (bad) return Value::error();
  if (fn.builtin >= 0) {
    BuiltinError err;
    Value r = call_builtin(fn.builtin, args.data(), err);
    if (r.is_error()) {
      Span at = err.arg >= 0 ? e.args[err.arg + 1]->span : e.span;
      error(err.kind, at, "'" + fn.name + "' " + err.message)
          .note(std::string(builtin_info(fn.builtin).signature));
      return r;
    }
    return finite_ok(r, e) ? r : Value::error();
  }
  Value r = call_user(fn, args, e);
  if (as_statement) return r;
  return r;
}

Value Evaluator::call_user(const Closure& fn, std::vector<Value>& args, const Expr& call) {
  if (depth_ >= kMaxCallDepth || stack_low(stack_floor_)) {
    error(DiagKind::RecursionLimit, call.span,
          depth_ >= kMaxCallDepth
              ? "calls are nested more than " + std::to_string(kMaxCallDepth) +
                    " deep here (endless recursion?)"
              : "calls are nested " + std::to_string(depth_) +
                    " deep here, each in deeply nested expressions: more than the "
                    "evaluator's stack holds (endless recursion?)")
        .note(fn.def->name_span, "'" + fn.name + "' is defined here");
    aborted_ = true;
    return Value::error();
  }
  const lang::Stmt& def = *fn.def;
  auto scope = std::make_shared<Env>();
  scope->parent = fn.env;
  scope->vars.reserve(args.size());
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (on_define_) [[unlikely]]
      on_define_(def.param_spans[i], args[i]);
    scope->vars.push_back({fn.params[i], std::move(args[i]), def.param_spans[i], false});
  }
  if (depth_ == 0) outer_call_ = call.span;
  ++depth_;
  Value result;
  if (!def.exprs.empty()) {
    result = eval(*def.exprs[0], scope);
  } else {
    Frame frame;
    frame.in_function = true;
    exec_block(def.body, scope, frame);
    result = std::move(frame.result);
  }
  --depth_;
  if (aborted_) return Value::error();
  return result;
}

Value Evaluator::eval_constructor(const Expr& e, const std::shared_ptr<Env>& env) {
  const BlockInfo* block = symbol_block_[symbol_of(e)];
  if (!block || block->kind != BlockKind::Constructor) return Value::error();  // parser-checked
  bool ok = true;
  PropsLease lease(*this);
  std::vector<EvaluatedProp>& props = lease.list();
  if (e.block) {
    eval_props(*block, *e.block, e.span, env, props, ok);
  } else if (!e.args.empty()) {
    // Positional form. Several parameters come as a vector literal of exactly that
    // many elements (`dielectric <1.5, <0.1, 0.2, 0.3>>`); any other argument is
    // the first parameter (`dielectric 1.5`, `glossy <1, 0.9, 0.8>`), or a 2-vector
    // value split over two parameters (`let g = <1.5, 0.1>; dielectric g`).
    const Expr& arg = *e.args[0];
    std::size_t n = block->props.size();
    auto take = [&](std::size_t i, const Expr& ex, Value v, bool evaluated) {
      EvaluatedProp p;
      p.info = block->props[i];
      p.name_span = ex.span;
      p.value_span = ex.span;
      if (!evaluated) {
        if (!eval_prop_value(*p.info, ex, env, p.value)) return false;
      } else {
        p.value = std::move(v);
        if (value_ok(*p.info, p.value)) [[likely]] {
          props.push_back(std::move(p));
          return true;
        }
        bool integral = false;
        std::string msg = check_value(*p.info, p.value, &integral);
        if (!msg.empty()) {
          error(integral ? DiagKind::NotAnInteger : DiagKind::InvalidValue, ex.span,
                "'" + e.text + "': " + msg);
          return false;
        }
      }
      props.push_back(std::move(p));
      return true;
    };
    if (n > 1 && arg.kind == ExprKind::Vector && arg.args.size() == n) {
      for (std::size_t i = 0; i < n; ++i) ok &= take(i, *arg.args[i], {}, false);
    } else {
      Value v = eval(arg, env);
      if (v.is_error()) return v;
      if (n == 2 && v.type == Type::Vec2) {
        ok &= take(0, arg, Value::number(v.v.x), true);
        ok &= take(1, arg, Value::number(v.v.y), true);
      } else {
        ok &= take(0, arg, std::move(v), true);
      }
    }
    if (ok)
      for (const PropInfo* info : block->props) {
        bool given = false;
        for (const EvaluatedProp& p : props) given |= p.info == info;
        if (!given) {
          EvaluatedProp d;
          d.info = info;
          d.value = info->default_value;
          props.push_back(std::move(d));
        }
      }
  }
  if (!ok) {
    // A colour map's own errors are independent of the other properties' (§10), and
    // so are an image's missing file (`image { file "nope.png" mapping "planer" }`)
    // and a shading function's faults.
    if (block->pattern_kind >= 0) {
      for (const EvaluatedProp& p : props) {
        if (p.info->name == "color_map") {
          std::vector<ir::ColorStop> map;
          color_map_of(p, diags_, map);
        } else if (p.info->name == "file" && p.value.type == Type::String) {
          std::uint32_t unused = 0;
          builder_.add_image(p.value.str(), p.value_span, unused);
        } else if (p.info->type == PropType::Function) {
          // `pattern { function f octaves 0 }`: f's own faults (its parameters,
          // its result, a scene item it makes) are said too.
          ir::Program unused;
          compile_shading_function(*this, p.value, p.value_span, e.span, unused);
        }
      }
    }
    return Value::error();
  }
  // A mirror or glossy surface that reflects more than it receives is legal, but
  // two of them facing each other multiply without bound (to inf, then dropped
  // samples): say so once per place.
  if (block->name == "mirror" || block->name == "glossy")
    for (const EvaluatedProp& p : props) {
      if (p.info->name != "color" || p.value.type != Type::Vec3) continue;
      double m = std::fmax(p.value.v.x, std::fmax(p.value.v.y, p.value.v.z));
      std::uint64_t key = (std::uint64_t(p.value_span.file) << 32) | p.value_span.begin;
      if (m > 1 && p.value_span.end > p.value_span.begin && energy_warned_.insert(key).second)
        error(DiagKind::EnergyGain, p.value_span,
              fmt::format("'{}' reflects more light than it receives (a colour component of "
                          "{:g} > 1): facing reflections grow without bound",
                          block->name, m));
    }
  Value made = make_constructor_value(*block, props, diags_);
  // §15 `pattern { function f }`: f compiled here, where the evaluator that owns its
  // scope is (lowering sees only values).
  if (made.type == Type::Pattern && std::holds_alternative<ir::FunctionPattern>(made.pat().pattern))
    for (const EvaluatedProp& p : props)
      if (p.info->type == PropType::Function) {
        ir::Texture t = made.pat();
        if (!compile_shading_function(*this, p.value, p.value_span, e.span,
                                      std::get<ir::FunctionPattern>(t.pattern).program))
          return Value::error();
        return Value::of_pattern(std::move(t));
      }
  // §17 `image`: its file checked and numbered by the scene builder (exit 3 when it
  // does not exist), as a mesh's is.
  if (made.type == Type::Pattern && std::holds_alternative<ir::ImageTexture>(made.pat().pattern))
    for (const EvaluatedProp& p : props)
      if (p.info->name == "color_map") {
        // Every pattern takes one (§15), but an image gives colours, not values.
        diags_.report(DiagKind::UnusedColorMap, p.name_span,
                      "an image gives its own colours: this 'color_map' is not used");
      }
  if (made.type == Type::Pattern && std::holds_alternative<ir::ImageTexture>(made.pat().pattern))
    for (const EvaluatedProp& p : props)
      if (p.info->name == "file") {
        ir::Texture t = made.pat();
        if (!builder_.add_image(p.value.str(), p.value_span,
                                std::get<ir::ImageTexture>(t.pattern).image))
          return Value::error();
        return Value::of_pattern(std::move(t));
      }
  return made;
}

}  // namespace snell::compile
