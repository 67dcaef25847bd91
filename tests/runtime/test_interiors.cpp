// §14 interiors (nested dielectrics with priorities) against analytic ray trees.
//
// The slab scenes are stacks of boxes wide enough to be infinite slabs for the one
// pixel looked at, between the camera and a large one-sided area light facing it,
// on a black background. Light reaches the camera only through the stack, so the
// pixel is L times the sum over the ray tree's paths that end on the light:
// products of Fresnel weights (exact Fresnel with the angles Snell's law gives in
// each medium, n·sinθ conserved) and Beer factors (thickness / cosθ per layer).
// `stack_tree` sums that tree for given layers, in double, with the renderer's
// max_depth rule (a child deeper than max_depth is dropped); its layers are what
// §14 says the media are, so a wrong medium, index or pass-through fails. The
// camera ray's direction is replayed from the sampler and camera, so the only
// difference is float rounding in the renderer's directions and weights (relative
// 1e-7 a step, a few dozen steps; measured under 1e-6): the tolerance is 1e-5
// relative.
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "runtime/camera.hpp"
#include "runtime/render.hpp"
#include "runtime/sampler.hpp"
#include "runtime/shading/fresnel.hpp"
#include "runtime/shading/interior.hpp"
#include "tests/runtime/effects_util.hpp"

using namespace snell;
using namespace snell::test;

namespace {

ir::Material prioritised(double ior, ir::Vec3 absorb, std::uint64_t priority) {
  return ir::Dielectric{ior, absorb, priority};
}

// A layer of the analytic model: z0 < z1, index n, Beer coefficient per channel.
struct Layer {
  double z0, z1, n;
  ir::Vec3 sigma;
};

struct Tree {
  const std::vector<Layer>& layers;
  double s;  // n·sinθ, conserved across parallel interfaces
  int channel;
  std::uint32_t max_depth;
  double light;

  double n_of(int k) const { return k < 0 || k >= int(layers.size()) ? 1.0 : layers[k].n; }
  double cos_in(int k) const {
    double sn = s / n_of(k);
    return std::sqrt(1 - sn * sn);
  }
  // A ray in region k (-1: the camera's side, size(): the light's) moving `dir`
  // (+1 towards the light) that left its last interface at `depth`.
  double walk(int k, int dir, std::uint32_t depth) const {
    if (k < 0) return 0;                        // escapes into the black background
    if (k >= int(layers.size())) return light;  // reaches the light
    const Layer& l = layers[k];
    double path = (l.z1 - l.z0) / cos_in(k);
    return std::exp(-l.sigma[channel] * path) * interface(k, dir, depth);
  }
  // The ray in region k meets the interface towards region k + dir.
  double interface(int k, int dir, std::uint32_t depth) const {
    if (depth + 1 > max_depth) return 0;
    rt::Interface f = rt::make_interface(cos_in(k), n_of(k + dir) / n_of(k));
    double R = rt::fresnel_exact(f);
    double sum = R * walk(k, -dir, depth + 1);
    if (!f.tir) sum += (1 - R) * walk(k + dir, dir, depth + 1);
    return sum;
  }
  double camera() const { return interface(-1, +1, 0); }
};

// Boxes from z0 to z1, 200 wide, of material m.
ir::Shape slab(double z0, double z1, std::uint32_t m) {
  return box({-100, -100, z0}, {100, 100, z1}, m);
}

// One pixel looking along `dir` (x-z plane) from z = -5 towards +z, with the light
// at z = 20 facing the camera (radiance 1 on every channel).
ir::Scene stack_scene(double angle_deg) {
  ir::Scene s = base_scene(1, 1, 1);
  s.settings.min_weight = 0;
  s.settings.max_depth = 10;
  double a = angle_deg * M_PI / 180;
  ir::Vec3 from{-5 * std::tan(a), 0, -5};
  look(s, from, from + ir::Vec3{std::sin(a), 0, std::cos(a)}, 1e-3);
  s.area_lights.push_back(area_light({-500, -500, 20}, {0, 1000, 0}, {1000, 0, 0}, {1, 1, 1}));
  return s;
}

// The pixel and the analytic tree for the given layers, per channel.
void check_against(const ir::Scene& s, const std::vector<Layer>& layers, double tol = 1e-5) {
  rt::RenderResult r = rt::render(s, {});
  ir::Vec3 d = camera_dir(s);
  double sin_t = std::sqrt(1 - d.z * d.z);
  for (int c = 0; c < 3; ++c) {
    Tree t{layers, sin_t, c, s.settings.max_depth, 1.0};
    double expect = t.camera();
    INFO("channel " << c << " angle " << std::asin(sin_t) * 180 / M_PI);
    CHECK(r.image.at(0, 0)[c] == Approx(expect).epsilon(tol));
  }
  CHECK(r.stats.nonfinite_samples == 0);
}

const ir::Vec3 kGlassAbsorb{0.1, 0.2, 0.3}, kWaterAbsorb{0.5, 0.05, 0.02};

}  // namespace

TEST_CASE("glass of water: overlapping slabs of priority 2 and 1 against the ray tree",
          "[runtime][interiors]") {
  // Glass (priority 2) from z = 0 to 2, water (priority 1) from 1 to 4: where they
  // overlap the glass wins, so the media are glass [0, 2] and water [2, 4]; the
  // water's face at z = 1 lies inside the glass and is passed straight through;
  // the glass-water interface at z = 2 refracts with 1.5 -> 1.33.
  const std::vector<Layer> media = {{0, 2, 1.5, kGlassAbsorb}, {2, 4, 1.33, kWaterAbsorb}};
  for (double angle : {0.0, 25.0, 55.0}) {
    ir::Scene s = stack_scene(angle);
    std::uint32_t glass = add_material(s, prioritised(1.5, kGlassAbsorb, 2));
    std::uint32_t water = add_material(s, prioritised(1.33, kWaterAbsorb, 1));
    s.shapes.push_back(slab(0, 2, glass));
    s.shapes.push_back(slab(1, 4, water));
    INFO("angle " << angle);
    check_against(s, media);
    // The file order does not matter: different priorities never tie.
    std::swap(s.shapes[0], s.shapes[1]);
    check_against(s, media);
    // Sensitivity: the core's rule (each surface air <-> ior) is another tree,
    // and the test tells them apart by far more than its tolerance.
    std::vector<Layer> core = {
        {0, 1, 1.5, kGlassAbsorb}, {1, 2, 1.0, {0, 0, 0}}, {2, 4, 1.33, kWaterAbsorb}};
    Tree a{media, std::sin(angle * M_PI / 180), 0, 10, 1}, b{core, a.s, 0, 10, 1};
    CHECK(std::fabs(a.camera() - b.camera()) > 1e-3 * a.camera());
  }
}

TEST_CASE("a surface inside a solid of higher priority is not there", "[runtime][interiors]") {
  // A glass sphere (priority 3) over a lit checker floor, with and without a water
  // sphere (priority 1) and an ior-2 sphere (priority 2) wholly inside it: every
  // pixel bit for bit the same, though the rays pass through the inner surfaces.
  auto scene = [](bool inner) {
    ir::Scene s = base_scene(48, 36, 2);
    s.background = ir::Vec3{0.6, 0.7, 0.9};
    s.settings.min_weight = 0;
    s.shapes.push_back(
        plane({0, 1, 0}, 0, add_material(s, checker({0.9, 0.9, 0.9}, {0.1, 0.2, 0.5}, 0.5))));
    s.point_lights.push_back({{-2, 5, -3}, {40, 40, 40}, {}});
    s.shapes.push_back(sphere({0, 1, 0}, 1, add_material(s, prioritised(1.5, {0.2, 0.1, 0}, 3))));
    if (inner) {
      s.shapes.push_back(
          sphere({0.2, 1, 0}, 0.5, add_material(s, prioritised(1.33, {1, 0, 0}, 1))));
      s.shapes.push_back(
          box({-0.5, 0.6, -0.3}, {0.1, 1.2, 0.3}, add_material(s, prioritised(2.0, {0, 0, 0}, 2))));
    }
    look(s, {0, 1.5, -4}, {0, 1, 0}, 45);
    return s;
  };
  rt::RenderResult a = rt::render(scene(false), {}), b = rt::render(scene(true), {});
  CHECK(a.stats.interior_passes == 0);
  CHECK(b.stats.interior_passes > 0);
  std::size_t differ = 0;
  for (std::size_t i = 0; i < a.image.rgb.size(); ++i)
    differ += !(a.image.rgb[i] == b.image.rgb[i]);
  CHECK(differ == 0);
  // ... and with the inner spheres outranking the glass they are seen.
  ir::Scene s = scene(true);
  s.materials[s.shapes[2].material] = prioritised(1.33, {1, 0, 0}, 4);
  rt::RenderResult c = rt::render(s, {});
  differ = 0;
  for (std::size_t i = 0; i < a.image.rgb.size(); ++i)
    differ += !(a.image.rgb[i] == c.image.rgb[i]);
  CHECK(differ > 100);
}

TEST_CASE("equal priorities: the solid entered last is the medium", "[runtime][interiors]") {
  // A (ior 1.5, red absorbs) from z = 0 to 2 and B (ior 1.2, clear) from 1 to 3,
  // both priority 1. A ray going +z enters A, then B: the overlap is B's, and A's
  // far face (inside B, entered last) passes. Going -z it enters B, then A: the
  // overlap is A's. max_depth 3 keeps exactly the straight path (three counting
  // interfaces; any reflection needs two more), so the pixel is its product.
  auto straight = [](const std::vector<Layer>& layers, double s, int c) {
    Tree t{layers, s, c, 3, 1.0};
    return t.camera();
  };
  const ir::Vec3 red{0.7, 0, 0};
  for (double angle : {0.0, 30.0}) {
    for (bool reverse : {false, true}) {
      ir::Scene s = stack_scene(angle);
      s.settings.max_depth = 3;
      std::uint32_t a = add_material(s, prioritised(1.5, red, 1));
      std::uint32_t b = add_material(s, prioritised(1.2, {0, 0, 0}, 1));
      // Reversed: the ray meets B first (A from 1 to 3, B from 0 to 2).
      s.shapes.push_back(reverse ? slab(1, 3, a) : slab(0, 2, a));
      s.shapes.push_back(reverse ? slab(0, 2, b) : slab(1, 3, b));
      std::vector<Layer> media = {{0, 1, 1.5, red}, {1, 3, 1.2, {0, 0, 0}}};
      if (reverse) media = {{0, 1, 1.2, {0, 0, 0}}, {1, 3, 1.5, red}};
      INFO("angle " << angle << (reverse ? " reverse" : ""));
      check_against(s, media);
      ir::Vec3 d = camera_dir(s);
      double sin_t = std::sqrt(1 - d.z * d.z);
      std::vector<Layer> other = reverse
                                     ? std::vector<Layer>{{0, 2, 1.2, {0, 0, 0}}, {2, 3, 1.5, red}}
                                     : std::vector<Layer>{{0, 2, 1.5, red}, {2, 3, 1.2, {0, 0, 0}}};
      // The other tie rule (first entered wins) gives a clearly different red.
      CHECK(std::fabs(straight(media, sin_t, 0) - straight(other, sin_t, 0)) > 0.1);
    }
  }
}

TEST_CASE("an air bubble of higher priority in water is the core's bubble",
          "[runtime][interiors]") {
  // The core writes a bubble as an interface of index 1/1.33 (tests/conformance/
  // bubble); §14 writes it as an air solid (ior 1, priority 2) inside water
  // (priority 1). The interfaces are the same up to the rounding of 1/(1/1.33)
  // against 1.33, so the images agree to float rounding.
  auto scene = [](bool nested) {
    ir::Scene s = base_scene(40, 30, 1);
    s.background = ir::Vec3{0.6, 0.7, 0.9};
    s.settings.min_weight = 0;
    look(s, {0, 1.2, -4}, {0, 0.6, 0}, 50);
    s.point_lights.push_back({{-2, 4, -3}, {40, 40, 40}, {}});
    s.shapes.push_back(plane({0, 1, 0}, 0, add_material(s, diffuse({0.6, 0.6, 0.6}))));
    if (nested) {
      s.shapes.push_back(sphere({0, 0.6, 0}, 0.6, add_material(s, prioritised(1.33, {}, 1))));
      s.shapes.push_back(sphere({0, 0.6, 0}, 0.3, add_material(s, prioritised(1.0, {}, 2))));
    } else {
      s.shapes.push_back(sphere({0, 0.6, 0}, 0.6, add_material(s, dielectric(1.33))));
      s.shapes.push_back(sphere({0, 0.6, 0}, 0.3, add_material(s, dielectric(1 / 1.33))));
    }
    return s;
  };
  rt::RenderResult core = rt::render(scene(false), {}), nested = rt::render(scene(true), {});
  double worst = 0;
  for (std::size_t i = 0; i < core.image.rgb.size(); ++i)
    worst = std::fmax(worst, std::fabs(core.image.rgb[i] - nested.image.rgb[i]) /
                                 std::fmax(1e-3, double(core.image.rgb[i])));
  CHECK(worst < 1e-4);
}

namespace {
// The scene of the two camera-inside tests: one pixel at the origin looking down
// +z through a tiny field, a white background, max_depth 3.
ir::Scene camera_inside_scene() {
  ir::Scene s = base_scene(1, 1, 1);
  s.background = ir::Vec3{1, 1, 1};
  s.settings.min_weight = 0;
  s.settings.max_depth = 3;
  look(s, {0, 0, 0}, {0, 0, 1}, 1e-3);
  return s;
}
// Their pixel: the two paths the first test's comment derives.
void check_camera_inside(const rt::RenderResult& r) {
  auto R = [](double a, double b) { return rt::fresnel_exact(rt::make_interface(1, b / a)); };
  double straight = (1 - R(1.33, 1.5)) * (1 - R(1.5, 1.33)) * (1 - R(1.33, 1));
  double back = R(1.33, 1.5) * (1 - R(1.33, 1));
  for (int c = 0; c < 3; ++c) {
    double sigma = kWaterAbsorb[c];
    double expect = std::exp(-sigma * 8) * straight + std::exp(-sigma * 14) * back;
    CHECK(r.image.at(0, 0)[c] == Approx(expect).epsilon(2e-5));
  }
}
}  // namespace

TEST_CASE("a camera inside a prioritised solid starts in its medium", "[runtime][interiors]") {
  // The camera sits inside an absorbing water sphere (priority 1, radius 10) and
  // looks through a clear glass sphere (priority 2, radius 1, 3 ahead). The centre
  // ray meets every surface head on: 2 of water, glass, 6 of water, then out into
  // the white background. max_depth 3 keeps two paths: the straight one,
  // exp(-σ·8) · T(1.33→1.5) T(1.5→1.33) T(1.33→1), and the reflection off the glass
  // back through 2 + 12 of water and out behind the camera, exp(-σ·14) · R(1.33→1.5)
  // T(1.33→1); every other path needs a fourth interaction. Starting in air
  // instead would make the first interface 1 -> 1.5 and drop the first 2 of water.
  ir::Scene s = camera_inside_scene();
  s.shapes.push_back(sphere({0, 0, 0}, 10, add_material(s, prioritised(1.33, kWaterAbsorb, 1))));
  s.shapes.push_back(sphere({0, 0, 3}, 1, add_material(s, prioritised(1.5, {}, 2))));
  rt::Interiors in(s);
  REQUIRE(in.camera().count == 1);
  CHECK(in.camera().medium() == 0);
  check_camera_inside(rt::render(s, {}));
}

TEST_CASE("each part of an instance is a prioritised solid of its own", "[runtime][interiors]") {
  // The camera-inside scene above as one object value placed twice (§13): its
  // parts are the water (no material: the instance's) and the glass sphere. The
  // instance at the origin holds the camera; the other, 100 away, is a second
  // glass of water that nothing sees. The analytic tree is the same, so every
  // part must be tracked as its own solid with its own medium: taken as one solid
  // (the instance, with its material) the glass would be water too, and its
  // surfaces would not count.
  ir::Scene s = camera_inside_scene();
  const std::uint32_t water = add_material(s, prioritised(1.33, kWaterAbsorb, 1));
  s.parts.push_back(sphere({0, 0, 0}, 10, ir::kInheritMaterial));
  s.parts.push_back(sphere({0, 0, 3}, 1, add_material(s, prioritised(1.5, {}, 2))));
  ir::Prototype proto;
  proto.parts = {0, 1};
  proto.lo = {-10, -10, -10}, proto.hi = {10, 10, 10};
  s.prototypes.push_back(proto);
  for (double x : {0.0, 100.0}) {
    ir::Shape inst;
    inst.geom = ir::Instance{0};
    inst.material = water;
    inst.set_world_from_object(ir::Transform::translate({x, 0, 0}));
    s.shapes.push_back(inst);
  }
  rt::Interiors in(s);
  REQUIRE(in.camera().count == 1);
  const std::uint32_t camera_solid = in.camera().medium();
  CHECK(camera_solid >= s.shapes.size());  // an instance's part, not a shape
  CHECK(in.priority(camera_solid) == 1);
  CHECK(in.ior(camera_solid) == 1.33);
  // Both instances' water and glass: four solids.
  CHECK(in.to_string().find("4 prioritised solid(s)") != std::string::npos);
  check_camera_inside(rt::render(s, {}));
}

TEST_CASE("interior stack: medium, ties, overflow and unknown exits", "[runtime][interiors]") {
  ir::Scene s = base_scene(1, 1, 1);
  for (std::uint64_t p : {1, 3, 3, 2, 1, 1, 1, 1, 1, 5})
    s.shapes.push_back(sphere({0, 0, 100}, 1, add_material(s, prioritised(1 + p / 10.0, {}, p))));
  rt::Interiors in(s);
  CHECK(in.camera().empty());
  rt::Interior st;
  auto enter = [&](std::uint32_t shape) {
    rt::Crossing c = in.cross(st, shape, true);
    st = c.after;
    return c;
  };
  CHECK(enter(0).counts);   // air -> #0
  CHECK(enter(1).counts);   // #0 -> #1 (priority 3)
  CHECK(!enter(3).counts);  // priority 2 inside 3: passes
  CHECK(enter(2).counts);   // priority 3 again: entered last wins
  CHECK(st.medium() == 2);
  rt::Crossing out1 = in.cross(st, 1, false);  // leaving #1 inside #2 (equal, later): passes
  CHECK(!out1.counts);
  rt::Crossing out2 = in.cross(st, 2, false);  // leaving #2: the medium falls back to #1
  CHECK(out2.counts);
  CHECK(out2.to == 1);
  // Fill the stack past kMax: the lowest priority, earliest, entries go first.
  for (std::uint32_t k = 4; k < 8; ++k) enter(k);
  CHECK(st.count == rt::Interior::kMax);
  rt::Crossing full = in.cross(st, 9, true);  // priority 5 pushes out #0 (priority 1, oldest)
  CHECK(full.overflow);
  CHECK(full.after.find(0) < 0);
  CHECK(full.after.medium() == 9);
  // Leaving a solid with no entry counts when it outranks the medium (a camera
  // inside a solid it did not detect): as if entered first.
  rt::Interior empty;
  rt::Crossing lost = in.cross(empty, 9, false);
  CHECK(lost.counts);
  CHECK(lost.from == 9);
  CHECK(lost.to == rt::Interior::kAir);
  CHECK(rt::to_string(full.after).find("medium #9") != std::string::npos);
}

TEST_CASE("a scene without priorities renders bit for bit as without interiors",
          "[runtime][interiors]") {
  // The general kernel (--features=all) compiles the interior code in; with no
  // priority in the scene it must change nothing: the specialised kernel (which
  // does not have it) and the general one agree on every bit.
  ir::Scene s = base_scene(40, 30, 2);
  s.background = ir::Vec3{0.6, 0.7, 0.9};
  look(s, {0, 1.5, -4}, {0, 1, 0}, 45);
  s.point_lights.push_back({{-2, 5, -3}, {40, 40, 40}, {}});
  s.shapes.push_back(plane({0, 1, 0}, 0, add_material(s, diffuse({0.6, 0.6, 0.6}))));
  s.shapes.push_back(sphere({0, 1, 0}, 1, add_material(s, dielectric(1.5, {0.2, 0.1, 0}))));
  s.shapes.push_back(sphere({0.3, 1, 0}, 0.4, add_material(s, dielectric(1.33, {0, 0.5, 1}))));
  rt::RenderOptions general;
  general.general_kernel = true;
  rt::RenderResult a = rt::render(s, {}), b = rt::render(s, general);
  REQUIRE(a.stats.kernel != b.stats.kernel);
  std::size_t differ = 0;
  for (std::size_t i = 0; i < a.image.rgb.size(); ++i)
    differ += !(a.image.rgb[i] == b.image.rgb[i]);
  CHECK(differ == 0);
  CHECK(b.stats.interior_passes == 0);
}
