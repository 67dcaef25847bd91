// Double-precision vectors and affine transforms for the IR (the runtime keeps its
// own float types for the hot path). Header-only, no dependencies.
#pragma once

#include <array>
#include <cmath>
#include <string>

namespace snell::ir {

struct Vec3 {
  double x = 0, y = 0, z = 0;
  constexpr Vec3() = default;
  constexpr Vec3(double a, double b, double c) : x(a), y(b), z(c) {}
  constexpr explicit Vec3(double s) : x(s), y(s), z(s) {}
  constexpr double operator[](int i) const { return i == 0 ? x : i == 1 ? y : z; }
  constexpr double& operator[](int i) { return i == 0 ? x : i == 1 ? y : z; }
  constexpr bool operator==(const Vec3&) const = default;
};

constexpr Vec3 operator+(Vec3 a, Vec3 b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
constexpr Vec3 operator-(Vec3 a, Vec3 b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
constexpr Vec3 operator-(Vec3 a) {
  return {-a.x, -a.y, -a.z};
}
constexpr Vec3 operator*(Vec3 a, Vec3 b) {
  return {a.x * b.x, a.y * b.y, a.z * b.z};
}
constexpr Vec3 operator*(Vec3 a, double s) {
  return {a.x * s, a.y * s, a.z * s};
}
constexpr Vec3 operator*(double s, Vec3 a) {
  return a * s;
}
constexpr Vec3 operator/(Vec3 a, double s) {
  return {a.x / s, a.y / s, a.z / s};
}
constexpr double dot(Vec3 a, Vec3 b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
constexpr Vec3 cross(Vec3 a, Vec3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
// Forced inline: GCC kept normalize out of line in the sphere test once the
// callers grew (4 % of a glass render in calls).
[[gnu::always_inline]] inline double length(Vec3 a) {
  return std::sqrt(dot(a, a));
}
// std::fmin and std::fmax (a NaN operand is ignored), inline and with the answers
// of glibc's x86-64 code (minsd, maxsd: of equal operands, ±0 included, the
// second): GCC calls libm for them, as it must honour NaNs and signed zeros, and
// the calls were 5 % of a render of CSG cones. test_shapes.cpp holds the two
// together on the machine that runs it, calling libm through a pointer: GCC takes
// fmin as commutative and may swap the operands of a direct call, so which of two
// equal zeros such a call gives is the compiler's choice.
[[gnu::always_inline]] inline double min_num(double x, double y) {
  if (x < y) return x;
  return y != y ? x : y;
}
[[gnu::always_inline]] inline double max_num(double x, double y) {
  if (x > y) return x;
  return y != y ? x : y;
}
// sqrt(x² + y²), as std::hypot but without its scaling where x² + y² can neither
// overflow nor underflow: within 1.25 ulps (hypot: under 1), at a fraction of
// glibc's cost (it was a quarter of a render of tori, whose root finder asks for
// it at every step). Outside [2^-900, 2^900], and for NaN, std::hypot itself.
[[gnu::always_inline]] inline double hypot_fast(double x, double y) {
  const double s = x * x + y * y;
  if (s >= 0x1p-900 && s <= 0x1p900) [[likely]]
    return std::sqrt(s);
  return std::hypot(x, y);
}
[[gnu::always_inline]] inline Vec3 normalize(Vec3 a) {
  return a / length(a);
}
inline double max_component(Vec3 a) {
  return std::fmax(a.x, std::fmax(a.y, a.z));
}
inline bool is_finite(Vec3 a) {
  return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z);
}

// Row-major 4x4 matrix of an affine transform; the last row is (0, 0, 0, 1).
struct Mat4 {
  std::array<double, 16> m{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  constexpr double operator()(int r, int c) const { return m[r * 4 + c]; }
  constexpr double& operator()(int r, int c) { return m[r * 4 + c]; }
  constexpr bool operator==(const Mat4&) const = default;
};

constexpr Mat4 operator*(const Mat4& a, const Mat4& b) {
  Mat4 r;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      double s = 0;
      for (int k = 0; k < 4; ++k) s += a(i, k) * b(k, j);
      r(i, j) = s;
    }
  return r;
}

// An affine transform with its inverse. Named by the spaces it joins, as pbrt does:
// `world_from_object` maps object-space points to world space.
struct Transform {
  Mat4 m;
  Mat4 inv;

  static Transform translate(Vec3 t);
  static Transform scale(Vec3 s);
  static Transform rotate_x(double degrees);
  static Transform rotate_y(double degrees);
  static Transform rotate_z(double degrees);
  // x, then y, then z (§8 `rotate V`).
  static Transform rotate_xyz(Vec3 degrees);

  bool is_identity() const { return m == Mat4{}; }
  Transform inverse() const { return {inv, m}; }
  Vec3 point(Vec3 p) const {
    return {m(0, 0) * p.x + m(0, 1) * p.y + m(0, 2) * p.z + m(0, 3),
            m(1, 0) * p.x + m(1, 1) * p.y + m(1, 2) * p.z + m(1, 3),
            m(2, 0) * p.x + m(2, 1) * p.y + m(2, 2) * p.z + m(2, 3)};
  }
  Vec3 vector(Vec3 v) const {
    return {m(0, 0) * v.x + m(0, 1) * v.y + m(0, 2) * v.z,
            m(1, 0) * v.x + m(1, 1) * v.y + m(1, 2) * v.z,
            m(2, 0) * v.x + m(2, 1) * v.y + m(2, 2) * v.z};
  }
  // Normals transform by the inverse transpose.
  Vec3 normal(Vec3 n) const {
    return {inv(0, 0) * n.x + inv(1, 0) * n.y + inv(2, 0) * n.z,
            inv(0, 1) * n.x + inv(1, 1) * n.y + inv(2, 1) * n.z,
            inv(0, 2) * n.x + inv(1, 2) * n.y + inv(2, 2) * n.z};
  }
};

// a * b applies b first, then a.
inline Transform operator*(const Transform& a, const Transform& b) {
  return {a.m * b.m, b.inv * a.inv};
}

// Only the inverse half of a chain of Transform products: (a * b).inv computed as
// operator* computes it (b.inv * a.inv), without the a.m * b.m nobody reads. A
// chain written with these gives the bits of the Transform chain's inv at half
// the matrix products (a moving sphere's object_from_rel at each ray's time).
struct InverseTransform {
  Mat4 inv;
  static InverseTransform of(const Transform& t) { return {t.inv}; }
};
inline InverseTransform operator*(const InverseTransform& a, const InverseTransform& b) {
  return {b.inv * a.inv};
}

inline Transform Transform::translate(Vec3 t) {
  Transform r;
  r.m(0, 3) = t.x, r.m(1, 3) = t.y, r.m(2, 3) = t.z;
  r.inv(0, 3) = -t.x, r.inv(1, 3) = -t.y, r.inv(2, 3) = -t.z;
  return r;
}

inline Transform Transform::scale(Vec3 s) {
  Transform r;
  r.m(0, 0) = s.x, r.m(1, 1) = s.y, r.m(2, 2) = s.z;
  r.inv(0, 0) = 1 / s.x, r.inv(1, 1) = 1 / s.y, r.inv(2, 2) = 1 / s.z;
  return r;
}

namespace detail {
// Exact sin/cos at multiples of 90 degrees so `rotate <0, 90, 0>` gives exact zeros.
inline void sincos_degrees(double deg, double& s, double& c) {
  double q = std::fmod(deg, 360.0);
  if (q < 0) q += 360.0;
  if (q == 0) {
    s = 0;
    c = 1;
    return;
  }
  if (q == 90) {
    s = 1;
    c = 0;
    return;
  }
  if (q == 180) {
    s = 0;
    c = -1;
    return;
  }
  if (q == 270) {
    s = -1;
    c = 0;
    return;
  }
  // Whole turns are taken off exactly first (fmod is exact; below 360 it returns
  // deg itself, so those keep their bits): converting 1e15 + 7 degrees to radians
  // lost the angle to the rounding of the product (cos 2.5e-5 off).
  double r = std::fmod(deg, 360.0) * (3.14159265358979323846 / 180.0);
  s = std::sin(r);
  c = std::cos(r);
}
inline Transform rotation(int axis, double deg) {
  double s, c;
  sincos_degrees(deg, s, c);
  int a = (axis + 1) % 3, b = (axis + 2) % 3;
  Transform r;
  r.m(a, a) = c, r.m(a, b) = -s, r.m(b, a) = s, r.m(b, b) = c;
  r.inv(a, a) = c, r.inv(a, b) = s, r.inv(b, a) = -s, r.inv(b, b) = c;
  return r;
}
}  // namespace detail

inline Transform Transform::rotate_x(double d) {
  return detail::rotation(0, d);
}
inline Transform Transform::rotate_y(double d) {
  return detail::rotation(1, d);
}
inline Transform Transform::rotate_z(double d) {
  return detail::rotation(2, d);
}
inline Transform Transform::rotate_xyz(Vec3 d) {
  return rotate_z(d.z) * rotate_y(d.y) * rotate_x(d.x);
}

// The rigid transform from a frame whose origin is `o` and whose +z is the unit
// vector `w` (x and y from Duff et al.'s basis, JCGT 6(1): no singularity) to the
// space o and w are given in: the local frame of the axial shapes (cylinder, cone,
// disc). Its inverse is exact up to rounding (the transpose).
inline Transform axis_frame(Vec3 o, Vec3 w) {
  double sign = std::copysign(1.0, w.z);
  double a = -1.0 / (sign + w.z), b = w.x * w.y * a;
  Vec3 u{1 + sign * w.x * w.x * a, sign * b, -sign * w.x};
  Vec3 v{b, sign + w.y * w.y * a, -w.y};
  Transform t;
  const Vec3 cols[3] = {u, v, w};
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) t.m(r, c) = cols[c][r], t.inv(c, r) = cols[c][r];
  for (int r = 0; r < 3; ++r) t.m(r, 3) = o[r], t.inv(r, 3) = -dot(cols[r], o);
  return t;
}

std::string to_string(Vec3 v);
std::string to_string(const Transform& t);

}  // namespace snell::ir
