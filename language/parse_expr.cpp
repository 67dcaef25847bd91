// Expressions (§3) with a Pratt table, and property blocks (§5).
#include <utility>

#include "language/parser_impl.hpp"

namespace snell::lang {
namespace {

// The Pratt table: the binding power of each infix operator, loosest first (§3).
// Every level is left-associative, comparisons included: `a < b < c` parses as
// `(a < b) < c` and the compiler rejects comparing a bool with a number, which
// gives a clearer message than a parse error would.
constexpr int kPowerOr = 1, kPowerAnd = 2, kPowerEquality = 3, kPowerCompare = 4, kPowerSum = 5,
              kPowerProduct = 6;

int infix_power(TokenKind k) {
  switch (k) {
    case TokenKind::PipePipe:
      return kPowerOr;
    case TokenKind::AmpAmp:
      return kPowerAnd;
    case TokenKind::EqualEqual:
    case TokenKind::BangEqual:
      return kPowerEquality;
    case TokenKind::Less:
    case TokenKind::LessEqual:
    case TokenKind::Greater:
    case TokenKind::GreaterEqual:
      return kPowerCompare;
    case TokenKind::Plus:
    case TokenKind::Minus:
      return kPowerSum;
    case TokenKind::Star:
    case TokenKind::Slash:
    case TokenKind::Percent:
      return kPowerProduct;
    default:
      return 0;  // not an infix operator: the expression ends here
  }
}

}  // namespace

bool is_constructor_name(std::string_view name) {
#define SNELL_CONSTRUCTOR(ctor, type) \
  if (name == #ctor) return true;
#include "language/constructors.def"
  return false;
}

std::vector<std::string_view> constructor_names() {
  return {
#define SNELL_CONSTRUCTOR(ctor, type) #ctor,
#include "language/constructors.def"
  };
}

bool is_block_only_constructor(std::string_view name) {
#define SNELL_CONSTRUCTOR(ctor, type)
#define SNELL_BLOCK_CONSTRUCTOR(ctor, type) \
  if (name == #ctor) return true;
#include "language/constructors.def"
  return false;
}

bool is_group_name(std::string_view name) {
#define SNELL_GROUP(group) \
  if (name == #group) return true;
#include "language/groups.def"
  return false;
}

bool is_instance_name(std::string_view name) {
#define SNELL_INSTANCE(keyword) \
  if (name == #keyword) return true;
#include "language/groups.def"
  return false;
}

bool is_item_name(std::string_view name) {
#define SNELL_ITEM(item) \
  if (name == #item) return true;
#include "language/groups.def"
  return false;
}

bool is_object_property(std::string_view name) {
#define SNELL_OBJECT_PROP(prop) \
  if (name == #prop) return true;
#include "language/groups.def"
  return false;
}

ExprPtr Parser::make(ExprKind kind, Span span) {
  ExprPtr e = arena_->make();
  e->kind = kind;
  e->span = span;
  return e;
}

ExprPtr Parser::error_expr(Span span) {
  return make(ExprKind::Error, span);
}

// Lists are collected on a stack shared by all nesting levels and moved out with
// their exact size: the AST is most of the parser's memory, and growth by doubling
// would leave a quarter of every vector's capacity unused.
template <typename T>
void Parser::take_scratch(std::vector<T>& out, std::size_t mark) {
  std::vector<T>& stack = scratch(static_cast<T*>(nullptr));
  out.reserve(stack.size() - mark);
  for (std::size_t i = mark; i < stack.size(); ++i) out.push_back(std::move(stack[i]));
  stack.resize(mark);
}

void Parser::take_scratch(ExprList& out, std::size_t mark) {
  out = ExprList(scratch_exprs_.begin() + static_cast<std::ptrdiff_t>(mark), scratch_exprs_.end());
  scratch_exprs_.resize(mark);
}

// expr -> unary { INFIX expr' }     where expr' binds tighter than INFIX (Pratt)
// Inside a vector literal, '>' ends the element (it closes the vector) and the other
// comparisons are errors unless parenthesised (§3).
ExprPtr Parser::parse_expr(int min_power) {
  DepthGuard guard(*this);
  if (too_deep()) return error_expr(here());
  ExprPtr lhs = parse_unary();
  for (;;) {
    TokenKind op = cur_.kind;
    int power = infix_power(op);
    if (power < min_power || power == 0) break;
    if (in_vector_ && op == TokenKind::Greater) break;
    // `<1, 2>==v`: the '>' closes the vector (§3), and '==' follows; maximal munch
    // had read '>=' and '='. (A lone '>=' stays a comparison, and its error below.)
    if (in_vector_ && op == TokenKind::GreaterEqual && peek_.kind == TokenKind::Equal &&
        peek_.span.begin == cur_.span.end) {
      cur_.kind = TokenKind::Greater;
      cur_.text = cur_.text.substr(0, 1);
      cur_.span.end = cur_.span.begin + 1;
      scanner_.rewind(cur_.span.end);
      peek_ = scanner_.next();
      break;
    }
    if (in_vector_ && power == kPowerCompare && !panic_) {
      diags_
          .report(DiagKind::ComparisonInVector, here(),
                  "comparison inside a vector literal must be parenthesised")
          .note("write it as <(a " + std::string(cur_.text) + " b), ...>");
    }
    advance();
    ExprPtr rhs = parse_expr(power + 1);
    auto bin = make(ExprKind::Binary, Span::join(lhs->span, rhs->span));
    bin->op = op;
    bin->args = ExprList::of(std::move(lhs), std::move(rhs));
    lhs = std::move(bin);
    // A left-deep chain is as deep as nested parentheses for every later walk.
    ++depth_;
    if (too_deep()) break;
  }
  return lhs;
}

// unary -> ( '-' | '!' ) unary | postfix
ExprPtr Parser::parse_unary() {
  if (!at(TokenKind::Minus) && !at(TokenKind::Bang)) return parse_postfix(parse_primary());
  DepthGuard guard(*this);
  Token op = take();
  if (too_deep()) return error_expr(op.span);
  ExprPtr operand = parse_unary();
  auto e = make(ExprKind::Unary, Span::join(op.span, operand->span));
  e->op = op.kind;
  e->args = ExprList::of(std::move(operand));
  return e;
}

// postfix -> primary { '(' args ')' | '.' IDENT }
ExprPtr Parser::parse_postfix(ExprPtr base) {
  int saved_depth = depth_;
  for (;;) {
    if (at(TokenKind::LParen)) {
      base = parse_call(std::move(base));
    } else if (at(TokenKind::Dot)) {
      advance();
      if (!at(TokenKind::Identifier)) {
        error_here(DiagKind::ExpectedToken,
                   "expected a component name (x, y or z) after '.', found " + describe(cur_));
        break;
      }
      auto e = make(ExprKind::Component, Span::join(base->span, here()));
      e->text = std::string(cur_.text);
      e->args = ExprList::of(std::move(base));
      base = std::move(e);
      advance();
    } else {
      break;
    }
    ++depth_;
    if (too_deep()) break;
  }
  depth_ = saved_depth;
  return base;
}

// call -> postfix '(' [ expr { ',' expr } ] ')'
ExprPtr Parser::parse_call(ExprPtr callee) {
  Token open = take();
  auto call = make(ExprKind::Call, callee->span);
  std::size_t mark = scratch_exprs_.size();
  scratch_exprs_.push_back(std::move(callee));
  bool saved_vector = in_vector_, saved_object = no_object_;
  in_vector_ = false;  // (a > b) in an argument list is unambiguous
  no_object_ = false;
  if (!at(TokenKind::RParen)) {
    for (;;) {
      scratch_exprs_.push_back(parse_expr());
      if (!accept(TokenKind::Comma)) break;
    }
  }
  in_vector_ = saved_vector;
  no_object_ = saved_object;
  take_scratch(call->args, mark);
  if (!accept(TokenKind::RParen)) missing_closer(open, ")", "the argument list");
  call->span = from(call->span);
  return call;
}

// primary -> NUMBER | STRING | 'true' | 'false' | constructor | IDENT | paren | vector
ExprPtr Parser::parse_primary() {
  switch (cur_.kind) {
    case TokenKind::Number: {
      // An unreadable number (already reported) is an error value, so no check
      // of its stand-in 0 is reported after it ('radius' must be > 0).
      auto e = cur_.invalid ? error_expr(here()) : make(ExprKind::Number, here());
      e->number = cur_.number;
      advance();
      return e;
    }
    case TokenKind::String: {
      auto e = make(ExprKind::String, here());
      e->text = std::move(cur_.string);
      advance();
      return e;
    }
    case TokenKind::KwTrue:
    case TokenKind::KwFalse: {
      auto e = make(ExprKind::Bool, here());
      e->boolean = at(TokenKind::KwTrue);
      advance();
      return e;
    }
    case TokenKind::Identifier: {
      // In a condition or loop bound the brace begins the body there too: `if noise {`
      // tests a variable named noise.
      if (is_constructor_name(cur_.text) &&
          ((peek_.kind == TokenKind::LBrace && !no_object_) ||
           (starts_operand(peek_.kind) && peek_.kind != TokenKind::Minus &&
            !is_block_only_constructor(cur_.text))))
        return parse_constructor();
      // `if c {` and `for i in 0..n {`: the brace begins the body (as in Rust, an
      // object value in a condition or loop bound needs parentheses).
      if (peek_.kind == TokenKind::LBrace && !no_object_) return parse_object_value();
      auto e = make(ExprKind::Name, here());
      e->text = std::string(cur_.text);
      advance();
      return e;
    }
    case TokenKind::LParen:
      return parse_paren();
    case TokenKind::Less:
      return parse_vector();
    case TokenKind::Error: {
      // Already reported by the lexer; the rest of the statement is suspect.
      panic_ = true;
      auto e = error_expr(here());
      advance();
      return e;
    }
    default:
      break;
  }
  if (at(TokenKind::KwIf)) {
    // `fn f(n) = if n <= 1 { 1 } else { … };`: an `if` where a value belongs. The
    // whole if/else is skipped here (its braces and `else` branches), so its
    // bodies are not read as statements of their own and the ';' after it ends
    // this statement: one error, not a cascade.
    Span at_if = here();
    error_here(DiagKind::ExpectedExpression, "expected an expression, found 'if'")
        .note(
            "'if' is a statement (§4), not a value: choose the value in a function with a "
            "body, fn f(n) { if … { return …; } return …; }");
    for (;;) {
      while (!at(TokenKind::EndOfFile) && !at(TokenKind::LBrace) && !at(TokenKind::Semicolon))
        advance();
      if (!at(TokenKind::LBrace)) break;
      skip_balanced_braces();
      if (!accept(TokenKind::KwElse)) break;
      accept(TokenKind::KwIf);
    }
    return error_expr(at_if);
  }
  error_here(DiagKind::ExpectedExpression, "expected an expression, found " + describe(cur_));
  return error_expr(here());
}

// constructor -> CTOR block | CTOR expr       (CTOR from constructors.def)
// The positional argument is a whole expression parsed in the current vector context,
// so `dielectric <1.5, <0.05, 0.2, 0.3>>` and `diffuse tint(i)` read naturally.
ExprPtr Parser::parse_constructor() {
  auto e = make(ExprKind::Constructor, here());
  e->text = std::string(cur_.text);
  advance();
  if (at(TokenKind::LBrace)) {
    e->block = parse_block(e->text);
    e->span = Span::join(e->span, e->block->span);
  } else {
    e->args = ExprList::of(parse_expr());
    e->span = Span::join(e->span, e->args[0]->span);
  }
  return e;
}

// object-value -> IDENT object-body        (§13: any object block as a value)
ExprPtr Parser::parse_object_value() {
  auto e = make(ExprKind::Object, here());
  e->text = std::string(cur_.text);
  advance();
  e->block = parse_object_body(e->text);
  e->span = Span::join(e->span, e->block->span);
  return e;
}

// paren -> '(' expr ')'
ExprPtr Parser::parse_paren() {
  Token open = take();
  bool saved_vector = in_vector_, saved_object = no_object_;
  in_vector_ = false;  // <(a > b), 1, 2> is how a comparison goes inside a vector
  no_object_ = false;
  ExprPtr inner = parse_expr();
  in_vector_ = saved_vector;
  no_object_ = saved_object;
  if (!accept(TokenKind::RParen)) {
    missing_closer(open, ")", "the parenthesised expression");
    return inner;
  }
  // An operation spans its parentheses, so an error's caret under an operand
  // `(1 > 2)` covers what was written; a name or literal keeps its own span.
  if (inner && (inner->kind == ExprKind::Binary || inner->kind == ExprKind::Unary))
    inner->span = from(open.span);
  return inner;
}

// vector -> '<' expr { ',' expr } '>'
ExprPtr Parser::parse_vector() {
  Token open = take();
  auto vec = make(ExprKind::Vector, open.span);
  std::size_t mark = scratch_exprs_.size();
  bool saved_vector = in_vector_, saved_object = no_object_;
  in_vector_ = true;
  no_object_ = false;
  for (;;) {
    scratch_exprs_.push_back(parse_expr());
    if (accept(TokenKind::Comma)) continue;
    if (at(TokenKind::Greater)) {
      vector_close_ = here();
      vector_closed_ = true;
      advance();
      break;
    }
    missing_closer(open, ">", "the vector literal");
    break;
  }
  in_vector_ = saved_vector;
  no_object_ = saved_object;
  take_scratch(vec->args, mark);
  vec->span = from(open.span);
  return vec;
}

// property -> IDENT ( block | expr )
bool Parser::parse_property(Property& prop) {
  panic_ = false;                          // a property name is a recovery point
  const std::uint32_t before = last_end_;  // the end of the token before the name
  prop.name = std::string(cur_.text);
  prop.name_span = here();
  advance();
  if (at(TokenKind::LBrace)) {
    prop.block = parse_block(prop.name);
  } else if (starts_operand(cur_.kind) || at(TokenKind::Error)) {
    prop.value = parse_expr();
  } else {
    auto d = error_here(DiagKind::ExpectedExpression,
                        "expected a value for '" + prop.name + "', found " + describe(cur_));
    // `center <1, a > b, 2>`: the '>' of the comparison closed the vector (§3), so
    // 'b' was taken for a property name.
    if (vector_closed_ && vector_close_.file == file_ && vector_close_.end == before &&
        at(TokenKind::Comma) && scanner_.stray_angle_on_line(cur_.span.end))
      d.note(vector_close_,
             "this '>' closed the vector (§3); a comparison inside a vector literal must be "
             "parenthesised: <(a > b), ...>");
    // `object { s s }`: the second 's' reads as a property.
    if (in_instance_ && !is_object_property(prop.name))
      d.note(prop.name_span,
             "an 'object { }' holds one object value, then its properties (material, "
             "translate, rotate, scale, motion): '" +
                 prop.name + "' was read as a property");
    prop.value = error_expr(here());
    return false;
  }
  return true;
}

namespace {
// The name in `rgb < …` (POV-Ray's colour keywords before a vector), in a value
// or a constructor's argument, or null.
const Expr* povray_colour_keyword(const Expr* e) {
  if (!e) return nullptr;
  if (e->kind == ExprKind::Constructor && !e->args.empty()) e = e->args[0].get();
  if (!e || e->kind != ExprKind::Binary || e->op != TokenKind::Less || e->args.size() != 2)
    return nullptr;
  const Expr* lhs = e->args[0].get();
  if (!lhs || lhs->kind != ExprKind::Name) return nullptr;
  for (std::string_view k : {"rgb", "rgbf", "rgbt", "rgbft", "srgb", "color", "colour"})
    if (lhs->text == k) return lhs;
  return nullptr;
}
}  // namespace

// block -> '{' [ positional ] { property } '}'
// positional -> expr ',' expr { ',' expr }
// Properties have no separators: a value ends where the next property name starts,
// since no expression can continue with an identifier.
// `positional` is not the language (§5): it is POV-Ray's habit, recorded so the
// compiler can say what to write instead. It is recognised only right after '{',
// where a value starts with '<', a number or '-' (or is a name followed by ','),
// and only when a ',' follows the first value; a lone value there stays the
// ExpectedProperty error it always was.
BlockPtr Parser::parse_block(std::string_view owner) {
  DepthGuard guard(*this);
  Token open = take();  // callers checked it is '{'
  if (too_deep()) {
    accept(TokenKind::RBrace);
    auto block = std::make_unique<Block>();
    block->span = from(open.span);
    return block;
  }
  return parse_block_rest(open, owner);
}

// The properties of a block after its '{' (`open`), up to its '}'.
BlockPtr Parser::parse_block_rest(const Token& open, std::string_view owner) {
  auto block = std::make_unique<Block>();
  // An instance body's own properties (a nested block's are not).
  const bool instance = std::exchange(instance_body_, false);
  const bool late = std::exchange(late_subject_, false);
  const bool saved_instance = std::exchange(in_instance_, instance);
  const bool outer = broke_;  // a block read to its '}' breaks nothing around it
  bool saved_vector = in_vector_, saved_object = no_object_;
  in_vector_ = false;
  no_object_ = false;
  std::size_t mark = scratch_properties_.size();
  bool leads_value = at(TokenKind::Less) || at(TokenKind::Number) || at(TokenKind::Minus) ||
                     (at(TokenKind::Identifier) && peek_.kind == TokenKind::Comma);
  if (leads_value) {
    std::string found = describe(cur_);
    Span first = here();
    std::size_t values = scratch_exprs_.size();
    scratch_exprs_.push_back(parse_expr());
    if (at(TokenKind::Comma)) {
      while (accept(TokenKind::Comma)) scratch_exprs_.push_back(parse_expr());
      take_scratch(block->positional, values);
    } else {
      scratch_exprs_.resize(values);
      error(DiagKind::ExpectedProperty, first, "expected a property name or '}', found " + found);
      block->broken = true;
    }
  }
  for (;;) {
    if (accept(TokenKind::RBrace)) break;
    // A statement keyword here means the block's '}' is missing; so does an item
    // block on a later line indented no deeper than the block's first line (no
    // block takes an item as a property, and a nested item would be indented):
    // `sphere { radius 1` then `box { ... }` below it is two items, and reading
    // the box as the sphere's property lost the errors of everything after it.
    // After a string missing its closing quote (it ate the rest of its line, '}'
    // and all) the block ends here without a word: the string's error says it.
    if (after_unterminated_string() && !at(TokenKind::RBrace)) {
      block->broken = true;
      break;
    }
    // (`background EXPR` likewise: no block has a property of that name.)
    if (at(TokenKind::EndOfFile) || starts_statement(cur_.kind) ||
        (at(TokenKind::Identifier) &&
         ((peek_.kind == TokenKind::LBrace && is_item_name(cur_.text)) ||
          cur_.text == "background") &&
         outdented(cur_.span.begin, open.span.end))) {
      panic_ = false;
      missing_closer(open, "}", "the '" + std::string(owner) + "' block");
      // Cut short by the end of the file (a truncated file, a '/*' never closed),
      // its properties were not all written: none is asked for as missing.
      if (at(TokenKind::EndOfFile)) block->broken = true;
      break;
    }
    // The value of an instance written after its properties (reported where the
    // first property stood): a lone name before the '}' is that value.
    if (late && at(TokenKind::Identifier) && peek_.kind == TokenKind::RBrace && !block->subject) {
      block->subject = make(ExprKind::Name, here());
      block->subject->text = std::string(cur_.text);
      advance();
      continue;
    }
    if (at(TokenKind::Identifier)) {
      Property prop;
      broke_ = false;
      parse_property(prop);
      // A value a syntax error cut short is dropped, not checked as read; so is
      // one that ends in a string missing its closing quote.
      if (after_unterminated_string()) broke_ = true;
      if (broke_)
        block->broken = true;
      else
        scratch_properties_.push_back(std::move(prop));
      continue;
    }
    block->broken = true;
    auto d = error_here(DiagKind::ExpectedProperty,
                        "expected a property name or '}', found " + describe(cur_));
    // `material difuse 0.5`: the name was meant as a constructor, and its argument
    // is what the block could not read.
    if (scratch_properties_.size() > mark) {
      const Property& last = scratch_properties_.back();
      if (last.value && !last.block && last.value->kind == ExprKind::Name &&
          !is_constructor_name(last.value->text)) {
        std::string guess = closest_match(last.value->text, constructor_names());
        if (!guess.empty())
          d.note(last.value->span,
                 "'" + last.value->text + "' is no constructor; did you mean '" + guess + "'?");
      }
      // POV-Ray's `rgb <1, 0, 0>` (or `color <…>`) reads as the comparison
      // `rgb < 1`, and the block stops at the ',' after it.
      if (const Expr* name = povray_colour_keyword(last.value.get()))
        d.note(name->span, "POV-Ray's '" + name->text +
                               " <r, g, b>': a colour is the vector itself here, write <r, g, b>");
      // The value before the stray tokens was cut short by them (`center <1, 2 >
      // 1, 0>` read as <1, 2>): dropped, not checked as read.
      scratch_properties_.pop_back();
    }
    // Skip the stray tokens (with any groups they open) up to the next name that
    // a value follows, as a property's does: `r * 3>` left of a vector cut short
    // (`<r * 2 0.1, r * 3>`) is its rest, not a property 'r', and `sin(a)` a call.
    int level = 0;
    while (!at(TokenKind::EndOfFile)) {
      TokenKind k = cur_.kind;
      const bool name_with_value =
          k == TokenKind::Identifier &&
          ((starts_operand(peek_.kind) && peek_.kind != TokenKind::LParen) ||
           peek_.kind == TokenKind::LBrace || scanner_.newline_between(last_end_, cur_.span.begin));
      if (level == 0 && (name_with_value || k == TokenKind::RBrace || starts_statement(k))) break;
      if (k == TokenKind::LParen || k == TokenKind::LBrace) ++level;
      if ((k == TokenKind::RParen || k == TokenKind::RBrace) && level > 0) --level;
      advance();
    }
  }
  in_vector_ = saved_vector;
  no_object_ = saved_object;
  in_instance_ = saved_instance;
  take_scratch(block->properties, mark);
  block->span = from(open.span);
  broke_ = outer;
  return block;
}

}  // namespace snell::lang
