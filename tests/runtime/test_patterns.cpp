// §15's patterns at exact points against the formulas docs/language.md gives
// (runtime/pattern/patterns.hpp), the colour map's interpolation, and how a hit
// becomes the pattern's point (runtime/shading/textures.hpp): moved inward by 1e-4
// of the pattern's unit, taken back through its transforms, into the object's
// space with `space "object"`, displaced by turbulence.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "runtime/pattern/patterns.hpp"
#include "runtime/shading/textures.hpp"

using namespace snell;
using Catch::Matchers::WithinAbs;
using ir::Vec3;
namespace pat = snell::pattern;

namespace {
constexpr double kEps = 1e-12;  // the formulas are a handful of double operations
}

TEST_CASE("patterns: each formula at exact points", "[patterns]") {
  CHECK_THAT(pat::value(ir::Gradient{{0, 2, 0}}, {5, 0.3, 7}, 6), WithinAbs(0.6, kEps));
  CHECK_THAT(pat::value(ir::Gradient{{1, 1, 0}}, {0.25, 0.5, 9}, 6), WithinAbs(0.75, kEps));
  CHECK_THAT(pat::value(ir::Gradient{{0, 1, 0}}, {0, -0.25, 0}, 6), WithinAbs(0.75, kEps));

  CHECK_THAT(pat::value(ir::Onion{}, {0.3, 0.4, 0}, 6), WithinAbs(0.5, kEps));
  CHECK_THAT(pat::value(ir::Onion{}, {0, 1.2, 1.6}, 6), WithinAbs(0.0, kEps));  // |p| = 2

  // Degrees around y from +z towards +x.
  CHECK_THAT(pat::value(ir::Radial{}, {1, 3, 0}, 6), WithinAbs(0.25, kEps));
  CHECK_THAT(pat::value(ir::Radial{}, {0, 0, -1}, 6), WithinAbs(0.5, kEps));
  CHECK_THAT(pat::value(ir::Radial{}, {-1, 0, 0}, 6), WithinAbs(0.75, kEps));
  CHECK_THAT(pat::value(ir::Radial{}, {1, 0, 1}, 6), WithinAbs(0.125, kEps));

  // Mortar: the band of width 0.02 ending 0.002 below each multiple of the size.
  ir::Brick b;                                           // size <0.5, 0.25, 0.25>, mortar 0.02
  CHECK(pat::value(b, {0.25, 0.125, 0.125}, 6) == 0);    // the middle of a brick
  CHECK(pat::value(b, {-0.005, 0.125, 0.125}, 6) == 1);  // just below x = 0
  CHECK(pat::value(b, {0.005, 0.125, 0.125}, 6) == 0);   // just above it: a brick
  CHECK(pat::value(b, {0.25, 0.245, 0.125}, 6) == 1);    // just below y = 0.25
  CHECK(pat::value(b, {0.25, 0.255, 0.125}, 6) == 0);
  CHECK(pat::value(b, {0.25, 0.125, 0.245}, 6) == 1);  // just below z = 0.25
  CHECK(pat::value(b, {0.25, 0.125, 0.255}, 6) == 0);
  // The band's edges: [k·size − 0.022, k·size − 0.002).
  CHECK(pat::value(b, {0.25, 0.25 - 0.0221, 0.125}, 6) == 0);
  CHECK(pat::value(b, {0.25, 0.25 - 0.0219, 0.125}, 6) == 1);
  CHECK(pat::value(b, {0.25, 0.25 - 0.0021, 0.125}, 6) == 1);
  CHECK(pat::value(b, {0.25, 0.25 - 0.0019, 0.125}, 6) == 0);
  // The next row (y in [0.25, 0.5), its mortar below it) is shifted half a brick:
  // x = -0.005 is mid-brick there, x = 0.245 a joint; in z, 0.12 is.
  CHECK(pat::value(b, {-0.005, 0.375, 0.0}, 6) == 0);
  CHECK(pat::value(b, {0.245, 0.375, 0.05}, 6) == 1);
  CHECK(pat::value(b, {0.05, 0.375, 0.12}, 6) == 1);
  CHECK(pat::value(b, {0.245, -0.125, 0.05}, 6) == 1);  // row -1 is odd too
  CHECK(pat::value(b, {-0.005, -0.125, 0.05}, 6) == 0);

  CHECK(pat::value(ir::Noise{}, {3, -2, 7}, 6) == 0.5);
  CHECK(pat::value(ir::Noise{}, {0.3, 0.2, 0.1}, 6) == pat::noise({0.3, 0.2, 0.1}));
  CHECK(pat::value(ir::Fbm{2.5, 0.4}, {0.3, 0.2, 0.1}, 4) ==
        pat::fbm({0.3, 0.2, 0.1}, 4, 2.5, 0.4));

  CHECK_THAT(pat::value(ir::Marble{}, {0.25, 9, 9}, 6), WithinAbs(0.5, kEps));
  CHECK_THAT(pat::value(ir::Marble{}, {1.5, 0, 0}, 6), WithinAbs(1.0, kEps));
  CHECK_THAT(pat::value(ir::Marble{}, {-2, 0, 0}, 6), WithinAbs(0.0, kEps));
  CHECK_THAT(pat::value(ir::Wood{}, {0.3, 0.4, 17}, 6), WithinAbs(1.0, kEps));  // r = 0.5
  CHECK_THAT(pat::value(ir::Wood{}, {0.6, 0.8, -3}, 6), WithinAbs(0.0, kEps));  // r = 1

  const double h = std::numbers::pi / 2;
  CHECK_THAT(pat::value(ir::Leopard{}, {h, h, h}, 6), WithinAbs(1.0, kEps));
  CHECK_THAT(pat::value(ir::Leopard{}, {0, 0, 0}, 6), WithinAbs(0.0, kEps));
  CHECK_THAT(pat::value(ir::Leopard{}, {h, -h, 0}, 6), WithinAbs(0.0, kEps));

  Vec3 q{0.7, -1.3, 2.2};
  CHECK(pat::value(ir::Cells{}, q, 6) == std::fmin(1.0, pat::cells(q)));
  double gran = 0;
  for (int i = 0, f = 1; i < 3; ++i, f *= 2) gran += std::fabs(0.5 - pat::noise(q * (4.0 * f))) / f;
  CHECK_THAT(pat::value(ir::Granite{}, q, 3), WithinAbs(std::fmin(1.0, gran), kEps));
  double ag = std::pow(
      0.5 + 0.5 * std::sin(2 * std::numbers::pi * (1.1 * q.z + 1.3 * pat::turbulence(q, 5))), 0.77);
  CHECK_THAT(pat::value(ir::Agate{}, q, 5), WithinAbs(ag, kEps));
  // A ripple source's own point: every ring there is at phase 0 for it.
  double rs = 0, ws = 0, wn = 0;
  for (int i = 0; i < pat::kWaves; ++i) {
    const pat::WaveSource& s = pat::wave_sources()[i];
    double d = ir::length(q - s.c);
    rs += std::sin(2 * std::numbers::pi * d);
    ws += std::sin(2 * std::numbers::pi * s.f * d) / s.f;
    wn += 1 / s.f;
  }
  CHECK_THAT(pat::value(ir::Ripples{}, q, 6), WithinAbs(0.5 + 0.5 * rs / pat::kWaves, kEps));
  CHECK_THAT(pat::value(ir::Waves{}, q, 6), WithinAbs(0.5 + 0.5 * ws / wn, kEps));
}

TEST_CASE("patterns: every value is in [0, 1] and deterministic", "[patterns]") {
  ir::PatternVariant kinds[] = {ir::Gradient{}, ir::Onion{}, ir::Radial{},  ir::Brick{},
                                ir::Noise{},    ir::Fbm{},   ir::Marble{},  ir::Wood{},
                                ir::Granite{},  ir::Agate{}, ir::Leopard{}, ir::Ripples{},
                                ir::Waves{},    ir::Cells{}};
  for (const ir::PatternVariant& k : kinds)
    for (int i = 0; i < 2000; ++i) {
      Vec3 p{std::sin(i * 1.7) * 40, std::cos(i * 0.37) * 40, (i - 1000) * 0.041};
      double v = std::visit(
          [&](const auto& kind) -> double {
            if constexpr (requires { pat::value(kind, p, 6); })
              return pat::value(kind, p, 6);
            else
              return 0.5;
          },
          k);
      INFO("kind " << k.index() << " at " << ir::to_string(p));
      REQUIRE(v >= 0);
      REQUIRE(v <= 1);
    }
}

TEST_CASE("colour map: linear between the stops around the value, held outside", "[patterns]") {
  std::vector<ir::ColorStop> map = {
      {0.2, {1, 0, 0}}, {0.6, {0, 1, 0}}, {0.6, {0, 0, 1}}, {1.0, {1, 1, 1}}};
  CHECK(pat::map_color(map, 0.0) == Vec3{1, 0, 0});  // held below the first
  CHECK(pat::map_color(map, 0.2) == Vec3{1, 0, 0});
  Vec3 mid = pat::map_color(map, 0.4);
  CHECK_THAT(mid.x, WithinAbs(0.5, kEps));
  CHECK_THAT(mid.y, WithinAbs(0.5, kEps));
  CHECK(mid.z == 0);
  CHECK(pat::map_color(map, 0.6) == Vec3{0, 0, 1});  // equal stops: a step, the later wins
  CHECK_THAT(pat::map_color(map, 0.8).x, WithinAbs(0.5, kEps));
  CHECK(pat::map_color(map, 1.0) == Vec3{1, 1, 1});
  CHECK(pat::map_color(map, 7.0) == Vec3{1, 1, 1});
  CHECK(pat::map_color(map, NAN) == Vec3{1, 0, 0});
  // The default: black at 0 to white at 1.
  CHECK(pat::map_color({}, 0.25) == Vec3(0.25));
  CHECK(pat::map_color({{0.5, {0.3, 0.2, 0.1}}}, 0.9) == Vec3{0.3, 0.2, 0.1});
}

TEST_CASE("colour map: a long map finds the stops a scan finds, equal stops and all",
          "[patterns]") {
  // 3000 stops, every third position doubled (a step), searched at random values,
  // at every stop and just around it, against the scan the rule describes.
  std::vector<ir::ColorStop> map;
  std::uint64_t h = 0x1234;
  auto next = [&] {
    h = h * 6364136223846793005ull + 1442695040888963407ull;
    return double(h >> 11) * 0x1p-53;
  };
  double at = -0.5;
  for (int i = 0; i < 3000; ++i) {
    if (i % 3 != 1) at += next() * 1e-3;
    map.push_back({at, {next(), next(), next()}});
  }
  auto scan = [&](double v) {
    if (!(v >= map.front().at)) return map.front().color;
    if (v >= map.back().at) return map.back().color;
    std::size_t i = 1;
    while (map[i].at <= v) ++i;
    const ir::ColorStop &a = map[i - 1], &b = map[i];
    return a.color + (b.color - a.color) * ((v - a.at) / (b.at - a.at));
  };
  std::vector<double> vs;
  for (int i = 0; i < 20000; ++i)
    vs.push_back(map.front().at - 0.1 + next() * (at + 0.2 - map.front().at));
  for (const ir::ColorStop& s : map)
    vs.insert(vs.end(), {s.at, std::nextafter(s.at, -1.0), std::nextafter(s.at, 2.0)});
  std::size_t differ = 0;
  for (double v : vs) differ += !(pat::map_color(map, v) == scan(v));
  INFO(vs.size() << " values");
  CHECK(differ == 0);
}

TEST_CASE("patterns: the hit point moved inward, through transforms and object space",
          "[patterns]") {
  ir::Texture t;
  t.pattern = ir::Gradient{{0, 1, 0}};
  // The top face of a box at y = 1 seen from above: the gradient's discontinuity.
  // Inward (against the outward +y normal) by 1e-4 it is just below 1: value ~1,
  // one value for the whole face.
  rt::TexturePoint tp{{0, 0, 0}, {0, 1, 0}, {0.3, 1, 0.2}};
  Vec3 q = rt::pattern_point(t, tp, 1, 1e4);
  CHECK_THAT(q.y, WithinAbs(1 - 1e-4, 1e-15));
  CHECK(rt::pattern_value(std::get<ir::Gradient>(t.pattern), t, tp) > 0.999);
  // Its bottom face (outward -y) at y = 1 is the next period's start: value ~0.
  rt::TexturePoint below{{0, 0, 0}, {0, -1, 0}, {0.3, 1, 0.2}};
  CHECK(rt::pattern_value(std::get<ir::Gradient>(t.pattern), t, below) < 0.001);

  // Scale 2 then translate <0, 1, 0>: the point is taken back through both, and the
  // inward step is 1e-4 of the pattern's unit (2 world units): 2e-4.
  t.world_from_pattern = ir::Transform::translate({0, 1, 0}) * ir::Transform::scale(Vec3(2));
  rt::TexturePoint tp2{{0, 0, 0}, {0, 1, 0}, {0.5, 2, 0}};
  q = rt::pattern_point(t, tp2, 1, 1e4);
  CHECK_THAT(q.x, WithinAbs(0.25, 1e-15));
  CHECK_THAT(q.y, WithinAbs((2 - 2e-4 - 1) / 2, 1e-15));

  // space "object": the point in the object's space, following its motion at the
  // ray's time.
  ir::Texture o;
  o.pattern = ir::Gradient{{1, 0, 0}};
  o.space = ir::PatternSpace::Object;
  ir::Shape sh;
  sh.set_world_from_object(ir::Transform::translate({5, 0, 0}));
  sh.set_motion({{{ir::TransformOp::Kind::Translate, {2, 0, 0}}}});
  rt::TexturePoint at0{{0, 0, 0}, {0, 0, 1}, {5.3, 0, 0}, &sh, 0.0f};
  rt::TexturePoint at1{{0, 0, 0}, {0, 0, 1}, {7.3, 0, 0}, &sh, 1.0f};
  CHECK_THAT(rt::pattern_point(o, at0, 1, 1e4).x, WithinAbs(0.3, 1e-12));
  CHECK_THAT(rt::pattern_point(o, at1, 1, 1e4).x, WithinAbs(0.3, 1e-12));
  // World space ignores the object.
  o.space = ir::PatternSpace::World;
  CHECK_THAT(rt::pattern_point(o, at1, 1, 1e4).x, WithinAbs(7.3, 1e-12));
}

// A floor at y = 0, a box's top at y = 1 or a wall at z = 0 lies on a multiple of
// the brick size: there POV-Ray shows bricks with their joints, and so must Snell,
// on either side of the face (the point is moved 1e-4 inward, up or down).
TEST_CASE("brick: a face on a multiple of the size shows bricks, as between multiples",
          "[patterns]") {
  ir::Texture t;
  t.pattern = ir::Brick{};
  const ir::Brick& b = std::get<ir::Brick>(t.pattern);
  // The fraction of mortar over a 4 × 4 square of the plane through `at` across
  // `axis`, seen from the side of outward normal `n`, at points of float hits.
  auto mortar_fraction = [&](int axis, double at, rt::Vec3f n) {
    int mortar = 0, total = 0;
    for (int i = 0; i < 400; ++i)
      for (int j = 0; j < 400; ++j) {
        double u = -2 + (i + 0.5) * 0.01, v = -2 + (j + 0.5) * 0.01;
        rt::Vec3f p = axis == 1 ? rt::Vec3f{float(u), float(at), float(v)}
                                : rt::Vec3f{float(u), float(v), float(at)};
        mortar += rt::pattern_value(b, t, rt::TexturePoint{p, n, {0, 0, 0}}) == 1;
        ++total;
      }
    return double(mortar) / total;
  };
  // Between multiples: y = 0.1 (joints in x and z: 1 − 0.96 · 0.92), z = 0.05 (the
  // rows' mortar and the joints in x: 1 − 0.92 · 0.96).
  const double between = 1 - (1 - 0.02 / 0.5) * (1 - 0.02 / 0.25);
  CHECK_THAT(mortar_fraction(1, 0.1, {0, 1, 0}), WithinAbs(between, 0.01));
  CHECK_THAT(mortar_fraction(2, 0.05, {0, 0, -1}), WithinAbs(between, 0.01));
  for (float s : {1.0f, -1.0f}) {
    INFO("outward normal " << s);
    CHECK_THAT(mortar_fraction(1, 0, {0, s, 0}), WithinAbs(between, 0.01));  // a floor
    CHECK_THAT(mortar_fraction(1, 1, {0, s, 0}), WithinAbs(between, 0.01));  // a box's top
    CHECK_THAT(mortar_fraction(2, 0, {0, 0, s}), WithinAbs(between, 0.01));  // a wall
    CHECK_THAT(mortar_fraction(2, -1, {0, 0, s}), WithinAbs(between, 0.01));
  }

  // On the floor, a brick away from the joints, whichever side it is seen from.
  for (float s : {1.0f, -1.0f}) {
    rt::TexturePoint floor{{0.25f, 0, 0.125f}, {0, s, 0}, {0, 0, 0}};
    CHECK(rt::pattern_value(b, t, floor) == 0);
    rt::TexturePoint top{{0.25f, 1, 0.125f}, {0, s, 0}, {0, 0, 0}};
    CHECK(rt::pattern_value(b, t, top) == 0);
  }
  // On the wall z = 0, every row has bricks, and its joints are half a brick from
  // the next row's: x = 0.49 is a joint in row 0 (the bricks standing on y = 0),
  // x = 0.24 in row 1.
  auto wall = [&](float x, float y) {
    return rt::pattern_value(b, t, rt::TexturePoint{{x, y, 0}, {0, 0, -1}, {0, 0, 0}});
  };
  for (int row = -4; row < 4; ++row) {
    INFO("row " << row);
    float y = float((row + 0.4) * 0.25);
    bool odd = row % 2 != 0;
    CHECK(wall(0.1f, y) == 0);
    CHECK(wall(0.37f, y) == 0);
    CHECK(wall(0.49f, y) == (odd ? 0 : 1));
    CHECK(wall(0.24f, y) == (odd ? 1 : 0));
  }
  // The mortar keeps its width: 0.02 of each 0.5 along x, 0.02 of each 0.25 along y.
  int in_x = 0, in_y = 0;
  const int steps = 100000;
  for (int i = 0; i < steps; ++i) {
    in_x += pat::value(b, {(i + 0.5) * 5.0 / steps, 0.1, 0.05}, 6) == 1;
    in_y += pat::value(b, {0.1, (i + 0.5) * 5.0 / steps, 0.05}, 6) == 1;
  }
  CHECK_THAT(in_x * 5.0 / steps, WithinAbs(10 * 0.02, 1e-3));  // ten joints
  CHECK_THAT(in_y * 5.0 / steps, WithinAbs(20 * 0.02, 1e-3));  // twenty rows
}

TEST_CASE("patterns: turbulence displaces the point by T times a vector fbm", "[patterns]") {
  ir::Texture t;
  t.pattern = ir::Marble{};
  t.turbulence = 0.7;
  t.octaves = 4;
  rt::TexturePoint tp{{0, 0, 0}, {0, 0, -1}, {0.37, 0.21, 0.5}};
  Vec3 p = rt::pattern_point(t, tp, 1, 1e4);
  Vec3 d = p + pat::vector_fbm(p, 4) * 0.7;
  CHECK(rt::pattern_value(ir::Marble{}, t, tp) == pat::triangle(d.x));
}

TEST_CASE("checker: the §8 formula, bit for bit, and a colour map", "[patterns]") {
  ir::Checker c;
  c.size = 0.37;
  ir::Texture t(c);
  for (int i = 0; i < 1000; ++i) {
    rt::Vec3f p{float(std::sin(i * 0.7) * 3), float(std::cos(i * 1.3) * 2), float(i * 0.01)};
    rt::Vec3f n = rt::normalize(rt::Vec3f{float(std::sin(i * 1.1)), 1, float(std::cos(i))});
    ir::Vec3 o{1.5, -2.25, 3};
    rt::TexturePoint tp{p, n, o};
    // §8 as written before patterns had transforms.
    double s = c.size;
    ir::Vec3 w(double(p.x) + o.x - n.x * s / 100, double(p.y) + o.y - n.y * s / 100,
               double(p.z) + o.z - n.z * s / 100);
    int odd = rt::floor_parity(w.x / s) ^ rt::floor_parity(w.y / s) ^ rt::floor_parity(w.z / s);
    rt::Color want = odd ? rt::Color(0) : rt::Color(1);
    rt::Color got = rt::texture_color(t, tp);
    REQUIRE(got.x == want.x);
  }
  t.color_map = {{0, {0.2, 0.4, 0.6}}, {1, {0.9, 0.8, 0.7}}};
  rt::TexturePoint even{{0.1f, 0.1f, 0.1f}, {0, 1, 0}, {0, 0, 0}};
  CHECK(rt::texture_color(t, even).x == 0.2f);
}

TEST_CASE("patterns: a point past where a pattern's arithmetic overflows gives 0, not NaN",
          "[patterns]") {
  // ripples { scale 1e-155 } puts the hit 1e155 out in the pattern's space: the
  // lengths to the wave sources are infinite and sin(inf) NaN, which dropped the
  // whole sample. Every value pattern, through the lookup the renderer uses.
  ir::PatternVariant kinds[] = {ir::Gradient{}, ir::Onion{}, ir::Radial{},  ir::Brick{},
                                ir::Noise{},    ir::Fbm{},   ir::Marble{},  ir::Wood{},
                                ir::Granite{},  ir::Agate{}, ir::Leopard{}, ir::Ripples{},
                                ir::Waves{},    ir::Cells{}};
  std::uint64_t nonfinite = 0;
  rt::TexturePoint tp{};
  tp.nonfinite = &nonfinite;
  for (const ir::PatternVariant& k : kinds)
    for (double x : {1e160, -1e200, 1e308}) {
      ir::Texture t;
      t.pattern = k;
      const double v = rt::value_at(t, Vec3{x, x, x}, rt::PatternFrame{}, tp);
      INFO("kind " << k.index() << " at " << x);
      CHECK(v >= 0);
      CHECK(v <= 1);
    }
  // Ripples, waves and onion overflowed there: their value is 0.
  ir::Texture ripples;
  ripples.pattern = ir::Ripples{};
  CHECK(rt::value_at(ripples, Vec3{1e160, 0, 0}, rt::PatternFrame{}, tp) == 0);
}
