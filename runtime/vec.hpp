// Float vectors for the hot path. The IR is double; the runtime converts to float
// only after moving the world so the camera sits at the origin (ir.hpp), so float
// precision is spent where the picture is.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>

namespace snell::rt {

struct Vec3f {
  float x = 0, y = 0, z = 0;
  constexpr Vec3f() = default;
  constexpr Vec3f(float a, float b, float c) : x(a), y(b), z(c) {}
  constexpr explicit Vec3f(float s) : x(s), y(s), z(s) {}
  constexpr float operator[](int i) const { return i == 0 ? x : i == 1 ? y : z; }
  constexpr float& operator[](int i) { return i == 0 ? x : i == 1 ? y : z; }
};

constexpr Vec3f operator+(Vec3f a, Vec3f b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
constexpr Vec3f operator-(Vec3f a, Vec3f b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
constexpr Vec3f operator-(Vec3f a) {
  return {-a.x, -a.y, -a.z};
}
constexpr Vec3f operator*(Vec3f a, Vec3f b) {
  return {a.x * b.x, a.y * b.y, a.z * b.z};
}
constexpr Vec3f operator*(Vec3f a, float s) {
  return {a.x * s, a.y * s, a.z * s};
}
constexpr Vec3f operator*(float s, Vec3f a) {
  return a * s;
}
constexpr Vec3f operator/(Vec3f a, float s) {
  return {a.x / s, a.y / s, a.z / s};
}
constexpr Vec3f& operator+=(Vec3f& a, Vec3f b) {
  return a = a + b;
}
constexpr Vec3f& operator*=(Vec3f& a, Vec3f b) {
  return a = a * b;
}
constexpr float dot(Vec3f a, Vec3f b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
constexpr Vec3f cross(Vec3f a, Vec3f b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline float length(Vec3f a) {
  return std::sqrt(dot(a, a));
}
inline Vec3f normalize(Vec3f a) {
  return a / length(a);
}
// std::fmax and std::nextafter towards ±infinity on float, inline: GCC calls libm
// for both (2 % of a thin-lens render). The same results as glibc's x86-64 fmaxf
// (maxss when ordered: a > b ? a : b, so of ±0 the second; the other operand when
// one is a quiet NaN, NaN when one is signalling) and nextafterf, bit for bit, for
// every input but NaN payloads (test_vec.cpp checks them against libm, ±0, ±inf,
// subnormals and NaN included). Floating-point exception flags are not kept.
inline bool is_signalling_nan(float x) {
  std::uint32_t u;
  std::memcpy(&u, &x, 4);
  return (u & 0x7f800000u) == 0x7f800000u && (u & 0x007fffffu) && !(u & 0x00400000u);
}
inline float fmax_f(float a, float b) {
  if (a != a || b != b) {  // IEEE 754-2008 maxNum: a signalling NaN gives NaN
    if (is_signalling_nan(a) || is_signalling_nan(b)) return a + b;
    return a != a ? b : a;
  }
  return a > b ? a : b;
}
// The next float above x (nextafterf(x, +inf)): +inf stays, NaN stays NaN.
inline float next_up(float x) {
  if (x != x || x == INFINITY) return x + x;
  if (x == 0) return 0x1p-149f;  // from either zero
  std::int32_t bits;
  std::memcpy(&bits, &x, 4);
  bits += x > 0 ? 1 : -1;
  float r;
  std::memcpy(&r, &bits, 4);
  return r;
}
// The next float below x (nextafterf(x, -inf)).
inline float next_down(float x) {
  return -next_up(-x);
}
inline float max_component(Vec3f a) {
  return fmax_f(a.x, fmax_f(a.y, a.z));
}
inline float max_abs(Vec3f a) {
  return fmax_f(std::fabs(a.x), fmax_f(std::fabs(a.y), std::fabs(a.z)));
}
inline bool is_finite(Vec3f a) {
  return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z);
}

// Colours share the vector type: linear RGB radiance or a per-channel weight.
using Color = Vec3f;

// The Wächter–Binder offset (Ray Tracing Gems ch. 6): move a hit point `p` off its
// surface along the unit normal `n` (pointing to the side the new ray leaves on) by
// a fixed number of ulps of each coordinate, or by a tiny absolute step near zero
// where ulps vanish. Scale-aware: no scene-size epsilon. Limits: assumes `p` is
// within a few hundred ulps of the true surface (true for our hit points, which are
// o + t·d with the camera at the origin) and that n is unit length.
[[gnu::always_inline]] inline float offset_coord(float p, float n, float scale) {
  const float origin = scale * (1.0f / 32.0f);
  const float float_scale = scale * (1.0f / 65536.0f);
  constexpr float kIntScale = 256.0f;
  if (std::fabs(p) < origin) return p + float_scale * n;
  std::int32_t of = static_cast<std::int32_t>(kIntScale * n);
  std::int32_t bits;
  std::memcpy(&bits, &p, 4);
  bits += (p < 0) ? -of : of;
  float r;
  std::memcpy(&r, &bits, 4);
  return r;
}
// `scale` is the scene's size around the camera, at most 1 (Integrator computes
// it). Wächter and Binder's constants assume scenes of unit size: near the origin
// they switch to a fixed step of 2^-16, which is larger than the features of a
// scene 1e-3 units across (robustness #2, #4). Scaling the switch point and that
// step with the scene keeps every scene of size >= 1 bit-identical to the
// published method and makes tiny scenes behave like unit ones.
[[gnu::always_inline]] inline Vec3f offset_ray_origin(Vec3f p, Vec3f n, float scale = 1.0f) {
  return {offset_coord(p.x, n.x, scale), offset_coord(p.y, n.y, scale),
          offset_coord(p.z, n.z, scale)};
}
// The Wächter–Binder scale for a point whose rounding comes from coordinates of at
// most `reach` (camera-relative): the scene's size around the camera, or less for a
// point much nearer the camera than that. With the scene's size alone, points near
// the camera of a tiny subject in a large scene (a 1e-6 scene with one light a unit
// away) took the fixed near-origin step of 2^-16, fifteen times the subject: its
// area light's shadow rays ended past the light (a black image), moving shapes
// near the camera lit nothing. Scenes whose points are all beyond 1/32 of the
// scene's size keep the scene's scale, to the bit.
[[gnu::always_inline]] inline float near_scale(float scale, float reach) {
  return std::fmin(scale, std::fmax(32.0f * reach, 0x1p-100f));
}

// An orthonormal basis around unit `n` (Duff et al. 2017, JCGT 6(1)): no
// singularity, accurate near n = (0, 0, -1).
inline void orthonormal_basis(Vec3f n, Vec3f& b1, Vec3f& b2) {
  float sign = std::copysign(1.0f, n.z);
  float a = -1.0f / (sign + n.z);
  float b = n.x * n.y * a;
  b1 = {1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x};
  b2 = {b, sign + n.y * n.y * a, -n.y};
}

inline Vec3f to_float(double x, double y, double z) {
  return {static_cast<float>(x), static_cast<float>(y), static_cast<float>(z)};
}

std::string to_string(Vec3f v);

}  // namespace snell::rt
