// The pinhole camera of §6. The world is camera-relative (camera at the origin).
// forward = normalize(look_at - location), right = normalize(cross(forward, up)),
// true up = cross(right, forward); horizontal field of view; square pixels;
// pixel (0, 0) is the top-left. Depth of field (aperture > 0) will add a lens
// sample (dimension kDimLens) to `generate`; the signature already takes it.
#pragma once

#include <cmath>
#include <string>

#include "runtime/embree_scene.hpp"
#include "runtime/ir/ir.hpp"
#include "runtime/vec.hpp"

namespace snell::rt {

class PinholeCamera {
 public:
  PinholeCamera(const ir::Camera& c, std::uint32_t width, std::uint32_t height) {
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
  }

  // (fx, fy): film position in pixels, (0, 0) the top-left corner of the image.
  // `lens` is unused by the pinhole (reserved for depth of field).
  Ray generate(double fx, double fy, float /*lens_u*/ = 0, float /*lens_v*/ = 0) const {
    double sx = (2 * fx / width_ - 1) * tan_x_;
    double sy = (1 - 2 * fy / height_) * tan_y_;
    Ray r;
    r.org = Vec3f(0, 0, 0);
    r.dir = normalize(forward_ + right_ * float(sx) + up_ * float(sy));
    return r;
  }

  std::string to_string() const;

 private:
  Vec3f forward_, right_, up_;
  double tan_x_ = 1, tan_y_ = 1;
  std::uint32_t width_ = 1, height_ = 1;
};

}  // namespace snell::rt
