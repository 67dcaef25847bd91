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

// cos t and sin t for |t| <= π/4, as Taylor polynomials to t^10 and t^9 (truncation
// below 3e-8 there, under float's half ulp of the results): inline and branch-free,
// so a block of lens samples vectorises, where libm's sincosf is a call per sample.
inline float cos_quarter(float t) {
  float t2 = t * t;
  return 1 + t2 * (-0.5f + t2 * (1 / 24.0f + t2 * (-1 / 720.0f +
                                                   t2 * (1 / 40320.0f + t2 * (-1 / 3628800.0f)))));
}
inline float sin_quarter(float t) {
  float t2 = t * t;
  return t + t * t2 * (-1 / 6.0f + t2 * (1 / 120.0f + t2 * (-1 / 5040.0f + t2 * (1 / 362880.0f))));
}

// Shirley–Chiu concentric map of [0,1)² onto the unit disk: uniform in area, and
// it keeps strata compact (better than the polar map for stratified samplers).
// The angle is π/4 · q/r with r the larger of the two coordinates (in magnitude), so
// only |t| <= π/4 is ever needed; (0.5, 0.5) maps to the centre (r = 0).
inline void concentric_disk(float u, float v, float& x, float& y) {
  constexpr float kQuarterPi = 0.785398163397448309616f;
  float a = 2 * u - 1, b = 2 * v - 1;
  bool wide = std::fabs(a) > std::fabs(b);
  float r = wide ? a : b, q = wide ? b : a;
  // |q| <= |r|, and r = 0 only with q = 0, where 0/0 gives NaN: then t = 0. (Not
  // q / (r != 0 ? r : 1): GCC turns that into a branch, and the loop stays scalar.)
  float ratio = q / r;
  float t = kQuarterPi * (ratio == ratio ? ratio : 0);
  float c = cos_quarter(t), s = sin_quarter(t);
  // wide: φ = t; else φ = π/2 − t, whose cosine and sine are sin t and cos t.
  x = r * (wide ? c : s);
  y = r * (wide ? s : c);
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
    film_x_ = 2 * tan_x_ / (width ? width : 1);
    film_y_ = 2 * tan_y_ / (height ? height : 1);
    lens_radius_ = c.aperture > 0 ? float(c.aperture * 0.5) : 0.0f;
    // The lens direction is d · focal − org, scaled by a positive factor so that
    // neither term can overflow float: 1/focal when the focal distance is at least
    // the lens radius (then |org/focal| <= 1), else 1/radius (then |org/radius| <= 1
    // and focal/radius < 1, floored at 1e-30 so the lens centre's ray stays finite).
    const double fd = c.focal_distance, radius = double(lens_radius_);
    if (fd >= radius) {
      dir_scale_ = 1, org_scale_ = float(1 / fd);
    } else {
      dir_scale_ = std::fmax(float(fd / radius), 1e-30f), org_scale_ = float(1 / radius);
    }
    focal_distance_ = fd;
  }

  bool has_lens() const { return lens_radius_ > 0; }

  // (fx, fy): film position in pixels, (0, 0) the top-left corner of the image.
  // (lens_u, lens_v): the lens sample, used only when the camera has a lens.
  // One ray; the same as generate_block's for the same inputs.
  Ray generate(double fx, double fy, float lens_u = 0.5f, float lens_v = 0.5f) const {
    Ray r;
    generate_block(1, &fx, &fy, &lens_u, &lens_v, &r);
    return r;
  }

  // n <= kMaxBlock rays at once: film points (fx[i], fy[i]) and, with a lens, lens
  // samples (lu[i], lv[i]). The lanes are independent and branch-free, so the loop
  // vectorises; each lane computes exactly what a lone ray would.
  static constexpr std::uint32_t kMaxBlock = 16;
  [[gnu::always_inline]] void generate_block(std::uint32_t n, const double* fx, const double* fy,
                                             const float* lu, const float* lv, Ray* out) const {
    float dx[kMaxBlock], dy[kMaxBlock], dz[kMaxBlock];
    float ox[kMaxBlock] = {}, oy[kMaxBlock] = {}, oz[kMaxBlock] = {};
    for (std::uint32_t i = 0; i < n; ++i) {
      // The film point in double: fx carries a pixel index and a 24-bit fraction.
      float sx = float(fx[i] * film_x_ - tan_x_), sy = float(tan_y_ - fy[i] * film_y_);
      dx[i] = forward_.x + right_.x * sx + up_.x * sy;  // forward component 1
      dy[i] = forward_.y + right_.y * sx + up_.y * sy;
      dz[i] = forward_.z + right_.z * sx + up_.z * sy;
    }
    if (lens_radius_ > 0) {
      for (std::uint32_t i = 0; i < n; ++i) {
        float lx, ly;
        concentric_disk(lu[i], lv[i], lx, ly);
        lx *= lens_radius_, ly *= lens_radius_;
        ox[i] = right_.x * lx + up_.x * ly;
        oy[i] = right_.y * lx + up_.y * ly;
        oz[i] = right_.z * lx + up_.z * ly;
        // Towards the focal plane's point d · focal_distance: d · focal − org, scaled
        // (constructor) and divided by its largest component before it is squared,
        // since with a wide fov its square overflows float (its forward component
        // is dir_scale_ > 0: it is never 0).
        float wx = dx[i] * dir_scale_ - ox[i] * org_scale_;
        float wy = dy[i] * dir_scale_ - oy[i] * org_scale_;
        float wz = dz[i] * dir_scale_ - oz[i] * org_scale_;
        float ax = std::fabs(wx), ay = std::fabs(wy), az = std::fabs(wz);
        float m = ax > ay ? ax : ay;
        m = m > az ? m : az;
        float s = 1 / m;
        wx *= s, wy *= s, wz *= s;
        float inv_len = 1 / std::sqrt(wx * wx + wy * wy + wz * wz);
        dx[i] = wx * inv_len, dy[i] = wy * inv_len, dz[i] = wz * inv_len;
      }
    } else {
      for (std::uint32_t i = 0; i < n; ++i) {
        float len = std::sqrt(dx[i] * dx[i] + dy[i] * dy[i] + dz[i] * dz[i]);
        dx[i] /= len, dy[i] /= len, dz[i] /= len;
      }
    }
    for (std::uint32_t i = 0; i < n; ++i) {
      out[i] = Ray();
      out[i].org = Vec3f(ox[i], oy[i], oz[i]);
      out[i].dir = Vec3f(dx[i], dy[i], dz[i]);
    }
  }

  std::string to_string() const;

 private:
  Vec3f forward_, right_, up_;
  double tan_x_ = 1, tan_y_ = 1;
  double film_x_ = 2, film_y_ = 2;  // d(sx)/d(fx), -d(sy)/d(fy): 2 tan / pixels
  std::uint32_t width_ = 1, height_ = 1;
  float lens_radius_ = 0, dir_scale_ = 1, org_scale_ = 1;
  double focal_distance_ = 1;
};

using PinholeCamera = Camera;  // the name before depth of field

}  // namespace snell::rt
