// Runs every tests/lang/**/*.scn whose first line is `// test: parse`: lexes and
// parses it, then compares
//   - the diagnostics, as the set of `// expect: error LINE:COL Kind` comments
//     (or `warning`), exactly: every expected one reported, nothing else reported;
//   - the AST dump, when the file ends with a `/* expect-ast: ... */` block.
// With SNELL_UPDATE_EXPECTATIONS=1 the expectations are rewritten in place from what
// the parser does now (SNELL_UPDATE_EXPECTATIONS=ast also adds AST blocks to files
// that have none); review the diff. Other directives (`// test: compile`) belong to
// other runners and are skipped. See tests/lang/README.md.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <tuple>

#include "test_support.hpp"

using namespace snell::lang;
namespace fs = std::filesystem;

namespace {

constexpr std::string_view kExpect = "// expect:";
constexpr std::string_view kAstOpen = "/* expect-ast:";

struct Expectation {
  std::string severity;
  std::uint32_t line = 0, col = 0;
  std::string kind;
  auto key() const { return std::tie(line, col, kind, severity); }
  bool operator<(const Expectation& o) const { return key() < o.key(); }
  bool operator==(const Expectation& o) const { return key() == o.key(); }
  std::string str() const {
    return severity + " " + std::to_string(line) + ":" + std::to_string(col) + " " + kind;
  }
};

struct CaseFile {
  fs::path path;
  std::string text;
  std::string directive;
  std::vector<Expectation> expected;
  bool has_ast = false;
  std::string expected_ast;
};

std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::vector<std::string> split_lines(const std::string& text) {
  std::vector<std::string> lines;
  std::size_t b = 0;
  while (b <= text.size()) {
    std::size_t e = text.find('\n', b);
    if (e == std::string::npos) e = text.size();
    lines.push_back(text.substr(b, e - b));
    b = e + 1;
  }
  return lines;
}

CaseFile load(const fs::path& path) {
  CaseFile c;
  c.path = path;
  c.text = read_file(path);
  std::string first = c.text.substr(0, c.text.find('\n'));
  if (first.rfind("// test:", 0) == 0) {
    std::istringstream ss(first.substr(8));
    ss >> c.directive;
  }
  std::size_t ast = c.text.find(kAstOpen);
  std::string head = c.text.substr(0, ast);
  if (ast != std::string::npos) {
    c.has_ast = true;
    std::size_t b = c.text.find('\n', ast);
    std::size_t e = c.text.find("*/", ast);
    if (b != std::string::npos && e != std::string::npos && b < e)
      c.expected_ast = c.text.substr(b + 1, e - b - 1);
  }
  for (const std::string& line : split_lines(head)) {
    std::size_t at = line.find(kExpect);
    if (at == std::string::npos) continue;
    std::istringstream ss(line.substr(at + kExpect.size()));
    Expectation x;
    std::string pos;
    ss >> x.severity >> pos >> x.kind;
    std::size_t colon = pos.find(':');
    if (colon != std::string::npos) {
      x.line = static_cast<std::uint32_t>(std::atoi(pos.substr(0, colon).c_str()));
      x.col = static_cast<std::uint32_t>(std::atoi(pos.substr(colon + 1).c_str()));
    }
    c.expected.push_back(x);
  }
  std::sort(c.expected.begin(), c.expected.end());
  return c;
}

struct Outcome {
  std::vector<Expectation> actual;
  std::string formatted;  // the diagnostics as a user sees them
  std::string ast;
};

Outcome run(const CaseFile& c) {
  SourceManager sm;
  FileId f = sm.add(c.path.filename().string(), c.text);
  DiagnosticEngine diags(sm);
  diags.set_max_errors(0);
  Program program = parse(sm, f, diags);
  Outcome out;
  out.ast = dump_ast(program);
  for (const Diagnostic& d : diags.diagnostics()) {
    LineCol lc = sm.file(d.span.file).line_col(d.span.begin);
    out.actual.push_back({d.severity == Severity::Error ? "error" : "warning", lc.line, lc.col,
                          std::string(diag_name(d.kind))});
    out.formatted += diags.format(d);
  }
  std::sort(out.actual.begin(), out.actual.end());
  return out;
}

// Rewrites the file's expectations: inline ones are cut, whole-line ones become blank
// lines (so no line number moves), and the new ones are appended at the end.
void update(const CaseFile& c, const Outcome& o, bool add_ast) {
  std::string head = c.text.substr(0, c.text.find(kAstOpen));
  std::vector<std::string> lines = split_lines(head);
  for (std::string& line : lines) {
    std::size_t at = line.find(kExpect);
    if (at == std::string::npos) continue;
    line.erase(at);
    while (!line.empty() && (line.back() == ' ' || line.back() == '\t')) line.pop_back();
  }
  while (!lines.empty() && lines.back().empty()) lines.pop_back();
  std::string out;
  for (const std::string& line : lines) out += line + "\n";
  if (!o.actual.empty()) out += "\n";
  for (const Expectation& x : o.actual) out += std::string(kExpect) + " " + x.str() + "\n";
  if (c.has_ast || add_ast)
    out.append("\n").append(kAstOpen).append("\n").append(o.ast).append("*/\n");
  std::ofstream(c.path, std::ios::binary) << out;
}

std::vector<fs::path> case_files() {
  std::vector<fs::path> files;
  for (const auto& entry : fs::recursive_directory_iterator(SNELL_LANG_TEST_DIR))
    if (entry.is_regular_file() && entry.path().extension() == ".scn")
      files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

std::string list(const std::vector<Expectation>& xs) {
  std::string s;
  for (const Expectation& x : xs) s += "  " + x.str() + "\n";
  return s.empty() ? "  (none)\n" : s;
}

}  // namespace

TEST_CASE("tests/lang parse cases", "[lang]") {
  const char* mode = std::getenv("SNELL_UPDATE_EXPECTATIONS");
  bool updating = mode && *mode && std::string(mode) != "0";
  int ran = 0;
  for (const fs::path& path : case_files()) {
    CaseFile c = load(path);
    if (c.directive != "parse") continue;
    ++ran;
    Outcome o = run(c);
    if (updating) {
      update(c, o, std::string(mode) == "ast");
      continue;
    }
    INFO("file: " << fs::relative(path, SNELL_LANG_TEST_DIR).string());
    INFO("expected:\n" << list(c.expected) << "reported:\n" << list(o.actual) << o.formatted);
    CHECK(c.expected == o.actual);
    if (c.has_ast) {
      INFO("AST dump:\n" << o.ast);
      CHECK(c.expected_ast == o.ast);
    }
  }
  CHECK(ran > 0);
}

TEST_CASE("every lexical and syntax diagnostic has a tests/lang case", "[lang]") {
  std::set<std::string> covered;
  for (const fs::path& path : case_files()) {
    CaseFile c = load(path);
    if (c.directive != "parse") continue;
    for (const Expectation& x : c.expected) covered.insert(x.kind);
  }
  for (DiagKind k : all_diag_kinds()) {
    // The language layer's kinds come before the compiler's (diagnostics.def order).
    if (k >= DiagKind::UndefinedName) break;
    if (k == DiagKind::BadVectorArity) continue;  // reported by the compiler
    if (k == DiagKind::FileTooLarge) continue;    // needs a 100 MB file: test_lexer.cpp
    INFO("no tests/lang case expects " << diag_name(k));
    CHECK(covered.count(std::string(diag_name(k))) == 1);
  }
}
