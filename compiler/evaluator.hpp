// The interpreter (§3-§4, §9): runs a parsed program top to bottom with lexical
// scopes, closures, loops and conditionals; evaluates property values and hands
// each scene item to the SceneBuilder (lower.hpp). Errors are reported through
// the DiagnosticEngine and evaluation goes on with the next statement, so every
// independent error is reported; only the recursion limit and the step budget
// stop evaluation outright.
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "compiler/lower.hpp"
#include "compiler/object_value.hpp"
#include "compiler/properties.hpp"
#include "compiler/stack_guard.hpp"
#include "compiler/value.hpp"
#include "language/ast.hpp"
#include "language/diagnostics.hpp"

namespace snell::compile {

struct Binding {
  std::int32_t symbol;
  Value value;
  lang::Span span;        // where it was defined (for "first defined here" notes)
  bool imported = false;  // bound by an import: not exported again
};

struct Env {
  std::shared_ptr<Env> parent;
  std::vector<Binding> vars;
  // An import here failed (not found, unreadable, syntax errors, a cycle): the
  // names it would have bound are unknown, so a name not found below this scope is
  // not reported again as undefined (its cause is reported at the import).
  bool failed_import = false;
  const Binding* find_local(std::int32_t symbol) const {
    const std::ptrdiff_t i = position(symbol);
    return i < 0 ? nullptr : &vars[std::size_t(i)];
  }
  Binding* find_local(std::int32_t symbol) {
    const std::ptrdiff_t i = position(symbol);
    return i < 0 ? nullptr : &vars[std::size_t(i)];
  }
  // Empties the scope (a loop body's, between iterations).
  void clear() {
    vars.clear();
    index_.clear();
    indexed_ = 0;
  }

 private:
  // A scope of a few names is scanned; past that a hash index, extended with the
  // bindings pushed since the last lookup, finds a name in constant time: a file
  // of 200 000 `let`s took 18 s, quadratic in the lookups of its definitions.
  static constexpr std::size_t kScanned = 16;
  mutable std::unordered_map<std::int32_t, std::uint32_t> index_;
  mutable std::size_t indexed_ = 0;
  std::ptrdiff_t position(std::int32_t symbol) const {
    if (vars.size() <= kScanned) {
      for (std::size_t i = 0; i < vars.size(); ++i)
        if (vars[i].symbol == symbol) return std::ptrdiff_t(i);
      return -1;
    }
    if (indexed_ > vars.size()) index_.clear(), indexed_ = 0;  // emptied without clear()
    for (; indexed_ < vars.size(); ++indexed_)  // emplace keeps the first, as the scan
      index_.emplace(vars[indexed_].symbol, std::uint32_t(indexed_));
    auto it = index_.find(symbol);
    return it == index_.end() ? -1 : std::ptrdiff_t(it->second);
  }
};

inline constexpr int kMaxCallDepth = 10000;
// The longest string a program may make (by `+`): far beyond any file name or
// label, and small enough that a loop of doublings stops in megabytes, not in
// the machine's whole memory (the step budget counts operations, not bytes).
inline constexpr std::size_t kMaxStringLength = 1 << 20;
// All string values alive at once hold at most this many bytes (LiveString).
inline constexpr std::int64_t kMaxLiveStringBytes = std::int64_t(1) << 30;
inline constexpr std::uint64_t kDefaultStepBudget = 400'000'000;

// Resolves and loads `import "path";` (compile.cpp implements it): returns the
// program to run, or null after reporting the error at `span`.
struct ImportedFile {
  lang::FileId file;
  const lang::Program* program;  // null: the file has syntax errors and is not run
  // Such a file's names that it might have bound (its top-level let and fn, and
  // every name of its broken statements): only these are not reported undefined
  // in the file that imports it. `binds_unknown`: it imports others, so any name.
  std::vector<std::string> binds;
  bool binds_unknown = false;
};
using ImportLoader = std::function<const ImportedFile*(const std::string& path, lang::Span span)>;
// Sees each binding as it is made (the name's span and its value); editors use it.
using DefineObserver = std::function<void(lang::Span name, const Value& value)>;

class Evaluator {
 public:
  Evaluator(const lang::SourceManager& sources, lang::DiagnosticEngine& diags,
            SceneBuilder& builder, ImportLoader loader,
            std::uint64_t step_budget = kDefaultStepBudget);

  // Breaks the closure <-> scope reference cycles (see closure_scopes_).
  ~Evaluator();
  Evaluator(const Evaluator&) = delete;
  Evaluator& operator=(const Evaluator&) = delete;

  // Runs a file's statements in a fresh top-level scope, returns that scope.
  std::shared_ptr<Env> run_file(const lang::Program& program);

  // §18: a predeclared name (clock, frame), visible in every file the evaluator
  // runs (the parent scope of each file's top level), so a file or a function may
  // shadow it as any inner scope may. Call before run_file.
  void predeclare(const std::string& name, Value value);

  // Evaluates a lone expression in an empty scope (for --set KEY=VALUE).
  Value eval_standalone(const lang::Expr& expr);

  std::uint64_t steps() const { return steps_; }
  // What an error costs of the step budget (Evaluator::error: why).
  static constexpr std::uint64_t kErrorSteps = 32;
  // Bytes of a string copied or compared per step of the budget: a step is ~7 ns,
  // and 64 bytes about as long to copy. Without it a loop over a 512 K string ran
  // for minutes inside its step budget.
  static constexpr std::uint64_t kStringBytesPerStep = 64;
  void set_define_observer(DefineObserver observer) { on_define_ = std::move(observer); }

 private:
  // §15: compiles user functions to shading programs with the evaluator's names,
  // scopes and diagnostics (shading_function.cpp).
  friend class ShadingCompiler;
  enum class Flow { Normal, Return };
  struct Frame {
    Value result;
    bool in_function = false;
  };

  Flow exec_block(const std::vector<lang::StmtPtr>& stmts, const std::shared_ptr<Env>& env,
                  Frame& frame);
  Flow exec(const lang::Stmt& s, const std::shared_ptr<Env>& env, Frame& frame);
  void exec_let(const lang::Stmt& s, const std::shared_ptr<Env>& env);
  void exec_fn(const lang::Stmt& s, const std::shared_ptr<Env>& env);
  Flow exec_for(const lang::Stmt& s, const std::shared_ptr<Env>& env, Frame& frame);
  void hint_objects(const lang::Stmt& loop, double from, double to, double by);
  Flow exec_if(const lang::Stmt& s, const std::shared_ptr<Env>& env, Frame& frame);
  void exec_import(const lang::Stmt& s, const std::shared_ptr<Env>& env);
  void exec_item(const lang::Stmt& s, const std::shared_ptr<Env>& env);
  // §12-§13 (evaluator_object.cpp): an object block's value (a shape, a CSG block
  // whose statements are run, or `object { EXPR ... }`), Error after errors; and
  // where a made object goes: into the CSG block being evaluated, else the scene.
  Value eval_object(std::string_view keyword, const BlockInfo* block, const lang::Block& body,
                    lang::Span kw, const std::shared_ptr<Env>& env);
  Value eval_object_expr(const lang::Expr& e, const std::shared_ptr<Env>& env);
  void emit(std::shared_ptr<const ObjectNode> node);
  // True (after reporting) when a non-object item stands inside a CSG block.
  bool inside_group_error(std::string_view what, lang::Span at);

  Value eval(const lang::Expr& e, const std::shared_ptr<Env>& env);
  // The numeric fast path (evaluator_number.cpp): evaluates `e` when it is pure
  // arithmetic on numbers (number literals, names bound to numbers, unary minus,
  // + - * / %, builtin calls on numbers) with every result finite, counting the
  // same steps as eval(). It has no other effect, so on false (anything else) the
  // caller restores the step count, checks the budget, and on failure evaluates
  // `e` the general way, which then reports any error exactly as before.
  // fast_number runs a root's compiled code (compiling it the first time);
  // eval_number walks the tree (for parts of a root whose code failed).
  bool fast_number(const lang::Expr& e, const Env* env, double& out);
  bool eval_number(const lang::Expr& e, const Env* env, double& out);
  bool number_operand(const lang::Expr& e, const Env* env, double& out) {
    if (e.kind == lang::ExprKind::Number) {  // the commonest leaf, without a call
      ++steps_;
      out = e.number;
      return true;
    }
    return eval_number(e, env, out);
  }
  static bool fail_number(const lang::Expr& e) {
    e.not_numeric = true;
    return false;
  }
  // Postfix code of a numeric expression: operands are pushed on num_stack_.
  struct NumOp {
    // ArithK: Arith whose right operand is the constant `value`.
    enum Kind : std::uint8_t { Const, Var, Neg, Arith, ArithK, Call };
    Kind kind;
    lang::TokenKind op;  // Arith, ArithK
    std::uint8_t argc;   // Call
    std::int32_t sym;    // Var: the name; Call: the callee's name
    double value;        // Const, ArithK: the number; Call: the builtin id
  };
  struct NumCode {
    std::uint32_t first = 0, count = 0;  // num_ops_[first, first + count)
    std::uint32_t steps = 0;             // what eval() would count for the tree
    std::uint32_t depth = 0;             // stack slots it needs
  };
  bool compile_number(const lang::Expr& e, NumCode& code, std::uint32_t depth);
  bool run_number(const NumCode& code, const Env* env, double& out);
  Value eval_name(const lang::Expr& e, const std::shared_ptr<Env>& env);
  Value eval_vector(const lang::Expr& e, const std::shared_ptr<Env>& env);
  Value eval_unary(const lang::Expr& e, const std::shared_ptr<Env>& env);
  Value eval_binary(const lang::Expr& e, const std::shared_ptr<Env>& env);
  Value eval_call(const lang::Expr& e, const std::shared_ptr<Env>& env, bool as_statement);
  Value eval_component(const lang::Expr& e, const std::shared_ptr<Env>& env);
  Value eval_constructor(const lang::Expr& e, const std::shared_ptr<Env>& env);
  Value call_user(const Closure& fn, std::vector<Value>& args, const lang::Expr& call);
  static const Value& builtin_value(int id);
  static const Closure& builtin_closure(int id);

  // Evaluates a block's properties against `block`'s table into `out` (appended):
  // unknown, duplicate, missing and invalid properties are reported; `ok` is false
  // after any error.
  void eval_props(const BlockInfo& block, const lang::Block& body, lang::Span keyword_span,
                  const std::shared_ptr<Env>& env, std::vector<EvaluatedProp>& out, bool& ok);
  // §10's independent errors of a block whose properties had errors: the checks
  // between its properties that involve none of the failed ones (a shape's,
  // lower_kinds.cpp; the camera's and an area light's, SceneBuilder).
  void check_rest(const BlockInfo& block, lang::Span kw, const lang::Block& body,
                  const std::vector<EvaluatedProp>& props);
  // A cleared property list from a pool indexed by nesting (a property's value may
  // call a function that makes items), so an item allocates no list once warm.
  class PropsLease {
   public:
    explicit PropsLease(Evaluator& ev) : ev_(ev) {
      if (ev.props_pool_.size() <= ev.props_depth_) ev.props_pool_.emplace_back();
      list_ = &ev.props_pool_[ev.props_depth_++];
      list_->clear();
    }
    ~PropsLease() {
      list_->clear();  // drop the values (materials) now, keep the capacity
      --ev_.props_depth_;
    }
    PropsLease(const PropsLease&) = delete;
    PropsLease& operator=(const PropsLease&) = delete;
    std::vector<EvaluatedProp>& list() { return *list_; }

   private:
    Evaluator& ev_;
    std::vector<EvaluatedProp>* list_;
  };
  bool eval_prop_value(const PropInfo& info, const lang::Expr& expr,
                       const std::shared_ptr<Env>& env, Value& out);
  // A Pair property's two parts into `parts` (properties.hpp PropType::Pair).
  bool eval_pair(const PropInfo& info, const lang::Expr& expr, const std::shared_ptr<Env>& env,
                 std::vector<EvaluatedProp>& parts);

  std::int32_t intern(const std::string& name);
  std::int32_t symbol_of(const lang::Expr& e) {
    if (e.symbol < 0) e.symbol = intern(e.text);
    return e.symbol;
  }
  std::int32_t symbol_of(const lang::Stmt& s) {
    if (s.symbol < 0) s.symbol = intern(s.name);
    return s.symbol;
  }
  void define(const std::shared_ptr<Env>& env, std::int32_t symbol, Value v, lang::Span span);
  // One evaluation step; false once the budget is spent or evaluation stopped.
  bool step(lang::Span at) {
    if (++steps_ <= step_budget_ && !aborted_) [[likely]]
      return true;
    return step_exhausted(at);
  }
  bool step_exhausted(lang::Span at);
  // Work worth `n` more steps (a long string's bytes); false once the budget is
  // spent.
  bool charge(lang::Span at, std::uint64_t n) {
    steps_ += n;
    if (steps_ <= step_budget_ && !aborted_) [[likely]]
      return true;
    return step_exhausted(at);
  }
  // Reports a NaN or infinite result at `e`; true when `v` is fine.
  bool finite_ok(const Value& v, const lang::Expr& e) {
    if (v.finite()) [[likely]]
      return true;
    report_non_finite(v, e);
    return false;
  }
  void report_non_finite(const Value& v, const lang::Expr& e);
  lang::DiagBuilder error(lang::DiagKind kind, lang::Span span, std::string message);

  const lang::SourceManager& sources_;
  lang::DiagnosticEngine& diags_;
  SceneBuilder& builder_;
  ImportLoader loader_;
  std::uint64_t step_budget_;
  DefineObserver on_define_;
  std::uint64_t steps_ = 0;
  int depth_ = 0;
  // The outermost call running (depth_ > 0): an error inside a function body says
  // which call of the scene reached it (`object { f(0) }`), once per place.
  lang::Span outer_call_{};
  bool aborted_ = false;  // recursion limit or step budget: stop everything
  // Below this the thread's stack has 4 MB left (stack_guard.hpp): a call stops
  // the evaluation there, as the call-depth limit does.
  const char* stack_floor_ = stack_floor(std::size_t(4) << 20);
  std::shared_ptr<Env> prelude_ = std::make_shared<Env>();  // predeclare()
  std::unordered_map<std::string, std::int32_t> symbol_ids_;
  std::vector<std::string> symbol_names_;
  std::vector<int> symbol_builtin_;             // builtin id per symbol, or -1
  std::vector<const BlockInfo*> symbol_block_;  // block named by the symbol, or null
  // Set once anything binds the symbol (let, fn, parameter, loop variable; imports
  // copy such bindings): while clear, no scope can shadow a builtin of that name.
  std::vector<std::uint8_t> symbol_bound_;
  // Files already run (import runs each once) with their exported names.
  std::unordered_map<lang::FileId, std::shared_ptr<Env>> imported_;
  std::vector<lang::FileId> running_;  // the import chain, for cycle errors
  // Names in statements a syntax error broke, of every file run (Program::unsure_names).
  std::unordered_set<std::string> unsure_names_;
  // Where an undefined name was reported: a repeat (a loop's) is counted without
  // looking for a "did you mean" among every visible name again.
  std::unordered_set<std::uint64_t> undefined_at_;
  static constexpr std::uint64_t kGuessWork = 20'000'000;
  std::uint64_t guess_work_ = 0;
  // Every scope a `fn` was defined in. A closure holds its defining scope and that
  // scope holds the closure (so the function can call itself): a reference cycle
  // that shared_ptr never frees. The destructor clears these scopes' bindings once
  // evaluation is over (the IR holds no values), which frees everything.
  std::vector<std::weak_ptr<Env>> closure_scopes_;
  // Constructors already warned about (EnergyGain), by source offset: a loop that
  // makes the same material a thousand times is told once.
  std::unordered_set<std::uint64_t> energy_warned_;
  std::deque<std::vector<Value>> args_pool_;  // argument lists of calls in progress
  std::size_t args_depth_ = 0;
  std::vector<NumOp> num_ops_;  // the compiled numeric expressions (fast_number)
  std::vector<NumCode> num_codes_;
  std::vector<double> num_stack_;
  // The CSG blocks being evaluated, innermost last: the objects made go to the
  // innermost one's children.
  struct Collector {
    std::vector<std::shared_ptr<const ObjectNode>>* children;
    const BlockInfo* block;
    lang::Span keyword;
    bool failed = false;  // an object statement in the body failed (its error said)
  };
  std::vector<Collector> collectors_;
  std::deque<std::vector<EvaluatedProp>> props_pool_;  // see PropsLease
  std::size_t props_depth_ = 0;
};

}  // namespace snell::compile
