// Runs every tests/lang/**/*.scn whose first line is `// test: compile`: compiles it
// (parse, evaluate, lower) and compares
//   - the diagnostics with the `// expect: error LINE:COL Kind` comments, exactly;
//   - the IR dump with a trailing `/* expect-ir: ... */` block, when there is one.
// `// max-errors: N` and `// max-steps: N` lines set those limits for the case;
// errors dropped past the limit are expected as `// expect: error TooManyErrors`.
// SNELL_UPDATE_EXPECTATIONS=1 rewrites the IR blocks from what the compiler does now
// (diagnostic expectations are written by hand). See tests/lang/README.md.
#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "compiler/compile.hpp"
#include "tests/compiler/compile_util.hpp"

namespace fs = std::filesystem;
using namespace snell;

namespace {

using test::slurp;

std::vector<fs::path> compile_cases() {
  std::vector<fs::path> out;
  for (const auto& e : fs::recursive_directory_iterator(SNELL_LANG_TEST_DIR))
    if (e.path().extension() == ".scn" && slurp(e.path()).rfind("// test: compile", 0) == 0)
      out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

std::set<std::string> expected_diags(const std::string& text) {
  std::set<std::string> out;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    auto at = line.find("// expect: ");
    if (at == std::string::npos) continue;
    std::string e = line.substr(at + 11);
    while (!e.empty() && (e.back() == ' ' || e.back() == '\r')) e.pop_back();
    out.insert(e);
  }
  return out;
}

// The number on a `// KEY N` line (`// max-errors: 3`), or `fallback`.
std::uint64_t directive(const std::string& text, const std::string& key, std::uint64_t fallback) {
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(key, 0) == 0) return std::stoull(line.substr(key.size()));
  return fallback;
}

constexpr std::string_view kIrOpen = "/* expect-ir:\n";

}  // namespace

TEST_CASE("tests/lang compile cases", "[compiler][lang]") {
  auto cases = compile_cases();
  REQUIRE(cases.size() >= 10);
  bool update = std::getenv("SNELL_UPDATE_EXPECTATIONS") != nullptr;
  for (const fs::path& path : cases) {
    std::string text = slurp(path);
    compile::CompileOptions opts;
    // The limits, as --max-errors and --max-steps set them; by default every
    // error is kept.
    opts.max_errors = directive(text, "// max-errors:", 0);
    opts.step_budget = directive(text, "// max-steps:", compile::kDefaultStepBudget);
    opts.stdlib_dir = std::string(SNELL_SOURCE_DIR) + "/stdlib";
    auto c = compile::compile_source(path.string(), text, opts);
    std::set<std::string> got;
    for (const auto& d : c->diags.diagnostics()) {
      auto lc = c->sources.file(d.span.file).line_col(d.span.begin);
      std::string where =
          d.span.file == 0
              ? ""
              : fs::path(c->sources.file(d.span.file).path()).filename().string() + ":";
      got.insert(std::string(d.severity == lang::Severity::Error ? "error " : "warning ") + where +
                 std::to_string(lc.line) + ":" + std::to_string(lc.col) + " " +
                 std::string(lang::diag_name(d.kind)));
    }
    if (c->status == compile::CompileStatus::UsageError) got.insert("usage " + c->message);
    // Errors past the limit are not diagnostics but one closing line, as printed.
    std::ostringstream printed_all;
    c->diags.print(printed_all);
    if (printed_all.str().find("[TooManyErrors]") != std::string::npos)
      got.insert("error TooManyErrors");
    INFO("case " << path.string());
    std::string printed;
    for (const auto& d : c->diags.diagnostics()) printed += c->diags.format(d);
    INFO("diagnostics:\n" << printed);
    CHECK(got == expected_diags(text));
    auto at = text.find(kIrOpen);
    if (at != std::string::npos) {
      auto end = text.find("*/", at);
      std::string want = text.substr(at + kIrOpen.size(), end - at - kIrOpen.size());
      std::string have = ir::to_string(c->scene);
      if (update && have != want) {
        std::ofstream(path, std::ios::binary)
            << text.substr(0, at + kIrOpen.size()) << have << text.substr(end);
        continue;
      }
      CHECK(have == want);
    }
  }
}

TEST_CASE("every compile diagnostic kind has a tests/lang case", "[compiler][lang]") {
  std::string all;
  for (const fs::path& p : compile_cases()) all += slurp(p);
  // Kinds of the lexer and parser are covered by tests/language; these by us.
  for (const char* kind :
       {"UndefinedName",    "Redefinition",          "TypeMismatch",       "WrongArgumentCount",
        "NotCallable",      "NonFiniteValue",        "NotAnInteger",       "BadComponent",
        "ZeroStep",         "ReturnOutsideFunction", "MissingReturn",      "RecursionLimit",
        "ValueAsStatement", "UnknownBlock",          "UnknownProperty",    "DuplicateProperty",
        "MissingProperty",  "InvalidValue",          "DuplicateSceneItem", "DegenerateGeometry",
        "ImportNotFound",   "ImportCycle",           "FileUnreadable",     "BadVectorArity",
        "EnergyGain",       "MalformedMesh",         "DiscardedObject"}) {
    INFO(kind);
    CHECK(all.find(std::string(" ") + kind) != std::string::npos);
  }
}
