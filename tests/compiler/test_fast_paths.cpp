// The evaluator's shortcuts (the numeric fast path, cached property lookups,
// pooled property lists) must be invisible: same values, same steps counted, same
// diagnostics at the same places as the general path. These cases pin the spots
// where a shortcut could differ.
#include <catch2/catch.hpp>

#include "compiler/compile.hpp"

using namespace snell;

namespace {

std::unique_ptr<compile::Compilation> run(const std::string& src, std::uint64_t budget = 0) {
  compile::CompileOptions opts;
  opts.stdlib_dir = std::string(SNELL_SOURCE_DIR) + "/stdlib";
  if (budget) opts.step_budget = budget;
  return compile::compile_source("test.scn", src, opts);
}

// Every diagnostic as "Kind@line:col", the place the shortcut must not move.
std::string diags(const compile::Compilation& c) {
  std::string s;
  for (const auto& d : c.diags.diagnostics()) {
    s += std::string(lang::diag_name(d.kind));
    if (d.span.file < c.sources.size()) {
      lang::LineCol lc = c.sources.file(d.span.file).line_col(d.span.begin);
      s += "@" + std::to_string(lc.line) + ":" + std::to_string(lc.col);
    }
    s += " ";
  }
  return s;
}

}  // namespace

TEST_CASE("fast path: the step budget runs out at the same node", "[compiler][fast]") {
  // Steps: the let (1), '+' (2), 1 (3), '*' (4), 2 (5), 3 (6), then the sphere.
  const std::string src = "let x = 1 + 2 * 3;\n";
  CHECK(diags(*run(src, 6)) == "");
  CHECK(diags(*run(src, 5)) == "StepBudget@1:17 ");  // at the literal 3
  CHECK(diags(*run(src, 4)) == "StepBudget@1:13 ");  // at the literal 2
  // A builtin call counts the call, the callee name and the argument.
  const std::string call = "let y = sqrt(4);\n";
  CHECK(diags(*run(call, 4)) == "");
  CHECK(diags(*run(call, 3)) == "StepBudget@1:14 ");
}

TEST_CASE("fast path: shadowed builtins, mixed types, non-finite results", "[compiler][fast]") {
  auto c = run(
      "fn random(x) = 7;\n"
      "fn twice(x) = x * 2;\n"
      "sphere { center twice(<1, 2, 3>) radius random(1) }\n"
      "for i in 0 .. 3 { sphere { center <twice(i), -i, i % 2> radius 1 + i } }\n");
  REQUIRE(diags(*c) == "");
  REQUIRE(c->scene.shapes.size() == 4);
  CHECK(c->scene.shapes[0].radius == 7);
  CHECK(c->scene.shapes[0].center == ir::Vec3{2, 4, 6});
  CHECK(c->scene.shapes[3].center == ir::Vec3{4, -2, 0});
  CHECK(c->scene.shapes[3].radius == 3);
  // The error is reported at the operation whose result is not finite.
  CHECK(diags(*run("let a = 2;\nlet b = 1 + a / (a - 2);\n")) == "NonFiniteValue@2:13 ");
  CHECK(diags(*run("let b = 1 + sqrt(-1) * 2;\n")) == "NonFiniteValue@1:13 ");
  CHECK(diags(*run("let v = <1, 2>;\nlet b = 1 + v * 2 + true;\n")) == "TypeMismatch@2:9 ");
  CHECK(diags(*run("let b = 1 + random(<1, 2>);\n")) == "TypeMismatch@1:20 ");
  CHECK(diags(*run("let b = 1 + sqrt(1, 2);\n")) == "WrongArgumentCount@1:13 ");
  CHECK(diags(*run("let b = -true;\n")) == "TypeMismatch@1:10 ");
}
