// The parser: the precedence table, vector and constructor rules, statements,
// recovery, and the nesting limits.
#include <catch2/catch.hpp>
#include <sstream>

#include "test_support.hpp"

using namespace snell::lang;
using namespace snell::lang::test;
using Diags = std::vector<std::string>;

namespace {

// A compact S-expression of an expression: (+ 1 (* 2 3)), <1 2>, (call f x), (. v x).
std::string sexpr(const Expr& e) {
  auto args = [&](std::size_t from) {
    std::string s;
    for (std::size_t i = from; i < e.args.size(); ++i) s.append(" ").append(sexpr(*e.args[i]));
    return s;
  };
  switch (e.kind) {
    case ExprKind::Number: {
      std::string s = std::to_string(e.number);
      s.erase(s.find_last_not_of('0') + 1);
      if (s.back() == '.') s.pop_back();
      return s;
    }
    case ExprKind::Bool:
      return e.boolean ? "true" : "false";
    case ExprKind::String:
      return "\"" + e.text + "\"";
    case ExprKind::Name:
      return e.text;
    case ExprKind::Vector:
      return "<" + args(0).substr(1) + ">";
    case ExprKind::Unary:
    case ExprKind::Binary:
      return "(" + std::string(token_spelling(e.op)) + args(0) + ")";
    case ExprKind::Call:
      return "(call" + args(0) + ")";
    case ExprKind::Component:
      return "(." + args(0) + " " + e.text + ")";
    case ExprKind::Constructor:
      if (e.block) {
        std::string s = "(" + e.text + " {";
        for (const Property& p : e.block->properties)
          s += " " + p.name + (p.value ? " " + sexpr(*p.value) : std::string(" {...}"));
        return s + " })";
      }
      return "(" + e.text + args(0) + ")";
    case ExprKind::Object:
      return "(object " + e.text + ")";
    case ExprKind::Error:
      return "ERROR";
  }
  return "?";
}

// Parses `let e = TEXT;` and returns the value as an S-expression; no diagnostics.
std::string expr(const std::string& text) {
  Parsed p = parse_text("let e = " + text + ";");
  INFO(text);
  REQUIRE(p.diags == Diags{});
  REQUIRE(p.program.statements.size() == 1);
  const Stmt& s = *p.program.statements[0];
  REQUIRE(s.kind == StmtKind::Let);
  return sexpr(*s.exprs[0]);
}

Diags diags_of(const std::string& text) {
  return parse_text(text).diags;
}

}  // namespace

TEST_CASE("precedence table, loosest first", "[parser]") {
  CHECK(expr("a || b && c") == "(|| a (&& b c))");
  CHECK(expr("a && b || c") == "(|| (&& a b) c)");
  CHECK(expr("a && b == c") == "(&& a (== b c))");
  CHECK(expr("a == b < c") == "(== a (< b c))");
  CHECK(expr("a != b >= c") == "(!= a (>= b c))");
  CHECK(expr("a <= b + c") == "(<= a (+ b c))");
  CHECK(expr("a > b - c") == "(> a (- b c))");
  CHECK(expr("a + b * c") == "(+ a (* b c))");
  CHECK(expr("a - b / c % d") == "(- a (% (/ b c) d))");
  CHECK(expr("-a * b") == "(* (- a) b)");
  CHECK(expr("!a && b") == "(&& (! a) b)");
  CHECK(expr("-a.x") == "(- (. a x))");
  CHECK(expr("-f(x).y") == "(- (. (call f x) y))");
  CHECK(expr("- -a") == "(- (- a))");
  CHECK(expr("(a + b) * c") == "(* (+ a b) c)");
  CHECK(expr("f(a, b + 1)(c)") == "(call (call f a (+ b 1)) c)");
  CHECK(expr("f()") == "(call f)");
}

TEST_CASE("every level is left-associative", "[parser]") {
  CHECK(expr("a - b - c") == "(- (- a b) c)");
  CHECK(expr("a / b * c") == "(* (/ a b) c)");
  CHECK(expr("a < b < c") == "(< (< a b) c)");
  CHECK(expr("a == b != c") == "(!= (== a b) c)");
  CHECK(expr("a || b || c") == "(|| (|| a b) c)");
}

TEST_CASE("literals", "[parser]") {
  CHECK(expr("true") == "true");
  CHECK(expr("false || true") == "(|| false true)");
  CHECK(expr("\"s\"") == "\"s\"");
  CHECK(expr(".5 + 2.5e-4") == "(+ 0.5 0.00025)");
}

TEST_CASE("vector literals", "[parser]") {
  CHECK(expr("<1, 2>") == "<1 2>");
  CHECK(expr("<1, 2, 3>") == "<1 2 3>");
  CHECK(expr("<1.5, <0.1, 0.2, 0.3>>") == "<1.5 <0.1 0.2 0.3>>");
  CHECK(expr("<<1, 2>, <3, 4>>") == "<<1 2> <3 4>>");
  CHECK(expr("<-1, a - b, -c>") == "<(- 1) (- a b) (- c)>");
  CHECK(expr("<(a > b), 1, 2>") == "<(> a b) 1 2>");
  CHECK(expr("<f(a > b), 1>") == "<(call f (> a b)) 1>");
  CHECK(expr("<1, 2> > x") == "(> <1 2> x)");
  CHECK(expr("<1, 2, 3>.x") == "(. <1 2 3> x)");
  CHECK(expr("<a == b, 1>") == "<(== a b) 1>");
  CHECK(expr("2 * <1, 2> + <3, 4>") == "(+ (* 2 <1 2>) <3 4>)");
  CHECK(expr("<1>") == "<1>");  // arity is the compiler's business
}

TEST_CASE("a comparison inside a vector must be parenthesised", "[parser]") {
  CHECK(diags_of("let v = <a < b, 1>;") == Diags{"ComparisonInVector@1:12"});
  CHECK(diags_of("let v = <a <= b, 1>;") == Diags{"ComparisonInVector@1:12"});
  CHECK(diags_of("let v = <1, a >= b>;") == Diags{"ComparisonInVector@1:15"});
  // Both errors in one vector are independent.
  CHECK(diags_of("let v = <a < b, c <= d>;") ==
        Diags{"ComparisonInVector@1:12", "ComparisonInVector@1:19"});
}

TEST_CASE("constructors", "[parser]") {
  CHECK(expr("diffuse <0.7, 0.1, 0.1>") == "(diffuse <0.7 0.1 0.1>)");
  CHECK(expr("diffuse 0.5") == "(diffuse 0.5)");
  CHECK(expr("diffuse tint(i)") == "(diffuse (call tint i))");
  CHECK(expr("mirror 0.8") == "(mirror 0.8)");
  CHECK(expr("mirror 0.4 + 0.4") == "(mirror (+ 0.4 0.4))");
  CHECK(expr("dielectric <1.5, <0.05, 0.2, 0.3>>") == "(dielectric <1.5 <0.05 0.2 0.3>>)");
  CHECK(expr("glossy <<0.9, 0.8, 0.5>, 0.2>") == "(glossy <<0.9 0.8 0.5> 0.2>)");
  CHECK(expr("glazed <c, 1.5>") == "(glazed <c 1.5>)");
  CHECK(expr("dielectric { ior 1.5 absorb 0.1 }") == "(dielectric { ior 1.5 absorb 0.1 })");
  CHECK(expr("diffuse checker { color1 1 color2 0 size 0.5 }") ==
        "(diffuse (checker { color1 1 color2 0 size 0.5 }))");
  CHECK(expr("diffuse { color checker { color1 1 color2 0 } }") ==
        "(diffuse { color (checker { color1 1 color2 0 }) })");
  CHECK(expr("diffuse !a") == "(diffuse (! a))");
  CHECK(expr("diffuse (0.5)") == "(diffuse 0.5)");
  CHECK(expr("diffuse \"x\"") == "(diffuse \"x\")");
  // Not followed by an operand or '{': a plain name (a variable may be called diffuse).
  CHECK(expr("diffuse") == "diffuse");
  CHECK(expr("diffuse - 1") == "(- diffuse 1)");
  CHECK(expr("diffuse * 2") == "(* diffuse 2)");
  CHECK(expr("<diffuse, 1>") == "<diffuse 1>");
  // Other names are never constructors.
  CHECK(expr("lambert < 1") == "(< lambert 1)");
}

TEST_CASE("statement forms", "[parser]") {
  Parsed p = parse_text(
      "import \"a.scn\";\n"
      "let x = 1;\n"
      "fn f(a, b) = a + b;\n"
      "fn g() { return 1; }\n"
      "for i in 0 .. 3 { f(i, 1); }\n"
      "for i in 3 .. 0 step -1 { }\n"
      "if a { } else if b { } else if c { } else { g(); }\n"
      "if a { }\n"
      "sphere { radius 1 };\n"
      "background <0, 0, 0>\n"
      "background(1);\n"
      ";;\n"
      "camera {}\n");
  REQUIRE(p.diags == Diags{});
  const auto& s = p.program.statements;
  REQUIRE(s.size() == 12);
  CHECK(s[0]->kind == StmtKind::Import);
  CHECK(s[0]->name == "a.scn");
  CHECK(s[1]->kind == StmtKind::Let);
  CHECK(s[2]->kind == StmtKind::Fn);
  CHECK(s[2]->params == std::vector<std::string>{"a", "b"});
  CHECK(s[2]->exprs.size() == 1);
  CHECK(s[3]->kind == StmtKind::Fn);
  CHECK(s[3]->exprs.empty());
  CHECK(s[3]->body.size() == 1);
  CHECK(s[3]->body[0]->kind == StmtKind::Return);
  CHECK(s[4]->kind == StmtKind::For);
  CHECK(s[4]->exprs.size() == 2);
  CHECK(s[5]->exprs.size() == 3);
  CHECK(s[6]->kind == StmtKind::If);
  CHECK(s[6]->exprs.size() == 3);
  CHECK(s[6]->branches.size() == 3);
  CHECK(s[6]->has_else);
  CHECK(s[6]->else_body.size() == 1);
  CHECK_FALSE(s[7]->has_else);
  CHECK(s[8]->kind == StmtKind::Item);
  CHECK(s[8]->name == "sphere");
  CHECK(s[8]->block->properties.size() == 1);
  CHECK(s[9]->kind == StmtKind::Background);
  CHECK(s[10]->kind == StmtKind::Background);  // §4: background EXPR, EXPR = (1)
  CHECK(s[11]->kind == StmtKind::Item);
}

TEST_CASE("property blocks", "[parser]") {
  Parsed p = parse_text(
      "sphere { center <0, 1, 0> radius r * 2 material glass translate <1, 0, 0>\n"
      "         motion { translate <1, 0, 0> rotate <0, 45, 0> } scale 2 }");
  REQUIRE(p.diags == Diags{});
  const Block& b = *p.program.statements[0]->block;
  REQUIRE(b.properties.size() == 6);
  CHECK(b.properties[1].name == "radius");
  CHECK(sexpr(*b.properties[1].value) == "(* r 2)");
  CHECK(b.properties[4].name == "motion");
  REQUIRE(b.properties[4].block);
  CHECK(b.properties[4].block->properties.size() == 2);
  CHECK_FALSE(b.properties[4].value);
  CHECK(b.properties[5].name == "scale");
}

TEST_CASE("recovery reports every independent error once", "[parser]") {
  CHECK(diags_of("let x = 1 2;\nlet y = ;\nlet z = 3;") ==
        Diags{"ExpectedToken@1:10", "ExpectedExpression@2:9"});
  CHECK(diags_of("sphere { radius 1 2 center <0,0,0> }\nbox { 3 }") ==
        Diags{"ExpectedProperty@1:19", "ExpectedProperty@2:7"});
  CHECK(diags_of("sphere { radius 1\nlet x = 1;") == Diags{"ExpectedToken@2:1"});
  CHECK(diags_of("fn f(a { }\nlet x = ;") == Diags{"ExpectedToken@1:8", "ExpectedExpression@2:9"});
  CHECK(diags_of("let v = <1, 2;\nlet w = (1;") ==
        Diags{"ExpectedToken@1:14", "ExpectedToken@2:11"});
  CHECK(diags_of("sphere {") == Diags{"UnclosedDelimiter@1:8"});
  CHECK(diags_of("for i in 0 .. 3 {\n f(i);") == Diags{"UnclosedDelimiter@1:17"});
  CHECK(diags_of("}\nelse { }") == Diags{"ExpectedStatement@1:1", "ExpectedStatement@2:1"});
  // A lexical error is not reported again by the parser.
  CHECK(diags_of("let x = 1 @ 2;\nlet y = \"open\nlet z = 1;") ==
        Diags{"InvalidCharacter@1:11", "UnterminatedString@2:9"});
  CHECK(diags_of("sphere { /* radius 1 }") == Diags{"UnterminatedComment@1:10"});
}

TEST_CASE("unclosed delimiters point at the opener", "[parser]") {
  SourceManager sm;
  FileId f = sm.add("t.scn", "let v = f(1, 2;\n");
  DiagnosticEngine diags(sm);
  parse(sm, f, diags);
  REQUIRE(diags.diagnostics().size() == 1);
  const Diagnostic& d = diags.diagnostics()[0];
  CHECK(d.kind == DiagKind::ExpectedToken);
  REQUIRE(d.notes.size() == 1);
  REQUIRE(d.notes[0].span);
  CHECK(d.notes[0].span->begin == 9);  // the '('
  CHECK(d.notes[0].message == "to close '(' opened here");
}

TEST_CASE("a comparison that closed a vector early says so", "[parser]") {
  // §3: a '>' that could close the innermost vector does, so 'b' below is taken
  // for the next property name and ', 2>' is left over.
  SourceManager sm;
  FileId f = sm.add("t.scn", "sphere { center <1, a > b, 2> }\n");
  DiagnosticEngine diags(sm);
  parse(sm, f, diags);
  REQUIRE(!diags.diagnostics().empty());
  const Diagnostic& d = diags.diagnostics()[0];
  CHECK(d.kind == DiagKind::ExpectedExpression);
  REQUIRE(d.notes.size() == 1);
  REQUIRE(d.notes[0].span);
  CHECK(d.notes[0].span->begin == 22);  // the '>' after 'a'
  CHECK(d.notes[0].message.find("must be parenthesised") != std::string::npos);
  // A missing value after an ordinary vector gets no such note.
  SourceManager sm2;
  FileId g = sm2.add("u.scn", "sphere { center <1, 2, 3> radius , }\n");
  DiagnosticEngine diags2(sm2);
  parse(sm2, g, diags2);
  REQUIRE(!diags2.diagnostics().empty());
  CHECK(diags2.diagnostics()[0].notes.empty());
}

TEST_CASE("the error limit stops the parse", "[parser]") {
  std::string text;
  for (int i = 0; i < 1000; ++i) text += "let = 1;\n";
  SourceManager sm;
  FileId f = sm.add("t.scn", text);
  DiagnosticEngine diags(sm);
  diags.set_max_errors(20);
  parse(sm, f, diags);
  CHECK(diags.diagnostics().size() == 20);
  CHECK(diags.limit_reached());
  // What it counted is a lower bound, and the closing line says so even when no
  // error past the limit was counted (25 errors showed 20 and "20 errors").
  CHECK(diags.counts_are_lower_bounds());
  std::ostringstream out;
  diags.print(out);
  CHECK(out.str().find("reading stopped at the limit, after 20, and more may follow") !=
        std::string::npos);
  // Under the limit every error is read and counted exactly.
  SourceManager sm2;
  FileId g = sm2.add("u.scn", "let = 1;\nlet = 2;\n");
  DiagnosticEngine all(sm2);
  all.set_max_errors(20);
  parse(sm2, g, all);
  CHECK(all.error_count() == 2);
  CHECK(!all.counts_are_lower_bounds());
}

TEST_CASE("nesting limits: clear errors, no stack overflow", "[parser][limits]") {
  auto first = [](const std::string& text) {
    Parsed p = parse_text(text + "\nlet after = ;");
    REQUIRE(p.diags.size() >= 1);
    CHECK(p.diags.back() == "ExpectedExpression@2:13");  // parsing went on after
    return p.diags[0].substr(0, p.diags[0].find('@'));
  };
  const int n = 10000;
  CHECK(first("let x = " + std::string(n, '(') + "1" + std::string(n, ')') + ";") ==
        "NestingTooDeep");
  CHECK(first("let x = " + std::string(n, '-') + "1;") == "NestingTooDeep");
  std::string vec = "let x = ";
  for (int i = 0; i < n; ++i) vec += "<1, ";
  vec += "1";
  for (int i = 0; i < n; ++i) vec += ">";
  CHECK(first(vec + ";") == "NestingTooDeep");
  std::string blocks = "sphere ";
  for (int i = 0; i < n; ++i) blocks += "{ motion ";
  blocks += "{ }";
  for (int i = 0; i < n; ++i) blocks += "}";
  CHECK(first(blocks) == "NestingTooDeep");
  std::string ifs = "fn f() { ";
  for (int i = 0; i < n; ++i) ifs += "if a { ";
  for (int i = 0; i < n; ++i) ifs += "} ";
  CHECK(first(ifs + "}") == "NestingTooDeep");
  std::string sum = "let x = 1";
  for (int i = 0; i < 1000000; ++i) sum += "+1";
  CHECK(first(sum + ";") == "NestingTooDeep");
  std::string calls = "let x = f";
  for (int i = 0; i < 100000; ++i) calls += "(1).x";
  CHECK(first(calls + ";") == "NestingTooDeep");
  std::string ctors = "let x = ";
  for (int i = 0; i < n; ++i) ctors += "diffuse ";
  CHECK(first(ctors + "1;") == "NestingTooDeep");
  // Just under the limit is fine.
  Parsed ok = parse_text("let x = " + std::string(kMaxNesting - 2, '(') + "1" +
                         std::string(kMaxNesting - 2, ')') + ";");
  CHECK(ok.diags == Diags{});
  // An unclosed deep group: one error, no hang.
  CHECK(diags_of("let x = " + std::string(n, '(')) == Diags{"NestingTooDeep@1:1009"});
}

TEST_CASE("AST dump format", "[parser][dump]") {
  Parsed p = parse_text("sphere { center <0, 1.5, -2> material diffuse 0.5 }\nlet s = \"a\\\"b\";");
  CHECK(p.dump ==
        "Item sphere @1:1\n"
        "  Property center @1:10\n"
        "    Vector @1:17\n"
        "      Number 0 @1:18\n"
        "      Number 1.5 @1:21\n"
        "      Unary - @1:26\n"
        "        Number 2 @1:27\n"
        "  Property material @1:30\n"
        "    Constructor diffuse @1:39\n"
        "      Number 0.5 @1:47\n"
        "Let s @2:1\n"
        "  String \"a\\\"b\" @2:9\n");
  CHECK(parse_text("let x = 0.1 + 1e300;").dump.find("Number 0.1 @") != std::string::npos);
  CHECK(parse_text("let x = 0.1 + 1e300;").dump.find("Number 1e+300 @") != std::string::npos);
}

TEST_CASE("object blocks are values where an expression is expected (§13)", "[parser]") {
  CHECK(expr("sphere { radius 1 }") == "(object sphere)");
  CHECK(expr("union { sphere { } box { } }") == "(object union)");
  CHECK(expr("f(torus { major 1 minor 0.2 })") == "(call f (object torus))");
  // In a condition or loop bound the brace begins the body; parentheses make it a
  // value there.
  Parsed p = parse_text("if ready { sphere { } } for i in 0 .. n { box { } }");
  CHECK(p.diags == Diags{});
  CHECK(p.dump.find("Object") == std::string::npos);
  Parsed q = parse_text("if (sphere { }) == x { }");
  CHECK(q.diags == Diags{});
  CHECK(q.dump.find("Object sphere") != std::string::npos);
}

TEST_CASE("a CSG body holds statements and object properties (§12)", "[parser]") {
  Parsed p = parse_text(
      "difference {\n"
      "  box { min <0, 0, 0> max <1, 1, 1> }\n"
      "  let r = 0.3;\n"
      "  for i in 0 .. 3 { sphere { center <i, 1, 0> radius r } }\n"
      "  if r > 0 { peg(1); }\n"
      "  material m  scale (2)  translate <1, 0, 0>  motion { rotate <0, 9, 0> }\n"
      "}\n"
      "object { w rotate <90, 0, 0> material glass }\n");
  CHECK(p.diags == Diags{});
  const Stmt& d = *p.program.statements[0];
  REQUIRE(d.block);
  CHECK(d.block->statements.size() == 4);
  REQUIRE(d.block->properties.size() == 4);
  CHECK(d.block->properties[1].name == "scale");
  CHECK(d.block->properties[3].block != nullptr);
  const Stmt& o = *p.program.statements[1];
  REQUIRE(o.block);
  REQUIRE(o.block->subject);
  CHECK(o.block->subject->text == "w");
  CHECK(o.block->properties.size() == 2);
}

TEST_CASE("POV-Ray's rgb <…> in a block names itself in a note", "[parser]") {
  // `diffuse rgb <1, 0, 0>` reads as the comparison `rgb < 1`, and the block stops
  // at the ',': the error is there, and a note at `rgb` says what to write.
  for (auto [text, word] : {std::pair{"sphere { material diffuse rgb <1, 0, 0> }", "rgb"},
                            std::pair{"sphere { material diffuse { color rgb <1, 0, 0> } }", "rgb"},
                            std::pair{"sphere { material diffuse color <1, 0, 0> }", "color"}}) {
    SourceManager sm;
    FileId f = sm.add("t.scn", text);
    DiagnosticEngine diags(sm);
    parse(sm, f, diags);
    INFO(text);
    REQUIRE(!diags.diagnostics().empty());
    const Diagnostic& d = diags.diagnostics()[0];
    CHECK(d.kind == DiagKind::ExpectedProperty);
    REQUIRE(d.notes.size() == 1);
    REQUIRE(d.notes[0].span);
    CHECK(std::string_view(text).substr(d.notes[0].span->begin,
                                        d.notes[0].span->end - d.notes[0].span->begin) == word);
    CHECK(d.notes[0].message.find("write <r, g, b>") != std::string::npos);
  }
  // A comparison of the user's own `rgb` elsewhere is still a comparison.
  SourceManager sm;
  FileId f = sm.add("t.scn", "let rgb = 2;\nlet b = rgb < 3;\n");
  DiagnosticEngine diags(sm);
  parse(sm, f, diags);
  CHECK(diags.diagnostics().empty());
}

TEST_CASE("diagnostics print in source order, files as they first appear", "[parser]") {
  // The parser's errors are found before the evaluator's: printed as found, a
  // file read 3:1 before 1:9.
  SourceManager sm;
  FileId a = sm.add("a.scn", "let x = 1;\nlet y = 2;\nlet z = 3;\n");
  FileId b = sm.add("b.scn", "let w = 4;\n");
  DiagnosticEngine diags(sm);
  diags.report(DiagKind::UndefinedName, Span{a, 22, 25}, "third line");
  diags.report(DiagKind::UndefinedName, Span{b, 4, 5}, "other file");
  diags.report(DiagKind::UndefinedName, Span{a, 4, 5}, "first line");
  diags.report(DiagKind::UndefinedName, Span{FileId(99), 0, 0}, "no place");
  std::ostringstream out;
  diags.print(out);
  const std::string s = out.str();
  const std::size_t none = s.find("no place"), first = s.find("first line"),
                    third = s.find("third line"), other = s.find("other file");
  REQUIRE(none != std::string::npos);
  CHECK(none < first);
  CHECK(first < third);
  CHECK(third < other);
  // The list itself keeps the order of discovery (the language server reads it).
  CHECK(diags.diagnostics()[0].message == "third line");
}
