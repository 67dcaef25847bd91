// §17 mapping "uv": a surface's own parameters (u, v) at a point, one function per
// shape kind, in the object space of the leaf that was hit (a CSG object's leaf,
// an instance's part). docs/language.md lists them:
//   sphere     the spherical mapping about its centre
//   plane      the point's coordinates along the plane's two axes (axis_frame)
//   box        per face, the face's two other coordinates as fractions of the box
//   triangle   the barycentrics of b and c
//   mesh       the corners' OBJ vt, interpolated; without vt, as a triangle
//   cylinder,  around the axis u = 0.5 + atan2(y, x) / 360° in the axis frame,
//   cone       v = the fraction of the way from base to cap; an end cap is the
//              square around it (u, v = 0.5 + x, y / (2 r))
//   disc       the square around it (u, v = 0.5 + x, y / (2 radius))
//   torus      u around the y axis (the spherical formula's u), v around the tube
// Defined off the surface too (the nearest face decides for boxes, cylinders and
// cones), so the filter's footprint takes differences of the same functions.
#pragma once

#include <cmath>
#include <cstdint>

#include "runtime/ir/ir.hpp"
#include "runtime/shading/image_texture.hpp"

namespace snell::rt {

// Where the hit's surface parameters come from: the leaf shape, its space at the
// ray's time, and the triangle hit (for a mesh or triangle).
struct SurfaceFrame {
  const ir::Shape* leaf = nullptr;
  ir::Transform leaf_from_world;
  const ir::Scene* scene = nullptr;
  std::uint32_t tri = 0;
};

// The frame of a hit on `top` (scene.shapes) at leaf `part` and, for a CSG leaf
// inside an instance, the instance's part `outer` (kNoPart: none), at shutter
// fraction `time`.
inline SurfaceFrame surface_frame(const ir::Scene& scene, const ir::Shape& top, std::uint32_t part,
                                  std::uint32_t outer, std::uint32_t tri, double time) {
  SurfaceFrame f;
  f.scene = &scene;
  f.tri = tri;
  ir::Transform world_from_leaf = top.motion().empty()
                                      ? top.world_from_object()
                                      : top.motion().at(time) * top.world_from_object();
  f.leaf = &top;
  if (part != ir::kNoPart && part < scene.parts.size()) {
    if (outer != ir::kNoPart && outer < scene.parts.size())
      world_from_leaf = world_from_leaf * scene.parts[outer].world_from_object();
    f.leaf = &scene.parts[part];
    // A CSG leaf may move inside its CSG object (§12), in that object's space.
    const ir::Motion& moves = f.leaf->motion();
    world_from_leaf =
        world_from_leaf * (moves.empty() ? f.leaf->world_from_object()
                                         : moves.at(time) * f.leaf->world_from_object());
  }
  f.leaf_from_world = world_from_leaf.inverse();
  return f;
}

namespace uvmap {

inline double turn(double y, double x) {
  return 0.5 + std::atan2(y, x) / (2 * kImagePi);
}

// (b, c) barycentrics of q's projection onto the plane of triangle abc.
inline ImageUV barycentric(ir::Vec3 a, ir::Vec3 b, ir::Vec3 c, ir::Vec3 q) {
  ir::Vec3 e1 = b - a, e2 = c - a, d = q - a;
  double d11 = ir::dot(e1, e1), d12 = ir::dot(e1, e2), d22 = ir::dot(e2, e2);
  double p1 = ir::dot(d, e1), p2 = ir::dot(d, e2);
  double den = d11 * d22 - d12 * d12;
  if (!(den > 0)) return {};
  return {(d22 * p1 - d12 * p2) / den, (d11 * p2 - d12 * p1) / den};
}

inline ImageUV of(const ir::Sphere& s, const SurfaceFrame&, ir::Vec3 q) {
  return image_uv(ir::ImageMapping::Spherical, q - s.center);
}
inline ImageUV of(const ir::Plane& p, const SurfaceFrame&, ir::Vec3 q) {
  ir::Vec3 l = ir::axis_frame(p.normal * p.distance, p.normal).inverse().point(q);
  return {l.x, l.y};
}
inline ImageUV of(const ir::Box& b, const SurfaceFrame&, ir::Vec3 q) {
  ir::Vec3 r;
  int face = 0;
  double nearest = INFINITY;
  for (int k = 0; k < 3; ++k) {
    double size = b.max[k] - b.min[k];
    r[k] = size > 0 ? (q[k] - b.min[k]) / size : 0;
    double d = std::fmin(std::fabs(q[k] - b.min[k]), std::fabs(b.max[k] - q[k]));
    if (d < nearest) nearest = d, face = k;
  }
  if (face == 0) return {r.z, r.y};
  if (face == 1) return {r.x, r.z};
  return {r.x, r.y};
}
inline ImageUV of(const ir::Triangle& t, const SurfaceFrame&, ir::Vec3 q) {
  return barycentric(t.a, t.b, t.c, q);
}
inline ImageUV of(const ir::Mesh& m, const SurfaceFrame& f, ir::Vec3 q) {
  if (m.mesh >= f.scene->meshes.size()) return {};
  const ir::MeshData& d = f.scene->meshes[m.mesh];
  std::size_t i = 3 * std::size_t(f.tri);
  if (i + 2 >= d.indices.size()) return {};
  for (int k = 0; k < 3; ++k)
    if (d.indices[i + k] >= d.positions.size()) return {};
  const ir::Vec3 a = d.positions[d.indices[i]], b = d.positions[d.indices[i + 1]],
                 c = d.positions[d.indices[i + 2]];
  ImageUV w = barycentric(a, b, c, q);
  if (d.texcoord_indices.size() < i + 3) return w;
  const ir::Vec3 ta = d.texcoords[d.texcoord_indices[i]],
                 tb = d.texcoords[d.texcoord_indices[i + 1]],
                 tc = d.texcoords[d.texcoord_indices[i + 2]];
  ir::Vec3 t = ta * (1 - w.u - w.v) + tb * w.u + tc * w.v;
  return {t.x, t.y};
}
// A truncated cone from radius r0 at base to r1 at cap (both ends capped unless
// `open`).
inline ImageUV axial(ir::Vec3 base, ir::Vec3 cap, double r0, double r1, bool open, ir::Vec3 q) {
  ir::Vec3 axis = cap - base;
  double h = ir::length(axis);
  if (!(h > 0)) return {};
  ir::Vec3 l = ir::axis_frame(base, axis / h).inverse().point(q);
  double rho = std::hypot(l.x, l.y);
  double z = std::fmin(1.0, std::fmax(0.0, l.z / h));
  double side = std::fabs(rho - (r0 + (r1 - r0) * z));
  double d0 = !open && r0 > 0 ? std::fabs(l.z) : INFINITY;
  double d1 = !open && r1 > 0 ? std::fabs(l.z - h) : INFINITY;
  if (side <= d0 && side <= d1) return {turn(l.y, l.x), l.z / h};
  double r = d0 <= d1 ? r0 : r1;
  return {0.5 + l.x / (2 * r), 0.5 + l.y / (2 * r)};
}
inline ImageUV of(const ir::Cylinder& c, const SurfaceFrame&, ir::Vec3 q) {
  return axial(c.base, c.cap, c.radius, c.radius, c.open, q);
}
inline ImageUV of(const ir::Cone& c, const SurfaceFrame&, ir::Vec3 q) {
  return axial(c.base, c.cap, c.base_radius, c.cap_radius, c.open, q);
}
inline ImageUV of(const ir::Disc& d, const SurfaceFrame&, ir::Vec3 q) {
  ir::Vec3 l = ir::axis_frame(d.center, d.normal).inverse().point(q);
  return {0.5 + l.x / (2 * d.radius), 0.5 + l.y / (2 * d.radius)};
}
inline ImageUV of(const ir::Torus& t, const SurfaceFrame&, ir::Vec3 q) {
  return {around_y(q), turn(q.y, std::hypot(q.x, q.z) - t.major)};
}
// Composites are never the leaf a hit names; the spherical mapping if one is.
template <class K>
ImageUV of(const K&, const SurfaceFrame&, ir::Vec3 q) {
  return image_uv(ir::ImageMapping::Spherical, q);
}

}  // namespace uvmap

// The surface's (u, v) at world point `w`.
inline ImageUV surface_uv(const SurfaceFrame& f, ir::Vec3 w) {
  ir::Vec3 q = f.leaf_from_world.point(w);
  return std::visit([&](const auto& g) { return uvmap::of(g, f, q); }, f.leaf->geom);
}

}  // namespace snell::rt
