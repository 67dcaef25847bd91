// The arithmetic operators on numbers (§3), in one place for the general
// evaluator and the numeric fast path, so both give the same bits.
#pragma once

#include <cmath>

#include "language/token.hpp"
#include "runtime/ir/scalar_math.hpp"

namespace snell::compile {

inline double arith(lang::TokenKind op, double a, double b) {
  using lang::TokenKind;
  switch (op) {
    case TokenKind::Plus:
      return a + b;
    case TokenKind::Minus:
      return a - b;
    case TokenKind::Star:
      return a * b;
    case TokenKind::Slash:
      return a / b;
    case TokenKind::Percent:
      return ir::scalar::floored_mod(a, b);
    default:
      return 0;
  }
}

inline bool is_arith(lang::TokenKind op) {
  using lang::TokenKind;
  return op == TokenKind::Plus || op == TokenKind::Minus || op == TokenKind::Star ||
         op == TokenKind::Slash || op == TokenKind::Percent;
}

}  // namespace snell::compile
