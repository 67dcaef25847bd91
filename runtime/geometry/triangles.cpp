#include "runtime/geometry/triangles.hpp"

#include <cmath>

namespace snell::rt::geom {

using ir::Vec3;

void object_triangles(const ir::Box& box, const ir::Scene&, bool flip, Soup& out) {
  Vec3 lo = box.min, hi = box.max;
  auto corner = [&](int i) {
    return Vec3(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z);
  };
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      // The face's four corners in cyclic order, then wound outward.
      int bit = 1 << axis, b1 = 1 << ((axis + 1) % 3), b2 = 1 << ((axis + 2) % 3);
      int f = side ? bit : 0;
      Vec3 q[4] = {corner(f), corner(f | b1), corner(f | b1 | b2), corner(f | b2)};
      Vec3 outward;
      outward[axis] = side ? 1 : -1;
      bool wrong = ir::dot(ir::cross(q[1] - q[0], q[2] - q[0]), outward) < 0;
      out.tri(q[0], q[1], q[2], flip != wrong);
      out.tri(q[0], q[2], q[3], flip != wrong);
    }
}

void object_triangles(const ir::Triangle& t, const ir::Scene&, bool flip, Soup& out) {
  out.tri(t.a, t.b, t.c, flip);
}

void object_triangles(const ir::Mesh& mesh, const ir::Scene& sc, bool flip, Soup& out) {
  if (mesh.mesh >= sc.meshes.size()) return;
  const ir::MeshData& m = sc.meshes[mesh.mesh];
  for (std::size_t i = 0; i + 2 < m.indices.size(); i += 3) {
    if (m.indices[i] >= m.positions.size() || m.indices[i + 1] >= m.positions.size() ||
        m.indices[i + 2] >= m.positions.size())
      continue;
    out.tri(m.positions[m.indices[i]], m.positions[m.indices[i + 1]], m.positions[m.indices[i + 2]],
            flip);
  }
}

bool object_normals(const ir::Mesh& mesh, const ir::Scene& sc, bool flip,
                    std::vector<ir::Vec3>& out) {
  if (mesh.mesh >= sc.meshes.size()) return false;
  const ir::MeshData& m = sc.meshes[mesh.mesh];
  if (!m.smooth() || m.normal_indices.size() != m.indices.size()) return false;
  auto normal = [&](std::size_t corner) {
    std::uint32_t k = m.normal_indices[corner];
    return k < m.normals.size() ? m.normals[k] : Vec3(0, 0, 0);
  };
  // The same triangles, in the same order, as object_triangles(mesh) emits.
  for (std::size_t i = 0; i + 2 < m.indices.size(); i += 3) {
    if (m.indices[i] >= m.positions.size() || m.indices[i + 1] >= m.positions.size() ||
        m.indices[i + 2] >= m.positions.size())
      continue;
    Vec3 a = normal(i), b = normal(i + 1), c = normal(i + 2);
    if (a == Vec3(0, 0, 0) || b == Vec3(0, 0, 0) || c == Vec3(0, 0, 0)) a = b = c = Vec3(0, 0, 0);
    out.push_back(a);
    out.push_back(flip ? c : b);
    out.push_back(flip ? b : c);
  }
  return true;
}

void SmoothNormals::add(std::size_t first_prim, const std::vector<ir::Vec3>& normals,
                        const ir::Transform& xf) {
  if (corners_.size() < 3 * first_prim + normals.size())
    corners_.resize(3 * first_prim + normals.size(), Vec3f(0));
  for (std::size_t t = 0; t + 2 < normals.size(); t += 3) {
    if (normals[t] == Vec3(0, 0, 0)) continue;  // a flat face stays zero
    for (std::size_t k = 0; k < 3; ++k) {
      Vec3 n = xf.normal(normals[t + k]);
      double len = ir::length(n);
      if (!(len > 0) || !std::isfinite(len)) {  // a singular transform: shade flat
        for (std::size_t j = 0; j < 3; ++j) corners_[3 * first_prim + t + j] = Vec3f(0);
        break;
      }
      n = n / len;
      corners_[3 * first_prim + t + k] = to_float(n.x, n.y, n.z);
    }
  }
}

bool SmoothNormals::shade(unsigned prim, float u, float v, Vec3f dir, const float* vb,
                          const unsigned* ib, Hit& hit) const {
  if (std::size_t(3) * prim + 2 >= corners_.size()) return false;
  const Vec3f* c = &corners_[std::size_t(3) * prim];
  if (c[0].x == 0 && c[0].y == 0 && c[0].z == 0) return false;
  float b[3] = {1 - u - v, u, v};
  Vec3f n = c[0] * b[0] + c[1] * b[1] + c[2] * b[2];
  float len = length(n);
  if (!(len > 1e-6f)) return false;
  n = n * (1 / len);
  // A vn that disagrees with the winding (a file whose faces wind inward but whose
  // normals point out): face-forwarded to Ng, which decides the sides.
  float flip = dot(n, hit.ng) < 0 ? -1.0f : 1.0f;
  hit.ns = n * flip;
  // The lift, with the corner normals on the ray's side of the facet.
  float side = dot(dir, hit.ng) < 0 ? flip : -flip;
  Vec3f lift(0);
  for (int i = 0; i < 3; ++i) {
    const float* q = vb + 3 * ib[3 * prim + i];
    Vec3f ni = c[i] * side;
    float depth = dot(hit.p - Vec3f(q[0], q[1], q[2]), ni);
    if (depth < 0) lift = lift - ni * (b[i] * depth);
  }
  Vec3f nf = dot(dir, hit.ng) < 0 ? hit.ng : -hit.ng;
  hit.ps = dot(lift, nf) > 0 ? hit.p + lift : hit.p;
  return true;
}

// The hit point of a static triangle from Embree's barycentrics, p = v0 + u·e1 + v·e2:
// an error in (u, v) moves p within the plane, never off it (as pbrt-v4's
// Triangle::InteractionFromIntersection rebuilds its hit points). Where the three
// vertices share a coordinate (an axis-aligned face) the edges' component is
// exactly 0 and p keeps that coordinate exactly; b0·v0 + u·v1 + v·v2 would be off
// by an ulp of it, since b0 + u + v rounds (2.4 % of the path through a 1e-5 slab
// 3 units away).
void triangle_point(const float* vb, const unsigned* ib, unsigned prim, float u, float v,
                    Vec3f& p) {
  const float* a = vb + 3 * ib[3 * prim];
  const float* b = vb + 3 * ib[3 * prim + 1];
  const float* c = vb + 3 * ib[3 * prim + 2];
  p = {a[0] + u * (b[0] - a[0]) + v * (c[0] - a[0]), a[1] + u * (b[1] - a[1]) + v * (c[1] - a[1]),
       a[2] + u * (b[2] - a[2]) + v * (c[2] - a[2])};
}

bool triangle_retrace(const float* vb, const unsigned* ib, unsigned prim, Vec3f o, Vec3f d,
                      float& t, float& u, float& v, Vec3f& ng) {
  auto vertex = [&](int k) {
    const float* x = vb + 3 * ib[3 * prim + k];
    return Vec3(x[0], x[1], x[2]);
  };
  const Vec3 a = vertex(0), b = vertex(1), c = vertex(2);
  const Vec3 od(o.x, o.y, o.z), dd(d.x, d.y, d.z);
  const Vec3 e1 = b - a, e2 = c - a;
  const Vec3 pv = ir::cross(dd, e2);
  const double det = ir::dot(e1, pv);
  if (!(det != 0) || !std::isfinite(det)) return false;
  const double inv = 1 / det;
  const Vec3 tv = od - a, qv = ir::cross(tv, e1);
  const double tt = ir::dot(e2, qv) * inv;
  if (!std::isfinite(tt)) return false;
  t = float(tt);
  u = float(ir::dot(tv, pv) * inv);
  v = float(ir::dot(dd, qv) * inv);
  const Vec3 n = ir::cross(c - a, a - b);
  ng = to_float(n.x, n.y, n.z);
  return true;
}

// How far a ray leaving a point of triangle abc must start (Hit::offset), in ulps
// (2^-24) of two sources; a constant of the triangle, computed once:
// - the point's own error off the plane, and Embree's rounding of the vertices when
//   it translates them to the new ray's origin: a few ulps of each coordinate,
//   weighted by how much that coordinate moves along the normal: Σ_i |n_i|·M_i
//   (M_i: largest |v_j,i|). An axis-aligned face needs ulps of its plane coordinate
//   only, however large it is.
// - Embree's normal, rebuilt from rounded edges: its direction is off by the
//   rounding of each component's cross products, seen from the origin over the
//   triangle's extent: Σ_i R_i·(|e1_j e2_k| + |e1_k e2_j|) / |e1 × e2| (R_i: the
//   extent along i). Zero for an axis-aligned face (every product it rounds is
//   along n); large for slivers, whose normal is ill-conditioned.
// kOffsetUlps: hc01's 6e4 random triangles at 1e-8..1e8 see self-hits at 0.5 and
// none from 1 (docs/hardcases.md); 8 leaves a factor 8. A result of 0 (a face in a
// coordinate plane through the camera) falls back to offset_ray_origin.
constexpr float kOffsetUlps = 8;
float triangle_offset(const float* a, const float* b, const float* c) {
  // In double: the cross products of edges 1e10 long overflow float.
  double e1[3], e2[3], big[3], extent[3], n[3];
  for (int i = 0; i < 3; ++i) {
    e1[i] = double(b[i]) - a[i], e2[i] = double(c[i]) - a[i];
    double lo = ir::min_num(a[i], ir::min_num(b[i], c[i])),
           hi = ir::max_num(a[i], ir::max_num(b[i], c[i]));
    big[i] = ir::max_num(std::fabs(lo), std::fabs(hi));
    extent[i] = hi - lo;
  }
  double cross_abs = 0, cross_sq = 0;
  for (int i = 0; i < 3; ++i) {
    int j = (i + 1) % 3, k = (i + 2) % 3;
    n[i] = e1[j] * e2[k] - e1[k] * e2[j];
    cross_sq += n[i] * n[i];
    cross_abs += extent[i] * (std::fabs(e1[j] * e2[k]) + std::fabs(e1[k] * e2[j]));
  }
  if (!(cross_sq > 0)) return 0;  // degenerate: never hit
  double len = std::sqrt(cross_sq), w = cross_abs / len;
  for (int i = 0; i < 3; ++i) w += std::fabs(n[i]) / len * big[i];
  double offset = kOffsetUlps * 0x1p-24 * w;
  // Finite and at most a float's range, or 0 (Wächter–Binder) when not.
  return offset < 1e30 ? float(offset) : 0.0f;
}

}  // namespace snell::rt::geom
