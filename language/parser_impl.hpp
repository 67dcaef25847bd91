// The parser's state, shared by parser.cpp (statements, blocks, recovery) and
// parse_expr.cpp (the Pratt table). Private to the language layer.
#pragma once

#include <string>

#include "language/parser.hpp"
#include "language/scanner.hpp"

namespace snell::lang {

class Parser {
 public:
  Parser(const SourceManager& sources, FileId file, DiagnosticEngine& diags);
  Program parse_program();

 private:
  friend class DepthGuard;

  // ---- tokens (parser.cpp)
  void advance();
  Token take();  // the current token, then advance
  bool at(TokenKind k) const { return cur_.kind == k; }
  bool accept(TokenKind k);
  Span here() const { return cur_.span; }
  // A string missing its closing quote: the token just read, or the current one.
  // It ran to the end of its line, eating whatever stood there.
  bool after_unterminated_string() const {
    return prev_kind_ == TokenKind::String && scanner_.unterminated_string_ends_at(last_end_);
  }
  bool at_unterminated_string() const {
    return at(TokenKind::String) && scanner_.unterminated_string_ends_at(cur_.span.end);
  }
  // Whether `at` is on a later line than `from` and indented no deeper than
  // `from`'s line: the layout of a sibling, not of something inside (the
  // recovery's sign of a '}' left out).
  bool outdented(std::uint32_t at, std::uint32_t from) const {
    return scanner_.newline_between(from, at) &&
           scanner_.column(at) <= scanner_.indent_of_line(from);
  }
  Span from(Span begin) const { return {file_, begin.begin, last_end_}; }
  std::string describe(const Token& t) const;  // "'radius'", "end of file", ...

  // ---- diagnostics and recovery (parser.cpp)
  // Reports unless the parser is in panic mode (clox), then enters panic mode.
  DiagBuilder error(DiagKind kind, Span span, std::string message);
  // As error(), at the current token; silent when that token is an Error token the
  // lexer already reported, or the end of a file an unclosed comment swallowed.
  DiagBuilder error_here(DiagKind kind, std::string message);
  DiagBuilder dropped() { return DiagBuilder(&diags_, static_cast<std::size_t>(-1)); }
  void expect_semicolon(std::string_view after);
  // Reports a missing closer: UnclosedDelimiter at the opener at end of file,
  // otherwise ExpectedToken here with a note at the opener.
  void missing_closer(const Token& opener, std::string_view closer, std::string_view what);
  void synchronize();
  void skip_balanced_braces();
  // True (after reporting NestingTooDeep and skipping the deep remainder) when the
  // nesting depth is past kMaxNesting.
  bool too_deep();

  // ---- statements (parser.cpp)
  void parse_statements(std::vector<StmtPtr>& out, bool nested);
  StmtPtr parse_statement();
  TokenKind keyword_slip() const;
  StmtPtr parse_let();
  StmtPtr parse_fn();
  StmtPtr parse_return();
  StmtPtr parse_for();
  StmtPtr parse_if();
  StmtPtr parse_import();
  StmtPtr parse_item();
  StmtPtr parse_background();
  StmtPtr parse_expr_stmt();
  bool parse_body(std::vector<StmtPtr>& out, const char* owner);
  bool expect_name(std::string& name, Span& span, const char* what);

  // ---- blocks and expressions (parse_expr.cpp)
  BlockPtr parse_block(std::string_view owner);  // owner: "sphere", "motion", ...
  // The body of an object block by its keyword: a CSG body (groups.def), an
  // instance body, or a plain property block.
  BlockPtr parse_object_body(std::string_view owner);
  bool reads_as_property() const;
  BlockPtr parse_group_body(std::string_view owner);
  BlockPtr parse_block_rest(const Token& open, std::string_view owner);
  BlockPtr parse_instance_body(std::string_view owner);
  bool parse_property(Property& prop);  // IDENT ( block | expr ), at the IDENT
  ExprPtr parse_object_value();
  ExprPtr parse_expr(int min_power = 1);
  ExprPtr parse_unary();
  ExprPtr parse_postfix(ExprPtr base);
  ExprPtr parse_primary();
  ExprPtr parse_paren();
  ExprPtr parse_vector();
  ExprPtr parse_call(ExprPtr callee);
  ExprPtr parse_constructor();
  ExprPtr make(ExprKind kind, Span span);  // a node from arena_
  ExprPtr error_expr(Span span);
  template <typename T>
  void take_scratch(std::vector<T>& out, std::size_t mark);
  void take_scratch(ExprList& out, std::size_t mark);
  std::vector<ExprPtr>& scratch(ExprPtr*) { return scratch_exprs_; }
  std::vector<Property>& scratch(Property*) { return scratch_properties_; }

  FileId file_;
  DiagnosticEngine& diags_;
  Scanner scanner_;
  Token cur_;
  Token peek_;
  TokenKind prev_kind_ = TokenKind::EndOfFile;
  std::uint32_t last_end_ = 0;  // end offset of the last consumed token
  std::uint64_t consumed_ = 0;  // tokens consumed so far (progress checks)
  bool panic_ = false;
  // A syntax error left the statement (or block property) being read unreadable:
  // it is dropped, not run on what was read before the error (§10: independent
  // errors only; `let v = (<1, 2 > 1);` bound v to <1, 2>). Kept per level: a
  // block that recovered at a property name or its '}', and a body whose broken
  // statements were dropped, do not break the statement around them; a missing ';'
  // breaks nothing.
  bool broke_ = false;
  // Every identifier consumed so far, and the names of broken statements
  // (Program::unsure_names): names_seen_ from `mark` on become unsure.
  std::vector<std::string_view> names_seen_;
  std::vector<std::string> unsure_;
  void make_unsure(std::size_t mark);
  bool errors_within(std::size_t kept, std::size_t errors) const;
  void hoist_unclosed(std::vector<StmtPtr>& body, const Token& open);
  void take_hoisted(std::vector<StmtPtr>& out);
  void skip_unbraced_body(std::uint32_t head_end);
  std::vector<StmtPtr> hoisted_;  // see hoist_unclosed
  bool eof_said_ = false;         // a statement's error at the end of the file was reported
  // parse_block_rest's next block is an instance body (instance_body_), whose value
  // may stand last (late_subject_); in_instance_ while its properties are read.
  bool instance_body_ = false, late_subject_ = false, in_instance_ = false;
  bool in_vector_ = false;  // parsing an element of a vector literal at its top level
  // The '>' that closed the last vector literal (a hint when a comparison in a
  // vector closed it early: `<1, a > b, 2>`).
  Span vector_close_{0, 0, 0};
  bool vector_closed_ = false;
  bool no_object_ = false;  // an `if` condition or loop bound: IDENT '{' is not a value
  int depth_ = 0;           // nesting of expressions, blocks and chains built so far
  std::unique_ptr<ExprArena> arena_ = std::make_unique<ExprArena>();  // moved into the Program
  std::vector<ExprPtr> scratch_exprs_;                                // see take_scratch()
  std::vector<Property> scratch_properties_;
};

// Counts one level of nesting for the lifetime of a parse function; chains
// (a + b + c, f(x)(y), v.x.y) add to depth_ inside it and are undone here too.
class DepthGuard {
 public:
  explicit DepthGuard(Parser& p) : p_(p), saved_(p.depth_) { ++p.depth_; }
  ~DepthGuard() { p_.depth_ = saved_; }
  DepthGuard(const DepthGuard&) = delete;
  DepthGuard& operator=(const DepthGuard&) = delete;

 private:
  Parser& p_;
  int saved_;
};

// Tokens that can begin an operand (and so an expression statement or a
// positional constructor argument).
bool starts_operand(TokenKind k);
// Keywords that begin a statement (recovery points).
bool starts_statement(TokenKind k);

}  // namespace snell::lang
