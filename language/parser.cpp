// Statements (§4). Expressions and property blocks are in parse_expr.cpp; token
// handling, diagnostics and error recovery in parse_recovery.cpp.
#include <algorithm>

#include "language/parser_impl.hpp"

namespace snell::lang {

bool starts_operand(TokenKind k) {
  switch (k) {
    case TokenKind::Number:
    case TokenKind::String:
    case TokenKind::Identifier:
    case TokenKind::LParen:
    case TokenKind::Less:
    case TokenKind::Bang:
    case TokenKind::Minus:
    case TokenKind::KwTrue:
    case TokenKind::KwFalse:
      return true;
    default:
      return false;
  }
}

bool starts_statement(TokenKind k) {
  switch (k) {
    case TokenKind::KwLet:
    case TokenKind::KwFn:
    case TokenKind::KwReturn:
    case TokenKind::KwIf:
    case TokenKind::KwFor:
    case TokenKind::KwImport:
      return true;
    default:
      return false;
  }
}

namespace {

bool is_keyword(TokenKind k) {
  return k >= TokenKind::KwLet;
}

}  // namespace

Parser::Parser(const SourceManager& sources, FileId file, DiagnosticEngine& diags)
    : file_(file), diags_(diags), scanner_(sources, file, diags) {
  cur_ = scanner_.next();
  peek_ = scanner_.next();
}

Program Parser::parse_program() {
  Program program;
  program.file = file_;
  parse_statements(program.statements, false);
  program.arena = std::move(arena_);
  std::sort(unsure_.begin(), unsure_.end());
  unsure_.erase(std::unique(unsure_.begin(), unsure_.end()), unsure_.end());
  program.unsure_names = std::move(unsure_);
  return program;
}

// statements -> { statement }      (up to '}' when nested, else to the end of file)
void Parser::parse_statements(std::vector<StmtPtr>& out, bool nested) {
  const bool outer = broke_;  // the statement around a body, when nested
  while (!at(TokenKind::EndOfFile)) {
    if (at(TokenKind::RBrace)) {
      if (nested) {
        broke_ = outer;
        return;
      }
      // Not after a string missing its quote: it most likely ate the '{'.
      if (!scanner_.unterminated_string_between(0, cur_.span.begin))
        error(DiagKind::ExpectedStatement, here(), "unmatched '}'");
      advance();
      continue;
    }
    if (panic_) {
      std::size_t mark = names_seen_.size();
      synchronize();
      make_unsure(mark);
      continue;
    }
    std::uint64_t before = consumed_;
    std::size_t mark = names_seen_.size(), errors = diags_.error_count();
    std::size_t kept = diags_.diagnostics().size();
    broke_ = false;
    StmtPtr s = parse_statement();
    if (s && !broke_) out.push_back(std::move(s));
    take_hoisted(out);
    if (consumed_ == before) advance();  // always make progress
    if (panic_ || errors_within(kept, errors))
      make_unsure(mark);
    else if (!nested)
      names_seen_.resize(mark);  // a whole statement: its names are sure
  }
  broke_ = outer;
}

// statement -> let | fn | return | for | if | import | item | background
//            | expr ';' | ';'
StmtPtr Parser::parse_statement() {
  switch (cur_.kind) {
    case TokenKind::KwLet:
      return parse_let();
    case TokenKind::KwFn:
      return parse_fn();
    case TokenKind::KwReturn:
      return parse_return();
    case TokenKind::KwFor:
      return parse_for();
    case TokenKind::KwIf:
      return parse_if();
    case TokenKind::KwImport:
      return parse_import();
    case TokenKind::Semicolon:
      advance();
      return nullptr;  // stray ';' is harmless
    case TokenKind::Identifier:
      if (peek_.kind == TokenKind::LBrace) return parse_item();
      if (peek_.kind == TokenKind::Identifier || peek_.kind == TokenKind::String) {
        // IDENT IDENT and IDENT STRING start no statement. A keyword one slip off
        // (`lett a = 1;`, `improt "x.scn";`, `fro i in ...`) is read as that
        // keyword's statement after an error naming it, so what it binds is bound
        // (its names were all "not defined" after it).
        if (TokenKind k = keyword_slip(); k != TokenKind::Error) {
          diags_
              .report(DiagKind::ExpectedStatement, here(),
                      "'" + std::string(cur_.text) + "' is not a keyword")
              .note("did you mean '" + std::string(token_spelling(k)) + "'?");
          cur_.kind = k;
          return parse_statement();
        }
        // An item's '{' left out (`sphere center <0, 1, 0> radius 1 }`, `object
        // cup translate <1, 0, 0> }`): its properties (an instance's value, then
        // its properties) are read as its block's, to the '}'.
        if (peek_.kind == TokenKind::Identifier && is_item_name(cur_.text) &&
            !is_group_name(cur_.text)) {
          auto stmt = std::make_unique<Stmt>();
          stmt->kind = StmtKind::Item;
          stmt->name = std::string(cur_.text);
          stmt->name_span = stmt->span = here();
          Token keyword = take();
          diags_.report(DiagKind::ExpectedToken, {file_, last_end_, last_end_},
                        "expected '{' after '" + stmt->name + "', found " + describe(cur_));
          ExprPtr subject;
          if (is_instance_name(stmt->name)) {
            subject = parse_expr();
            instance_body_ = true;
          }
          stmt->block = parse_block_rest(keyword, stmt->name);
          stmt->block->subject = std::move(subject);
          stmt->block->broken = true;  // its required properties are not asked for
          accept(TokenKind::Semicolon);
          stmt->span = from(stmt->span);
          return stmt;
        }
      }
      // §4 `background EXPR`, EXPR any expression: `background (0.5)` too (it was
      // read as a call of a function named background).
      if (cur_.text == "background" && peek_.kind != TokenKind::Equal) return parse_background();
      return parse_expr_stmt();
    default:
      break;
  }
  if (starts_operand(cur_.kind)) return parse_expr_stmt();
  auto stmt = std::make_unique<Stmt>();
  stmt->span = here();
  if (at(TokenKind::KwElse))
    error_here(DiagKind::ExpectedStatement, "'else' without a matching 'if'");
  else
    error_here(DiagKind::ExpectedStatement, "expected a statement, found " + describe(cur_));
  advance();
  return stmt;
}

bool Parser::expect_name(std::string& name, Span& span, const char* what) {
  if (at(TokenKind::Identifier)) {
    name = std::string(cur_.text);
    span = here();
    advance();
    return true;
  }
  if (is_keyword(cur_.kind)) {
    error_here(DiagKind::ExpectedToken,
               std::string("expected ") + what + ", found the reserved word " + describe(cur_));
    // `fn let() = 1;` is one mistake: take the word as the name so the rest of the
    // line does not read as a second statement. A keyword on the next line is more
    // likely the start of that statement.
    if (!scanner_.newline_between(last_end_, cur_.span.begin)) {
      name = std::string(cur_.text);
      span = here();
      advance();
      return true;
    }
    return false;
  }
  error_here(DiagKind::ExpectedToken,
             std::string("expected ") + what + ", found " + describe(cur_));
  return false;
}

// let -> 'let' IDENT '=' expr ';'
StmtPtr Parser::parse_let() {
  auto stmt = std::make_unique<Stmt>();
  Span begin = take().span;
  if (expect_name(stmt->name, stmt->name_span, "a name after 'let'")) {
    if (accept(TokenKind::Equal)) {
      stmt->kind = StmtKind::Let;
      stmt->exprs.push_back(parse_expr());
      expect_semicolon("the value of '" + stmt->name + "'");
    } else {
      error_here(DiagKind::ExpectedToken,
                 "expected '=' after 'let " + stmt->name + "', found " + describe(cur_));
    }
  }
  stmt->span = from(begin);
  return stmt;
}

// fn -> 'fn' IDENT '(' [ IDENT { ',' IDENT } ] ')' ( '=' expr ';' | '{' statements '}' )
StmtPtr Parser::parse_fn() {
  auto stmt = std::make_unique<Stmt>();
  Span begin = take().span;
  if (!expect_name(stmt->name, stmt->name_span, "a function name after 'fn'")) {
    stmt->span = from(begin);
    return stmt;
  }
  Token open = cur_;
  if (!accept(TokenKind::LParen)) {
    error_here(DiagKind::ExpectedToken,
               "expected '(' after 'fn " + stmt->name + "', found " + describe(cur_));
    stmt->span = from(begin);
    return stmt;
  }
  bool ok = true;
  if (!at(TokenKind::RParen)) {
    for (;;) {
      std::string param;
      Span span;
      if (!expect_name(param, span, "a parameter name")) {
        ok = false;
        break;
      }
      stmt->params.push_back(std::move(param));
      stmt->param_spans.push_back(span);
      if (!accept(TokenKind::Comma)) break;
    }
  }
  if (ok && !accept(TokenKind::RParen)) {
    missing_closer(open, ")", "the parameter list");
    ok = false;
  }
  if (ok && accept(TokenKind::Equal)) {
    stmt->kind = StmtKind::Fn;
    stmt->exprs.push_back(parse_expr());
    expect_semicolon("the function's value");
  } else if (ok && at(TokenKind::LBrace)) {
    stmt->kind = StmtKind::Fn;
    parse_body(stmt->body, "the function body");
  } else if (ok) {
    const std::uint32_t head_end = last_end_;
    error_here(DiagKind::ExpectedToken, "expected '=' or '{' after the parameters of 'fn " +
                                            stmt->name + "', found " + describe(cur_));
    skip_unbraced_body(head_end);
  }
  stmt->span = from(begin);
  return stmt;
}

// return -> 'return' expr ';'
StmtPtr Parser::parse_return() {
  auto stmt = std::make_unique<Stmt>();
  stmt->kind = StmtKind::Return;
  Span begin = take().span;
  stmt->exprs.push_back(parse_expr());
  expect_semicolon("the value of 'return'");
  stmt->span = from(begin);
  return stmt;
}

// for -> 'for' IDENT 'in' expr '..' expr [ 'step' expr ] '{' statements '}'
StmtPtr Parser::parse_for() {
  auto stmt = std::make_unique<Stmt>();
  Span begin = take().span;
  auto fail = [&] {
    stmt->kind = StmtKind::Error;
    stmt->span = from(begin);
    return std::move(stmt);
  };
  if (!expect_name(stmt->name, stmt->name_span, "a loop variable after 'for'")) return fail();
  if (!accept(TokenKind::KwIn)) {
    error_here(DiagKind::ExpectedToken,
               "expected 'in' after 'for " + stmt->name + "', found " + describe(cur_));
    return fail();
  }
  no_object_ = true;
  stmt->exprs.push_back(parse_expr());
  no_object_ = false;
  if (!accept(TokenKind::DotDot)) {
    error_here(DiagKind::ExpectedToken,
               "expected '..' between the bounds of the loop, found " + describe(cur_));
    return fail();
  }
  no_object_ = true;
  stmt->exprs.push_back(parse_expr());
  if (accept(TokenKind::KwStep)) stmt->exprs.push_back(parse_expr());
  no_object_ = false;
  stmt->kind = StmtKind::For;
  parse_body(stmt->body, "the loop body");
  stmt->span = from(begin);
  return stmt;
}

// if -> 'if' expr '{' statements '}' { 'else' 'if' expr '{' statements '}' }
//       [ 'else' '{' statements '}' ]
StmtPtr Parser::parse_if() {
  auto stmt = std::make_unique<Stmt>();
  stmt->kind = StmtKind::If;
  Span begin = take().span;
  // else-if chains are a loop, not recursion: a long chain is not deep nesting.
  for (;;) {
    no_object_ = true;
    stmt->exprs.push_back(parse_expr());
    no_object_ = false;
    stmt->branches.emplace_back();
    if (!parse_body(stmt->branches.back(), "the 'if' body")) break;
    if (!accept(TokenKind::KwElse)) break;
    if (accept(TokenKind::KwIf)) continue;
    if (at(TokenKind::LBrace)) {
      stmt->has_else = true;
      parse_body(stmt->else_body, "the 'else' body");
    } else {
      error_here(DiagKind::ExpectedToken,
                 "expected '{' or 'if' after 'else', found " + describe(cur_));
    }
    break;
  }
  stmt->span = from(begin);
  return stmt;
}

// import -> 'import' STRING ';'
StmtPtr Parser::parse_import() {
  auto stmt = std::make_unique<Stmt>();
  Span begin = take().span;
  if (at(TokenKind::String)) {
    stmt->kind = StmtKind::Import;
    stmt->name = cur_.string;
    stmt->name_span = here();
    advance();
    expect_semicolon("the imported file name");
  } else {
    error_here(DiagKind::ExpectedToken,
               "expected a file name in quotes after 'import', found " + describe(cur_));
  }
  stmt->span = from(begin);
  return stmt;
}

// item -> IDENT object-body [ ';' ]
StmtPtr Parser::parse_item() {
  auto stmt = std::make_unique<Stmt>();
  stmt->kind = StmtKind::Item;
  stmt->name = std::string(cur_.text);
  stmt->name_span = stmt->span = here();
  advance();
  stmt->block = parse_object_body(stmt->name);
  accept(TokenKind::Semicolon);
  stmt->span = from(stmt->span);
  return stmt;
}

// object-body -> group-body | instance-body | block      (by the keyword: groups.def)
BlockPtr Parser::parse_object_body(std::string_view owner) {
  if (is_group_name(owner)) return parse_group_body(owner);
  if (is_instance_name(owner)) return parse_instance_body(owner);
  return parse_block(owner);
}

// A name followed by a value no statement can continue with (`radius 2`,
// `color <1, 0, 0>`, `mortar -1`, `file "a.obj"`, `pattern marble`): in a CSG body
// it is a property the block does not take, reported as one (with the block's
// properties and a near miss) rather than as an expression statement missing its
// ';'. `background` keeps its statement, and `f(2)` or `x.y` stay expressions.
bool Parser::reads_as_property() const {
  if (cur_.text == "background") return false;
  switch (peek_.kind) {
    case TokenKind::Number:
    case TokenKind::String:
    case TokenKind::Less:
    case TokenKind::Minus:
    case TokenKind::Identifier:
      return true;
    default:
      return false;
  }
}

// group-body -> '{' { object-property | statement } '}'
// object-property -> OBJPROP ( block | expr )         (OBJPROP: groups.def)
// A line that starts with an object property's name is that property; any other is
// a statement, so `scale (2)` is the property and `f(2);` a call.
BlockPtr Parser::parse_group_body(std::string_view owner) {
  auto block = std::make_unique<Block>();
  block->span = here();
  DepthGuard guard(*this);
  Token open = take();  // callers checked it is '{'
  if (too_deep()) {
    accept(TokenKind::RBrace);
    block->span = from(open.span);
    return block;
  }
  bool saved_vector = in_vector_, saved_object = no_object_;
  in_vector_ = no_object_ = false;
  std::vector<Property> props;  // not the scratch list: statements below use it
  for (;;) {
    if (accept(TokenKind::RBrace)) break;
    if (at(TokenKind::EndOfFile)) {
      panic_ = false;
      const bool broke = broke_;
      missing_closer(open, "}", "the '" + std::string(owner) + "' block");
      hoist_unclosed(block->statements, open);  // and the block stands, as a body does
      broke_ = broke;
      break;
    }
    if (panic_) {
      synchronize();
      continue;
    }
    std::uint64_t before = consumed_;
    const bool outer = broke_;
    broke_ = false;
    // (An item keyword before a name is no property: its '{' was left out, which
    // parse_statement reads.)
    if (at(TokenKind::Identifier) && (is_object_property(cur_.text) || reads_as_property()) &&
        !(is_item_name(cur_.text) && peek_.kind == TokenKind::Identifier)) {
      Property prop;
      parse_property(prop);
      if (!broke_) props.push_back(std::move(prop));
    } else if (StmtPtr st = parse_statement()) {
      if (!broke_) block->statements.push_back(std::move(st));
    }
    take_hoisted(block->statements);
    broke_ = outer;                      // what broke was dropped
    if (consumed_ == before) advance();  // always make progress
  }
  in_vector_ = saved_vector;
  no_object_ = saved_object;
  block->properties = std::move(props);
  block->span = from(open.span);
  return block;
}

// instance-body -> '{' expr { property } '}'
BlockPtr Parser::parse_instance_body(std::string_view owner) {
  Span begin = here();
  Token open = cur_;
  if (peek_.kind == TokenKind::RBrace || peek_.kind == TokenKind::EndOfFile) {
    take();
    error_here(DiagKind::ExpectedExpression, "'" + std::string(owner) +
                                                 " { }' places an object value: write " +
                                                 std::string(owner) + " { NAME ... }");
    accept(TokenKind::RBrace);
    auto block = std::make_unique<Block>();
    block->span = from(begin);
    return block;
  }
  // The subject is parsed as the first "property value" of a block: take the
  // brace, the expression, then the rest as a plain block body.
  DepthGuard guard(*this);
  take();
  if (too_deep()) {
    accept(TokenKind::RBrace);
    auto block = std::make_unique<Block>();
    block->span = from(begin);
    return block;
  }
  // A property first (`object { translate <1, 0, 0> s }`): read as the block's
  // properties, after an error saying the value comes first (it was read as the
  // value `translate < 1`, and then `, 0>` as a stray).
  if (at(TokenKind::Identifier) && is_object_property(cur_.text) &&
      (starts_operand(peek_.kind) || peek_.kind == TokenKind::LBrace)) {
    error_here(DiagKind::ExpectedExpression,
               "'" + std::string(owner) + " { }' takes its object value first: write " +
                   std::string(owner) + " { NAME " + std::string(cur_.text) + " ... }");
    panic_ = false;  // the properties are read, and judged, as written
    instance_body_ = late_subject_ = true;
    BlockPtr block = parse_block_rest(open, owner);
    block->span = from(begin);
    return block;
  }
  bool saved_vector = in_vector_, saved_object = no_object_;
  in_vector_ = no_object_ = false;
  ExprPtr subject = parse_expr();
  in_vector_ = saved_vector;
  no_object_ = saved_object;
  instance_body_ = true;
  BlockPtr block = parse_block_rest(open, owner);
  block->subject = std::move(subject);
  block->span = from(begin);
  return block;
}

// background -> 'background' expr [ ';' ]
StmtPtr Parser::parse_background() {
  auto stmt = std::make_unique<Stmt>();
  stmt->kind = StmtKind::Background;
  stmt->name_span = stmt->span = here();
  advance();
  stmt->exprs.push_back(parse_expr());
  accept(TokenKind::Semicolon);
  stmt->span = from(stmt->span);
  return stmt;
}

// expr-stmt -> expr ';'      (the compiler checks that expr is a call)
StmtPtr Parser::parse_expr_stmt() {
  auto stmt = std::make_unique<Stmt>();
  stmt->kind = StmtKind::ExprStmt;
  Span begin = here();
  stmt->exprs.push_back(parse_expr());
  // Ended by a string missing its closing quote (which ate the rest of the line):
  // dropped, not also "a value thrown away".
  if (after_unterminated_string()) broke_ = true;
  if (stmt->exprs[0]->kind == ExprKind::Call)
    expect_semicolon("the call");
  else
    expect_semicolon("the expression");
  stmt->span = from(begin);
  return stmt;
}

// body -> '{' statements '}'
bool Parser::parse_body(std::vector<StmtPtr>& out, const char* owner) {
  if (!at(TokenKind::LBrace)) {
    const std::uint32_t head_end = last_end_;
    error_here(DiagKind::ExpectedToken,
               std::string("expected '{' to begin ") + owner + ", found " + describe(cur_));
    skip_unbraced_body(head_end);
    return false;
  }
  DepthGuard guard(*this);
  Token open = take();
  if (too_deep()) return accept(TokenKind::RBrace);
  bool saved_vector = in_vector_;
  in_vector_ = false;
  parse_statements(out, true);
  in_vector_ = saved_vector;
  if (accept(TokenKind::RBrace)) return true;
  panic_ = false;  // an unclosed body is worth reporting even after an inner error
  const bool broke = broke_;
  missing_closer(open, "}", owner);
  if (at(TokenKind::EndOfFile)) {
    // Only its '}' is missing: the statement stands (and runs, and an editor still
    // sees the names it binds), less what followed it (hoist_unclosed).
    hoist_unclosed(out, open);
    broke_ = broke;
  }
  return false;
}

Program parse(const SourceManager& sources, FileId file, DiagnosticEngine& diags) {
  Parser parser(sources, file, diags);
  Program program = parser.parse_program();
  program.source = &sources.file(file);
  return program;
}

}  // namespace snell::lang
