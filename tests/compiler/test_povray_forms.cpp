// The POV-Ray habit diagnostic: blocks written with POV-Ray's positional values get
// one PositionalValues error at the first value, with the named form (the user's
// values filled in when their count fits) as its note, and nothing else.
#include <catch2/catch.hpp>
#include <string>

#include "compiler/compile.hpp"
#include "compiler/povray_forms.hpp"
#include "compiler/properties.hpp"
#include "tests/compiler/compile_util.hpp"

using namespace snell;

namespace {

// "Kind@line:col message | note" for each diagnostic.
std::string diags(const std::string& src) {
  auto c = test::compile_text(src);
  std::string out;
  for (const auto& d : c->diags.diagnostics()) {
    lang::LineCol lc = c->sources.file(d.span.file).line_col(d.span.begin);
    out += std::string(lang::diag_name(d.kind)) + "@" + std::to_string(lc.line) + ":" +
           std::to_string(lc.col) + " " + d.message;
    for (const auto& n : d.notes) out += " | " + n.message;
    out += "\n";
  }
  return out;
}

}  // namespace

TEST_CASE("every shape kind has a POV-Ray form row, naming properties of its block",
          "[compiler][registry]") {
  std::size_t kinds = 0;
#define SNELL_SHAPE(name, Type)                                             \
  {                                                                         \
    ++kinds;                                                                \
    INFO(#name);                                                            \
    const compile::PovrayForm* f = compile::find_povray_form(#name);        \
    REQUIRE(f);                                                             \
    const compile::BlockInfo* b = compile::find_block(#name);               \
    REQUIRE(b);                                                             \
    for (std::string_view p : f->props()) CHECK(compile::find_prop(*b, p)); \
    CHECK(f->required() <= f->props().size());                              \
  }
#include "runtime/ir/kinds.def"
  CHECK(compile::povray_forms().size() == kinds);  // and no row for anything else
}

TEST_CASE("POV-Ray's positional shapes get one error with the named form filled in",
          "[compiler][diagnostics]") {
  CHECK(diags("cylinder { <0,0,0>, <0,1,0>, 0.5 }") ==
        "PositionalValues@1:12 'cylinder' takes named properties, not POV-Ray's positional "
        "values | write: cylinder { base <0,0,0> cap <0,1,0> radius 0.5 }\n");
  CHECK(diags("sphere { <0, 0, 0>, 1 }") ==
        "PositionalValues@1:10 'sphere' takes named properties, not POV-Ray's positional values "
        "| write: sphere { center <0, 0, 0> radius 1 }\n");
  CHECK(diags("box { <0,0,0>, <1,1,1> }").find("| write: box { min <0,0,0> max <1,1,1> }\n") !=
        std::string::npos);
  CHECK(diags("cone { <0,0,0>, 1, <0,2,0>, 0 }")
            .find("| write: cone { base <0,0,0> base_radius 1 cap <0,2,0> cap_radius 0 }\n") !=
        std::string::npos);
  CHECK(diags("torus { 1, 0.25 }").find("| write: torus { major 1 minor 0.25 }\n") !=
        std::string::npos);
  CHECK(diags("disc { <0,0,0>, <0,1,0>, 1 }")
            .find("| write: disc { center <0,0,0> normal <0,1,0> radius 1 }\n") !=
        std::string::npos);
  CHECK(diags("disc { <0,0,0>, <0,1,0>, 1, 0.5 }")
            .find("| write: disc { center <0,0,0> normal <0,1,0> radius 1 hole 0.5 }\n") !=
        std::string::npos);
  CHECK(diags("plane { <0,1,0>, 0 }").find("| write: plane { normal <0,1,0> distance 0 }\n") !=
        std::string::npos);
  CHECK(diags("triangle { <0,0,0>, <1,0,0>, <0,1,0> }")
            .find("| write: triangle { a <0,0,0> b <1,0,0> c <0,1,0> }\n") != std::string::npos);
}

TEST_CASE("the note keeps the user's expressions and names, on one line",
          "[compiler][diagnostics]") {
  CHECK(diags("let c = <0, 1, 0>;\nlet r = 2;\nsphere { c, r * 2 }")
            .find("| write: sphere { center c radius r * 2 }\n") != std::string::npos);
  CHECK(diags("let y = <0, 1, 0>;\nplane { y, -1 }")
            .find("| write: plane { normal y distance -1 }\n") != std::string::npos);
  // POV-Ray's own x, y, z (not defined in Snell) are written out, so the note
  // compiles as it stands.
  CHECK(diags("plane { y, -1 }").find("| write: plane { normal <0, 1, 0> distance -1 }\n") !=
        std::string::npos);
  CHECK(diags("sphere { <0,\n   0, 0>,\n 1 }")
            .find("| write: sphere { center <0, 0, 0> radius 1 }\n") != std::string::npos);
}

TEST_CASE("a count that does not fit POV-Ray's order shows the form with placeholders",
          "[compiler][diagnostics]") {
  CHECK(diags("cylinder { <0,0,0>, <0,1,0> }") ==
        "PositionalValues@1:12 'cylinder' takes named properties, not POV-Ray's positional "
        "values | write: cylinder { base … cap … radius … } (POV-Ray's order is base, cap, "
        "radius; 2 values given)\n");
  CHECK(diags("torus { 1, 2, 3 }").find("3 values given") != std::string::npos);
}

TEST_CASE("blocks POV-Ray has no positional form for still get one clear error",
          "[compiler][diagnostics]") {
  CHECK(diags("camera { <0,0,0>, <0,0,1> }") ==
        "PositionalValues@1:10 'camera' takes named properties, not positional values | write "
        "each value after its property name; 'camera' takes: location, look_at, up, fov, "
        "aperture, focal_distance, shutter\n");
  CHECK(diags("mesh { 1, 2 }")
            .find("PositionalValues@1:8 'mesh' takes named properties, not "
                  "positional values") == 0);
  CHECK(diags("sphere { center <0,0,0> material dielectric { 1.5, 0 } }")
            .find("PositionalValues@1:47 'dielectric' takes named properties") == 0);
}

TEST_CASE("no cascade: the positional error is the only one, other items still checked",
          "[compiler][diagnostics]") {
  // Not "needs 'base'" etc. after it; named properties after the values are checked.
  std::string d = diags(
      "cylinder { <0,0,0>, <0,1,0>, 0.5 material diffuse 0.5 }\n"
      "sphere { radius -1 }\n"
      "cone { <0,0,0>, 1, <0,2,0>, 0 colour 1 }\n");
  CHECK(d.find("PositionalValues@1:12") == 0);
  CHECK(d.find("InvalidValue@2:17") != std::string::npos);
  CHECK(d.find("PositionalValues@3:8") != std::string::npos);
  CHECK(d.find("UnknownProperty@3:31") != std::string::npos);
  CHECK(d.find("MissingProperty") == std::string::npos);
  std::size_t lines = 0;
  for (char ch : d) lines += ch == '\n';
  CHECK(lines == 4);
  // The positional values are not evaluated: an undefined name there is not a
  // second error (the note shows it as written).
  CHECK(diags("plane { up_vector, 0 }").find("UndefinedName") == std::string::npos);
}

TEST_CASE("a lone value at the start of a block is still the parse error it was",
          "[compiler][diagnostics]") {
  CHECK(diags("box { 3 }")
            .find("ExpectedProperty@1:7 expected a property name or '}', found "
                  "'3'") == 0);
  CHECK(diags("sphere { <0,0,0> radius 1 }").find("ExpectedProperty@1:10") == 0);
}
