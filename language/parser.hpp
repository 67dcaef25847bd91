// The recursive-descent parser (Pratt table for expressions). It reports every
// independent syntax error (panic-mode recovery at ';', '}' and statement keywords)
// and always returns a Program; nodes after an error are ExprKind/StmtKind::Error.
#pragma once

#include "language/ast.hpp"
#include "language/diagnostics.hpp"

namespace snell::lang {

// Parentheses, vectors, blocks, unary chains and left-deep operator chains. Every
// walk of the tree (the parser, the evaluator, the destructor) recurses once per
// level; under ASan a level of parsing costs about 2 KB of stack, so 1000 keeps a
// wide margin in an 8 MB stack (4000 overflowed there).
inline constexpr int kMaxNesting = 1000;

Program parse(const SourceManager& sources, FileId file, DiagnosticEngine& diags);

}  // namespace snell::lang
