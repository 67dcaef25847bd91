// Tokens of the .scn language; the kinds come from tokens.def.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "language/source.hpp"

namespace snell::lang {

enum class TokenKind : std::uint8_t {
#define SNELL_TOKEN(name, spelling) name,
#include "language/tokens.def"
};

// "(" for punctuation, "let" for keywords, "number" for literal kinds.
std::string_view token_spelling(TokenKind kind);
// The keyword kind for a word, or Identifier.
TokenKind keyword_kind(std::string_view word);

struct Token {
  TokenKind kind = TokenKind::EndOfFile;
  Span span;
  std::string_view text;  // the source bytes of the token (view into the SourceFile)
  double number = 0;      // Number: its value
  bool invalid = false;   // Number: unreadable (reported by the lexer); its value is 0
  std::string string;     // String: its value with escapes decoded
};

}  // namespace snell::lang
