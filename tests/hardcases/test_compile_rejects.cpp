// The compile-time half of the hard cases (robustness.md §1): inputs that must
// never reach the renderer are rejected with a diagnostic that names the place:
// non-finite numbers (#37, #40), zero-size lights and spheres (#9), invalid ior and
// absorption (#15, #22), degenerate triangles (#8: warned and dropped), and an
// out-of-range depth-of-field focus (#35). tests/lang/compile/non-finite.scn and
// degenerate.scn hold the language-level goldens; this checks the rules across
// every property that takes a number.
#include <catch2/catch.hpp>
#include <string>
#include <vector>

#include "hc_util.hpp"
#include "language/diagnostics.hpp"

using namespace snell;
using namespace snell::hc;

namespace {
// The diagnostic kinds a compilation reported, by name.
std::vector<std::string> kinds(const compile::Compilation& c) {
  std::vector<std::string> out;
  for (const auto& d : c.diags.diagnostics()) out.emplace_back(lang::diag_name(d.kind));
  return out;
}
bool has(const std::vector<std::string>& v, const std::string& k) {
  for (const auto& s : v)
    if (s == k) return true;
  return false;
}
}  // namespace

TEST_CASE("hc37 hc40 non-finite numbers are rejected wherever they are written",
          "[hardcase][compile]") {
  // 1e308 * 10 overflows to ∞; 0/0 is NaN. Each property gets one; each must be an
  // error at the expression, so no NaN or ∞ ever reaches a ray or the IR.
  const char* places[] = {
      "sphere { center <INF, 0, 0> }",
      "sphere { radius INF }",
      "plane { normal <0, 1, 0> distance NAN }",
      "box { min <0, 0, 0> max <1, INF, 1> }",
      "triangle { a <NAN, 0, 0> b <1, 0, 0> c <0, 1, 0> }",
      "sphere { translate <INF, 0, 0> }",
      "sphere { scale NAN }",
      "sphere { rotate <0, INF, 0> }",
      "point_light { position <0, 0, 0> intensity INF }",
      "area_light { corner <0, 0, 0> edge1 <1, 0, 0> edge2 <0, 0, 1> radiance NAN }",
      "camera { location <INF, 0, 0> }",
      "camera { fov NAN }",
      "sphere { material dielectric { ior INF } }",
      "sphere { material dielectric { absorb NAN } }",
      "sphere { material diffuse INF }",
      "settings { min_weight NAN }",
      "background INF",
  };
  for (const char* p : places) {
    std::string text = std::string("let INF = 1e308 * 10;\nlet NAN = 0 / 0;\n") + p + "\n";
    auto c = compile_text(text);
    INFO(p << "\n" << diagnostics(*c));
    CHECK(c->diags.has_errors());
    CHECK(has(kinds(*c), "NonFiniteValue"));
  }
  // The literal 1e999 is already out of range for the lexer.
  auto lit = compile_text("sphere { radius 1e999 }\n");
  INFO(diagnostics(*lit));
  CHECK(lit->diags.has_errors());
}

TEST_CASE("hc09 hc15 hc22 zero sizes, invalid ior and negative absorption are errors",
          "[hardcase][compile]") {
  const char* bad[] = {
      "sphere { radius 0 }",  // #9
      "sphere { radius -1 }",
      "area_light { corner <0, 0, 0> edge1 <1, 0, 0> edge2 <0, 0, 0> radiance 1 }",  // #9
      "area_light { corner <0, 0, 0> edge1 <1, 0, 0> edge2 <2, 0, 0> radiance 1 }",  // parallel
      "sphere { material dielectric { ior 0 } }",                                    // #15
      "sphere { material dielectric { ior -1.5 } }",
      "sphere { material glazed { ior 0 } }",
      "sphere { material dielectric { absorb -0.1 } }",  // #22
      "sphere { material dielectric { absorb <0.1, -1, 0> } }",
      "sphere { scale <1, 0, 1> }",
      "camera { focal_distance 0 }",  // #35
      "camera { focal_distance -2 }",
      "camera { aperture -0.1 }",
      "camera { shutter <1, 0> }",  // #32
  };
  for (const char* p : bad) {
    auto c = compile_text(std::string(p) + "\n");
    INFO(p << "\n" << diagnostics(*c));
    CHECK(c->diags.has_errors());
  }
  // A relative ior below 1 is legal: the bubble of #15.
  auto ok = compile_text("sphere { material dielectric { ior 0.75 } }\n");
  INFO(diagnostics(*ok));
  CHECK_FALSE(ok->diags.has_errors());
  CHECK(ir::validate(ok->scene).empty());
}

TEST_CASE("hc08 degenerate triangles are warned about and left out of the IR",
          "[hardcase][compile]") {
  auto c = compile_text(
      "triangle { a <0, 0, 0> b <1, 1, 1> c <2, 2, 2> }\n"  // collinear
      "triangle { a <0, 0, 0> b <0, 0, 0> c <1, 0, 0> }\n"  // repeated vertex
      "triangle { a <1, 2, 3> b <1, 2, 3> c <1, 2, 3> }\n"  // a point
      "triangle { a <0, 0, 0> b <1, 0, 0> c <0, 1, 0> }\n");
  INFO(diagnostics(*c));
  CHECK_FALSE(c->diags.has_errors());
  int warnings = 0;
  for (const auto& k : kinds(*c)) warnings += k == "DegenerateGeometry";
  CHECK(warnings == 3);
  CHECK(c->scene.shapes.size() == 1);
  CHECK(ir::validate(c->scene).empty());
}
