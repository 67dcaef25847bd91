#include "language/token.hpp"

#include <cstddef>

namespace snell::lang {
namespace {

constexpr std::string_view kSpellings[] = {
#define SNELL_TOKEN(name, spelling) spelling,
#include "language/tokens.def"
};

struct Keyword {
  std::string_view word;
  TokenKind kind;
};

constexpr Keyword kKeywords[] = {
#define SNELL_TOKEN(name, spelling)
#define SNELL_KEYWORD(name, word) {word, TokenKind::name},
#include "language/tokens.def"
};

}  // namespace

std::string_view token_spelling(TokenKind kind) {
  auto i = static_cast<std::size_t>(kind);
  return i < std::size(kSpellings) ? kSpellings[i] : std::string_view("?");
}

TokenKind keyword_kind(std::string_view word) {
  // Every identifier goes through here, so reject most words on their length
  // before comparing (keywords are 2 to 6 bytes).
  if (word.size() < 2 || word.size() > 6) return TokenKind::Identifier;
  for (const Keyword& k : kKeywords)
    if (k.word == word) return k.kind;
  return TokenKind::Identifier;
}

}  // namespace snell::lang
