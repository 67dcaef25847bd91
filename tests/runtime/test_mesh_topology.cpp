// ir::mesh_closure: the definition of a closed mesh (ir/mesh_topology.hpp) on meshes
// built by hand, one rule each, and has_inside / no_inside_reason for mesh shapes.
#include <catch2/catch.hpp>
#include <string>

#include "runtime/geometry/intervals.hpp"
#include "runtime/ir/mesh_topology.hpp"

using namespace snell;

namespace {

// The unit cube, outward, as 12 triangles over 8 shared vertices (1-based in the
// reasons: v1 = (0,0,0) ... v8 = (1,1,1), bit i of (k-1) = coordinate i).
ir::MeshData cube() {
  ir::MeshData m;
  m.path = "cube";
  for (int i = 0; i < 8; ++i)
    m.positions.push_back({double(i & 1), double(i >> 1 & 1), double(i >> 2 & 1)});
  // Each face's corners counter-clockwise seen from outside.
  const std::uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                     {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads)
    m.indices.insert(m.indices.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
  return m;
}

// The same cube with every face's four corners its own vertices (as OBJ exporters
// write meshes with per-face normals or UVs): 24 vertices, welding makes it closed.
ir::MeshData unwelded_cube() {
  ir::MeshData c = cube(), m;
  m.path = "unwelded";
  for (std::size_t t = 0; t < c.indices.size(); t += 6) {
    std::uint32_t base = std::uint32_t(m.positions.size());
    for (std::uint32_t k : {0u, 1u, 2u, 5u}) m.positions.push_back(c.positions[c.indices[t + k]]);
    m.indices.insert(m.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
  }
  return m;
}

}  // namespace

TEST_CASE("a shared-vertex cube is closed, so is one whose faces repeat their vertices",
          "[mesh][topology]") {
  ir::MeshClosure c = ir::mesh_closure(cube());
  CHECK(c.closed);
  CHECK(c.reason.empty());
  ir::MeshData u = unwelded_cube();
  REQUIRE(u.positions.size() == 24);
  CHECK(ir::mesh_closure(u).closed);
}

TEST_CASE("welding treats -0 and +0 as one position", "[mesh][topology]") {
  ir::MeshData m = unwelded_cube();
  for (ir::Vec3& p : m.positions)
    if (p.x == 0 && (&p - m.positions.data()) % 2 == 0) p.x = -0.0;
  CHECK(ir::mesh_closure(m).closed);
}

TEST_CASE("a cube without its top has 4 boundary edges", "[mesh][topology]") {
  ir::MeshData m = cube();
  m.indices.erase(m.indices.begin() + 18, m.indices.begin() + 24);  // face {2, 6, 7, 3}: y = 1
  ir::MeshClosure c = ir::mesh_closure(m);
  CHECK_FALSE(c.closed);
  CHECK(c.reason.find("has 4 boundary edges, e.g. (v") == 0);
  // A cube whose faces are not welded and cannot be (one corner moved a little).
  ir::MeshData u = unwelded_cube();
  u.positions[0].x += 1e-12;
  // Both of its edges on its face, and their partners on the two other faces.
  CHECK(ir::mesh_closure(u).reason.find("has 4 boundary edges") == 0);
}

TEST_CASE("an edge with a third triangle (a fin) is named", "[mesh][topology]") {
  ir::MeshData m = cube();
  m.positions.push_back({0.5, 0.5, -1});         // v9
  m.indices.insert(m.indices.end(), {0, 1, 8});  // on edge (v1, v2), the cube's bottom front
  ir::MeshClosure c = ir::mesh_closure(m);
  CHECK_FALSE(c.closed);
  CHECK(c.reason == "has an edge (v1, v2) used by 3 triangles");
}

TEST_CASE("one triangle wound the other way is inconsistent winding", "[mesh][topology]") {
  ir::MeshData m = cube();
  std::swap(m.indices[1], m.indices[2]);
  ir::MeshClosure c = ir::mesh_closure(m);
  CHECK_FALSE(c.closed);
  CHECK(c.reason.find("is wound inconsistently: edge (v") == 0);
}

TEST_CASE("a cube wound inward is inside out", "[mesh][topology]") {
  ir::MeshData m = cube();
  for (std::size_t t = 0; t < m.indices.size(); t += 3)
    std::swap(m.indices[t + 1], m.indices[t + 2]);
  ir::MeshClosure c = ir::mesh_closure(m);
  CHECK_FALSE(c.closed);
  CHECK(c.reason.find("is inside out: its signed volume is -1 ") == 0);
}

TEST_CASE("a hollow cube (an inward cube inside an outward one) is closed", "[mesh][topology]") {
  ir::MeshData m = cube(), inner = cube();
  for (ir::Vec3 p : inner.positions) m.positions.push_back(p * 0.5 + ir::Vec3(0.25));
  for (std::size_t t = 0; t < inner.indices.size(); t += 3)
    m.indices.insert(m.indices.end(),
                     {inner.indices[t] + 8, inner.indices[t + 2] + 8, inner.indices[t + 1] + 8});
  CHECK(ir::mesh_closure(m).closed);
}

TEST_CASE("a zero-area triangle of welded vertices is ignored, a lone sheet is open",
          "[mesh][topology]") {
  ir::MeshData m = unwelded_cube();
  m.positions.push_back(m.positions[0]);  // a copy of v1: welds to it
  m.indices.insert(m.indices.end(), {0, 24, 1});
  CHECK(ir::mesh_closure(m).closed);
  ir::MeshData sheet;
  sheet.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  sheet.indices = {0, 1, 2, 0, 2, 1};  // both sides: every edge twice, opposite ways
  CHECK(ir::mesh_closure(sheet).reason.find("encloses no volume") == 0);
  CHECK(ir::mesh_closure(ir::MeshData{}).reason == "has no triangles with area");
}

TEST_CASE("has_inside and no_inside_reason for mesh shapes", "[mesh][topology]") {
  ir::Scene s;
  s.meshes.push_back(cube());
  ir::MeshData open = cube();
  open.indices.resize(33);  // the last triangle, (v2, v8, v6), left out
  ir::MeshClosure c = ir::mesh_closure(open);
  open.closed = c.closed, open.open_reason = c.reason;
  s.meshes[0].closed = true;
  s.meshes.push_back(open);
  ir::Shape a, b, t;
  a.geom = ir::Mesh{0};
  b.geom = ir::Mesh{1};
  t.geom = ir::Triangle{};
  CHECK(rt::geom::has_inside(a, s));
  CHECK(rt::geom::no_inside_reason(a, s).empty());
  CHECK_FALSE(rt::geom::has_inside(b, s));
  CHECK(rt::geom::no_inside_reason(b, s) ==
        "mesh 'cube' is not closed: it has 3 boundary edges, e.g. (v2, v6) (an edge used by one "
        "triangle only)");
  CHECK(rt::geom::no_inside_reason(t, s) == "a triangle has no inside");
  CHECK(ir::to_string(c).find("mesh_closure { open: has 3 boundary edges") == 0);
}
