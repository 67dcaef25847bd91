// The camera of §6: a pinhole, or a thin lens when aperture > 0. The world is
// camera-relative (camera at the origin). forward = normalize(look_at - location),
// right = normalize(cross(forward, up)), true up = cross(right, forward);
// horizontal field of view; square pixels; pixel (0, 0) is the top-left.
//
// Thin lens (pbrt's model): the pinhole ray through a film point meets the focal
// plane — the plane at `focal_distance` along `forward` — at pFocus; the lens ray
// starts at a point of the lens disk (diameter `aperture`, in the right/up plane
// through the camera) and aims at pFocus. Points on the focal plane are therefore
// sharp whatever the lens sample; a point at depth z spreads over a disk of diameter
// aperture·|z − focal_distance|/z measured on the focal plane.
// With aperture 0 `generate` ignores the lens sample and returns the pinhole ray bit
// for bit (the specialised kernel does not even draw the sample).
#pragma once

#include <cmath>
#include <string>

#include "runtime/embree_scene.hpp"
#include "runtime/ir/ir.hpp"
#include "runtime/vec.hpp"

namespace snell::rt {

// Shirley–Chiu concentric map of [0,1)² onto the unit disk: uniform in area, and
// it keeps strata compact (better than the polar map for stratified samplers).
// (0.5, 0.5) maps to the centre without dividing 0 by 0.
inline void concentric_disk(float u, float v, float& x, float& y) {
  float a = 2 * u - 1, b = 2 * v - 1;
  if (a == 0 && b == 0) {
    x = y = 0;
    return;
  }
  constexpr float kQuarterPi = 0.785398163397448309616f;
  float r, phi;
  if (std::fabs(a) > std::fabs(b)) {
    r = a;
    phi = kQuarterPi * (b / a);
  } else {
    r = b;
    phi = 2 * kQuarterPi - kQuarterPi * (a / b);
  }
  x = r * std::cos(phi);
  y = r * std::sin(phi);
}

class Camera {
 public:
  Camera(const ir::Camera& c, std::uint32_t width, std::uint32_t height) {
    ir::Vec3 f = ir::normalize(c.look_at - c.location);
    ir::Vec3 r = ir::normalize(ir::cross(f, c.up));
    ir::Vec3 u = ir::cross(r, f);
    forward_ = to_float(f.x, f.y, f.z);
    right_ = to_float(r.x, r.y, r.z);
    up_ = to_float(u.x, u.y, u.z);
    double tx = std::tan(c.fov * 0.5 * 3.14159265358979323846 / 180.0);
    tan_x_ = tx;
    tan_y_ = width ? tx * double(height) / double(width) : tx;
    width_ = width;
    height_ = height;
    lens_radius_ = c.aperture > 0 ? float(c.aperture * 0.5) : 0.0f;
    focal_distance_ = float(c.focal_distance);
  }

  bool has_lens() const { return lens_radius_ > 0; }

  // (fx, fy): film position in pixels, (0, 0) the top-left corner of the image.
  // (lens_u, lens_v): the lens sample, used only when the camera has a lens.
  Ray generate(double fx, double fy, float lens_u = 0.5f, float lens_v = 0.5f) const {
    double sx = (2 * fx / width_ - 1) * tan_x_;
    double sy = (1 - 2 * fy / height_) * tan_y_;
    Vec3f d = forward_ + right_ * float(sx) + up_ * float(sy);  // forward component 1
    Ray r;
    if (lens_radius_ > 0) {
      float lx, ly;
      concentric_disk(lens_u, lens_v, lx, ly);
      Vec3f focus = d * focal_distance_;
      r.org = right_ * (lx * lens_radius_) + up_ * (ly * lens_radius_);
      // In double: with a wide fov and a far focal plane |focus|² overflows float.
      ir::Vec3 w(double(focus.x) - r.org.x, double(focus.y) - r.org.y, double(focus.z) - r.org.z);
      w = ir::normalize(w);
      r.dir = to_float(w.x, w.y, w.z);
      return r;
    }
    r.org = Vec3f(0, 0, 0);
    r.dir = normalize(d);
    return r;
  }

  std::string to_string() const;

 private:
  Vec3f forward_, right_, up_;
  double tan_x_ = 1, tan_y_ = 1;
  std::uint32_t width_ = 1, height_ = 1;
  float lens_radius_ = 0, focal_distance_ = 1;
};

using PinholeCamera = Camera;  // the name before depth of field

}  // namespace snell::rt
