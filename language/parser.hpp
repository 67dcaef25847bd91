// The recursive-descent parser (Pratt table for expressions). It reports every
// independent syntax error (panic-mode recovery at ';', '}' and statement keywords)
// and always returns a Program; nodes after an error are ExprKind/StmtKind::Error.
#pragma once

#include "language/ast.hpp"
#include "language/diagnostics.hpp"

namespace snell::lang {

inline constexpr int kMaxNesting = 10000;  // parentheses, vectors, blocks, unary chains

Program parse(const SourceManager& sources, FileId file, DiagnosticEngine& diags);

}  // namespace snell::lang
