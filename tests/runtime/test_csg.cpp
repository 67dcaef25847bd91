// §12 CSG and §13 instances through the scene query (rt::EmbreeScene, as the
// integrator sees them), against analytic answers: a lens (the intersection of
// two spheres) hit where its spheres' formulas say, with normals out of the
// result, and refracting through it like the analytic ray tree; a difference's
// removed surfaces facing into the removed region; merge hiding the inner
// surfaces that union keeps; coincident faces decided one way for the whole
// face even when their transforms round differently; per-leaf materials; and
// instances sharing one prototype (a test that fails if geometry is copied per
// instance). t is compared to 2e-6 relative (a float t is good to an ulp, 6e-8),
// normals to 1e-6.
#include <catch2/catch.hpp>
#include <cmath>
#include <functional>
#include <random>

#include "runtime/embree_scene.hpp"
#include "runtime/geometry/csg.hpp"
#include "runtime/ir/mesh_topology.hpp"
#include "tests/runtime/effects_util.hpp"

using namespace snell;
using namespace snell::test;
using ir::Vec3;

namespace {

rt::Vec3f f(Vec3 v) {
  return rt::to_float(v.x, v.y, v.z);
}

// Builds CSG trees in a scene: leaves are parts, operations nodes.
struct Csg {
  ir::Scene& sc;
  std::uint32_t leaf(ir::ShapeGeom g, ir::Transform xf = {}, std::uint32_t material = 0) {
    ir::Shape p;
    p.geom = g;
    p.set_world_from_object(xf);
    p.material = material;
    sc.parts.push_back(p);
    ir::CsgNode n;
    n.part = static_cast<std::uint32_t>(sc.parts.size() - 1);
    sc.csg_nodes.push_back(n);
    return static_cast<std::uint32_t>(sc.csg_nodes.size() - 1);
  }
  std::uint32_t op(ir::CsgOp o, std::vector<std::uint32_t> children) {
    ir::CsgNode n;
    n.op = o;
    n.children = std::move(children);
    sc.csg_nodes.push_back(n);
    return static_cast<std::uint32_t>(sc.csg_nodes.size() - 1);
  }
  void place(std::uint32_t root, ir::Transform xf = {}, std::uint32_t material = 0) {
    ir::Shape s;
    s.geom = ir::Csg{root};
    s.set_world_from_object(xf);
    s.material = material;
    sc.shapes.push_back(s);
  }
};

ir::Sphere sphere(Vec3 c, double r) {
  ir::Sphere s;
  s.center = c, s.radius = r;
  return s;
}
ir::Box box(Vec3 lo, Vec3 hi) {
  ir::Box b;
  b.min = lo, b.max = hi;
  return b;
}

struct Query {
  ir::Scene scene = base_scene(1, 1);
  std::unique_ptr<rt::EmbreeScene> es;
  void build() {
    REQUIRE(ir::validate(scene).empty());
    es = std::make_unique<rt::EmbreeScene>(scene, Vec3{0, 0, 0});
  }
  bool cast(Vec3 o, Vec3 d, rt::Hit& h) const {
    return es->intersect(rt::Ray{f(o), rt::normalize(f(d)), INFINITY, 0}, h);
  }
  // Every boundary crossing along a line, by re-casting from just past each hit.
  int crossings(Vec3 o, Vec3 d) const {
    int n = 0;
    rt::Ray r{f(o), rt::normalize(f(d)), INFINITY, 0};
    rt::Hit h;
    while (n < 32 && es->intersect(r, h)) {
      ++n;
      r.org = rt::spawn_origin(h, r.dir, 1);
    }
    return n;
  }
};

// The near and far roots of the unit ray from o along d against a sphere.
void roots(Vec3 o, Vec3 d, Vec3 c, double r, double& t0, double& t1) {
  Vec3 oc = o - c;
  double b = ir::dot(oc, d), cc = ir::dot(oc, oc) - r * r;
  double disc = std::sqrt(b * b - cc);
  t0 = -b - disc, t1 = -b + disc;
}

}  // namespace

TEST_CASE("csg: a lens is hit on its two spherical caps, normals out of the result", "[csg]") {
  // Spheres of radius 2 at z = ±1.6: the lens is |z| <= 0.4, radius 1.2 at z = 0.
  Query q;
  Csg c{q.scene};
  Vec3 ca{0, 0, 1.6}, cb{0, 0, -1.6};
  c.place(c.op(ir::CsgOp::Intersection, {c.leaf(sphere(ca, 2)), c.leaf(sphere(cb, 2))}));
  q.build();
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  int hits = 0;
  for (int i = 0; i < 500; ++i) {
    Vec3 o{u(rng) * 1.3, u(rng) * 1.3, -5};
    Vec3 d = ir::normalize(Vec3{0.1 * u(rng), 0.1 * u(rng), 1});
    rt::Hit h;
    bool hit = q.cast(o, d, h);
    // Entering the lens: through the far sphere's near cap (centre +1.6), into
    // the near sphere; analytically the later of the two entries if inside both.
    double a0, a1, b0, b1;
    roots(o, d, ca, 2, a0, a1);
    roots(o, d, cb, 2, b0, b1);
    bool expect = std::isfinite(a0) && std::isfinite(b0) && std::fmax(a0, b0) < std::fmin(a1, b1);
    REQUIRE(hit == expect);
    if (!hit) continue;
    ++hits;
    double t = std::fmax(a0, b0);
    CHECK(double(h.t) == Approx(t).epsilon(2e-6));
    Vec3 p = o + d * t;
    Vec3 n = ir::normalize(p - (a0 > b0 ? ca : cb));
    CHECK(double(h.ng.x) == Approx(n.x).margin(1e-6));
    CHECK(double(h.ng.y) == Approx(n.y).margin(1e-6));
    CHECK(double(h.ng.z) == Approx(n.z).margin(1e-6));
    CHECK(ir::dot(Vec3(h.ng.x, h.ng.y, h.ng.z), d) < 0);  // entering: against the ray
  }
  CHECK(hits > 150);
}

TEST_CASE("csg: a ray refracts through a lens as through its two analytic spheres", "[csg]") {
  // Glass 1.5: the path through the CSG lens, built from the scene query's hits
  // and normals, matches the path computed from the sphere formulas alone.
  Query q;
  Csg c{q.scene};
  Vec3 ca{0, 0, 1.6}, cb{0, 0, -1.6};
  c.place(c.op(ir::CsgOp::Intersection, {c.leaf(sphere(ca, 2)), c.leaf(sphere(cb, 2))}));
  q.build();
  auto refract = [](Vec3 d, Vec3 n, double eta) {  // n against d, eta = n1 / n2
    double ci = -ir::dot(n, d);
    double k = 1 - eta * eta * (1 - ci * ci);
    return ir::normalize(d * eta + n * (eta * ci - std::sqrt(k)));
  };
  for (double y : {0.0, 0.2, 0.5, 0.8, 1.0}) {
    Vec3 o{0, y, -5}, d{0, 0, 1};
    // Analytic: enter the sphere centred at +1.6 (its near cap), leave through the
    // sphere centred at -1.6 (its far cap).
    double a0, a1, b0, b1;
    roots(o, d, ca, 2, a0, a1);
    Vec3 p1 = o + d * a0;
    Vec3 d1 = refract(d, ir::normalize(p1 - ca), 1 / 1.5);
    roots(p1, d1, cb, 2, b0, b1);
    Vec3 p2 = p1 + d1 * b1;
    Vec3 d2 = refract(d1, -ir::normalize(p2 - cb), 1.5);
    // Through the scene query.
    rt::Hit h1, h2;
    REQUIRE(q.cast(o, d, h1));
    Vec3 n1(h1.ng.x, h1.ng.y, h1.ng.z);
    Vec3 e1 = refract(d, n1, 1 / 1.5);
    rt::Ray inner{rt::spawn_origin(h1, -h1.ng, 1), f(e1), INFINITY, 0};
    REQUIRE(q.es->intersect(inner, h2));
    Vec3 n2(h2.ng.x, h2.ng.y, h2.ng.z);
    CHECK(ir::dot(n2, e1) > 0);  // leaving: the outward normal along the ray
    Vec3 e2 = refract(e1, -n2, 1.5);
    INFO("y " << y);
    CHECK(double(h2.p.x) == Approx(p2.x).margin(2e-6));
    CHECK(double(h2.p.y) == Approx(p2.y).margin(2e-6));
    CHECK(double(h2.p.z) == Approx(p2.z).margin(2e-6));
    CHECK(e2.y == Approx(d2.y).margin(2e-6));
    CHECK(e2.z == Approx(d2.z).margin(2e-6));
  }
}

TEST_CASE("csg: a difference's removed surfaces face into the removed region", "[csg]") {
  // A unit box minus a sphere of radius 0.5 at its top face's centre: a ray down
  // the middle enters the bowl's surface, whose normal points to the centre.
  Query q;
  Csg c{q.scene};
  c.place(c.op(ir::CsgOp::Difference,
               {c.leaf(box({-1, -1, -1}, {1, 1, 1})), c.leaf(sphere({0, 1, 0}, 0.5), {}, 0)}));
  q.build();
  for (double x : {0.0, 0.2, -0.3}) {
    rt::Hit h;
    REQUIRE(q.cast({x, 5, 0}, {0, -1, 0}, h));
    double y = 1 - std::sqrt(0.25 - x * x);
    CHECK(double(h.t) == Approx(5 - y).epsilon(2e-6));
    Vec3 n = ir::normalize(Vec3{0, 1, 0} - Vec3{x, y, 0});  // towards the sphere's centre
    CHECK(double(h.ng.x) == Approx(n.x).margin(1e-6));
    CHECK(double(h.ng.y) == Approx(n.y).margin(1e-6));
  }
  rt::Hit h;  // beside the bowl: the box's top face
  REQUIRE(q.cast({0.8, 5, 0}, {0, -1, 0}, h));
  CHECK(double(h.t) == Approx(4).epsilon(2e-6));
  CHECK(double(h.ng.y) == Approx(1).margin(1e-6));
  // Through the whole: bowl in, bottom out.
  CHECK(q.crossings({0, 5, 0}, {0, -1, 0}) == 2);
}

TEST_CASE("csg: merge hides the surfaces inside another child, union keeps them", "[csg]") {
  Query qm, qu;
  Csg m{qm.scene};
  m.place(
      m.op(ir::CsgOp::Merge, {m.leaf(sphere({-0.5, 0, 0}, 1)), m.leaf(sphere({0.5, 0, 0}, 1))}));
  qm.build();
  // The union of the compiler is its children placed one by one.
  for (double x : {-0.5, 0.5}) {
    ir::Shape s;
    s.geom = sphere({x, 0, 0}, 1);
    qu.scene.shapes.push_back(s);
  }
  qu.build();
  CHECK(qm.crossings({-5, 0, 0}, {1, 0, 0}) == 2);
  CHECK(qu.crossings({-5, 0, 0}, {1, 0, 0}) == 4);
  CHECK(qm.crossings({-5, 0.3, 0}, {1, 0, 0}) == 2);
}

TEST_CASE("csg: coincident faces are decided one way for the whole face", "[csg]") {
  // A box minus a box sharing its top, bottom, front and back faces; the second
  // box is placed through rotations that round (90° about y four times), so its
  // faces differ from the first's by ulps in a pattern over the face. The shared
  // part of the top face is removed everywhere (FIRST ∩ not REST is empty there),
  // the rest of it present everywhere: no speckle.
  Query q;
  Csg c{q.scene};
  ir::Transform spin = ir::Transform::rotate_xyz({0, 90, 0});
  ir::Transform round_trip = spin * spin * spin * spin;
  c.place(c.op(ir::CsgOp::Difference, {c.leaf(box({0, 0, 0}, {1, 1, 1})),
                                       c.leaf(box({0.5, 0, 0}, {1.5, 1, 1}), round_trip)}));
  q.build();
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.001, 0.999);
  int wrong = 0;
  for (int i = 0; i < 4000; ++i) {
    double x = u(rng), z = u(rng);
    if (std::fabs(x - 0.5) < 1e-3) continue;
    rt::Hit h;
    bool hit = q.cast({x, 3, z}, {0, -1, 0}, h);
    bool expect = x < 0.5;
    if (hit != expect || (hit && std::fabs(h.t - 2) > 1e-5)) ++wrong;
  }
  CHECK(wrong == 0);
}

TEST_CASE("csg: each surface keeps the material of the child it comes from", "[csg]") {
  Query q;
  q.scene.materials.resize(3);
  Csg c{q.scene};
  c.place(c.op(ir::CsgOp::Difference, {c.leaf(box({-1, -1, -1}, {1, 1, 1}), {}, 1),
                                       c.leaf(sphere({0, 1, 0}, 0.5), {}, 2)}),
          {}, 0);
  q.build();
  rt::Hit h;
  REQUIRE(q.cast({0, 5, 0}, {0, -1, 0}, h));
  CHECK(h.material == 2);
  REQUIRE(q.cast({0.8, 5, 0}, {0, -1, 0}, h));
  CHECK(h.material == 1);
}

TEST_CASE("csg: a plane's half-space bounds an otherwise open CSG object", "[csg]") {
  // A sphere cut by the half-space y < 0.25: a hemisphere-like cap, unbounded
  // child, bounded result; and a plane minus a sphere (unbounded result).
  Query q;
  Csg c{q.scene};
  ir::Plane p;
  p.normal = {0, 1, 0}, p.distance = 0.25;
  c.place(c.op(ir::CsgOp::Intersection, {c.leaf(sphere({0, 0, 0}, 1)), c.leaf(p)}));
  ir::Plane floor;
  floor.normal = {0, 1, 0}, floor.distance = -2;
  c.place(c.op(ir::CsgOp::Difference, {c.leaf(floor), c.leaf(sphere({5, -2, 0}, 1))}));
  q.build();
  rt::Hit h;
  REQUIRE(q.cast({0, 5, 0}, {0, -1, 0}, h));
  CHECK(double(h.t) == Approx(4.75).epsilon(2e-6));  // the cut face
  CHECK(double(h.ng.y) == Approx(1).margin(1e-6));
  REQUIRE(q.cast({5, 5, 0}, {0, -1, 0}, h));  // into the pit in the floor
  CHECK(double(h.t) == Approx(8).epsilon(2e-6));
  REQUIRE(q.cast({300, 5, 0}, {0, -1, 0}, h));  // the floor far away
  CHECK(double(h.t) == Approx(7).epsilon(2e-6));
}

TEST_CASE("instances: one prototype shared by every instance, placed by each", "[csg]") {
  Query q;
  ir::Shape part;
  part.geom = box({-0.5, -0.5, -0.5}, {0.5, 0.5, 0.5});
  part.material = ir::kInheritMaterial;
  q.scene.parts.push_back(part);
  ir::Prototype proto;
  proto.parts = {0};
  proto.lo = {-0.5, -0.5, -0.5}, proto.hi = {0.5, 0.5, 0.5};
  q.scene.prototypes.push_back(proto);
  q.scene.materials.resize(40);
  for (int i = 0; i < 40; ++i) {
    ir::Shape s;
    s.geom = ir::Instance{0};
    s.material = static_cast<std::uint32_t>(i);
    s.set_world_from_object(ir::Transform::translate({10.0 * i, 0, 0}) *
                            ir::Transform::rotate_xyz({0, 0, 9.0 * i}) *
                            ir::Transform::scale({1 + 0.1 * i, 1, 1}));
    q.scene.shapes.push_back(s);
  }
  q.build();
  // The geometry exists once: the world BVH holds no triangles of its own.
  std::string text = q.es->to_string();
  CHECK_THAT(text, Catch::Contains("triangles 0 "));
  CHECK_THAT(text, Catch::Contains("instances 40 prototypes 1"));
  for (int i = 0; i < 40; ++i) {
    // Down onto each box's top: its top face, rotated about z by 9i degrees.
    ir::Transform xf = q.scene.shapes[i].world_from_object();
    Vec3 top = xf.point({0, 0.5, 0});
    Vec3 n = ir::normalize(xf.normal({0, 1, 0}));
    rt::Hit h;
    Vec3 o = top + n * 4.0;
    REQUIRE(q.cast(o, -n, h));
    INFO("instance " << i);
    // Embree carries the ray into the instance in float: t and p are good to a few
    // ulps of the origin's coordinates (up to 400 here), not of t.
    double ulps4 = 4 * 0x1p-23 * (std::fabs(o.x) + std::fabs(o.y) + 1);
    CHECK(double(h.t) == Approx(4).margin(ulps4));
    CHECK(double(h.ng.x) == Approx(n.x).margin(1e-6));
    CHECK(double(h.ng.y) == Approx(n.y).margin(1e-6));
    CHECK(h.index == static_cast<std::uint32_t>(i));
    CHECK(h.material == static_cast<std::uint32_t>(i));  // the part inherits
    CHECK(double(h.p.x) == Approx(top.x).margin(ulps4));
    CHECK(double(h.p.y) == Approx(top.y).margin(ulps4));
  }
}

namespace {
// The cube [-1, 1]³ as a closed OBJ-like mesh: 8 shared corners, 12 triangles
// wound outward.
ir::MeshData cube_mesh() {
  ir::MeshData m;
  m.path = "cube";
  for (int i = 0; i < 8; ++i)
    m.positions.push_back({i & 1 ? 1.0 : -1.0, i & 2 ? 1.0 : -1.0, i & 4 ? 1.0 : -1.0});
  const int quads[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  for (const auto& q : quads)
    for (int k : {q[0], q[1], q[2], q[0], q[2], q[3]}) m.indices.push_back(std::uint32_t(k));
  ir::MeshClosure c = ir::mesh_closure(m);
  m.closed = c.closed;
  return m;
}
}  // namespace

TEST_CASE("csg: a closed mesh is a solid, answering as the box it bounds", "[csg]") {
  // The same difference twice — a cube minus a sphere at its corner — with the
  // cube as a box and as a mesh, turned and mirrored alike: every ray finds the
  // same t (2e-6), normal (1e-6) and number of crossings, corners and edges
  // included (a ray through a shared edge crosses once, not twice).
  ir::Transform xf = ir::Transform::rotate_y(30) * ir::Transform::scale({-1, 1, 1});
  Query qb, qm;
  Csg cb{qb.scene}, cm{qm.scene};
  cb.place(cb.op(ir::CsgOp::Difference,
                 {cb.leaf(box({-1, -1, -1}, {1, 1, 1}), xf), cb.leaf(sphere({1, 1, -1}, 0.8))}));
  qm.scene.meshes.push_back(cube_mesh());
  REQUIRE(qm.scene.meshes[0].closed);
  cm.place(
      cm.op(ir::CsgOp::Difference, {cm.leaf(ir::Mesh{0}, xf), cm.leaf(sphere({1, 1, -1}, 0.8))}));
  qb.build();
  qm.build();
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  int hits = 0;
  std::vector<std::pair<Vec3, Vec3>> rays;
  for (int i = 0; i < 400; ++i) rays.push_back({Vec3{u(rng), u(rng), -6}, Vec3{0, 0, 1}});
  for (int i = 0; i < 100; ++i)
    rays.push_back({Vec3{u(rng), 6, u(rng)}, ir::normalize(Vec3{u(rng) * 0.3, -1, u(rng) * 0.3})});
  // Through corners and along an edge's line of the turned cube.
  for (int i = 0; i < 8; ++i) {
    Vec3 corner = xf.point({i & 1 ? 1.0 : -1.0, i & 2 ? 1.0 : -1.0, i & 4 ? 1.0 : -1.0});
    rays.push_back({corner * 4, ir::normalize(corner * -1)});
  }
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const auto& [o, d] = rays[i];
    bool corner = i >= 500;  // three faces meet: either may own the normal
    rt::Hit hb, hm;
    bool fb = qb.cast(o, d, hb), fm = qm.cast(o, d, hm);
    INFO("ray from " << o.x << "," << o.y << "," << o.z);
    REQUIRE(fb == fm);
    CHECK(qb.crossings(o, d) == qm.crossings(o, d));
    if (!fb) continue;
    ++hits;
    CHECK(double(hm.t) == Approx(double(hb.t)).epsilon(2e-6));
    if (corner) continue;
    CHECK(double(hm.ng.x) == Approx(double(hb.ng.x)).margin(1e-6));
    CHECK(double(hm.ng.y) == Approx(double(hb.ng.y)).margin(1e-6));
    CHECK(double(hm.ng.z) == Approx(double(hb.ng.z)).margin(1e-6));
  }
  CHECK(hits > 200);
}

TEST_CASE("csg: a mirror lens reflects once, out of the result", "[csg][scene]") {
  // A convex mirror (the lens, tinted 0.5) under a white sky: every ray that meets
  // it reflects once and escapes (a convex surface never sees itself), so each
  // pixel is 1 or 0.5 exactly (edges: a multiple of 1/8 of 4 samples), with both
  // kernels. A reflected ray started on the wrong side of the leaf it hit (its
  // offset or side from the CSG normal) would stay inside and reflect again off
  // the far cap (0.25, or black at max_depth).
  ir::Scene s = base_scene(48, 36, 4);
  s.background = ir::Vec3{1, 1, 1};
  s.settings.max_depth = 8;
  std::uint32_t m = add_material(s, mirror({0.5, 0.5, 0.5}));
  Csg c{s};
  c.place(c.op(ir::CsgOp::Intersection,
               {c.leaf(sphere({0, 0, 0.6}, 1), {}, m), c.leaf(sphere({0, 0, -0.6}, 1), {}, m)}),
          ir::Transform::rotate_y(25) * ir::Transform::rotate_x(-20), m);
  look(s, {0, 0, -4}, {0, 0, 0}, 30);
  for (bool general : {false, true}) {
    rt::RenderResult r = render_with(s, 1, general);
    int lens = 0, other = 0;
    for (std::uint32_t y = 0; y < 36; ++y)
      for (std::uint32_t x = 0; x < 48; ++x) {
        float v = r.image.at(x, y)[0];
        // Edge pixels average lens and sky samples: 0.5 + k/8 for k of 4 samples.
        bool ok = std::fabs(v * 8 - std::round(v * 8)) < 1e-4 && v >= 0.5f - 1e-5f;
        if (std::fabs(v - 0.5f) < 1e-5f) ++lens;
        if (!ok) ++other;
      }
    INFO("general kernel " << general);
    CHECK(lens > 200);
    CHECK(other == 0);
  }
}

namespace {

// Whether p is inside the result of CSG node `n` (spheres only, no transforms),
// straight from §12's definitions: the reference for the trees below.
bool member(const ir::Scene& sc, std::uint32_t n, Vec3 p) {
  const ir::CsgNode& node = sc.csg_nodes[n];
  if (node.leaf()) {
    const auto& s = std::get<ir::Sphere>(sc.parts[node.part].geom);
    Vec3 v = p - s.center;
    return ir::dot(v, v) < s.radius * s.radius;
  }
  bool first = member(sc, node.children[0], p);
  if (node.op == ir::CsgOp::Difference) {
    for (std::size_t i = 1; first && i < node.children.size(); ++i)
      first = !member(sc, node.children[i], p);
    return first;
  }
  bool all = first, any = first;
  for (std::size_t i = 1; i < node.children.size(); ++i) {
    bool m = member(sc, node.children[i], p);
    all = all && m, any = any || m;
  }
  return node.op == ir::CsgOp::Intersection ? all : any;
}

}  // namespace

TEST_CASE("csg: a box with 900 holes is hit where each hole says", "[csg]") {
  // The leaves' BVH must find the one hole a ray meets among 900: a vertical ray
  // meets the box's top at y = 0 unless it passes within r of a hole's centre,
  // where it goes down the hole to the sphere's lower half.
  ir::Scene sc = base_scene(1, 1);
  Csg g{sc};
  const int n = 30;
  const double r = 0.35;
  std::vector<std::uint32_t> kids{g.leaf(box({-16, -1, -16}, {16, 0, 16}))};
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) kids.push_back(g.leaf(sphere({i - 14.5, 0, j - 14.5}, r)));
  std::uint32_t root = g.op(ir::CsgOp::Difference, kids);
  rt::geom::CsgProgram prog(sc, root);
  CHECK(prog.leaf_count() == 901);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-15, 15);
  int holes = 0;
  for (int k = 0; k < 3000; ++k) {
    double x = u(rng), z = u(rng);
    double cx = std::floor(x + 15) - 14.5, cz = std::floor(z + 15) - 14.5;
    double rho2 = (x - cx) * (x - cx) + (z - cz) * (z - cz);
    double t, expect_t = 5;
    Vec3 nrm;
    std::uint32_t leaf = ~0u;
    REQUIRE(prog.intersect({x, 5, z}, {0, -1, 0}, 0, INFINITY, t, nrm, leaf));
    if (rho2 < r * r) {
      ++holes;
      expect_t = 5 + std::sqrt(r * r - rho2);
      std::uint32_t hole = 1 + std::uint32_t((cx + 14.5) * n + (cz + 14.5));
      CHECK(leaf == hole);
    } else {
      CHECK(leaf == 0);
    }
    CHECK(t == Approx(expect_t).epsilon(1e-9));
    CHECK(nrm.y > 0);  // out of the result: up, at the top and at a hole's floor
  }
  CHECK(holes > 300);  // the holes cover 38 % of the top
}

TEST_CASE("csg: random trees are hit where their inside test changes first", "[csg]") {
  // Trees of merges, intersections and differences, five levels of up to four
  // operands over spheres: along random rays the hit must be the first t where
  // §12's membership (member() above) changes. Samples every 0.01 before the hit
  // must agree with the start; points 1e-7 either side of it must differ.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  int hits = 0;
  for (int tree = 0; tree < 20; ++tree) {
    ir::Scene sc = base_scene(1, 1);
    Csg g{sc};
    std::function<std::uint32_t(int)> make = [&](int depth) -> std::uint32_t {
      if (depth == 0 || rng() % 5 == 0)
        return g.leaf(sphere({2 * u(rng), 2 * u(rng), 2 * u(rng)}, 0.4 + 0.8 * (u(rng) + 1)));
      std::vector<std::uint32_t> kids;
      for (int i = 0, k = 2 + int(rng() % 3); i < k; ++i) kids.push_back(make(depth - 1));
      const ir::CsgOp ops[] = {ir::CsgOp::Merge, ir::CsgOp::Intersection, ir::CsgOp::Difference};
      return g.op(ops[rng() % 3], kids);
    };
    std::uint32_t root = make(5);
    rt::geom::CsgProgram prog(sc, root);
    for (int k = 0; k < 200; ++k) {
      Vec3 o{6 * u(rng), 6 * u(rng), 6 * u(rng)};
      Vec3 d = ir::normalize(Vec3{u(rng), u(rng), u(rng)} - o * 0.1);
      double t = 0, tmax = 20;
      Vec3 nrm;
      std::uint32_t leaf;
      bool hit = prog.intersect(o, d, 1e-9, tmax, t, nrm, leaf);
      bool start = member(sc, root, o + d * 1e-6);
      double end = hit ? t - 1e-7 : tmax;
      for (double s = 0.01; s < end; s += 0.01) {
        INFO("tree " << tree << " ray " << k << " sample " << s << " hit " << hit << " at " << t);
        REQUIRE(member(sc, root, o + d * s) == start);
      }
      if (!hit) continue;
      ++hits;
      INFO("tree " << tree << " ray " << k << " t " << t);
      CHECK(member(sc, root, o + d * (t - 1e-7)) != member(sc, root, o + d * (t + 1e-7)));
    }
  }
  CHECK(hits > 200);
}
