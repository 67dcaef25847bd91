// Property test: lex + parse of random bytes and of random token sequences always
// returns (no crash, hang or runaway memory), whatever the input. Fixed seeds, so a
// failure reproduces; the failing input is printed.
#include <catch2/catch.hpp>
#include <random>

#include "test_support.hpp"

using namespace snell::lang;

namespace {

void parse_and_dump(const std::string& text) {
  SourceManager sm;
  FileId f = sm.add("fuzz.scn", text);
  DiagnosticEngine diags(sm);  // default error limit, as the CLI has
  Program p = parse(sm, f, diags);
  std::string dump = dump_ast(p);
  for (const Diagnostic& d : diags.diagnostics()) {
    // Every diagnostic points inside the file (or at its end).
    REQUIRE(d.span.begin <= text.size());
    REQUIRE(d.span.end <= text.size());
    (void)diags.format(d);
  }
}

std::string printable(const std::string& s) {
  std::string out;
  for (unsigned char c : s) {
    if (c >= 0x20 && c < 0x7F && c != '\\') {
      out += static_cast<char>(c);
    } else {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02X", c);
      out += buf;
    }
  }
  return out;
}

}  // namespace

TEST_CASE("random bytes never break the lexer or parser", "[fuzz]") {
  std::mt19937 rng(20260101);
  // Mostly characters that mean something to the lexer, so the parser is reached.
  const std::string alphabet =
      "(){}<>,;.=!+-*/%&|\"\\ \n\t\r_abexyz019 letfnifforinstep sphere diffuse\x00\xC3\xA9\xFF";
  std::uniform_int_distribution<int> length(0, 80);
  std::uniform_int_distribution<int> any_byte(0, 255);
  std::uniform_int_distribution<std::size_t> pick(0, alphabet.size() - 1);
  for (int i = 0; i < 100000; ++i) {
    int n = length(rng);
    bool raw = i % 4 == 0;
    std::string text;
    for (int j = 0; j < n; ++j)
      text += raw ? static_cast<char>(any_byte(rng)) : alphabet[pick(rng)];
    INFO("input " << i << ": \"" << printable(text) << "\"");
    parse_and_dump(text);
  }
}

TEST_CASE("random token sequences never break the parser", "[fuzz]") {
  std::vector<std::string> words;
#define SNELL_TOKEN(name, spelling) words.push_back(spelling);
#include "language/tokens.def"
  // Replace the literal kinds' descriptions by real literals.
  words.erase(words.begin(), words.begin() + 5);
  for (const char* w :
       {"1",      "0.5",        ".5",      "1e3",     "\"s\"",      "\"a\\nb\"", "x",   "sphere",
        "motion", "background", "diffuse", "checker", "dielectric", "radius",    "v.x", "<1, 2>",
        "{",      "}",          "(",       ")",       "<",          ">",         ";",   "\n"})
    words.push_back(w);
  std::mt19937 rng(4242);
  std::uniform_int_distribution<int> length(1, 60);
  std::uniform_int_distribution<std::size_t> pick(0, words.size() - 1);
  for (int i = 0; i < 30000; ++i) {
    int n = length(rng);
    std::string text;
    for (int j = 0; j < n; ++j) text += words[pick(rng)] + " ";
    INFO("input " << i << ": \"" << printable(text) << "\"");
    parse_and_dump(text);
  }
}

TEST_CASE("hostile shapes: long lines, many errors, deep garbage", "[fuzz]") {
  parse_and_dump(std::string(200000, '{'));
  parse_and_dump(std::string(200000, '}'));
  parse_and_dump(std::string(200000, '<'));
  parse_and_dump(std::string(200000, '>'));
  parse_and_dump(std::string(200000, '('));
  parse_and_dump(std::string(200000, '"'));
  parse_and_dump(std::string(100000, '!') + "x");
  std::string mixed;
  for (int i = 0; i < 50000; ++i) mixed += "sphere { radius (<1, ";
  parse_and_dump(mixed);
  std::string ifs;
  for (int i = 0; i < 50000; ++i) ifs += "if x { } else ";
  parse_and_dump(ifs + "{ }");  // a long else-if chain is a loop, not nesting
}
