// Motion inside CSG blocks and inside moving objects (§8, §12, §13, §19), from the
// language to the rays: at a time u a scene whose motions nest is hit where the
// static scene with each motion's transforms at u written out is hit, each motion
// after its object's own transforms and the parent's transforms and motion after
// the child's. Rotations are in every case, so a composition in the wrong order
// (or a pivot in the wrong space) moves the surfaces.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <string>

#include "compiler/compile.hpp"
#include "runtime/embree_scene.hpp"
#include "runtime/render.hpp"
#include "tests/compiler/compile_util.hpp"

using namespace snell;

namespace {

using test::num;
std::string vec(double x, double y, double z) {
  return "<" + num(x) + ", " + num(y) + ", " + num(z) + ">";
}

const std::string kMotionHead =
    "camera { location <0, 2, -9> look_at <0, 1, 0> shutter <0, 1> }\n"
    "point_light { position <3, 6, -4> intensity 60 }\n";

ir::Scene motion_scene(const std::string& body) {
  auto c = test::compile_text(kMotionHead + body);
  INFO(body << "\n" << test::messages(*c));
  REQUIRE(c->status == compile::CompileStatus::Ok);
  REQUIRE(c->diags.diagnostics().empty());
  return c->scene;
}

// `src` (a whole scene) compiled and rendered on one thread.
rt::RenderResult rendered(const std::string& src) {
  auto c = test::compile_text(src);
  INFO(test::messages(*c));
  REQUIRE(c->status == compile::CompileStatus::Ok);
  rt::RenderOptions o;
  o.threads = 1;
  return rt::render(c->scene, o);
}

// Traces a 48×48 fan of rays from the camera at time u through `moving` and at
// shutter open through `still`: every ray hits or misses both alike, at the same
// distance (relative error below `tol`) and with the same normal. Returns the
// rays that hit. Analytic shapes and CSG are placed exactly at the ray's time, so
// they agree to rounding; moving triangles follow Embree's time steps, whose
// chords are within 1e-4 of the shape's size of the exact path (motion.hpp).
int same_hits(const std::string& moving, const std::string& still, double u, double tol = 1e-5) {
  ir::Scene a = motion_scene(moving), b = motion_scene(still);
  rt::EmbreeScene ea(a, {0, 0, 0}), eb(b, {0, 0, 0});
  CHECK(ea.has_motion());
  CHECK_FALSE(eb.has_motion());
  const rt::Vec3f eye{0, 2, -9};
  int hits = 0, disagree = 0;
  double worst_t = 0, worst_n = 0;
  for (int j = 0; j < 48; ++j)
    for (int i = 0; i < 48; ++i) {
      // About ±2.7 across at the origin, 9 away.
      rt::Vec3f d{(i + 0.5f) / 48 * 0.6f - 0.3f, (j + 0.5f) / 48 * 0.6f - 0.41f, 1};
      rt::Hit ha, hb;
      bool fa = ea.intersect(rt::Ray{eye, d, INFINITY, float(u)}, ha);
      bool fb = eb.intersect(rt::Ray{eye, d, INFINITY, 0}, hb);
      if (fa != fb) {
        ++disagree;
        continue;
      }
      if (!fa) continue;
      ++hits;
      worst_t = std::fmax(worst_t, std::fabs(double(ha.t) - double(hb.t)) / double(hb.t));
      worst_n = std::fmax(worst_n, 1 - double(rt::dot(ha.ng, hb.ng)));
    }
  INFO("time " << u << ": " << disagree << " rays hit one scene only; worst relative t " << worst_t
               << ", worst normal 1 - cos " << worst_n);
  CHECK(disagree == 0);
  CHECK(worst_t < tol);
  CHECK(worst_n < tol);
  return hits;
}

}  // namespace

TEST_CASE("a CSG child's motion moves it inside the CSG object (§12)", "[compiler][motion]") {
  // A box with a sphere cut out of its front face, the sphere crossing it: at u
  // the hole stands where `translate u·V` puts it; the whole difference also turns.
  auto scene = [](double u, bool moving) {
    std::string cut =
        moving ? " motion { translate <2.2, 0, 0> }" : " translate " + vec(2.2 * u, 0, 0);
    std::string whole =
        moving ? " motion { rotate <0, 40, 0> pivot <0, 0, 0.5> }"
               : " translate <0, 0, -0.5> rotate " + vec(0, 40 * u, 0) + " translate <0, 0, 0.5>";
    return "difference {\n"
           "  box { min <-1.5, 0, -0.5> max <1.5, 1.2, 0.5> }\n"
           "  sphere { center <-1.1, 0.6, -0.5> radius 0.55" +
           cut +
           " }\n"
           "  rotate <0, 10, 0> translate <0, 0.2, 0.5>" +
           whole + "\n}\n";
  };
  for (double u : {0.0, 0.25, 0.6, 1.0}) CHECK(same_hits(scene(u, true), scene(u, false), u) > 200);
}

TEST_CASE("a moving object inside a moving union: the motions compose (§8, §13)",
          "[compiler][motion]") {
  // world(u) = union motion(u) · union transforms · sphere motion(u) · sphere transforms.
  auto scene = [](double u, bool moving) {
    std::string inner = moving
                            ? " motion { rotate <0, 0, 90> translate <0, 0.5, 0> }"
                            : " rotate " + vec(0, 0, 90 * u) + " translate " + vec(0, 0.5 * u, 0);
    std::string outer = moving ? " motion { rotate <0, 60, 0> translate <-1, 0, 0> }"
                               : " rotate " + vec(0, 60 * u, 0) + " translate " + vec(-u, 0, 0);
    return "union {\n"
           "  sphere { center <1.2, 0, 0> radius 0.5 scale <1, 0.6, 1>" +
           inner +
           " }\n"
           "  cylinder { base <0, -0.3, 0> cap <0, 0.3, 0> radius 0.25 }\n"
           "  rotate <30, 0, 0> translate <0.5, 1, 0>" +
           outer + "\n}\n";
  };
  for (double u : {0.0, 0.3, 0.8, 1.0}) CHECK(same_hits(scene(u, true), scene(u, false), u) > 40);
}

TEST_CASE("a pivot nested in a moving object is a point of its parent's space (§19)",
          "[compiler][motion]") {
  // A bar turning about its end (the pivot, in the union's space) inside a union
  // that is scaled, turned and moved, and moves: a cylinder (exact at the ray's
  // time) and a box (triangles, Embree's time steps).
  auto scene = [](double u, bool moving, bool box) {
    std::string inner =
        moving ? " motion { rotate <0, 0, 90> pivot <0.5, 0, 0> }"
               : " translate <-0.5, 0, 0> rotate " + vec(0, 0, 90 * u) + " translate <0.5, 0, 0>";
    std::string outer =
        moving ? " motion { translate <1.5, 0.5, 0> }" : " translate " + vec(1.5 * u, 0.5 * u, 0);
    return std::string("union {\n") +
           (box ? "  box { min <0.5, 0, -0.2> max <1.5, 0.4, 0.2>"
                : "  cylinder { base <0.5, 0.2, 0> cap <1.5, 0.2, 0> radius 0.2") +
           inner +
           " }\n"
           "  scale 1.5 rotate <0, 30, 0> translate <-1, 0.5, 0>" +
           outer + "\n}\n";
  };
  for (double u : {0.0, 0.4, 0.9, 1.0}) {
    CHECK(same_hits(scene(u, true, false), scene(u, false, false), u) > 40);
    CHECK(same_hits(scene(u, true, true), scene(u, false, true), u, 1e-3) > 40);
  }
}

TEST_CASE("a moving instance of a value that moves inside (§13)", "[compiler][motion]") {
  // A wheel value spinning about its axle, placed on its side and rolling: copied
  // in (the BVH instances static values only), every part composed.
  auto scene = [](double u, bool moving) {
    std::string spin =
        moving ? " motion { rotate <0, 180, 0> pivot <0, 0, 0> }" : " rotate " + vec(0, 180 * u, 0);
    std::string roll = moving
                           ? " motion { rotate <0, 0, -45> pivot <0, 1, 0> translate <0.8, 0, 0> }"
                           : " translate <0, -1, 0> rotate " + vec(0, 0, -45 * u) +
                                 " translate <0, 1, 0> translate " + vec(0.8 * u, 0, 0);
    return "let wheel = union {\n"
           "  torus { major 0.8 minor 0.15 }\n"
           "  cylinder { base <-0.75, 0, 0> cap <0.75, 0, 0> radius 0.08" +
           spin +
           " }\n"
           "};\n"
           "object { wheel rotate <90, 0, 0> translate <0, 1, 0>" +
           roll + " }\n";
  };
  for (double u : {0.0, 0.35, 0.7, 1.0}) CHECK(same_hits(scene(u, true), scene(u, false), u) > 80);
}

TEST_CASE("motion in a union inside a moving merge (§12)", "[compiler][motion]") {
  // A CSG leaf two motions deep inside its CSG object, which moves too.
  auto scene = [](double u, bool moving) {
    std::string leaf =
        moving ? " motion { translate <0, 0.6, 0> }" : " translate " + vec(0, 0.6 * u, 0);
    std::string group =
        moving ? " motion { rotate <0, 0, 50> pivot <0.3, 0, 0> }"
               : " translate <-0.3, 0, 0> rotate " + vec(0, 0, 50 * u) + " translate <0.3, 0, 0>";
    std::string whole = moving ? " motion { rotate <0, 70, 0> }" : " rotate " + vec(0, 70 * u, 0);
    return "merge {\n"
           "  box { min <-1, 0, -0.4> max <1, 0.8, 0.4> }\n"
           "  union { sphere { center <0.9, 0.4, 0> radius 0.45" +
           leaf + " } scale <1.2, 1, 1>" + group +
           " }\n"
           "  translate <0.3, 0.5, 0>" +
           whole + "\n}\n";
  };
  for (double u : {0.0, 0.5, 1.0}) CHECK(same_hits(scene(u, true), scene(u, false), u) > 100);
}

TEST_CASE("a moving CSG child blurs: a hole smeared along its path", "[compiler][motion]") {
  // A thin lit slab facing the camera with a hole of radius r cut by a sphere that
  // crosses it at constant speed: a pixel is the slab's radiance times the
  // fraction of the shutter during which its ray misses the hole (black behind).
  const double r = 0.5, speed = 4;
  std::string src =
      "settings { resolution <61, 1> samples 256 sampler \"sobol\" max_depth 0 }\n"
      "camera { location <0, 0, -10> look_at <0, 0, 0> fov " +
      num(2 * std::atan(0.2) * 180 / 3.14159265358979323846) +
      " shutter <0, 1> }\n"
      "point_light { position <0, 0, -10> intensity 100 }\n"
      "difference {\n"
      "  box { min <-3, -1, -0.005> max <3, 1, 0.005> }\n"
      "  sphere { center <-2, 0, 0> radius " +
      num(r) + " motion { translate " + vec(speed, 0, 0) +
      " } }\n"
      "  material diffuse 1\n"
      "}\n";
  rt::RenderResult res = rendered(src);
  CHECK(res.stats.time_samples > 0);
  double worst = 0, darkest = 1;
  for (std::uint32_t x = 0; x < 61; ++x) {
    // 64 rays across the pixel: slope sx hits the slab at X = 10·sx, inside the
    // hole while |X - (-2 + speed·u)| < r (the slab is thin: a cylinder of radius
    // r). Lit from the camera, the slab's radiance there is 1/π · I cos θ / d² =
    // cos³θ / π.
    double e = 0, open = 0;
    const int n = 64;
    for (int k = 0; k < n; ++k) {
      double sx = -((x + (k + 0.5) / n) / 61.0 * 2 - 1) * 0.2;
      double X = 10 * sx;
      double a = std::fmax(0.0, (X - r + 2) / speed), b = std::fmin(1.0, (X + r + 2) / speed);
      double radiance = std::pow(1 + sx * sx, -1.5) / 3.14159265358979323846;
      e += (1 - std::fmax(0.0, b - a)) * radiance;
      open += radiance;
    }
    double got = res.image.at(x, 0)[0];
    worst = std::fmax(worst, std::fabs(got - e / n) / (open / n));
    darkest = std::fmin(darkest, got / (open / n));
  }
  INFO("worst pixel error " << worst << ", darkest " << darkest);
  CHECK(worst < 0.03);
  // Smeared: no pixel is dark all the shutter long (a static hole would be black).
  CHECK(darkest > 0.6);
  CHECK(darkest < 0.95);
}

TEST_CASE("a space \"object\" pattern moves with a moving CSG leaf", "[compiler][motion]") {
  // The leaf stands inside one checker cell of its CSG object's space at shutter
  // open and then leaves it by its motion; the pattern moves with it, so the
  // leaf shows that cell's colour (red) the whole shutter long, never the next
  // cell's (blue).
  std::string src =
      "settings { resolution <48, 32> samples 16 max_depth 0 }\n"
      "camera { location <0.5, 0.5, -6> look_at <1.5, 0.5, 0.5> fov 40 shutter <0, 1> }\n"
      "point_light { position <0.5, 3, -6> intensity 80 }\n"
      "intersection {\n"
      "  sphere { center <0.5, 0.5, 0.5> radius 0.4\n"
      "    material diffuse checker { color1 <1, 0, 0> color2 <0, 0, 1> size 1 space \"object\" }\n"
      "    motion { translate <1.8, 0, 0> } }\n"
      "  box { min <-5, -5, -5> max <5, 5, 5> }\n"
      "}\n";
  rt::RenderResult res = rendered(src);
  double red = 0, blue = 0;
  for (std::uint32_t y = 0; y < 32; ++y)
    for (std::uint32_t x = 0; x < 48; ++x)
      red += res.image.at(x, y)[0], blue += res.image.at(x, y)[2];
  INFO("red " << red << " blue " << blue);
  CHECK(red > 1);
  CHECK(blue == 0);
}

TEST_CASE("a space \"object\" pattern moves with an object moving inside a union",
          "[compiler][motion]") {
  // A top-level union's children take the union's space, and one that moves
  // carries it along, as a moving CSG leaf does: written in a union, in a union
  // value placed with `object`, or alone, the blurred picture is the same. The
  // union's space stood still (a sharp gradient under a sliding box, 0.18 off).
  const std::string head =
      "settings { resolution <40, 4> samples 64 }\n"
      "camera { location <0, 0, -10> look_at <0, 0, 0> fov 30 shutter <0, 1> }\n"
      "point_light { position <0, 0, -10> intensity 100 }\n"
      "let g = gradient { direction <0.5, 0, 0> space \"object\" color_map { stop <0.5, 0.2> "
      "stop <0.5, 0.8> } };\n";
  const std::string box =
      "box { min <-4, -1, 0> max <4, 1, 1> material diffuse { color g } "
      "motion { translate <-1, 0, 0> } }";
  auto worst = [](const rt::RenderResult& a, const rt::RenderResult& b) {
    REQUIRE(a.image.rgb.size() == b.image.rgb.size());
    float w = 0;
    for (std::size_t i = 0; i < a.image.rgb.size(); ++i)
      w = std::max(w, std::fabs(a.image.rgb[i] - b.image.rgb[i]));
    return w;
  };
  rt::RenderResult alone = rendered(head + box + "\n");
  CHECK(worst(alone, rendered(head + "union { " + box + " }\n")) < 1e-6);
  CHECK(worst(alone, rendered(head + "let u = union { " + box + " };\nobject { u }\n")) < 1e-6);
  // The union's own motion, then the child's: as an instance's motion is.
  CHECK(worst(rendered(head + "object { " + box + " motion { translate <0.5, 0, 0> } }\n"),
              rendered(head + "union { " + box + " motion { translate <0.5, 0, 0> } }\n")) < 1e-6);
}

TEST_CASE("a spinning instance of a symmetric CSG value renders as the still one",
          "[compiler][motion]") {
  // A wheel (a disc-shaped cylinder less a through hole) spinning 45° about its
  // own axis during the shutter is the same wheel at every instant. Embree
  // interpolates an instance's matrices linearly between time steps while its hits
  // are resolved with the exact placement; at 1e-4 of the wheel's size apart, rays
  // grazing the hole's rim were shaded as the front cap (three times as bright).
  const std::string wheel =
      "settings { resolution <100, 75> samples 8 max_depth 4 }\n"
      "camera { location <-2.2, 1.5, -9> look_at <-2.2, 1, 0> fov 60 shutter <0, 1> }\n"
      "background <0.2, 0.3, 0.5>\n"
      "point_light { position <-5.2, 8.5, -9> intensity 300 }\n"
      "let wheel = difference {\n"
      "  cylinder { base <0, 0, -0.2> cap <0, 0, 0.2> radius 0.8 }\n"
      "  cylinder { base <0, 0, -1> cap <0, 0, 1> radius 0.3 }\n"
      "  material diffuse <0.9, 0.9, 0.2> };\n";
  rt::RenderResult still = rendered(wheel + "object { wheel }\n");
  auto off = [&](const std::string& motion) {
    rt::RenderResult spun = rendered(wheel + "object { wheel " + motion + " }\n");
    REQUIRE(still.image.rgb.size() == spun.image.rgb.size());
    int n = 0;
    for (std::size_t i = 0; i < still.image.rgb.size(); ++i)
      n += std::fabs(still.image.rgb[i] - spun.image.rgb[i]) > 0.01;
    return n;
  };
  CHECK(off("motion { rotate <0, 0, 45> }") == 0);
  // Whole turns: linearly interpolated matrices, even at Embree's 128 segments, cut
  // the arc's chords 3e-4 of the size inside it (110 rim pixels off); the
  // quaternion steps follow the arc.
  CHECK(off("motion { rotate <0, 0, 360> }") == 0);
  CHECK(off("motion { rotate <0, 0, -720> }") == 0);
  // Placed away from the origin and spun about its own axis (§19's pivot).
  rt::RenderResult moved = rendered(wheel + "object { wheel translate <1, 0.5, 0> }\n");
  rt::RenderResult pivot = rendered(
      wheel +
      "object { wheel translate <1, 0.5, 0> motion { rotate <0, 0, 360> pivot <1, 0.5, 0> } }\n");
  int n = 0;
  for (std::size_t i = 0; i < moved.image.rgb.size(); ++i)
    n += std::fabs(moved.image.rgb[i] - pivot.image.rgb[i]) > 0.01;
  CHECK(n == 0);
}

TEST_CASE("an instance's space \"object\" holds the value's own transforms", "[compiler]") {
  // §13: the instance's transforms come after the value's own, so `object { v }`
  // is v's objects written out; its object-space gradient was in the instance's
  // frame alone (0.97 of the ramp where the written-out box gives 0.47).
  const std::string head =
      "settings { resolution <32, 24> samples 1 }\n"
      "camera { location <0, 0, -5> look_at <0, 0, 0> fov 50 }\n"
      "background 1\n"
      "point_light { position <0, 0, -5> intensity 25 }\n"
      "let m = diffuse gradient { direction <1, 0, 0> space \"object\" };\n";
  auto same = [](const rt::RenderResult& a, const rt::RenderResult& b) {
    REQUIRE(a.image.rgb.size() == b.image.rgb.size());
    float worst = 0;
    for (std::size_t i = 0; i < a.image.rgb.size(); ++i)
      worst = std::max(worst, std::fabs(a.image.rgb[i] - b.image.rgb[i]));
    return worst;
  };
  const std::string box = "box { min -1 max 1 material m translate <0.5, 0, 0> rotate <0, 20, 0> }";
  CHECK(same(rendered(head + "let v = " + box + ";\nobject { v translate <0.2, 0, 0> }\n"),
             rendered(head + box.substr(0, box.size() - 1) + " translate <0.2, 0, 0> }\n")) < 1e-5);
  // A union value: its own transforms are the object's space, placed twice.
  const std::string u =
      "union { box { min -1 max 1 material m } sphere { radius 0.5 center <0, 1.5, 0> "
      "material m } translate <0.4, -0.5, 0> }";
  CHECK(
      same(rendered(head + "let v = " + u + ";\nobject { v }\nobject { v translate <0, 0, 4> }\n"),
           rendered(head + u + "\n" + u.substr(0, u.size() - 1) + " translate <0, 0, 4> }\n")) <
      1e-5);
}
