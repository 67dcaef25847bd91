// The numeric fast path of the evaluator. Most of a scene program's work is
// arithmetic on numbers (positions, radii, colours computed in loops); the
// general path wraps every intermediate result in a Value. Here:
//  - eval_number walks a pure numeric expression on doubles;
//  - a root of such an expression is compiled once into postfix code (NumCode)
//    and then run without recursion.
// Neither has any effect but counting steps, so on anything unusual (a name not
// bound to a number, a shadowed builtin, a non-finite result, the budget running
// out) the caller restores the step count and evaluates the general way, which
// reports exactly what it always did. Failing nodes are marked not_numeric so a
// failure costs one extra walk in all, not one per evaluation.
#include <cmath>

#include "compiler/arith.hpp"
#include "compiler/builtins.hpp"
#include "compiler/evaluator.hpp"

namespace snell::compile {

using lang::Expr;
using lang::ExprKind;
using lang::TokenKind;

// Every node on the way to a failure is marked not_numeric, so a failing
// expression pays for at most one extra walk in all (not one per nesting level).
// Steps are counted but the budget is checked by the caller at the end: the walk
// has no other effect, so running past the budget and then failing is the same
// as stopping at the step that spent it.
bool Evaluator::eval_number(const Expr& e, const Env* env, double& out) {
  ++steps_;
  switch (e.kind) {
    case ExprKind::Number:
      out = e.number;
      return true;
    case ExprKind::Name: {
      std::int32_t sym = symbol_of(e);
      for (const Env* s = env; s; s = s->parent.get())
        if (const Binding* b = s->find_local(sym)) {
          if (b->value.type != Type::Number) return false;
          out = b->value.n;
          return true;
        }
      return false;
    }
    case ExprKind::Unary:
      if (e.op == TokenKind::Minus && number_operand(*e.args[0], env, out)) {
        out = -out;
        return true;
      }
      break;
    case ExprKind::Binary: {
      double a, b;
      if (is_arith(e.op) && number_operand(*e.args[0], env, a) &&
          number_operand(*e.args[1], env, b)) {
        out = arith(e.op, a, b);
        if (std::isfinite(out)) [[likely]]
          return true;
      }
      break;
    }
    case ExprKind::Call: {
      const Expr& f = *e.args[0];
      if (f.kind != ExprKind::Name) break;
      ++steps_;  // the callee name, as eval_call counts it
      std::int32_t sym = symbol_of(f);
      int id = symbol_builtin_[sym];
      if (id < 0) break;
      if (symbol_bound_[sym])
        for (const Env* s = env; s; s = s->parent.get())
          if (s->find_local(sym)) return fail_number(e);  // a user binding shadows the builtin
      std::size_t n = e.args.size() - 1;
      if (n != builtin_arity(id) || n > 3) break;
      double a[3] = {0, 0, 0};
      for (std::size_t i = 0; i < n; ++i)
        if (!number_operand(*e.args[i + 1], env, a[i])) return fail_number(e);
      if (call_builtin_number(id, a, out) && std::isfinite(out)) [[likely]]
        return true;
      break;
    }
    default:
      return false;
  }
  return fail_number(e);
}

// Compiles `e` into num_ops_ in postfix order; false when its shape rules the fast
// path out (then every node on the way down to the reason is marked not_numeric,
// so none of them is compiled again). Whether a name holds a number is known
// only when the code runs. Interior nodes get code -2: they belong to this root
// and are never compiled on their own (if the root fails at run time, they are
// evaluated by eval_number, node by node).
bool Evaluator::compile_number(const Expr& e, NumCode& code, std::uint32_t depth) {
  auto push = [&](NumOp op) {
    num_ops_.push_back(op);
    ++code.count;
  };
  ++code.steps;
  switch (e.kind) {
    case ExprKind::Number:
      push({NumOp::Const, TokenKind::Error, 0, 0, e.number});
      break;
    case ExprKind::Name:
      push({NumOp::Var, TokenKind::Error, 0, symbol_of(e), 0});
      break;
    case ExprKind::Unary:
      if (e.op != TokenKind::Minus || !compile_number(*e.args[0], code, depth))
        return fail_number(e);
      push({NumOp::Neg, TokenKind::Error, 0, 0, 0});
      break;
    case ExprKind::Binary:
      if (!is_arith(e.op) || !compile_number(*e.args[0], code, depth)) return fail_number(e);
      if (const Expr& rhs = *e.args[1]; rhs.kind == ExprKind::Number) {
        // `x * 100`: the constant travels in the op (one op instead of two).
        ++code.steps;
        if (rhs.code == -1) rhs.code = -2;
        push({NumOp::ArithK, e.op, 0, 0, rhs.number});
      } else {
        if (!compile_number(rhs, code, depth + 1)) return fail_number(e);
        push({NumOp::Arith, e.op, 0, 0, 0});
      }
      break;
    case ExprKind::Call: {
      const Expr& f = *e.args[0];
      if (f.kind != ExprKind::Name) return fail_number(e);
      ++code.steps;  // the callee name, as eval_call counts it
      std::int32_t sym = symbol_of(f);
      int id = symbol_builtin_[sym];
      std::size_t n = e.args.size() - 1;
      if (id < 0 || !builtin_numeric(id) || n != builtin_arity(id) || n > 3) return fail_number(e);
      for (std::size_t i = 0; i < n; ++i)
        if (!compile_number(*e.args[i + 1], code, depth + static_cast<std::uint32_t>(i)))
          return fail_number(e);
      push({NumOp::Call, TokenKind::Error, static_cast<std::uint8_t>(n), sym,
            static_cast<double>(id)});
      break;
    }
    default:
      return false;
  }
  if (depth + 1 > code.depth) code.depth = depth + 1;
  if (e.code == -1) e.code = -2;
  return true;
}

bool Evaluator::run_number(const NumCode& code, const Env* env, double& out) {
  double* base = num_stack_.data();
  double* sp = base;
  const NumOp* op = num_ops_.data() + code.first;
  for (const NumOp* end = op + code.count; op != end; ++op) {
    switch (op->kind) {
      case NumOp::Const:
        *sp++ = op->value;
        break;
      case NumOp::Var: {
        const Binding* b = nullptr;
        for (const Env* s = env; s && !b; s = s->parent.get()) b = s->find_local(op->sym);
        if (!b || b->value.type != Type::Number) return false;
        *sp++ = b->value.n;
        break;
      }
      case NumOp::Neg:
        sp[-1] = -sp[-1];
        break;
      case NumOp::ArithK: {
        double r = arith(op->op, sp[-1], op->value);
        if (!std::isfinite(r)) return false;
        sp[-1] = r;
        break;
      }
      case NumOp::Arith: {
        --sp;
        double r = arith(op->op, sp[-1], sp[0]);
        if (!std::isfinite(r)) return false;
        sp[-1] = r;
        break;
      }
      case NumOp::Call: {
        if (symbol_bound_[op->sym])
          for (const Env* s = env; s; s = s->parent.get())
            if (s->find_local(op->sym)) return false;  // a user binding shadows the builtin
        double a[3] = {0, 0, 0};
        sp -= op->argc;
        for (int i = 0; i < op->argc; ++i) a[i] = sp[i];
        double r;
        if (!call_builtin_number(static_cast<int>(op->value), a, r) || !std::isfinite(r))
          return false;
        *sp++ = r;
        break;
      }
    }
  }
  out = sp[-1];
  steps_ += code.steps;
  return true;
}

bool Evaluator::fast_number(const Expr& e, const Env* env, double& out) {
  if (e.code >= 0) {
    if (run_number(num_codes_[static_cast<std::size_t>(e.code)], env, out)) [[likely]]
      return true;
    e.not_numeric = true;  // callers check it before coming here again
    return false;
  }
  if (e.code == -1 &&
      (e.kind == ExprKind::Binary || e.kind == ExprKind::Unary || e.kind == ExprKind::Call)) {
    NumCode code;
    code.first = static_cast<std::uint32_t>(num_ops_.size());
    if (!compile_number(e, code, 0)) {
      num_ops_.resize(code.first);
      return false;
    }
    e.code = static_cast<std::int32_t>(num_codes_.size());
    num_codes_.push_back(code);
    if (num_stack_.size() < code.depth) num_stack_.resize(code.depth);
    return fast_number(e, env, out);
  }
  return number_operand(e, env, out);
}

}  // namespace snell::compile
