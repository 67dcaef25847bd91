// The lexer as a token stream, private to the language layer. lex() drains it into a
// vector for tests and tools; the parser pulls tokens one at a time so a 100 MB file
// never holds all its tokens in memory at once.
#pragma once

#include <string_view>
#include <vector>

#include "language/diagnostics.hpp"
#include "language/token.hpp"

namespace snell::lang {

class Scanner {
 public:
  Scanner(const SourceManager& sources, FileId file, DiagnosticEngine& diags);

  // The next token; EndOfFile forever once the text is exhausted.
  Token next();
  // Scans on from `pos`, an offset inside a token already returned (the parser
  // splits '>=' where its '>' closes a vector: §3).
  void rewind(std::uint32_t pos) { pos_ = pos; }

  // True when a /* comment ran to the end of the file: errors the parser would
  // report at the end of the file are consequences of that one, so it keeps quiet.
  bool ate_rest_of_file() const { return ate_rest_; }

  // True when a string that ends at this offset had no closing quote: the ';' the
  // parser then misses was most likely swallowed by it.
  bool unterminated_string_ends_at(std::uint32_t end) const;
  // True when a string missing its closing quote ended in [from, to): it may have
  // eaten a brace, so brace errors after it are most likely its consequence.
  bool unterminated_string_between(std::uint32_t from, std::uint32_t to) const;

  // True when the text between two offsets contains a newline (the parser's
  // "first token on its line" recovery heuristic).
  bool newline_between(std::uint32_t from, std::uint32_t to) const;
  // The byte column (0-based) of `offset`, and of the first character that is no
  // space or tab on its line: how far a line is indented (the parser's hint of a
  // block's missing '}').
  std::uint32_t column(std::uint32_t offset) const;
  std::uint32_t indent_of_line(std::uint32_t offset) const;

  // True when the rest of the line from `from` has a '>' before any brace: what is
  // left of a vector literal a comparison closed early (`<1, a > b, 2>`).
  bool stray_angle_on_line(std::uint32_t from) const;

 private:
  void skip_trivia();
  void skip_line_comment();
  void skip_block_comment();
  // Checks one non-ASCII or NUL byte inside a comment or string; returns the number
  // of bytes it covers and reports NulByte or InvalidUtf8 (once per run of bad bytes).
  std::uint32_t check_text_byte(std::uint32_t pos, std::string* decoded);
  Token make(TokenKind kind, std::uint32_t begin, std::uint32_t end) const;
  Token identifier(std::uint32_t begin);
  Token number(std::uint32_t begin);
  bool simple_decimal(std::uint32_t begin, std::uint32_t end, double& out) const;
  Token string(std::uint32_t begin);
  Token invalid(std::uint32_t begin);
  Span span(std::uint32_t begin, std::uint32_t end) const { return {file_, begin, end}; }

  FileId file_;
  DiagnosticEngine& diags_;
  std::string_view src_;
  std::uint32_t pos_ = 0;
  bool ate_rest_ = false;
  std::vector<std::uint32_t> unterminated_ends_;  // ascending
};

// The length of the valid UTF-8 sequence starting at text[pos], or 0 when the
// bytes there are not valid UTF-8 (overlong forms and surrogates included).
std::uint32_t utf8_sequence_length(std::string_view text, std::size_t pos);

}  // namespace snell::lang
