// §14 `priority`: what the compiler accepts, the messages it gives for what it
// does not, and what reaches the IR (tests/lang/compile/interiors*.scn hold the
// positions and the dump).
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

TEST_CASE("priority: an integer >= 1, with messages that say so", "[compiler][interiors]") {
  struct Case {
    const char* value;
    const char* kind;
    const char* says;
  };
  const Case cases[] = {
      {"0", "InvalidValue", "'priority' must be >= 1"},
      {"-3", "InvalidValue", "'priority' must be >= 1"},
      {"1.5", "NotAnInteger", "'priority' must be an integer, not 1.5"},
      {"true", "InvalidValue", "'priority' takes an integer >= 1, not a bool"},
      {"1e10", "InvalidValue", "'priority' must be at most 4294967295, not 1e+10"},
  };
  for (const Case& k : cases) {
    auto c = test::compile_text(std::string("sphere { material dielectric { priority ") + k.value +
                                " } }\n");
    std::string m = messages(*c);
    INFO("priority " << k.value << "\n" << m);
    CHECK(c->status != compile::CompileStatus::Ok);
    CHECK(m.find(std::string(k.kind) + ": " + k.says) != std::string::npos);
  }
}

TEST_CASE("priority reaches the IR, is not positional, and 0 means none", "[compiler][interiors]") {
  auto c = test::compile_text(
      "sphere { material dielectric { ior 1.33 priority 2 } }\n"
      "sphere { material dielectric <1.33, 0> }\n"
      "sphere { material dielectric { ior 1.33 priority 4294967295 } }\n");
  INFO(messages(*c));
  REQUIRE(c->status == compile::CompileStatus::Ok);
  REQUIRE(c->scene.shapes.size() == 3);
  auto prio = [&](std::size_t i) {
    return c->scene.materials[c->scene.shapes[i].material].as<ir::Dielectric>()->priority;
  };
  CHECK(prio(0) == 2);
  CHECK(prio(1) == 0);
  CHECK(prio(2) == 4294967295u);  // the largest: the runtime keeps 32 bits
  // Different priorities are different materials.
  CHECK(c->scene.shapes[0].material != c->scene.shapes[1].material);
  CHECK(ir::to_string(c->scene.materials[c->scene.shapes[0].material]) ==
        "dielectric { ior 1.33 absorb <0, 0, 0> priority 2 }");
  // The positional form is the core's two parameters, whatever §14 adds.
  const compile::BlockInfo* d = compile::find_block("dielectric");
  REQUIRE(d);
  CHECK(d->props.size() == 2);
  REQUIRE(compile::find_prop(*d, "priority"));
  CHECK(compile::find_prop(*d, "priority")->named_only());
  auto features = ir::analyze_features(c->scene);
  CHECK(features.interiors);
  CHECK(ir::to_string(features).find("interiors: a dielectric of priority 2") != std::string::npos);
}

TEST_CASE("a prioritised dielectric needs a solid", "[compiler][interiors]") {
  auto c = test::compile_text(
      "let water = dielectric { priority 1 };\n"
      "disc { center <0, 0, 0> normal <0, 1, 0> radius 1 material water }\n"
      "box { min <0, 0, 0> max <1, 1, 1> material water }\n");
  std::string m = messages(*c);
  INFO(m);
  CHECK(c->status != compile::CompileStatus::Ok);
  CHECK(m ==
        "InvalidValue: a dielectric with a 'priority' must fill a solid (§14), and this disc has "
        "no inside\n");
  // Through an instance: the value's parts must all be solids (an instance of a
  // triangle was accepted, and its one surface entered the water for good).
  auto i = test::compile_text(
      "let water = dielectric { priority 1 };\n"
      "let t = triangle { a <0, 0, 0> b <1, 0, 0> c <0, 1, 0> };\n"
      "let cup = union { sphere { } cylinder { base 0 cap <0, 1, 0> radius 0.5 open true } };\n"
      "let ok = union { sphere { } box { min 0 max 1 } };\n"
      "object { t material water }\n"
      "object { cup material water }\n"
      "object { ok material water }\n");
  m = messages(*i);
  INFO(m);
  CHECK(i->status != compile::CompileStatus::Ok);
  CHECK(m ==
        "InvalidValue: a dielectric with a 'priority' must fill a solid (§14), and this object "
        "holds a triangle, which has no inside\n"
        "InvalidValue: a dielectric with a 'priority' must fill a solid (§14), and this object "
        "holds an open cylinder, which has no inside\n");
  // §13: the instance's material reaches only the parts that have none; a part
  // with its own material (or the union's) is no part of the prioritised solid.
  auto own = test::compile_text(
      "let disc_v = disc { center 0 normal <0, 0, 1> radius 1 material diffuse 0.5 };\n"
      "let mixed = union { disc { center 0 normal <0, 1, 0> radius 2 material diffuse 0.5 } "
      "sphere { } "
      "};\n"
      "let all_own = union { disc { center 0 normal <0, 1, 0> radius 2 } sphere { } material "
      "diffuse "
      "0.5 };\n"
      "let tri = triangle { a <0, 0, 0> b <1, 0, 0> c <0, 1, 0> material dielectric 1.5 };\n"
      "object { disc_v material dielectric { priority 1 } }\n"
      "object { mixed material dielectric { priority 1 } }\n"
      "object { all_own material dielectric { priority 1 } }\n"
      "object { tri material dielectric { priority 1 } }\n");
  INFO(messages(*own));
  CHECK(own->status == compile::CompileStatus::Ok);
}
