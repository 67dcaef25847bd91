// Helpers shared by the language unit tests.
#pragma once

#include <string>
#include <vector>

#include "language/lexer.hpp"
#include "language/parser.hpp"

namespace snell::lang::test {

// "Kind@line:col" for each diagnostic, in report order.
inline std::vector<std::string> diag_list(const DiagnosticEngine& diags) {
  std::vector<std::string> out;
  for (const Diagnostic& d : diags.diagnostics()) {
    LineCol lc = diags.sources().file(d.span.file).line_col(d.span.begin);
    out.push_back(std::string(diag_name(d.kind)) + "@" + std::to_string(lc.line) + ":" +
                  std::to_string(lc.col));
  }
  return out;
}

struct Lexed {
  std::vector<Token> tokens;
  std::vector<std::string> diags;
  std::vector<TokenKind> kinds() const {
    std::vector<TokenKind> k;
    for (const Token& t : tokens) k.push_back(t.kind);
    return k;
  }
};

inline Lexed lex_text(std::string text) {
  SourceManager sm;
  FileId f = sm.add("t.scn", std::move(text));
  DiagnosticEngine diags(sm);
  diags.set_max_errors(0);
  Lexed out;
  out.tokens = lex(sm, f, diags);
  // Token::text views the SourceManager's copy, which dies here: keep only owned data.
  for (Token& t : out.tokens) t.text = {};
  out.diags = diag_list(diags);
  return out;
}

struct Parsed {
  Program program;
  std::vector<std::string> diags;
  std::string dump;
};

inline Parsed parse_text(std::string text) {
  SourceManager sm;
  FileId f = sm.add("t.scn", std::move(text));
  DiagnosticEngine diags(sm);
  diags.set_max_errors(0);
  Parsed out;
  out.program = parse(sm, f, diags);
  out.dump = dump_ast(out.program);
  out.program.source = nullptr;  // the SourceManager dies here
  out.diags = diag_list(diags);
  return out;
}

}  // namespace snell::lang::test
