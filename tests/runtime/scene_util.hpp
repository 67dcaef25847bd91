// Helpers to build small ir::Scene values in C++ for runtime tests.
#pragma once

#include <cmath>
#include <cstdint>

#include "runtime/ir/ir.hpp"

namespace snell::test {

inline ir::Scene base_scene(std::uint32_t w, std::uint32_t h, std::uint32_t spp = 1) {
  ir::Scene s;
  s.files.push_back("test");
  s.settings.width = w;
  s.settings.height = h;
  s.settings.samples = spp;
  s.materials.push_back(ir::Material{});  // index 0: default diffuse 0.8
  return s;
}

inline std::uint32_t add_material(ir::Scene& s, ir::Material m) {
  s.materials.push_back(m);
  return static_cast<std::uint32_t>(s.materials.size() - 1);
}

inline ir::Material diffuse(ir::Vec3 c) {
  ir::Material m;
  m.kind = ir::MaterialKind::Diffuse;
  m.color.color = c;
  return m;
}
inline ir::Material mirror(ir::Vec3 c) {
  ir::Material m = diffuse(c);
  m.kind = ir::MaterialKind::Mirror;
  return m;
}
inline ir::Material dielectric(double ior, ir::Vec3 absorb = {}) {
  ir::Material m;
  m.kind = ir::MaterialKind::Dielectric;
  m.ior = ior;
  m.absorb = absorb;
  return m;
}
inline ir::Material glazed(ir::Vec3 c, double ior) {
  ir::Material m = diffuse(c);
  m.kind = ir::MaterialKind::Glazed;
  m.ior = ior;
  return m;
}

// A square-gridded area light: `n`×`n` shadow samples, one-sided.
inline ir::AreaLight area_light(ir::Vec3 corner, ir::Vec3 edge1, ir::Vec3 edge2, ir::Vec3 radiance,
                                std::uint32_t n = 1) {
  ir::AreaLight l;
  l.corner = corner;
  l.edge1 = edge1;
  l.edge2 = edge2;
  l.radiance = radiance;
  l.samples_u = l.samples_v = n;
  return l;
}

// A diffuse material with the §8 checker pattern.
inline ir::Material checker(ir::Vec3 c1, ir::Vec3 c2, double size) {
  ir::Material m = diffuse(c1);
  m.color.kind = ir::Texture::Kind::Checker;
  m.color.color2 = c2;
  m.color.size = size;
  return m;
}

inline ir::Shape sphere(ir::Vec3 c, double r, std::uint32_t mat) {
  ir::Shape s;
  s.kind = ir::ShapeKind::Sphere;
  s.center = c;
  s.radius = r;
  s.material = mat;
  return s;
}
inline ir::Shape plane(ir::Vec3 n, double d, std::uint32_t mat) {
  ir::Shape s;
  s.kind = ir::ShapeKind::Plane;
  s.normal = ir::normalize(n);
  s.distance = d;
  s.material = mat;
  return s;
}
inline ir::Shape box(ir::Vec3 lo, ir::Vec3 hi, std::uint32_t mat) {
  ir::Shape s;
  s.kind = ir::ShapeKind::Box;
  s.min = lo;
  s.max = hi;
  s.material = mat;
  return s;
}

inline void look(ir::Scene& s, ir::Vec3 from, ir::Vec3 at, double fov, ir::Vec3 up = {0, 1, 0}) {
  s.camera.location = from;
  s.camera.look_at = at;
  s.camera.up = up;
  s.camera.fov = fov;
  s.camera.focal_distance = ir::length(at - from);
}

}  // namespace snell::test
