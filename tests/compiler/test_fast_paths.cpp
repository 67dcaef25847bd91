// The evaluator's shortcuts (the numeric fast path, cached property lookups,
// pooled property lists) must be invisible: same values, same steps counted, same
// diagnostics at the same places as the general path. These cases pin the spots
// where a shortcut could differ.
#include <catch2/catch.hpp>

#include "compiler/compile.hpp"

using namespace snell;

namespace {

std::unique_ptr<compile::Compilation> run_budgeted(const std::string& src,
                                                   std::uint64_t budget = 0) {
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
  CHECK(diags(*run_budgeted(src, 6)) == "");
  CHECK(diags(*run_budgeted(src, 5)) == "StepBudget@1:17 ");  // at the literal 3
  CHECK(diags(*run_budgeted(src, 4)) == "StepBudget@1:13 ");  // at the literal 2
  // A builtin call counts the call, the callee name and the argument.
  const std::string call = "let y = sqrt(4);\n";
  CHECK(diags(*run_budgeted(call, 4)) == "");
  CHECK(diags(*run_budgeted(call, 3)) == "StepBudget@1:14 ");
}

TEST_CASE("fast path: shadowed builtins, mixed types, non-finite results", "[compiler][fast]") {
  auto c = run_budgeted(
      "fn random(x) = 7;\n"
      "fn twice(x) = x * 2;\n"
      "sphere { center twice(<1, 2, 3>) radius random(1) }\n"
      "for i in 0 .. 3 { sphere { center <twice(i), -i, i % 2> radius 1 + i } }\n");
  REQUIRE(diags(*c) == "");
  REQUIRE(c->scene.shapes.size() == 4);
  CHECK(c->scene.shapes[0].as<ir::Sphere>()->radius == 7);
  CHECK(c->scene.shapes[0].as<ir::Sphere>()->center == ir::Vec3{2, 4, 6});
  CHECK(c->scene.shapes[3].as<ir::Sphere>()->center == ir::Vec3{4, -2, 0});
  CHECK(c->scene.shapes[3].as<ir::Sphere>()->radius == 3);
  // The error is reported at the operation whose result is not finite.
  CHECK(diags(*run_budgeted("let a = 2;\nlet b = 1 + a / (a - 2);\n")) == "NonFiniteValue@2:13 ");
  CHECK(diags(*run_budgeted("let b = 1 + sqrt(-1) * 2;\n")) == "NonFiniteValue@1:13 ");
  CHECK(diags(*run_budgeted("let v = <1, 2>;\nlet b = 1 + v * 2 + true;\n")) ==
        "TypeMismatch@2:9 ");
  CHECK(diags(*run_budgeted("let b = 1 + random(<1, 2>);\n")) == "TypeMismatch@1:20 ");
  CHECK(diags(*run_budgeted("let b = 1 + sqrt(1, 2);\n")) == "WrongArgumentCount@1:13 ");
  CHECK(diags(*run_budgeted("let b = -true;\n")) == "TypeMismatch@1:10 ");
}

TEST_CASE("fast path: compiled code falls back when a run differs", "[compiler][fast]") {
  // f's body is compiled on its first (numeric) call; a vector argument later
  // makes the code fail and the general path take over, with the same results.
  auto c = run_budgeted(
      "fn f(x) = x * 2 + 1;\n"
      "sphere { center <f(1), f(2), 0> }\n"
      "sphere { center f(<1, 2, 3>) }\n"
      "sphere { center <f(3), 0, 0> }\n"
      "fn g(x) = sqrt(x) + 1;\n"
      "sphere { center <g(4), 0, 0> }\n"
      "fn h(sqrt) = sqrt * 2;\n"  // binds the builtin's name, in h only
      "sphere { center <h(5), g(9), 0> }\n");
  REQUIRE(diags(*c) == "");
  REQUIRE(c->scene.shapes.size() == 5);
  CHECK(c->scene.shapes[0].as<ir::Sphere>()->center == ir::Vec3{3, 5, 0});
  CHECK(c->scene.shapes[1].as<ir::Sphere>()->center == ir::Vec3{3, 5, 7});
  CHECK(c->scene.shapes[2].as<ir::Sphere>()->center == ir::Vec3{7, 0, 0});
  CHECK(c->scene.shapes[3].as<ir::Sphere>()->center == ir::Vec3{3, 0, 0});
  CHECK(c->scene.shapes[4].as<ir::Sphere>()->center == ir::Vec3{10, 4, 0});
  // A loop variable that shadows a builtin makes the call an error, as always (in
  // both iterations: one diagnostic, repeated once).
  auto shadowed = run_budgeted(
      "fn k(x) = random(x) * 2;\nlet a = k(1);\n"
      "for random in 0 .. 2 { sphere { center <random(1), 0, 0> } }\n");
  CHECK(diags(*shadowed) == "NotCallable@3:41 ");
  REQUIRE(shadowed->diags.diagnostics().size() == 1);
  CHECK(shadowed->diags.diagnostics()[0].repeats == 1);
  // Steps: a compiled call counts like the walk: let, 2, let, '*', the call, the
  // callee name, x, 3.
  CHECK(diags(*run_budgeted("let x = 2;\nlet y = sqrt(x) * 3;\n", 8)) == "");
  CHECK(diags(*run_budgeted("let x = 2;\nlet y = sqrt(x) * 3;\n", 7)) == "StepBudget@2:19 ");
  CHECK(diags(*run_budgeted("let x = 2;\nlet y = sqrt(x) * 3;\n", 6)) == "StepBudget@2:14 ");
}
