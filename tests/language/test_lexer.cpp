// The lexer (§2): every token kind, numbers, strings, comments, and its diagnostics.
#include <catch2/catch.hpp>
#include <charconv>
#include <cstring>
#include <random>

#include "test_support.hpp"

using namespace snell::lang;
using namespace snell::lang::test;
using K = TokenKind;
using Kinds = std::vector<TokenKind>;

TEST_CASE("every punctuation token and keyword lexes from its spelling", "[lexer]") {
  struct Entry {
    TokenKind kind;
    std::string_view spelling;
  };
  const Entry table[] = {
#define SNELL_TOKEN(name, spelling) {TokenKind::name, spelling},
#include "language/tokens.def"
  };
  int checked = 0;
  for (const Entry& e : table) {
    if (e.kind <= K::Identifier) continue;  // literal kinds have no fixed spelling
    CAPTURE(e.spelling);
    Lexed l = lex_text(std::string(e.spelling));
    REQUIRE(l.diags.empty());
    REQUIRE(l.tokens.size() == 2);
    CHECK(l.tokens[0].kind == e.kind);
    CHECK(token_spelling(e.kind) == e.spelling);
    ++checked;
  }
  CHECK(checked == 34);
  CHECK(lex_text("").kinds() == Kinds{K::EndOfFile});
  CHECK(lex_text("x").kinds() == Kinds{K::Identifier, K::EndOfFile});
  CHECK(lex_text("1").kinds() == Kinds{K::Number, K::EndOfFile});
  CHECK(lex_text("\"s\"").kinds() == Kinds{K::String, K::EndOfFile});
  CHECK(lex_text("@").kinds() == Kinds{K::Error, K::EndOfFile});
}

TEST_CASE("block and property names are identifiers, not keywords", "[lexer]") {
  for (const char* word :
       {"sphere", "radius", "diffuse", "background", "camera", "steps", "iff", "Let", "_", "x1_"})
    CHECK(keyword_kind(word) == K::Identifier);
  CHECK(keyword_kind("step") == K::KwStep);
  CHECK(keyword_kind("import") == K::KwImport);
}

TEST_CASE("token spans and text", "[lexer]") {
  SourceManager sm;
  FileId f = sm.add("t.scn", "let x=1.5;\n  sphere");
  DiagnosticEngine diags(sm);
  auto toks = lex(sm, f, diags);
  REQUIRE(toks.size() == 7);
  CHECK(toks[1].text == "x");
  CHECK(toks[3].text == "1.5");
  CHECK(toks[3].number == 1.5);
  CHECK(toks[5].text == "sphere");
  LineCol lc = sm.file(f).line_col(toks[5].span.begin);
  CHECK(lc.line == 2);
  CHECK(lc.col == 3);
  CHECK(toks[6].kind == K::EndOfFile);
}

TEST_CASE("number literals", "[lexer]") {
  auto value = [](const char* text) {
    Lexed l = lex_text(text);
    REQUIRE(l.diags.empty());
    REQUIRE(l.tokens.size() == 2);
    REQUIRE(l.tokens[0].kind == K::Number);
    return l.tokens[0].number;
  };
  CHECK(value("12") == 12);
  CHECK(value("0.5") == 0.5);
  CHECK(value(".5") == 0.5);
  CHECK(value("1e3") == 1000);
  CHECK(value("2.5e-4") == 2.5e-4);
  CHECK(value("1E+2") == 100);
  CHECK(value("007") == 7);
  CHECK(value("1e-999") == 0);  // underflow is a tiny number, not an error
  // No trailing-dot form: 0..5 is a range, 1.x a component.
  CHECK(lex_text("0..5").kinds() == Kinds{K::Number, K::DotDot, K::Number, K::EndOfFile});
  CHECK(lex_text("1.x").kinds() == Kinds{K::Number, K::Dot, K::Identifier, K::EndOfFile});
  CHECK(lex_text("v.x").kinds() == Kinds{K::Identifier, K::Dot, K::Identifier, K::EndOfFile});
  CHECK(lex_text("-1").kinds() == Kinds{K::Minus, K::Number, K::EndOfFile});
}

TEST_CASE("short decimals (the scanner's fast path) read exactly as from_chars", "[lexer]") {
  // Every digit/fraction split up to 16 characters, with leading zeros and the
  // '.5' form: the bits must equal std::from_chars's correctly rounded result.
  std::mt19937_64 rng(11);
  int checked = 0;
  for (int len = 1; len <= 17; ++len)
    for (int rep = 0; rep < 400; ++rep) {
      std::string digits;
      for (int i = 0; i < len; ++i) digits += static_cast<char>('0' + rng() % 10);
      if (rep % 7 == 0) digits[0] = '0';
      for (int dot = -1; dot <= len; ++dot) {  // -1: no dot
        std::string text = digits;
        if (dot >= 0 && dot < len) text.insert(static_cast<std::size_t>(dot), ".");
        if (dot == len) continue;
        CAPTURE(text);
        Lexed l = lex_text(text);
        REQUIRE(l.tokens.size() == 2);
        REQUIRE(l.tokens[0].kind == K::Number);
        double want = 0;
        std::from_chars(text.data(), text.data() + text.size(), want);
        double got = l.tokens[0].number;
        CHECK(std::memcmp(&got, &want, sizeof got) == 0);
        ++checked;
      }
    }
  CHECK(checked > 50000);
}

TEST_CASE("malformed numbers are one diagnostic and still a number token", "[lexer]") {
  for (const char* text : {"1e999", "12abc", "1e", "1e+", "2ex"}) {
    CAPTURE(text);
    Lexed l = lex_text(text);
    CHECK(l.diags == std::vector<std::string>{"InvalidNumber@1:1"});
    CHECK(l.kinds() == Kinds{K::Number, K::EndOfFile});
  }
}

TEST_CASE("strings and escapes", "[lexer]") {
  Lexed l = lex_text(R"("a\"b\\c\nd\te")");
  REQUIRE(l.diags.empty());
  CHECK(l.tokens[0].string == "a\"b\\c\nd\te");
  CHECK(lex_text("\"h\xC3\xA9llo\"").tokens[0].string == "h\xC3\xA9llo");  // UTF-8 kept

  Lexed bad = lex_text("let s = \"a\\qb\";");
  CHECK(bad.diags == std::vector<std::string>{"InvalidEscape@1:11"});
  CHECK(bad.tokens[3].kind == K::String);

  Lexed open = lex_text("x\n  \"abc\nlet");
  CHECK(open.diags == std::vector<std::string>{"UnterminatedString@2:3"});
  CHECK(open.kinds() == Kinds{K::Identifier, K::String, K::KwLet, K::EndOfFile});
  CHECK(open.tokens[1].string == "abc");

  CHECK(lex_text("\"abc").diags == std::vector<std::string>{"UnterminatedString@1:1"});
  CHECK(lex_text("\"a\xFF\xFE b\"").diags == std::vector<std::string>{"InvalidUtf8@1:3"});
  CHECK(lex_text(std::string("\"a\0b\"", 5)).diags == std::vector<std::string>{"NulByte@1:3"});
}

TEST_CASE("comments", "[lexer]") {
  CHECK(lex_text("a // b c\nd").kinds() == Kinds{K::Identifier, K::Identifier, K::EndOfFile});
  CHECK(lex_text("a /* b\n c */ d").kinds() == Kinds{K::Identifier, K::Identifier, K::EndOfFile});
  // Block comments do not nest: the first */ ends the comment.
  CHECK(lex_text("/* a /* b */ c */").kinds() ==
        Kinds{K::Identifier, K::Star, K::Slash, K::EndOfFile});
  Lexed open = lex_text("x\n /* never closed");
  CHECK(open.diags == std::vector<std::string>{"UnterminatedComment@2:2"});
  CHECK(open.kinds() == Kinds{K::Identifier, K::EndOfFile});
  CHECK(lex_text("// caf\xC3\xA9").diags.empty());
  CHECK(lex_text("// bad \xC0\xAF here\nx").diags == std::vector<std::string>{"InvalidUtf8@1:8"});
  CHECK(lex_text("/* \xED\xA0\x80 */").diags == std::vector<std::string>{"InvalidUtf8@1:4"});
}

TEST_CASE("a UTF-8 byte-order mark at the start of a file is skipped", "[lexer]") {
  CHECK(lex_text("\xEF\xBB\xBFsphere { }").kinds() ==
        Kinds{K::Identifier, K::LBrace, K::RBrace, K::EndOfFile});
  CHECK(lex_text("\xEF\xBB\xBFsphere { }").diags.empty());
  // Anywhere else it is the invisible character it is, and an error.
  CHECK(lex_text("a \xEF\xBB\xBF").diags == std::vector<std::string>{"InvalidCharacter@1:3"});
}

TEST_CASE("no >> token: two vectors close", "[lexer]") {
  CHECK(lex_text("<1, <2, 3>>").kinds() == Kinds{K::Less, K::Number, K::Comma, K::Less, K::Number,
                                                 K::Comma, K::Number, K::Greater, K::Greater,
                                                 K::EndOfFile});
  CHECK(lex_text("a>=b<=c==d!=e").kinds() ==
        Kinds{K::Identifier, K::GreaterEqual, K::Identifier, K::LessEqual, K::Identifier,
              K::EqualEqual, K::Identifier, K::BangEqual, K::Identifier, K::EndOfFile});
}

TEST_CASE("invalid characters and bytes", "[lexer]") {
  CHECK(lex_text("a @ b").diags == std::vector<std::string>{"InvalidCharacter@1:3"});
  CHECK(lex_text("a & b").diags == std::vector<std::string>{"InvalidCharacter@1:3"});
  CHECK(lex_text("a | b").diags == std::vector<std::string>{"InvalidCharacter@1:3"});
  CHECK(lex_text("\n  \xC3\xA9").diags == std::vector<std::string>{"InvalidCharacter@2:3"});
  // A run of bytes that are not UTF-8 is one diagnostic.
  Lexed run = lex_text("x \xFF\xFE\xFD y");
  CHECK(run.diags == std::vector<std::string>{"InvalidCharacter@1:3"});
  CHECK(run.kinds() == Kinds{K::Identifier, K::Error, K::Identifier, K::EndOfFile});
  Lexed nul = lex_text(std::string("a\0\0b", 4));
  CHECK(nul.diags == std::vector<std::string>{"NulByte@1:2"});
}

TEST_CASE("identifier length limit", "[lexer]") {
  std::string ok(kMaxIdentifierBytes, 'a');
  CHECK(lex_text(ok).diags.empty());
  Lexed l = lex_text("let " + std::string(1000000, 'b') + " = 1;");
  CHECK(l.diags == std::vector<std::string>{"IdentifierTooLong@1:5"});
  CHECK(l.kinds() ==
        Kinds{K::KwLet, K::Identifier, K::Equal, K::Number, K::Semicolon, K::EndOfFile});
}

TEST_CASE("file size limit", "[lexer]") {
  std::string big(kMaxSourceBytes + 1, ' ');
  Lexed l = lex_text(std::move(big));
  CHECK(l.diags == std::vector<std::string>{"FileTooLarge@1:1"});
  CHECK(l.kinds() == Kinds{K::EndOfFile});
}

TEST_CASE("diagnostics: one per place, repeats counted, up to three messages apart",
          "[diagnostics]") {
  SourceManager sm;
  FileId f = sm.add("loop.scn", "for i in 0 .. 9 { sphere { radius x } }\n");
  DiagnosticEngine diags(sm);
  diags.set_max_errors(0);
  Span at{f, 35, 36};
  for (int i = 0; i < 9; ++i) diags.report(DiagKind::UndefinedName, at, "'x' is not defined");
  REQUIRE(diags.diagnostics().size() == 1);
  CHECK(diags.error_count() == 1);
  CHECK(diags.diagnostics()[0].repeats == 8);
  CHECK(diags.format(diags.diagnostics()[0]).find("'x' is not defined (and 8 more times)") !=
        std::string::npos);
  // Different words at one place stay apart up to three; later ones count on the first.
  for (int i = 0; i < 6; ++i)
    diags.report(DiagKind::InvalidValue, at, "value " + std::to_string(i) + " is wrong");
  REQUIRE(diags.diagnostics().size() == 4);
  CHECK(diags.diagnostics()[1].repeats == 3);
  // Another kind, or another place, is another diagnostic.
  diags.report(DiagKind::UndefinedName, Span{f, 4, 5}, "'x' is not defined");
  CHECK(diags.diagnostics().size() == 5);
}

TEST_CASE("diagnostics: a source line or message shows as text, the caret under its character",
          "[diagnostics]") {
  // Invalid UTF-8 is shown as U+FFFD, control characters (an escape sequence, a
  // C1 CSI) as spaces, valid UTF-8 as it is; the caret counts characters, not
  // bytes, so it stands under 'x' after three two-byte letters.
  SourceManager sm;
  FileId f =
      sm.add("u.scn", "let s = \"\xc3\xa9\xc3\xa9\xc3\xa9\xff\x1b[31m\xc2\x9b\"; let t = x;\n");
  DiagnosticEngine diags(sm);
  std::size_t x = sm.file(f).text().find(" x;") + 1;
  diags.report(DiagKind::UndefinedName,
               Span{f, static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(x + 1)},
               "'x\xfe' is not defined \x1b[2J");
  std::string shown = diags.format(diags.diagnostics()[0]);
  INFO(shown);
  CHECK(shown.find('\x1b') == std::string::npos);
  CHECK(shown.find("\xc2\x9b") == std::string::npos);
  CHECK(shown.find('\xff') == std::string::npos);
  CHECK(shown.find('\xfe') == std::string::npos);
  CHECK(shown.find("'x\xEF\xBF\xBD' is not defined  [2J") != std::string::npos);
  CHECK(shown.find(" 1 | let s = \"\xc3\xa9\xc3\xa9\xc3\xa9\xEF\xBF\xBD [31m \"; let t = x;\n") !=
        std::string::npos);
  // "let s = \"" (9) + 3 letters + U+FFFD + 5 (space and "[31m") + space + "\"; let t = " (11).
  CHECK(shown.find("\n   | " + std::string(9 + 3 + 1 + 5 + 1 + 11, ' ') + "^\n") !=
        std::string::npos);
}

TEST_CASE("diagnostics: the caret counts two columns for a wide character", "[diagnostics]") {
  // A terminal shows CJK and fullwidth characters two columns wide: the caret was
  // one column per character, so it stood two columns left of 'x' after "日本".
  SourceManager sm;
  FileId f = sm.add("w.scn", "let s = \"\xe6\x97\xa5\xe6\x9c\xac\xc3\xa9\"; let t = x;\n");
  DiagnosticEngine diags(sm);
  std::size_t x = sm.file(f).text().find(" x;") + 1;
  diags.report(DiagKind::UndefinedName,
               Span{f, static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(x + 1)},
               "'x' is not defined");
  std::string shown = diags.format(diags.diagnostics()[0]);
  INFO(shown);
  // "let s = \"" (9) + two wide characters (4) + é (1) + "\"; let t = " (11).
  CHECK(shown.find("\n   | " + std::string(9 + 4 + 1 + 11, ' ') + "^\n") != std::string::npos);
  // An underline under wide characters is as wide as they are.
  diags.report(DiagKind::InvalidValue, Span{f, 9, 15}, "wide");
  shown = diags.format(diags.diagnostics()[1]);
  INFO(shown);
  CHECK(shown.find("\n   | " + std::string(9, ' ') + "^~~~\n") != std::string::npos);
}

TEST_CASE("POV-Ray's # directives say what to write instead", "[lexer]") {
  for (auto [text, hint] : {std::pair{"#include \"colors.inc\"", "import \"file.scn\";"},
                            std::pair{"#declare R = 1;", "let NAME = VALUE;"},
                            std::pair{"#macro M(a) #end", "fn NAME(P, ...)"},
                            std::pair{"#while (i < 3) #end", "for, if and recursion"}}) {
    SourceManager sm;
    FileId f = sm.add("t.scn", text);
    DiagnosticEngine diags(sm);
    lex(sm, f, diags);
    INFO(text);
    REQUIRE(!diags.diagnostics().empty());
    const Diagnostic& d = diags.diagnostics()[0];
    CHECK(d.kind == DiagKind::InvalidCharacter);
    REQUIRE(d.notes.size() == 1);
    CHECK(d.notes[0].message.find(hint) != std::string::npos);
  }
}
