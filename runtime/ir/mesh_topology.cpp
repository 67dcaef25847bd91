#include "runtime/ir/mesh_topology.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <vector>

namespace snell::ir {

namespace {

std::string vertex_pair(std::uint32_t a, std::uint32_t b) {
  return "(v" + std::to_string(a + 1) + ", v" + std::to_string(b + 1) + ")";
}

struct Edge {
  std::uint32_t lo, hi;
  bool forward;  // used as lo -> hi
};

}  // namespace

MeshClosure mesh_closure(const MeshData& m) {
  MeshClosure out;
  const std::size_t nv = m.positions.size();
  // 1. Weld by sorting the used vertices by position: equal positions form a run
  //    whose smallest index stands for all of them. Sorting (not hashing) keeps
  //    -0 == +0 and costs no table.
  std::vector<std::uint32_t> used;
  std::vector<std::uint8_t> seen(nv, 0);
  for (std::uint32_t i : m.indices) {
    if (i >= nv) {
      out.reason = "has a vertex index out of range";
      return out;
    }
    if (!seen[i]) {
      if (!is_finite(m.positions[i])) {
        out.reason = "has a non-finite vertex (v" + std::to_string(i + 1) + ")";
        return out;
      }
      seen[i] = 1;
      used.push_back(i);
    }
  }
  auto less = [&](std::uint32_t a, std::uint32_t b) {
    const Vec3 &p = m.positions[a], &q = m.positions[b];
    if (p.x != q.x) return p.x < q.x;
    if (p.y != q.y) return p.y < q.y;
    if (p.z != q.z) return p.z < q.z;
    return a < b;
  };
  std::sort(used.begin(), used.end(), less);
  std::vector<std::uint32_t> weld(nv, 0);
  for (std::size_t k = 0; k < used.size(); ++k) {
    bool same = k > 0 && m.positions[used[k]] == m.positions[used[k - 1]];
    weld[used[k]] = same ? weld[used[k - 1]] : used[k];
  }

  // 2-3. Directed edges of the triangles with three distinct welded vertices.
  std::vector<Edge> edges;
  edges.reserve(m.indices.size());
  Vec3 centroid{0, 0, 0};
  for (std::uint32_t i : used) centroid = centroid + m.positions[i];
  if (!used.empty()) centroid = centroid / double(used.size());
  double volume6 = 0;
  std::size_t faces = 0;
  for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
    std::uint32_t v[3] = {weld[m.indices[t]], weld[m.indices[t + 1]], weld[m.indices[t + 2]]};
    if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0]) continue;
    ++faces;
    for (int k = 0; k < 3; ++k) {
      std::uint32_t a = v[k], b = v[(k + 1) % 3];
      edges.push_back({std::min(a, b), std::max(a, b), a < b});
    }
    Vec3 a = m.positions[v[0]] - centroid, b = m.positions[v[1]] - centroid,
         c = m.positions[v[2]] - centroid;
    volume6 += dot(a, cross(b, c));
  }
  if (faces == 0) {
    out.reason = "has no triangles with area";
    return out;
  }
  std::sort(edges.begin(), edges.end(), [](const Edge& a, const Edge& b) {
    return a.lo != b.lo ? a.lo < b.lo : a.hi != b.hi ? a.hi < b.hi : a.forward < b.forward;
  });
  std::size_t boundary = 0, fins = 0, same_way = 0;
  std::string first_boundary, first_fin, first_same;
  for (std::size_t k = 0; k < edges.size();) {
    std::size_t j = k;
    while (j < edges.size() && edges[j].lo == edges[k].lo && edges[j].hi == edges[k].hi) ++j;
    std::size_t uses = j - k;
    std::string name = vertex_pair(edges[k].lo, edges[k].hi);
    if (uses == 1) {
      if (boundary++ == 0) first_boundary = name;
    } else if (uses > 2) {
      if (fins++ == 0)
        first_fin = "has an edge " + name + " used by " + std::to_string(uses) + " triangles";
    } else if (edges[k].forward == edges[k + 1].forward) {
      if (same_way++ == 0) first_same = name;
    }
    k = j;
  }
  if (fins > 0) {
    out.reason = first_fin;
    if (fins > 1) out.reason += " (and " + std::to_string(fins - 1) + " more such edges)";
  } else if (boundary > 0) {
    out.reason = boundary == 1 ? "has 1 boundary edge " + first_boundary
                               : "has " + std::to_string(boundary) + " boundary edges, e.g. " +
                                     first_boundary;
    out.reason += " (an edge used by one triangle only)";
  } else if (same_way > 0) {
    out.reason =
        "is wound inconsistently: edge " + first_same + " is used twice in the same direction";
    if (same_way > 1) out.reason += " (" + std::to_string(same_way) + " such edges)";
  } else if (!(volume6 > 0)) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.6g", volume6 / 6);
    out.reason = std::string(volume6 < 0 ? "is inside out" : "encloses no volume") +
                 ": its signed volume is " + buf +
                 " (triangles must wind counter-clockwise seen from outside)";
  } else {
    out.closed = true;
  }
  return out;
}

std::string to_string(const MeshClosure& c) {
  return c.closed ? "mesh_closure { closed }" : "mesh_closure { open: " + c.reason + " }";
}

}  // namespace snell::ir
