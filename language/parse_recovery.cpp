// The parser's token handling, its diagnostics and its recovery from syntax
// errors (parser.cpp: statements; parse_expr.cpp: expressions and blocks).
//
// Recovery follows clox: the first error of a statement sets panic mode, which
// silences further errors until synchronize() reaches a statement boundary (or a
// property block reaches its next property name). So every independent error is
// reported once and none is a consequence of another. Beyond clox: a body left
// open at the end of the file gives back what followed it (hoist_unclosed), and a
// keyword one slip off is read as the keyword (keyword_slip).
#include <algorithm>
#include <cctype>

#include "language/parser_impl.hpp"

namespace snell::lang {

void Parser::advance() {
  if (cur_.kind == TokenKind::Identifier) names_seen_.push_back(cur_.text);
  // A string missing its closing quote ran to the end of its line: the names it
  // swallowed (`let "angle = 30;`) count as seen, so a statement it broke makes
  // them unsure rather than "not defined" at every later use.
  if (at_unterminated_string())
    for (std::size_t i = 0; i < cur_.text.size();) {
      auto word = [&](char c, bool first) {
        return c == '_' || std::isalpha(static_cast<unsigned char>(c)) ||
               (!first && std::isdigit(static_cast<unsigned char>(c)));
      };
      if (!word(cur_.text[i], true)) {
        ++i;
        continue;
      }
      std::size_t j = i + 1;
      while (j < cur_.text.size() && word(cur_.text[j], false)) ++j;
      names_seen_.push_back(cur_.text.substr(i, j - i));
      i = j;
    }
  prev_kind_ = cur_.kind;
  last_end_ = cur_.span.end;
  ++consumed_;
  cur_ = std::move(peek_);
  // Past the error limit nothing more can be shown: pretend the file ends here so
  // every loop unwinds at once (hostile input stays cheap).
  if (diags_.limit_reached() && cur_.kind != TokenKind::EndOfFile) {
    diags_.stopped_reading();
    cur_.kind = TokenKind::EndOfFile;
    peek_ = cur_;
    return;
  }
  peek_ = cur_.kind == TokenKind::EndOfFile ? cur_ : scanner_.next();
}

Token Parser::take() {
  Token t = cur_;
  advance();
  return t;
}

bool Parser::accept(TokenKind k) {
  if (!at(k)) return false;
  advance();
  return true;
}

std::string Parser::describe(const Token& t) const {
  switch (t.kind) {
    case TokenKind::EndOfFile:
      return "the end of the file";
    case TokenKind::String:
      return "a string";
    default:
      break;
  }
  std::string_view text = t.text;
  std::string out = "'";
  out.append(text.substr(0, 24));
  if (text.size() > 24) out += "...";
  out += '\'';
  return out;
}

DiagBuilder Parser::error(DiagKind kind, Span span, std::string message) {
  if (panic_) return dropped();
  panic_ = true;
  broke_ = true;
  return diags_.report(kind, span, std::move(message));
}

DiagBuilder Parser::error_here(DiagKind kind, std::string message) {
  if (at(TokenKind::Error) || (at(TokenKind::EndOfFile) && scanner_.ate_rest_of_file()) ||
      at_unterminated_string()) {
    panic_ = true;
    broke_ = true;
    return dropped();
  }
  if (at(TokenKind::EndOfFile) && !panic_) eof_said_ = true;
  return error(kind, here(), std::move(message));
}

// Reported just after the previous token (as clang does), so a missing ';' at the
// end of a line points at that line, not at the next statement.
void Parser::expect_semicolon(std::string_view after) {
  if (accept(TokenKind::Semicolon)) return;
  if (at(TokenKind::Error) || (at(TokenKind::EndOfFile) && scanner_.ate_rest_of_file()) ||
      after_unterminated_string()) {
    panic_ = true;
    return;
  }
  const bool whole = !broke_;  // what came before the missing ';' was read whole
  const bool was_panicking = panic_;
  if (at(TokenKind::EndOfFile) && !panic_) eof_said_ = true;
  error(DiagKind::ExpectedToken, {file_, last_end_, last_end_},
        "expected ';' after " + std::string(after) + ", found " + describe(cur_));
  if (whole) broke_ = false;
  // What follows starts a statement (a keyword, an item's `NAME {`, a call's
  // `NAME (`): it is read as one, on this line too, where synchronize() would skip
  // it to the next line (`let a = 1 sphere { radius -2 }` lost the sphere).
  if (whole && !was_panicking &&
      (starts_statement(cur_.kind) ||
       (at(TokenKind::Identifier) &&
        (peek_.kind == TokenKind::LBrace || peek_.kind == TokenKind::LParen))))
    panic_ = false;
}

void Parser::missing_closer(const Token& opener, std::string_view closer, std::string_view what) {
  std::string open(opener.text);
  // A string missing its closing quote since the opener ate the closer, most
  // likely: its own error says so.
  if (closer == "}" && scanner_.unterminated_string_between(opener.span.end, cur_.span.begin + 1)) {
    panic_ = true;
    broke_ = true;
    return;
  }
  if (at(TokenKind::EndOfFile)) {
    if (scanner_.ate_rest_of_file()) return;
    // A file cut short in the middle of a statement leaves every enclosing
    // delimiter open: the statement's error at the end says it (one mistake, one
    // error), the delimiters around it are not said again. Cut between statements,
    // each delimiter left open is said (each needs its closer).
    if (eof_said_) {
      panic_ = true;
      broke_ = true;
      return;
    }
    error(DiagKind::UnclosedDelimiter, opener.span,
          "unclosed '" + open + "' of " + std::string(what))
        .note("the file ends before its '" + std::string(closer) + "'");
    return;
  }
  error_here(DiagKind::ExpectedToken, "expected '" + std::string(closer) + "' to close " +
                                          std::string(what) + ", found " + describe(cur_))
      .note(opener.span, "to close '" + open + "' opened here");
}

void Parser::skip_balanced_braces() {
  int level = 0;
  while (!at(TokenKind::EndOfFile)) {
    if (at(TokenKind::LBrace)) ++level;
    if (at(TokenKind::RBrace) && --level <= 0) {
      advance();
      return;
    }
    advance();
  }
}

// Skips to the start of the next statement: just past a ';' or a '{ }' group, or
// before a statement keyword, a '}', or an identifier that begins a line and is
// followed by '{' (a scene item).
void Parser::synchronize() {
  panic_ = false;
  if (prev_kind_ == TokenKind::Semicolon || prev_kind_ == TokenKind::RBrace ||
      prev_kind_ == TokenKind::LBrace)
    return;
  while (!at(TokenKind::EndOfFile)) {
    if (at(TokenKind::Semicolon)) {
      advance();
      return;
    }
    if (at(TokenKind::RBrace) || starts_statement(cur_.kind)) return;
    if (at(TokenKind::LBrace)) {
      skip_balanced_braces();
      return;
    }
    if (at(TokenKind::Identifier) && peek_.kind == TokenKind::LBrace &&
        scanner_.newline_between(last_end_, cur_.span.begin))
      return;
    advance();
  }
}

bool Parser::too_deep() {
  if (depth_ <= kMaxNesting) return false;
  error(DiagKind::NestingTooDeep, here(),
        "nesting is deeper than " + std::to_string(kMaxNesting) + " levels")
      .note("split the expression or block with 'let' or 'fn'");
  panic_ = true;
  // Skip the rest of the deep construct, up to the first ')' '}' or ';' that belongs
  // to an enclosing level, so the levels above close normally and nothing deeper is
  // ever built (every later walk of the tree, its destructor included, is recursive).
  int level = 0;
  while (!at(TokenKind::EndOfFile)) {
    TokenKind k = cur_.kind;
    if (k == TokenKind::LParen || k == TokenKind::LBrace) ++level;
    if (k == TokenKind::RParen || k == TokenKind::RBrace) {
      if (level == 0) break;
      --level;
    }
    if (k == TokenKind::Semicolon && level == 0) break;
    advance();
  }
  return true;
}

// Whether an error since (kept, errors) lies in the statement just read. The
// parser's own errors set panic_; the lexer's are reported as it scans the
// lookahead, so an error past the statement's last token (a '/*' never closed
// after it) is the next statement's, and does not make this one's names unsure.
// An error dropped past --max-errors cannot be placed, so it counts.
bool Parser::errors_within(std::size_t kept, std::size_t errors) const {
  const std::size_t now = diags_.error_count();
  if (now == errors) return false;
  const auto& all = diags_.diagnostics();
  std::size_t placed = 0;
  for (std::size_t i = kept; i < all.size(); ++i) {
    if (all[i].severity != Severity::Error) continue;
    ++placed;
    if (all[i].span.file != file_ || all[i].span.begin < last_end_) return true;
  }
  return placed < now - errors;
}

// A body (or CSG body) still open at the end of the file swallowed what followed
// it: its statements from the first that starts a later line indented no deeper
// than the body's opening line are taken out of it, to follow the statement that
// holds the body in the list around it (take_hoisted), so they run and their own
// errors are said (a `fn` missing its '}' hid every error after it).
void Parser::hoist_unclosed(std::vector<StmtPtr>& body, const Token& open) {
  auto starts_line = [&](std::uint32_t at) {
    return scanner_.indent_of_line(at) == scanner_.column(at);
  };
  std::size_t k = 0;
  while (k < body.size() &&
         !(outdented(body[k]->span.begin, open.span.end) && starts_line(body[k]->span.begin)))
    ++k;
  for (std::size_t i = k; i < body.size(); ++i) hoisted_.push_back(std::move(body[i]));
  body.resize(k);
}

void Parser::take_hoisted(std::vector<StmtPtr>& out) {
  for (StmtPtr& s : hoisted_) out.push_back(std::move(s));
  hoisted_.clear();
}

void Parser::make_unsure(std::size_t mark) {
  for (std::size_t i = mark; i < names_seen_.size(); ++i) unsure_.emplace_back(names_seen_[i]);
  names_seen_.resize(mark);  // each once, however deep the statement
}

// After a body's missing '{' (reported): when only the '{' was left out, the
// body starts the next line, indented deeper than the head that ends at
// `head_end`. It is read to its '}' and dropped with its statement, so neither
// its lines nor the '}' are reported again as statements out of place.
void Parser::skip_unbraced_body(std::uint32_t head_end) {
  if (at(TokenKind::EndOfFile) || !scanner_.newline_between(head_end, cur_.span.begin) ||
      scanner_.column(cur_.span.begin) <= scanner_.indent_of_line(head_end ? head_end - 1 : 0))
    return;
  std::vector<StmtPtr> body;
  panic_ = false;
  const bool broke = broke_;
  parse_statements(body, true);
  broke_ = broke;
  accept(TokenKind::RBrace);
}

// The statement keyword the current identifier is one slip from, given what follows
// it (a file name: `import`; a name: `let`, `fn`, `for`, `if`, `return`), else
// TokenKind::Error.
TokenKind Parser::keyword_slip() const {
  std::vector<std::string_view> words;
  if (peek_.kind == TokenKind::String)
    words = {"import"};
  else
    words = {"let", "fn", "for", "if", "return"};
  const std::string guess = closest_match(cur_.text, words);
  if (guess.empty()) return TokenKind::Error;
  for (TokenKind k : {TokenKind::KwImport, TokenKind::KwLet, TokenKind::KwFn, TokenKind::KwFor,
                      TokenKind::KwIf, TokenKind::KwReturn})
    if (token_spelling(k) == guess) return k;
  return TokenKind::Error;
}

}  // namespace snell::lang
