// §16 `specular` and `shininess`: what the compiler accepts, the messages it gives
// for what it does not, and what reaches the IR (tests/lang/compile/highlights*.scn
// hold the positions and the dump).
#include <catch2/catch.hpp>
#include <string>

#include "compiler/compile.hpp"
#include "compiler/properties.hpp"
#include "runtime/ir/dump.hpp"
#include "tests/compiler/compile_util.hpp"

using namespace snell;

namespace {

using test::messages;

}  // namespace

TEST_CASE("specular >= 0 and shininess > 0, with messages that say so", "[compiler][highlights]") {
  struct Case {
    const char* props;
    const char* says;
  };
  const Case cases[] = {
      {"specular -1", "InvalidValue: 'specular' must be >= 0"},
      {"specular -1e-9", "InvalidValue: 'specular' must be >= 0"},
      {"specular 1e31", "InvalidValue: 'specular' must be at most 1e30"},
      {"shininess 0", "InvalidValue: 'shininess' must be > 0"},
      {"shininess -50", "InvalidValue: 'shininess' must be > 0"},
      {"specular <1, 1, 1>", "InvalidValue: 'specular' takes a number >= 0, not a 3-vector"},
  };
  for (const char* kind : {"diffuse", "glazed"})
    for (const Case& k : cases) {
      auto c =
          test::compile_text(std::string("sphere { material ") + kind + " { " + k.props + " } }\n");
      std::string m = messages(*c);
      INFO(kind << " " << k.props << "\n" << m);
      CHECK(c->status != compile::CompileStatus::Ok);
      CHECK(m.find(k.says) != std::string::npos);
    }
}

TEST_CASE("specular and shininess reach the IR and are not positional", "[compiler][highlights]") {
  auto c = test::compile_text(
      "sphere { material diffuse { color 0.5 specular 0.25 shininess 120 } }\n"
      "sphere { material diffuse 0.5 }\n"
      "sphere { material glazed { color 0 specular 1 } }\n");
  INFO(messages(*c));
  REQUIRE(c->status == compile::CompileStatus::Ok);
  REQUIRE(c->scene.shapes.size() == 3);
  auto mat = [&](std::size_t i) -> const ir::Material& {
    return c->scene.materials[c->scene.shapes[i].material];
  };
  REQUIRE(mat(0).as<ir::Diffuse>());
  CHECK(mat(0).as<ir::Diffuse>()->specular == 0.25);
  CHECK(mat(0).as<ir::Diffuse>()->shininess == 120);
  CHECK(mat(1).as<ir::Diffuse>()->specular == 0);  // the defaults: no highlight
  CHECK(mat(1).as<ir::Diffuse>()->shininess == 50);
  CHECK(ir::to_string(mat(2)) == "glazed { color <0, 0, 0> ior 1.5 specular 1 shininess 50 }");
  // Different highlights are different materials.
  CHECK(c->scene.shapes[0].material != c->scene.shapes[1].material);
  // The positional forms keep the core's parameters.
  for (const char* name : {"diffuse", "glazed"}) {
    const compile::BlockInfo* b = compile::find_block(name);
    REQUIRE(b);
    CHECK(b->props.size() == (std::string(name) == "diffuse" ? 1u : 2u));
    for (const char* p : {"specular", "shininess"}) {
      REQUIRE(compile::find_prop(*b, p));
      CHECK(compile::find_prop(*b, p)->named_only());
    }
  }
  auto features = ir::analyze_features(c->scene);
  CHECK(features.highlights);
  CHECK(ir::to_string(features).find("highlights: specular 0.25 shininess 120") !=
        std::string::npos);
  // specular 0 is no highlight, whatever the shininess.
  auto none = test::compile_text("sphere { material diffuse { shininess 3 } }\n");
  REQUIRE(none->status == compile::CompileStatus::Ok);
  CHECK(!ir::analyze_features(none->scene).highlights);
}
