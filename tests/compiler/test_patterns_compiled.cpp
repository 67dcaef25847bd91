// §15 from the language to the renderer's lookups: a shading function that writes
// a built-in pattern's formula gives that pattern's colours at every hit; the
// `noise`, `fbm`, `turbulence` and `cells` builtins at scene-build time equal the
// patterns at render time.
#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "compiler/compile.hpp"
#include "runtime/shading/textures.hpp"
#include "tests/compiler/compile_util.hpp"

using namespace snell;

namespace {

const ir::Texture& color_of(const ir::Scene& s, std::size_t shape) {
  return std::get<ir::Diffuse>(s.materials[s.shapes[shape].material].model).color;
}

}  // namespace

TEST_CASE("a shading function equal to the built-in pattern it mimics", "[compiler][patterns]") {
  struct Case {
    const char* builtin;
    const char* fn;
  };
  const Case cases[] = {
      {"gradient { direction <0, 1, 0> }", "fn f(p) = p.y - floor(p.y);"},
      {"onion { }", "fn f(p) = length(p) - floor(length(p));"},
      {"noise { }", "fn f(p) = noise(p);"},
      {"fbm { octaves 4 }", "fn f(p) = fbm(p, 4);"},
      {"cells { }", "fn f(p) = min(cells(p), 1);"},
      {"leopard { }",
       "fn f(p) = pow((sin(p.x * 57.29577951308232) + sin(p.y * 57.29577951308232) + "
       "sin(p.z * 57.29577951308232)) / 3, 2);"},
  };
  for (const Case& k : cases) {
    std::string src =
        std::string(k.fn) +
        "\n"
        "sphere { material diffuse { color " +
        k.builtin +
        " } }\n"
        "sphere { center <3, 0, 0> material diffuse { color pattern { function f } } }\n";
    auto c = test::compile_text(src);
    INFO(k.builtin << " vs " << k.fn);
    REQUIRE(c->status == compile::CompileStatus::Ok);
    const ir::Scene& s = c->scene;
    const ir::Texture &a = color_of(s, 0), &b = color_of(s, 1);
    REQUIRE(std::holds_alternative<ir::FunctionPattern>(b.pattern));
    double worst = 0;
    for (int i = 0; i < 2000; ++i) {
      rt::Vec3f p{float(std::sin(i * 0.77) * 4), float(std::cos(i * 0.31) * 3), float(i * 0.013)};
      rt::Vec3f n = rt::normalize(rt::Vec3f{float(std::sin(i * 1.3)), 0.5f, float(std::cos(i))});
      rt::TexturePoint tp{p, n, {0.25, -1.5, 2}};
      rt::Color ca = rt::texture_color(a, tp), cb = rt::texture_color(b, tp);
      worst = std::fmax(worst, std::fabs(double(ca.x) - double(cb.x)));
    }
    // The same operations on the same doubles, then one rounding to float: equal,
    // but leopard's sin(x radians) is the language's sin(x·180/π degrees), which
    // rounds differently (a few ulps of the value).
    CHECK(worst <= 1e-6);
  }
}

TEST_CASE("noise builtins at scene-build time are the patterns' values", "[compiler][patterns]") {
  auto c = test::compile_text(
      "let p = <0.37, 1.21, -2.5>;\n"
      "sphere { radius 1 + noise(p) + fbm(p, 5) + turbulence(p, 3) + cells(p) }\n");
  REQUIRE(c->status == compile::CompileStatus::Ok);
  ir::Vec3 p{0.37, 1.21, -2.5};
  double want =
      1 + pattern::noise(p) + pattern::fbm(p, 5) + pattern::turbulence(p, 3) + pattern::cells(p);
  CHECK(std::get<ir::Sphere>(c->scene.shapes[0].geom).radius == want);
}

TEST_CASE("a pattern's lengths are not colours: only colours are held to 1e30",
          "[compiler][patterns]") {
  // `gradient { direction <1e31, 0, 0> }` was refused as "material colours must be
  // at most 1e30", at the material, naming no direction (and for a background at
  // 1:1, the settings line).
  const std::string head =
      "camera { location <0, 0, -5> look_at <0, 0, 0> }\n"
      "point_light { position <0, 0, -5> intensity 25 }\n";
  for (const char* item : {"sphere { material diffuse gradient { direction <1e31, 0, 0> } }\n",
                           "sphere { material diffuse brick { size <1e31, 1, 1> } }\n",
                           "background gradient { direction <0, 1e31, 0> }\nsphere { }\n"}) {
    auto c = test::compile_text(head + item);
    INFO(item << test::messages(*c));
    CHECK(c->status == compile::CompileStatus::Ok);
  }
  // A colour past it is still refused, where it is written.
  auto c =
      test::compile_text(head + "sphere { material diffuse checker { color1 <1e31, 0, 0> } }\n");
  CHECK(c->status != compile::CompileStatus::Ok);
  CHECK(test::messages(*c).find("1e30") != std::string::npos);
}
