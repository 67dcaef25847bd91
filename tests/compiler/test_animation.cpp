// §18's predeclared names: `clock` and `frame` default to 0, take the values the
// command line compiles a frame with, are visible in every file and function, and
// may be shadowed as any outer name may (docs/language.md).
#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "compile_util.hpp"

using namespace snell;
namespace fs = std::filesystem;

namespace {

std::unique_ptr<compile::Compilation> compile_at(const std::string& src, double clock, double frame,
                                                 const std::string& path = "t.scn") {
  compile::CompileOptions opts;
  opts.stdlib_dir = std::string(SNELL_SOURCE_DIR) + "/stdlib";
  opts.clock = clock;
  opts.frame = frame;
  return compile::compile_source(path, src, opts);
}

// The centre of the scene's first sphere.
ir::Vec3 first_center(const compile::Compilation& c) {
  REQUIRE(c.status == compile::CompileStatus::Ok);
  REQUIRE(!c.scene.shapes.empty());
  const ir::Sphere* s = c.scene.shapes[0].as<ir::Sphere>();
  REQUIRE(s);
  return s->center;
}

}  // namespace

TEST_CASE("clock and frame are predeclared, 0 by default", "[compiler][animation]") {
  auto c = test::compile_text("sphere { center <clock + 1, frame + 2, 0> radius 1 }");
  INFO(test::messages(*c));
  ir::Vec3 p = first_center(*c);
  CHECK(p.x == 1);
  CHECK(p.y == 2);
}

TEST_CASE("clock and frame take the compilation's values", "[compiler][animation]") {
  const std::string src =
      "fn x() = clock * 8;\n"
      "for i in 0 .. 1 { sphere { center <x(), frame, i> radius 1 } }\n";
  auto c = compile_at(src, 0.375, 17);
  INFO(test::messages(*c));
  ir::Vec3 p = first_center(*c);
  CHECK(p.x == 3);
  CHECK(p.y == 17);
}

TEST_CASE("an imported file sees the predeclared names", "[compiler][animation]") {
  fs::path dir = fs::temp_directory_path() / ("snell_anim_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "lib.scn") << "fn spin() = 360 * clock;\nlet at_frame = frame;\n";
  auto c = compile_at("import \"lib.scn\";\nsphere { center <spin(), at_frame, 0> radius 1 }", 0.5,
                      3, (dir / "main.scn").string());
  fs::remove_all(dir);
  INFO(test::messages(*c));
  ir::Vec3 p = first_center(*c);
  CHECK(p.x == 180);
  CHECK(p.y == 3);
}

TEST_CASE("clock may be shadowed, once per scope", "[compiler][animation]") {
  SECTION("a file's own let shadows it") {
    auto c = compile_at("let clock = 0.75;\nsphere { center <clock, 0, 0> radius 1 }", 0.25, 0);
    INFO(test::messages(*c));
    CHECK(first_center(*c).x == 0.75);
  }
  SECTION("a parameter shadows it inside the function only") {
    auto c =
        compile_at("fn f(clock) = clock;\nsphere { center <f(9), clock, 0> radius 1 }", 0.25, 0);
    INFO(test::messages(*c));
    ir::Vec3 p = first_center(*c);
    CHECK(p.x == 9);
    CHECK(p.y == 0.25);
  }
  SECTION("defining it twice in one scope is the usual error") {
    auto c = compile_at("let frame = 1;\nlet frame = 2;\n", 0, 0);
    CHECK(c->status == compile::CompileStatus::SceneErrors);
    CHECK(test::messages(*c).find("'frame' is already defined in this scope") != std::string::npos);
  }
}
