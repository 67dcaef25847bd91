// Helpers to build small ir::Scene values in C++ for runtime tests.
#pragma once

#include <cmath>
#include <cstdint>

#include "runtime/ir/ir.hpp"

namespace snell::test {

inline constexpr double kPi = 3.14159265358979323846;

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
  return ir::Diffuse{c};
}
inline ir::Material mirror(ir::Vec3 c) {
  return ir::Mirror{c};
}
inline ir::Material dielectric(double ior, ir::Vec3 absorb = {}) {
  return ir::Dielectric{ior, absorb};
}
inline ir::Material glazed(ir::Vec3 c, double ior) {
  return ir::Glazed{c, ior};
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
  return ir::Diffuse{ir::Checker{c1, c2, size}};
}

inline ir::Shape shape_of(ir::ShapeGeom g, std::uint32_t mat) {
  ir::Shape s;
  s.geom = g;
  s.material = mat;
  return s;
}
inline ir::Shape sphere(ir::Vec3 c, double r, std::uint32_t mat) {
  return shape_of(ir::Sphere{c, r}, mat);
}
inline ir::Shape plane(ir::Vec3 n, double d, std::uint32_t mat) {
  return shape_of(ir::Plane{ir::normalize(n), d}, mat);
}
inline ir::Shape box(ir::Vec3 lo, ir::Vec3 hi, std::uint32_t mat) {
  return shape_of(ir::Box{lo, hi}, mat);
}
inline ir::Shape triangle(ir::Vec3 a, ir::Vec3 b, ir::Vec3 c, std::uint32_t mat) {
  return shape_of(ir::Triangle{a, b, c}, mat);
}

inline void look(ir::Scene& s, ir::Vec3 from, ir::Vec3 at, double fov, ir::Vec3 up = {0, 1, 0}) {
  s.camera.location = from;
  s.camera.look_at = at;
  s.camera.up = up;
  s.camera.fov = fov;
  s.camera.focal_distance = ir::length(at - from);
}

}  // namespace snell::test
