// The hand-written lexer (§2). Every byte of input is either part of a token, trivia,
// or covered by exactly one diagnostic; lexing always reaches the end of the file.
#include "language/lexer.hpp"

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "language/scanner.hpp"

namespace snell::lang {
namespace {

bool is_digit(char c) {
  return c >= '0' && c <= '9';
}
bool is_ident_start(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_';
}
bool is_ident_char(char c) {
  return is_ident_start(c) || is_digit(c);
}

std::string hex_byte(unsigned char b) {
  char buf[8];
  std::snprintf(buf, sizeof buf, "0x%02X", b);
  return buf;
}

// U+XXXX of a valid UTF-8 sequence, for messages about stray characters.
std::string code_point_name(std::string_view seq) {
  auto b = [&](std::size_t i) { return static_cast<unsigned char>(seq[i]) & 0x3Fu; };
  unsigned lead = static_cast<unsigned char>(seq[0]);
  unsigned cp = lead;
  if (seq.size() == 2) cp = ((lead & 0x1Fu) << 6) | b(1);
  if (seq.size() == 3) cp = ((lead & 0x0Fu) << 12) | (b(1) << 6) | b(2);
  if (seq.size() == 4) cp = ((lead & 0x07u) << 18) | (b(1) << 12) | (b(2) << 6) | b(3);
  char buf[16];
  std::snprintf(buf, sizeof buf, "U+%04X", cp);
  return buf;
}

}  // namespace

std::uint32_t utf8_sequence_length(std::string_view text, std::size_t pos) {
  auto at = [&](std::size_t i) -> unsigned {
    return pos + i < text.size() ? static_cast<unsigned char>(text[pos + i]) : 0u;
  };
  auto cont = [&](std::size_t i) { return (at(i) & 0xC0u) == 0x80u; };
  unsigned c = at(0);
  if (c < 0x80) return 1;
  if (c >= 0xC2 && c <= 0xDF) return cont(1) ? 2 : 0;
  if (c >= 0xE0 && c <= 0xEF) {
    // E0 needs A0..BF (no overlongs), ED needs 80..9F (no surrogates).
    unsigned lo = c == 0xE0 ? 0xA0 : 0x80, hi = c == 0xED ? 0x9F : 0xBF;
    return at(1) >= lo && at(1) <= hi && cont(2) ? 3 : 0;
  }
  if (c >= 0xF0 && c <= 0xF4) {
    unsigned lo = c == 0xF0 ? 0x90 : 0x80, hi = c == 0xF4 ? 0x8F : 0xBF;
    return at(1) >= lo && at(1) <= hi && cont(2) && cont(3) ? 4 : 0;
  }
  return 0;
}

Scanner::Scanner(const SourceManager& sources, FileId file, DiagnosticEngine& diags)
    : file_(file), diags_(diags), src_(sources.file(file).text()) {
  if (src_.size() > kMaxSourceBytes) {
    // Spans are 32-bit and every later stage is linear in the size; refuse early.
    // The text was read only up to the limit: the size on disk is the real one.
    std::error_code ec;
    std::uintmax_t size = std::filesystem::file_size(sources.file(file).path(), ec);
    if (ec || size < src_.size()) size = src_.size();
    double mb = double(size) / (1024.0 * 1024.0);
    char shown[32];
    if (mb >= 1024)
      std::snprintf(shown, sizeof shown, "%.1f GB", mb / 1024);
    else
      std::snprintf(shown, sizeof shown, "%.0f MB", mb);
    diags_.report(DiagKind::FileTooLarge, span(0, 0),
                  "the file is " + std::string(shown) + "; source files may be at most " +
                      std::to_string(kMaxSourceBytes / (1024 * 1024)) + " MB");
    src_ = {};
  }
}

bool Scanner::stray_angle_on_line(std::uint32_t from) const {
  for (std::size_t i = from; i < src_.size(); ++i) {
    char c = src_[i];
    if (c == '\n' || c == '{' || c == '}') return false;
    if (c == '>') return true;
  }
  return false;
}

bool Scanner::newline_between(std::uint32_t from, std::uint32_t to) const {
  if (to > src_.size()) to = static_cast<std::uint32_t>(src_.size());
  return from < to && src_.substr(from, to - from).find('\n') != std::string_view::npos;
}

std::uint32_t Scanner::column(std::uint32_t offset) const {
  if (offset > src_.size()) offset = static_cast<std::uint32_t>(src_.size());
  if (offset == 0) return 0;
  const std::size_t nl = src_.rfind('\n', offset - 1);
  return static_cast<std::uint32_t>(nl == std::string_view::npos ? offset : offset - (nl + 1));
}

std::uint32_t Scanner::indent_of_line(std::uint32_t offset) const {
  std::uint32_t start = offset - column(offset), i = start;
  while (i < src_.size() && (src_[i] == ' ' || src_[i] == '\t')) ++i;
  return i - start;
}

bool Scanner::unterminated_string_between(std::uint32_t from, std::uint32_t to) const {
  auto it = std::lower_bound(unterminated_ends_.begin(), unterminated_ends_.end(), from);
  return it != unterminated_ends_.end() && *it < to;
}

bool Scanner::unterminated_string_ends_at(std::uint32_t end) const {
  return std::binary_search(unterminated_ends_.begin(), unterminated_ends_.end(), end);
}

Token Scanner::make(TokenKind kind, std::uint32_t begin, std::uint32_t end) const {
  Token t;
  t.kind = kind;
  t.span = span(begin, end);
  t.text = src_.substr(begin, end - begin);
  return t;
}

std::uint32_t Scanner::check_text_byte(std::uint32_t pos, std::string* decoded) {
  if (src_[pos] == '\0') {
    diags_.report(DiagKind::NulByte, span(pos, pos + 1), "NUL byte in the source text");
    return 1;
  }
  std::uint32_t n = utf8_sequence_length(src_, pos);
  if (n > 0) {
    if (decoded) decoded->append(src_.substr(pos, n));
    return n;
  }
  // One diagnostic for the whole run of bad bytes (a Latin-1 word, a binary blob).
  std::uint32_t end = pos + 1;
  while (end < src_.size() && static_cast<unsigned char>(src_[end]) >= 0x80 &&
         utf8_sequence_length(src_, end) == 0)
    ++end;
  diags_
      .report(DiagKind::InvalidUtf8, span(pos, end),
              end - pos == 1 ? "invalid UTF-8 byte " + hex_byte(src_[pos])
                             : "invalid UTF-8 bytes (" + std::to_string(end - pos) + " bytes)")
      .note("source files must be UTF-8 encoded");
  if (decoded) decoded->append("\xEF\xBF\xBD");  // U+FFFD keeps the value valid UTF-8
  return end - pos;
}

void Scanner::skip_line_comment() {
  pos_ += 2;
  while (pos_ < src_.size() && src_[pos_] != '\n') {
    auto c = static_cast<unsigned char>(src_[pos_]);
    pos_ += (c != 0 && c < 0x80) ? 1 : check_text_byte(pos_, nullptr);
  }
}

void Scanner::skip_block_comment() {
  std::uint32_t begin = pos_;
  pos_ += 2;
  for (;;) {
    if (pos_ >= src_.size()) {
      diags_
          .report(DiagKind::UnterminatedComment, span(begin, begin + 2),
                  "'/*' comment is never closed")
          .note("block comments end at the first '*/' and do not nest");
      ate_rest_ = true;
      return;
    }
    char c = src_[pos_];
    if (c == '*' && pos_ + 1 < src_.size() && src_[pos_ + 1] == '/') {
      pos_ += 2;
      return;
    }
    auto u = static_cast<unsigned char>(c);
    pos_ += (u != 0 && u < 0x80) ? 1 : check_text_byte(pos_, nullptr);
  }
}

void Scanner::skip_trivia() {
  while (pos_ < src_.size()) {
    char c = src_[pos_];
    if (c == ' ' || c == '\n' || c == '\t' || c == '\r' || c == '\f' || c == '\v') {
      ++pos_;
    } else if (c == '/' && pos_ + 1 < src_.size() && src_[pos_ + 1] == '/') {
      skip_line_comment();
    } else if (c == '/' && pos_ + 1 < src_.size() && src_[pos_ + 1] == '*') {
      skip_block_comment();
    } else {
      return;
    }
  }
}

Token Scanner::identifier(std::uint32_t begin) {
  while (pos_ < src_.size() && is_ident_char(src_[pos_])) ++pos_;
  Token t = make(TokenKind::Identifier, begin, pos_);
  if (pos_ - begin > kMaxIdentifierBytes) {
    diags_.report(DiagKind::IdentifierTooLong, span(begin, pos_),
                  "identifier is " + std::to_string(pos_ - begin) + " bytes long; the limit is " +
                      std::to_string(kMaxIdentifierBytes));
    return t;  // still an identifier, so the parser does not cascade
  }
  t.kind = keyword_kind(t.text);
  return t;
}

// number -> digits [ '.' digits ] [ ('e'|'E') ['+'|'-'] digits ]  |  '.' digits [ exponent ]
// There is no "1." form, so "0..5" is 0 .. 5 and "v.x" after a number is a component.
// Digits with an optional fraction, at most 15 digits in all: the digits as an
// integer m < 10^15 < 2^53 and the power 10^k (k <= 15) are exact doubles, so the
// one correctly rounded division m / 10^k is the correctly rounded value of the
// literal, the same double from_chars gives (Clinger's fast path). Anything
// else (exponents, long literals) goes to from_chars.
bool Scanner::simple_decimal(std::uint32_t begin, std::uint32_t end, double& out) const {
  static constexpr double kPow10[] = {1e0, 1e1, 1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                      1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15};
  if (end - begin > 16) return false;
  std::uint64_t m = 0;
  int digits = 0, fraction = -1;
  for (std::uint32_t i = begin; i < end; ++i) {
    char c = src_[i];
    if (c == '.') {
      fraction = 0;
      continue;
    }
    if (!is_digit(c)) return false;
    m = m * 10 + static_cast<std::uint64_t>(c - '0');
    ++digits;
    if (fraction >= 0) ++fraction;
  }
  if (digits == 0 || digits > 15) return false;
  out = static_cast<double>(m) / kPow10[fraction > 0 ? fraction : 0];
  return true;
}

Token Scanner::number(std::uint32_t begin) {
  auto digit_at = [&](std::size_t i) { return i < src_.size() && is_digit(src_[i]); };
  while (digit_at(pos_)) ++pos_;
  if (pos_ < src_.size() && src_[pos_] == '.' && digit_at(pos_ + 1)) {
    ++pos_;
    while (digit_at(pos_)) ++pos_;
  }
  std::string problem;
  if (pos_ < src_.size() && (src_[pos_] == 'e' || src_[pos_] == 'E')) {
    std::uint32_t p = pos_ + 1;
    if (p < src_.size() && (src_[p] == '+' || src_[p] == '-')) ++p;
    if (digit_at(p)) {
      pos_ = p;
      while (digit_at(pos_)) ++pos_;
    } else {
      pos_ = p;
      problem = "the exponent has no digits";
    }
  }
  std::uint32_t value_end = pos_;
  if (pos_ < src_.size() && is_ident_char(src_[pos_])) {
    while (pos_ < src_.size() && is_ident_char(src_[pos_])) ++pos_;
    if (problem.empty())
      problem = "invalid suffix '" + std::string(src_.substr(value_end, pos_ - value_end)) + "'";
  }
  Token t = make(TokenKind::Number, begin, pos_);
  if (problem.empty() && simple_decimal(begin, value_end, t.number)) {
    // done: the common short literal, exactly as from_chars would read it
  } else if (problem.empty()) {
    const char* first = src_.data() + begin;
    const char* last = src_.data() + value_end;
    auto [ptr, ec] = std::from_chars(first, last, t.number);
    if (ec == std::errc::result_out_of_range) {
      // from_chars reports underflow and overflow alike; only overflow is an error.
      double v = std::strtod(std::string(first, last).c_str(), nullptr);
      if (v > 1.0)
        problem = "the number is too large for a 64-bit real";
      else
        t.number = v;
    } else if (ec != std::errc() || ptr != last) {
      problem = "the number cannot be read";
    }
  }
  if (!problem.empty()) {
    diags_.report(DiagKind::InvalidNumber, t.span,
                  "invalid number '" + std::string(t.text.substr(0, 40)) + "': " + problem);
    t.number = 0;  // keep a Number token so the parser does not cascade
    t.invalid = true;
  }
  return t;
}

// string -> '"' { char | '\' ( '"' | '\' | 'n' | 't' ) } '"'   (on one line)
Token Scanner::string(std::uint32_t begin) {
  ++pos_;
  std::string value;
  for (;;) {
    if (pos_ >= src_.size() || src_[pos_] == '\n') {
      std::uint32_t end = pos_;
      if (end > begin && src_[end - 1] == '\r') --end;
      diags_
          .report(DiagKind::UnterminatedString, span(begin, end),
                  "string is missing its closing '\"'")
          .note("a string ends on the line where it starts");
      Token t = make(TokenKind::String, begin, pos_);
      unterminated_ends_.push_back(pos_);
      if (!value.empty() && value.back() == '\r') value.pop_back();
      t.string = std::move(value);
      return t;
    }
    char c = src_[pos_];
    if (c == '"') {
      ++pos_;
      break;
    }
    if (c == '\\') {
      char e = pos_ + 1 < src_.size() ? src_[pos_ + 1] : '\n';
      switch (e) {
        case '"':
          value += '"';
          pos_ += 2;
          continue;
        case '\\':
          value += '\\';
          pos_ += 2;
          continue;
        case 'n':
          value += '\n';
          pos_ += 2;
          continue;
        case 't':
          value += '\t';
          pos_ += 2;
          continue;
        case '\n':
        case '\r':
          ++pos_;
          continue;  // reported as unterminated
        default:
          break;
      }
      std::uint32_t n = 1 + std::max<std::uint32_t>(1, utf8_sequence_length(src_, pos_ + 1));
      diags_
          .report(DiagKind::InvalidEscape, span(pos_, pos_ + n),
                  "invalid escape '" + std::string(src_.substr(pos_, n)) + "' in string")
          .note("the escapes are \\\" \\\\ \\n and \\t");
      pos_ += 1;  // the escaped character is kept as written
      continue;
    }
    auto u = static_cast<unsigned char>(c);
    if (u != 0 && u < 0x80) {
      value += c;
      ++pos_;
    } else {
      pos_ += check_text_byte(pos_, &value);
    }
  }
  Token t = make(TokenKind::String, begin, pos_);
  t.string = std::move(value);
  return t;
}

// A byte that starts no token: one Error token and one diagnostic per character, or
// per run of bytes that are not UTF-8 at all.
Token Scanner::invalid(std::uint32_t begin) {
  auto c = static_cast<unsigned char>(src_[begin]);
  if (c == 0) {
    while (pos_ < src_.size() && src_[pos_] == '\0') ++pos_;
    diags_.report(DiagKind::NulByte, span(begin, pos_), "NUL byte in the source text");
    return make(TokenKind::Error, begin, pos_);
  }
  std::string message;
  if (c >= 0x80) {
    std::uint32_t n = utf8_sequence_length(src_, begin);
    if (n > 0) {
      pos_ = begin + n;
      message = "unexpected character '" + std::string(src_.substr(begin, n)) + "' (" +
                code_point_name(src_.substr(begin, n)) + ")";
    } else {
      pos_ = begin + 1;
      while (pos_ < src_.size() && static_cast<unsigned char>(src_[pos_]) >= 0x80 &&
             utf8_sequence_length(src_, pos_) == 0)
        ++pos_;
      message = "invalid UTF-8 byte " + hex_byte(c) + " outside a string or comment";
    }
  } else {
    pos_ = begin + 1;
    if (c < 0x20 || c == 0x7F)
      message = "unexpected control character " + hex_byte(c);
    else
      message = std::string("unexpected character '") + static_cast<char>(c) + "'";
  }
  auto builder = diags_.report(DiagKind::InvalidCharacter, span(begin, pos_), message);
  if (c == '&') builder.note("the logical 'and' operator is '&&'");
  if (c == '|') builder.note("the logical 'or' operator is '||'");
  if (c == '[' || c == ']') builder.note("vectors are written in angle brackets: <1, 2, 3>");
  if (c == '#') {
    // POV-Ray's directives: say what Snell writes instead.
    std::string_view word = src_.substr(pos_, 8);
    if (word.starts_with("include"))
      builder.note("Snell has no directives: write import \"file.scn\"; (§9)");
    else if (word.starts_with("declare") || word.starts_with("local"))
      builder.note("Snell has no directives: write let NAME = VALUE; (§4)");
    else if (word.starts_with("macro"))
      builder.note("Snell has no directives: write fn NAME(P, ...) { ... } (§4)");
    else if (word.starts_with("while") || word.starts_with("for") || word.starts_with("if"))
      builder.note("Snell has no directives: write for, if and recursion as statements (§4)");
  }
  return make(TokenKind::Error, begin, pos_);
}

Token Scanner::next() {
  skip_trivia();
  std::uint32_t b = pos_;
  if (pos_ >= src_.size()) return make(TokenKind::EndOfFile, b, b);
  char c = src_[pos_];
  if (is_ident_start(c)) return identifier(b);
  if (is_digit(c) || (c == '.' && pos_ + 1 < src_.size() && is_digit(src_[pos_ + 1])))
    return number(b);
  if (c == '"') return string(b);
  char n = pos_ + 1 < src_.size() ? src_[pos_ + 1] : '\0';
  auto one = [&](TokenKind k) {
    pos_ += 1;
    return make(k, b, pos_);
  };
  auto two = [&](TokenKind k) {
    pos_ += 2;
    return make(k, b, pos_);
  };
  switch (c) {
    case '(':
      return one(TokenKind::LParen);
    case ')':
      return one(TokenKind::RParen);
    case '{':
      return one(TokenKind::LBrace);
    case '}':
      return one(TokenKind::RBrace);
    case ',':
      return one(TokenKind::Comma);
    case ';':
      return one(TokenKind::Semicolon);
    case '.':
      return n == '.' ? two(TokenKind::DotDot) : one(TokenKind::Dot);
    case '=':
      return n == '=' ? two(TokenKind::EqualEqual) : one(TokenKind::Equal);
    case '!':
      return n == '=' ? two(TokenKind::BangEqual) : one(TokenKind::Bang);
    case '<':
      return n == '=' ? two(TokenKind::LessEqual) : one(TokenKind::Less);
    // No '>>': "<1, <2, 3>>" closes two vectors.
    case '>':
      return n == '=' ? two(TokenKind::GreaterEqual) : one(TokenKind::Greater);
    case '+':
      return one(TokenKind::Plus);
    case '-':
      return one(TokenKind::Minus);
    case '*':
      return one(TokenKind::Star);
    case '/':
      return one(TokenKind::Slash);
    case '%':
      return one(TokenKind::Percent);
    case '&':
      if (n == '&') return two(TokenKind::AmpAmp);
      break;
    case '|':
      if (n == '|') return two(TokenKind::PipePipe);
      break;
    default:
      break;
  }
  return invalid(b);
}

std::vector<Token> lex(const SourceManager& sources, FileId file, DiagnosticEngine& diags) {
  Scanner scanner(sources, file, diags);
  std::vector<Token> tokens;
  for (;;) {
    tokens.push_back(scanner.next());
    if (tokens.back().kind == TokenKind::EndOfFile) return tokens;
  }
}

}  // namespace snell::lang
