#include "compiler/evaluator.hpp"

#include <algorithm>
#include <bitset>
#include <cmath>

#include "compiler/builtins.hpp"
#include "compiler/povray_forms.hpp"
#include "compiler/properties.hpp"

namespace snell::compile {

using lang::DiagKind;
using lang::Expr;
using lang::ExprKind;
using lang::Span;
using lang::Stmt;
using lang::StmtKind;
using lang::TokenKind;

Evaluator::Evaluator(const lang::SourceManager& sources, lang::DiagnosticEngine& diags,
                     SceneBuilder& builder, ImportLoader loader, std::uint64_t step_budget)
    : sources_(sources),
      diags_(diags),
      builder_(builder),
      loader_(std::move(loader)),
      step_budget_(step_budget) {}

std::int32_t Evaluator::intern(const std::string& name) {
  auto [it, inserted] =
      symbol_ids_.try_emplace(name, static_cast<std::int32_t>(symbol_names_.size()));
  if (inserted) {
    symbol_names_.push_back(name);
    symbol_builtin_.push_back(find_builtin(name));
    symbol_block_.push_back(find_block(name));
    symbol_bound_.push_back(0);
  }
  return it->second;
}

// An error costs kErrorSteps of the step budget: building its message and finding
// it a repeat takes about as long as 25 plain steps (a loop whose body fails each
// time: 350 ns an iteration for two errors, where a step is 7 ns). Without the
// charge, `for i in 0 .. 1e9 { box {} }` ran for 72 s before its budget stopped it,
// and a language server analysing it spent 0.6 s on each keystroke.
lang::DiagBuilder Evaluator::error(DiagKind kind, Span span, std::string message) {
  steps_ += kErrorSteps + message.size() / kStringBytesPerStep;
  lang::DiagBuilder d = diags_.report(kind, span, std::move(message));
  if (depth_ > 0 && outer_call_.end > outer_call_.begin)
    d.note(outer_call_, "in the call from here");
  return d;
}

bool Evaluator::step_exhausted(Span at) {
  if (aborted_) return false;
  if (steps_ > step_budget_) {
    error(DiagKind::StepBudget, at,
          "evaluation stopped here after " + std::to_string(step_budget_) +
              " steps; the program runs too long (an endless or very large loop?)")
        .note("raise the budget with --max-steps N if the scene really needs it");
    aborted_ = true;
    return false;
  }
  return true;
}

void Evaluator::define(const std::shared_ptr<Env>& env, std::int32_t symbol, Value v, Span span) {
  symbol_bound_[symbol] = 1;
  if (on_define_) on_define_(span, v);
  if (Binding* old = env->find_local(symbol)) {
    // An imported name is a library default: the file's own definition replaces it
    // (`import "materials.scn"; let glass = ...;` is the core's own example).
    if (old->imported) {
      *old = {symbol, std::move(v), span, false};
      return;
    }
    error(DiagKind::Redefinition, span,
          "'" + symbol_names_[symbol] + "' is already defined in this scope")
        .note(old->span, "first defined here");
    return;
  }
  env->vars.push_back({symbol, std::move(v), span, false});
}

void Evaluator::report_non_finite(const Value& v, const Expr& e) {
  bool nan = false;
  if (v.type == Type::Number) nan = std::isnan(v.n);
  if (v.type == Type::Vec2 || v.type == Type::Vec3)
    nan = std::isnan(v.v.x) || std::isnan(v.v.y) || std::isnan(v.v.z);
  // glibc prints a NaN as "-nan" or "nan" by its sign bit: say what it is instead.
  std::string shown = v.type == Type::Number && nan ? "NaN" : to_string(v);
  error(DiagKind::NonFiniteValue, e.span,
        "this expression evaluates to " + shown + " (not a finite number)")
      .note(nan ? "an operation with no real result: the square root or logarithm of a negative "
                  "number, 0 / 0, x % 0, asin or acos outside [-1, 1], or inf - inf"
                : "an overflow or a division by zero: a number beyond ±1.8e308, x / 0, or log(0)");
}

// ---------------------------------------------------------------------------
// Statements

void Evaluator::predeclare(const std::string& name, Value value) {
  std::int32_t sym = intern(name);
  if (Binding* b = prelude_->find_local(sym))
    b->value = std::move(value);
  else
    prelude_->vars.push_back({sym, std::move(value), Span{}, false});
}

std::shared_ptr<Env> Evaluator::run_file(const lang::Program& program) {
  unsure_names_.insert(program.unsure_names.begin(), program.unsure_names.end());
  auto env = std::make_shared<Env>();
  env->parent = prelude_;
  Frame frame;
  running_.push_back(program.file);
  exec_block(program.statements, env, frame);
  running_.pop_back();
  return env;
}

Evaluator::Flow Evaluator::exec_block(const std::vector<lang::StmtPtr>& stmts,
                                      const std::shared_ptr<Env>& env, Frame& frame) {
  for (const lang::StmtPtr& s : stmts) {
    if (aborted_) return Flow::Return;
    if (exec(*s, env, frame) == Flow::Return) return Flow::Return;
  }
  return Flow::Normal;
}

Evaluator::Flow Evaluator::exec(const Stmt& s, const std::shared_ptr<Env>& env, Frame& frame) {
  if (!step(s.span)) return Flow::Return;
  switch (s.kind) {
    case StmtKind::Let:
      exec_let(s, env);
      return Flow::Normal;
    case StmtKind::Fn:
      exec_fn(s, env);
      return Flow::Normal;
    case StmtKind::Return:
      if (!frame.in_function) {
        error(DiagKind::ReturnOutsideFunction, s.span, "'return' outside a function body");
        return Flow::Normal;
      }
      frame.result = s.exprs.empty() ? Value::none() : eval(*s.exprs[0], env);
      return Flow::Return;
    case StmtKind::For:
      return exec_for(s, env, frame);
    case StmtKind::If:
      return exec_if(s, env, frame);
    case StmtKind::Import:
      exec_import(s, env);
      return Flow::Normal;
    case StmtKind::ExprStmt: {
      const Expr& e = *s.exprs[0];
      if (e.kind == ExprKind::Call) {
        // §13: an object value adds nothing to the scene; a call that returns one
        // as a statement is most likely meant to place it.
        Value r = eval_call(e, env, /*as_statement=*/true);
        if (r.type == Type::Object) {
          std::string_view call =
              sources_.file(e.span.file).text().substr(e.span.begin, e.span.end - e.span.begin);
          if (call.size() > 40 || call.find('\n') != std::string_view::npos) call = "...";
          error(DiagKind::DiscardedObject, e.span,
                "the object this call returns is not placed (§13: an object value adds "
                "nothing to the scene)")
              .note("place it with 'object { " + std::string(call) + " }'");
        }
      } else if (e.kind != ExprKind::Error) {
        Value v = eval(e, env);
        if (!v.is_error())
          error(DiagKind::ValueAsStatement, e.span,
                "this " + std::string(type_name(v.type)) +
                    " is computed and thrown away; only a call can stand as a statement");
      }
      return Flow::Normal;
    }
    case StmtKind::Item:
      exec_item(s, env);
      return Flow::Normal;
    case StmtKind::Background: {
      if (inside_group_error("background", s.span)) return Flow::Normal;
      Value v = eval(*s.exprs[0], env);
      const Span at = s.name_span.end > s.name_span.begin ? s.name_span : s.span;
      if (v.is_error()) {
        builder_.failed_singleton("background", at);
        return Flow::Normal;
      }
      PropInfo color{
          "background", "background", PropType::ColorOrPattern, Check::NonNegative, 0, {}};
      std::string msg = check_value(color, v);
      if (!msg.empty()) {
        error(DiagKind::InvalidValue, s.exprs[0]->span, msg);
        builder_.failed_singleton("background", at);
        return Flow::Normal;
      }
      builder_.set_background(v, at);
      return Flow::Normal;
    }
    case StmtKind::Error:
      return Flow::Normal;
  }
  return Flow::Normal;
}

void Evaluator::exec_let(const Stmt& s, const std::shared_ptr<Env>& env) {
  Value v = eval(*s.exprs[0], env);
  if (v.type == Type::None) {
    error(DiagKind::MissingReturn, s.exprs[0]->span,
          "this call returns nothing to bind to '" + s.name + "'");
    v = Value::error();
  }
  if (v.type == Type::Object) builder_.check_value(v.object());
  define(env, symbol_of(s), std::move(v), s.name_span);
}

Evaluator::~Evaluator() {
  for (const std::weak_ptr<Env>& w : closure_scopes_)
    if (std::shared_ptr<Env> scope = w.lock()) scope->clear();
}

void Evaluator::exec_fn(const Stmt& s, const std::shared_ptr<Env>& env) {
  if (closure_scopes_.empty() || closure_scopes_.back().lock() != env)
    closure_scopes_.push_back(env);
  auto closure = std::make_shared<Closure>();
  closure->def = &s;
  closure->env = env;  // lexical scope; the function sees itself through it
  closure->name = s.name;
  for (const std::string& p : s.params) {
    closure->params.push_back(intern(p));
    symbol_bound_[closure->params.back()] = 1;
  }
  // By symbol: comparing every pair of names took 6 s for 100 000 parameters.
  std::unordered_map<std::int32_t, std::size_t> first;
  for (std::size_t i = 0; i < s.params.size(); ++i)
    if (auto [at, fresh] = first.emplace(closure->params[i], i); !fresh)
      error(DiagKind::Redefinition, s.param_spans[i],
            "parameter '" + s.params[i] + "' is named twice")
          .note(s.param_spans[at->second], "first named here");
  define(env, symbol_of(s), Value::of_function(std::move(closure)), s.name_span);
}

Evaluator::Flow Evaluator::exec_for(const Stmt& s, const std::shared_ptr<Env>& env, Frame& frame) {
  Value from = eval(*s.exprs[0], env);
  Value to = eval(*s.exprs[1], env);
  Value by = s.exprs.size() > 2 ? eval(*s.exprs[2], env) : Value::number(1);
  bool ok = true;
  for (std::size_t i = 0; i < 3 && i < s.exprs.size(); ++i) {
    const Value& v = i == 0 ? from : i == 1 ? to : by;
    if (v.is_error()) {
      ok = false;
    } else if (v.type != Type::Number) {
      error(DiagKind::TypeMismatch, s.exprs[i]->span,
            std::string(i == 2 ? "the step" : "a loop bound") + " must be a number, not " +
                a_type(v.type));
      ok = false;
    }
  }
  if (!ok) return Flow::Normal;
  if (by.n == 0) {
    error(DiagKind::ZeroStep, s.exprs[2]->span, "a for loop's step must not be 0");
    return Flow::Normal;
  }
  std::int32_t sym = symbol_of(s);
  symbol_bound_[sym] = 1;
  hint_objects(s, from.n, to.n, by.n);
  // NAME = from + k·step, computed afresh each time so no rounding accumulates.
  std::shared_ptr<Env> scope;
  for (std::uint64_t k = 0;; ++k) {
    double x = from.n + static_cast<double>(k) * by.n;
    if (by.n > 0 ? !(x < to.n) : !(x > to.n)) break;
    if (!step(s.span)) return Flow::Return;
    // Each iteration has a fresh scope; the previous one is recycled unless a
    // closure defined in the body still holds it.
    if (!scope || scope.use_count() > 1) {
      scope = std::make_shared<Env>();
      scope->parent = env;
    } else {
      scope->clear();
    }
    scope->vars.push_back({sym, Value::number(x), s.name_span, false});
    if (exec_block(s.body, scope, frame) == Flow::Return) return Flow::Return;
  }
  return Flow::Normal;
}

// Tells the builder how many objects a loop is about to make when its body
// makes some directly (not under an `if` or in a call): iterations times the
// object items of the body. Only a hint for memory; see expect_objects.
void Evaluator::hint_objects(const Stmt& loop, double from, double to, double by) {
  double trips = by > 0 ? std::ceil((to - from) / by) : std::ceil((from - to) / -by);
  if (!(trips >= 1024)) return;  // small loops (and NaN) grow the vector as usual
  std::size_t items = 0;
  for (const lang::StmtPtr& st : loop.body) {
    if (st->kind != StmtKind::Item) continue;
    const BlockInfo* b = symbol_block_[symbol_of(*st)];
    items += b && b->is_object;
  }
  if (items == 0) return;
  // Each object item takes at least one evaluation step, so the loop cannot make
  // more objects than the steps left (a fuzzed `for k in 0 .. 1e37` under a small
  // budget reserved room for 20 M shapes, 2.2 GB, before the budget stopped it).
  double left = step_budget_ > steps_ ? static_cast<double>(step_budget_ - steps_) : 0;
  double n =
      std::min({trips * static_cast<double>(items), static_cast<double>(kMaxSceneObjects), left});
  builder_.expect_objects(static_cast<std::size_t>(n));
}

Evaluator::Flow Evaluator::exec_if(const Stmt& s, const std::shared_ptr<Env>& env, Frame& frame) {
  for (std::size_t i = 0; i < s.branches.size(); ++i) {
    Value c = eval(*s.exprs[i], env);
    if (c.is_error()) return Flow::Normal;
    if (c.type != Type::Bool) {
      error(DiagKind::TypeMismatch, s.exprs[i]->span,
            "a condition must be a bool, not " + a_type(c.type))
          .note("there is no truthiness: write a comparison such as 'x != 0'");
      return Flow::Normal;
    }
    if (c.truth()) {
      auto scope = std::make_shared<Env>();
      scope->parent = env;
      return exec_block(s.branches[i], scope, frame);
    }
  }
  if (s.has_else) {
    auto scope = std::make_shared<Env>();
    scope->parent = env;
    return exec_block(s.else_body, scope, frame);
  }
  return Flow::Normal;
}

void Evaluator::exec_import(const Stmt& s, const std::shared_ptr<Env>& env) {
  const ImportedFile* f =
      loader_(s.name, s.name_span.end > s.name_span.begin ? s.name_span : s.span);
  if (!f || (!f->program && f->binds_unknown)) {
    env->failed_import = true;
    return;
  }
  if (!f->program) {  // syntax errors, reported: its names are unsure, no others
    unsure_names_.insert(f->binds.begin(), f->binds.end());
    return;
  }
  for (std::size_t i = 0; i < running_.size(); ++i) {
    if (running_[i] != f->file) continue;
    std::string chain;
    for (std::size_t j = i; j < running_.size(); ++j)
      chain += sources_.file(running_[j]).path() + " -> ";
    chain += sources_.file(f->file).path();
    // §9: a second import of the same file does nothing, and a file still running
    // has been imported. A warning, since a name it was meant to bind is then
    // undefined here (and reported so).
    error(DiagKind::ImportCycle, s.span,
          "import cycle: " + chain + ": '" + sources_.file(f->file).path() +
              "' is already running, so this import does nothing (§9)");
    return;
  }
  std::shared_ptr<Env> exported;
  if (auto it = imported_.find(f->file); it != imported_.end()) {
    exported = it->second;
  } else {
    exported = run_file(*f->program);
    imported_[f->file] = exported;
  }
  // The importing file's own definitions win over imported ones, whichever comes
  // first; between two imports the later one wins (as a later #include would).
  for (const Binding& b : exported->vars) {
    if (b.imported) continue;
    if (Binding* old = env->find_local(b.symbol)) {
      if (old->imported) *old = {b.symbol, b.value, b.span, true};
      continue;
    }
    env->vars.push_back({b.symbol, b.value, b.span, true});
  }
}

void Evaluator::exec_item(const Stmt& s, const std::shared_ptr<Env>& env) {
  const BlockInfo* block = symbol_block_[symbol_of(s)];
  bool instance = lang::is_instance_name(s.name);
  if (instance || (block && block->csg_op >= 0) ||
      (block && block->is_object && !collectors_.empty())) {
    if (builder_.too_many_objects()) {
      error(DiagKind::StepBudget, s.name_span,
            "the scene has more than " + std::to_string(kMaxSceneObjects) + " objects");
      aborted_ = true;
      return;
    }
    Value v = eval_object(s.name, instance ? nullptr : block, *s.block, s.name_span, env);
    if (v.type == Type::Object) {
      emit(v.object());
    } else if (!collectors_.empty()) {
      Collector& c = collectors_.back();
      c.failed = true;
      // A disc or triangle is no solid whatever else is wrong with it (§10:
      // independent errors); placed children are judged when the CSG is lowered.
      if (block && c.block->csg_op != static_cast<int>(ir::CsgOp::Union))
        if (std::string why = no_inside_of_kind(*block); !why.empty())
          report_no_inside(*block, s.name_span, *c.block, c.keyword, why, diags_);
    }
    return;
  }
  if (block && block->kind == BlockKind::Item && !block->is_object &&
      inside_group_error(block->name, s.name_span)) {
    // Its own errors are independent of where it stands (§10): checked, not placed.
    bool ok = true;
    PropsLease props(*this);
    eval_props(*block, *s.block, s.name_span, env, props.list(), ok);
    return;
  }
  if (!block || block->kind != BlockKind::Item) {
    auto names = block_names(BlockKind::Item);
    names.push_back("background");
    auto d = error(DiagKind::UnknownBlock, s.name_span, "'" + s.name + "' is not a scene item");
    std::string guess = lang::closest_match(s.name, names);
    if (const char* pov = povray_note(PovrayWordKind::Block, s.name))
      d.note(pov);
    else if (!guess.empty())
      d.note("did you mean '" + guess + "'?");
    else if (block && block->kind == BlockKind::Constructor)
      d.note("'" + s.name + "' makes a material or pattern; use it as a property value");
    return;
  }
  if (builder_.too_many_objects()) {
    error(DiagKind::StepBudget, s.name_span,
          "the scene has more than " + std::to_string(kMaxSceneObjects) + " objects");
    aborted_ = true;
    return;
  }
  bool ok = true;
  PropsLease props(*this);
  eval_props(*block, *s.block, s.name_span, env, props.list(), ok);
  if (ok) {
    builder_.add_item(*block, s.name_span, props.list());
    return;
  }
  check_rest(*block, s.name_span, *s.block, props.list());
  if (block->name == "settings" || block->name == "camera")
    builder_.failed_singleton(block->name, s.name_span);
}

// ---------------------------------------------------------------------------
// Blocks and properties

bool Evaluator::eval_prop_value(const PropInfo& info, const Expr& expr,
                                const std::shared_ptr<Env>& env, Value& out) {
  out = eval(expr, env);
  if (out.is_error()) return false;
  if (value_ok(info, out)) [[likely]]
    return true;
  bool integral = false;
  std::string msg = check_value(info, out, &integral);
  if (!msg.empty()) {
    error(integral ? DiagKind::NotAnInteger : DiagKind::InvalidValue, expr.span, msg);
    return false;
  }
  return true;
}

// pair -> '<' expr ',' expr '>' | expr (a 2-vector value: two numbers)
// Written as a vector literal, each part is evaluated and checked on its own, so a
// part may be a colour or a pattern (`stop <0.5, <1, 0, 0>>`, `bump <noise { }, 0.2>`).
bool Evaluator::eval_pair(const PropInfo& info, const Expr& expr, const std::shared_ptr<Env>& env,
                          std::vector<EvaluatedProp>& parts) {
  const BlockInfo* block = find_block(info.name);
  // A part's errors name the pair: "'pattern' takes a pattern" alone did not say
  // that it was bump's first part. Made only for an error (stops are evaluated by
  // the thousand).
  auto parts_form = [&] {
    return "<" + std::string(block->props[0]->name) + ", " + std::string(block->props[1]->name) +
           ">";
  };
  auto take = [&](std::size_t i, const Expr& ex, const Value* given) {
    EvaluatedProp& q = parts.emplace_back();
    q.info = block->props[i];
    q.name_span = ex.span;
    q.value_span = ex.span;
    if (given) {
      q.value = *given;
    } else {
      q.value = eval(ex, env);
      if (q.value.is_error()) {
        parts.pop_back();
        return false;
      }
    }
    if (value_ok(*q.info, q.value)) return true;
    bool integral = false;
    std::string msg = check_value(*q.info, q.value, &integral);
    if (msg.empty()) return true;
    error(integral ? DiagKind::NotAnInteger : DiagKind::InvalidValue, ex.span,
          "in '" + std::string(info.name) + " " + parts_form() + "': " + msg);
    parts.pop_back();
    return false;
  };
  if (expr.kind == ExprKind::Vector && expr.args.size() == 2) {
    bool a = take(0, *expr.args[0], nullptr);
    bool b = take(1, *expr.args[1], nullptr);
    return a && b;
  }
  if (expr.kind == ExprKind::Vector) {
    error(DiagKind::InvalidValue, expr.span,
          "'" + std::string(info.name) + "' takes two parts, " + parts_form() + ", not " +
              std::to_string(expr.args.size()));
    return false;
  }
  Value v = eval(expr, env);
  if (v.is_error()) return false;
  if (v.type == Type::Vec2) {
    Value a = Value::number(v.v.x), b = Value::number(v.v.y);
    bool ok = take(0, expr, &a);
    return take(1, expr, &b) && ok;
  }
  error(DiagKind::InvalidValue, expr.span,
        "'" + std::string(info.name) + "' takes " + describe(info) + ", not " + a_type(v.type));
  return false;
}

void Evaluator::eval_props(const BlockInfo& block, const lang::Block& body, Span keyword_span,
                           const std::shared_ptr<Env>& env, std::vector<EvaluatedProp>& out,
                           bool& ok) {
  std::bitset<kPropCount> given;  // the properties given and good (by id)
  if (!body.positional.empty()) [[unlikely]] {
    // POV-Ray's positional values: one error that shows the named form, and no
    // "needs 'radius'" errors after it (they would say the same thing again).
    std::vector<std::string> texts;
    // POV-Ray's axis vectors x, y and z, where no such name is defined here, are
    // shown as the vectors they stand for, so the note compiles as written.
    auto axis = [&](const lang::Expr& v) -> const char* {
      if (v.kind != ExprKind::Name || v.text.size() != 1) return nullptr;
      for (const Env* s = env.get(); s; s = s->parent.get())
        if (s->find_local(symbol_of(v))) return nullptr;
      return v.text == "x"   ? "<1, 0, 0>"
             : v.text == "y" ? "<0, 1, 0>"
             : v.text == "z" ? "<0, 0, 1>"
                             : nullptr;
    };
    for (const lang::ExprPtr& v : body.positional) {
      if (const char* a = axis(*v)) {
        texts.emplace_back(a);
        continue;
      }
      std::string_view src =
          v->span.file < sources_.size() ? sources_.file(v->span.file).text() : std::string_view();
      texts.emplace_back(v->span.end <= src.size()
                             ? src.substr(v->span.begin, v->span.end - v->span.begin)
                             : std::string_view("…"));
    }
    PositionalHint hint = positional_hint(block, texts);
    error(DiagKind::PositionalValues, body.positional[0]->span, hint.message).note(hint.note);
    ok = false;
  }
  std::vector<std::string> guessed;                  // what misspelt properties were taken for
  std::vector<std::pair<std::int32_t, Span>> named;  // each property met, and where
  for (const lang::Property& p : body.properties) {
    // A Block is always checked against the same table (its keyword's), so the
    // property it names can be remembered on the node.
    const PropInfo* info = p.prop >= 0 ? &prop_by_id(p.prop) : find_prop(block, p.name);
    if (info && p.prop < 0) p.prop = info->id;
    if (!info) {
      auto d = error(DiagKind::UnknownProperty, p.name_span,
                     "'" + std::string(block.name) + "' has no property '" + p.name + "'");
      const auto names = prop_names(block);
      std::string guess = lang::closest_match(p.name, names);
      if (const char* pov = povray_note(PovrayWordKind::Property, p.name, block.name)) {
        d.note(pov);
      } else if (!guess.empty()) {
        d.note("did you mean '" + guess + "'?");
        guessed.push_back(std::move(guess));
      } else if (!names.empty()) {
        // §5: the error says what the block accepts.
        std::string list;
        for (const auto& n : names) list += (list.empty() ? "" : ", ") + std::string(n);
        d.note("'" + std::string(block.name) + "' takes " + list);
      }
      ok = false;
      continue;
    }
    // A property whose value the parser could not read is reported there, and is
    // no second `radius` either (`sphere { radius 1 radius }`).
    if (p.value && p.value->kind == lang::ExprKind::Error) {
      ok = false;
      continue;
    }
    // Twice is an error whether or not the first one's value was good (§5): the
    // first's place is remembered as it is met.
    if (!info->repeats()) {
      const Span* first_at = nullptr;
      for (const auto& [id, at] : named)
        if (id == info->id) first_at = &at;
      if (first_at) {
        error(DiagKind::DuplicateProperty, p.name_span,
              "'" + p.name + "' is given twice in '" + std::string(block.name) + "'")
            .note(*first_at, "first given here");
        ok = false;
        continue;
      }
      named.emplace_back(info->id, p.name_span);
    }
    if (info->type == PropType::Block) {
      if (!p.block) {
        error(DiagKind::InvalidValue, p.value ? p.value->span : p.name_span,
              "'" + p.name + "' takes a block: " + p.name + " { ... }");
        ok = false;
        continue;
      }
    } else {
      if (p.block) {
        error(DiagKind::InvalidValue, p.block->span,
              "'" + p.name + "' takes " + describe(*info) + ", not a block");
        ok = false;
        continue;
      }
      if (!p.value) continue;  // a syntax error, already reported
    }
    // Built in place; taken back out if its value fails. Nothing else appends to
    // `out` meanwhile (nested items and constructors lease their own lists).
    EvaluatedProp& ep = out.emplace_back();
    ep.info = info;
    ep.name_span = p.name_span;
    if (info->type == PropType::Block) {
      ep.value_span = p.block->span;
      ep.written = std::uint32_t(p.block->properties.size() + (p.block->broken ? 1 : 0));
      const BlockInfo* nested = find_block(info->name);  // only `motion`: rare
      eval_props(*nested, *p.block, p.name_span, env, ep.nested, ok);
    } else {
      ep.value_span = p.value->span;
      if (info->type == PropType::Pair ? !eval_pair(*info, *p.value, env, ep.nested)
                                       : !eval_prop_value(*info, *p.value, env, ep.value)) {
        out.pop_back();
        ok = false;
        continue;
      }
    }
    given.set(static_cast<std::size_t>(info->id));
  }
  static const BlockInfo* const object_props = find_block("object");
  const BlockInfo* object = block.is_object ? object_props : nullptr;
  for (const BlockInfo* b : {&block, object}) {
    if (!b) continue;
    for (const PropInfo* info : b->props) {
      if (given.test(static_cast<std::size_t>(info->id))) continue;
      if (info->required()) {
        // A property that failed its own check counts as given: no second error.
        // So does a misspelling of it: its "did you mean" says all there is to say.
        bool attempted = false;
        for (const lang::Property& p : body.properties) attempted |= p.name == info->name;
        for (const std::string& g : guessed) attempted |= g == info->name;
        if (!attempted && body.positional.empty() && !body.broken)
          error(DiagKind::MissingProperty, keyword_span,
                "'" + std::string(block.name) + "' needs '" + std::string(info->name) + "' (" +
                    describe(*info) + ")");
        ok = false;
      } else if (info->default_value.type != Type::None) {
        EvaluatedProp& d = out.emplace_back();
        d.info = info;
        d.name_span = keyword_span;
        d.value_span = keyword_span;
        d.value = info->default_value;
      }
    }
  }
}

}  // namespace snell::compile
