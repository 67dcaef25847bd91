// The AST dump: one node per line, two spaces of indent per level, each line ending
// in @line:col of the node's first character. tests/lang compares against it, so the
// format only changes together with every expect-ast block (see tests/lang/README.md).
//
//   Let glass @2:1
//     Constructor dielectric @2:13
//       Vector @2:24
//         Number 1.5 @2:25
//
// Statements: Let NAME, Fn NAME(P, ...) = (expression form) or {} (body form),
// Return, For NAME (with from:/to:/step:/do: children), If (if:/then:, else if:/then:,
// else:), Import "PATH", ExprStmt, Item KEYWORD, Background, ErrorStmt.
// Expressions: Number, Bool, String, Name, Vector, Unary OP, Binary OP, Call (callee
// first), Component NAME, Constructor NAME (positional) or Constructor NAME {} (named),
// Error. Properties: Property NAME, or Property NAME {} for a nested block; a block's
// leading POV-Ray-style values (Block::positional) come first, under Positional.
#include <charconv>
#include <cstdio>
#include <optional>

#include "language/ast.hpp"

namespace snell::lang {
namespace {

std::string number_text(double v) {
  char buf[64];
  auto [ptr, ec] = std::to_chars(buf, buf + sizeof buf, v);  // shortest round trip
  return ec == std::errc() ? std::string(buf, ptr) : "?";
}

std::string quoted(std::string_view s) {
  std::string out = "\"";
  for (char c : s) {
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\t':
        out += "\\t";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7F) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\x%02X", static_cast<unsigned char>(c));
          out += buf;
        } else {
          out += c;
        }
    }
  }
  return out + "\"";
}

class Dumper {
 public:
  explicit Dumper(const SourceFile* source) : source_(source) {}
  std::string out;

  void stmts(const std::vector<StmtPtr>& list, int indent) {
    for (const StmtPtr& s : list)
      if (s) stmt(*s, indent);
  }

  void stmt(const Stmt& s, int indent) {
    switch (s.kind) {
      case StmtKind::Let:
        line(indent, "", "Let " + s.name, s.span);
        expr_children(s.exprs, indent + 1);
        break;
      case StmtKind::Fn: {
        std::string head = "Fn " + s.name + "(";
        for (std::size_t i = 0; i < s.params.size(); ++i) head += (i ? ", " : "") + s.params[i];
        head += s.exprs.empty() ? ") {}" : ") =";
        line(indent, "", head, s.span);
        expr_children(s.exprs, indent + 1);
        stmts(s.body, indent + 1);
        break;
      }
      case StmtKind::Return:
        line(indent, "", "Return", s.span);
        expr_children(s.exprs, indent + 1);
        break;
      case StmtKind::For: {
        line(indent, "", "For " + s.name, s.span);
        static const char* const kLabels[] = {"from: ", "to: ", "step: "};
        for (std::size_t i = 0; i < s.exprs.size() && i < 3; ++i)
          if (s.exprs[i]) expr(*s.exprs[i], indent + 1, kLabels[i]);
        line(indent + 1, "", "do:", std::nullopt);
        stmts(s.body, indent + 2);
        break;
      }
      case StmtKind::If:
        line(indent, "", "If", s.span);
        for (std::size_t i = 0; i < s.exprs.size(); ++i) {
          if (s.exprs[i]) expr(*s.exprs[i], indent + 1, i == 0 ? "if: " : "else if: ");
          line(indent + 1, "", "then:", std::nullopt);
          if (i < s.branches.size()) stmts(s.branches[i], indent + 2);
        }
        if (s.has_else) {
          line(indent + 1, "", "else:", std::nullopt);
          stmts(s.else_body, indent + 2);
        }
        break;
      case StmtKind::Import:
        line(indent, "", "Import " + quoted(s.name), s.span);
        break;
      case StmtKind::ExprStmt:
        line(indent, "", "ExprStmt", s.span);
        expr_children(s.exprs, indent + 1);
        break;
      case StmtKind::Item:
        line(indent, "", "Item " + s.name, s.span);
        if (s.block) properties(*s.block, indent + 1);
        break;
      case StmtKind::Background:
        line(indent, "", "Background", s.span);
        expr_children(s.exprs, indent + 1);
        break;
      case StmtKind::Error:
        line(indent, "", "ErrorStmt", s.span);
        break;
    }
  }

  void properties(const Block& b, int indent) {
    if (b.subject) expr(*b.subject, indent, "places: ");
    if (!b.positional.empty()) {
      line(indent, "", "Positional", b.positional[0]->span);
      expr_children(b.positional, indent + 1);
    }
    for (const Property& p : b.properties) {
      if (p.block) {
        line(indent, "", "Property " + p.name + " {}", p.name_span);
        properties(*p.block, indent + 1);
      } else {
        line(indent, "", "Property " + p.name, p.name_span);
        if (p.value) expr(*p.value, indent + 1, "");
      }
    }
    stmts(b.statements, indent);
  }

  template <typename List>  // std::vector<ExprPtr> or ExprList
  void expr_children(const List& list, int indent) {
    for (const ExprPtr& e : list)
      if (e) expr(*e, indent, "");
  }

  void expr(const Expr& e, int indent, const char* label) {
    std::string head;
    switch (e.kind) {
      case ExprKind::Number:
        head = "Number " + number_text(e.number);
        break;
      case ExprKind::Bool:
        head = e.boolean ? "Bool true" : "Bool false";
        break;
      case ExprKind::String:
        head = "String " + quoted(e.text);
        break;
      case ExprKind::Name:
        head = "Name " + e.text;
        break;
      case ExprKind::Vector:
        head = "Vector";
        break;
      case ExprKind::Unary:
        head = "Unary " + std::string(token_spelling(e.op));
        break;
      case ExprKind::Binary:
        head = "Binary " + std::string(token_spelling(e.op));
        break;
      case ExprKind::Call:
        head = "Call";
        break;
      case ExprKind::Component:
        head = "Component " + e.text;
        break;
      case ExprKind::Constructor:
        head = "Constructor " + e.text + (e.block ? " {}" : "");
        break;
      case ExprKind::Object:
        head = "Object " + e.text;
        break;
      case ExprKind::Error:
        head = "Error";
        break;
    }
    line(indent, label, head, e.span);
    expr_children(e.args, indent + 1);
    if (e.block) properties(*e.block, indent + 1);
  }

 private:
  void line(int indent, std::string_view label, const std::string& text, std::optional<Span> at) {
    out.append(static_cast<std::size_t>(indent) * 2, ' ');
    out += label;
    out += text;
    if (at && source_) {
      LineCol lc = source_->line_col(at->begin);
      out += " @" + std::to_string(lc.line) + ":" + std::to_string(lc.col);
    }
    out += '\n';
  }

  const SourceFile* source_;
};

}  // namespace

std::string dump_ast(const Program& program) {
  Dumper d(program.source);
  d.stmts(program.statements, 0);
  return std::move(d.out);
}

}  // namespace snell::lang
