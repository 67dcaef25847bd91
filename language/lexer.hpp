// The hand-written lexer (§2). It never throws: bad input becomes a diagnostic and
// an Error token, and lexing goes on.
#pragma once

#include <vector>

#include "language/diagnostics.hpp"
#include "language/token.hpp"

namespace snell::lang {

// Limits that keep hostile input from exhausting memory or time.
inline constexpr std::size_t kMaxSourceBytes = 100u * 1024 * 1024;  // 100 MB
inline constexpr std::size_t kMaxIdentifierBytes = 1024;

// Lexes the whole file; the last token is always EndOfFile.
std::vector<Token> lex(const SourceManager& sources, FileId file, DiagnosticEngine& diags);

}  // namespace snell::lang
