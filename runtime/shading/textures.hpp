// Colour sources evaluated at a hit (§8, §15): constants and patterns, one overload
// per pattern kind of runtime/ir/kinds.def (the value patterns share one, over
// runtime/pattern/patterns.hpp). Points arrive camera-relative in float and are
// taken back to world space in double here.
#pragma once

#include <cmath>
#include <utility>
#include <variant>

#include "runtime/ir/ir.hpp"
#include "runtime/pattern/patterns.hpp"
#include "runtime/pattern/program_eval.hpp"
#include "runtime/shading/image_texture.hpp"
#include "runtime/shading/surface_uv.hpp"
#include "runtime/vec.hpp"

namespace snell::rt {

// The parity of floor(x) for every finite x, without converting a huge x to an
// integer (undefined behaviour past 2^63): every double of magnitude >= 2^53 is an
// even integer. (A checker of size 1e-9 seen 1e10 away has cell indices ~1e19.)
inline int floor_parity(double x) {
  double f = std::floor(x);
  if (!(std::fabs(f) < 9007199254740992.0)) return 0;
  return int(static_cast<long long>(f) & 1);
}

// Where a pattern is looked up: the camera-relative hit point, the outward normal,
// the world point of the camera-relative origin, and for `space "object"` the
// object hit (the top-level object: a CSG object's or an instance's own space) and
// the ray's time (its motion).
struct TexturePoint {
  Vec3f p, n_out;
  ir::Vec3 origin;
  const ir::Shape* shape = nullptr;
  float time = 0;
  std::uint64_t* nonfinite = nullptr;  // counts shading functions' non-finite values
  // §17 images: the render's texture system (null: images are black), the unit
  // direction of the ray that hit, and the width in world units of the pixel's
  // footprint across that ray at p (0: a point lookup). A background's point is
  // the direction itself, with n_out = 0 and the footprint the pixel's angle.
  const ImageTextures* images = nullptr;
  Vec3f dir{};
  float footprint = 0;
  // §17 mapping "uv": the hit's surface (null: a background, or no image maps "uv").
  const SurfaceFrame* surface = nullptr;
  // §12: the motion of the CSG leaf hit, in its CSG object's space, when it moves
  // inside that object (null: it does not).
  const ir::Motion* leaf_motion = nullptr;
};

// The length in world units of one unit of the space a pattern is evaluated in
// (the cube root of its volume scale): §15 moves the point inward by 1e-4 of it.
inline double unit_length(const ir::Mat4& world_from_space) {
  const ir::Mat4& m = world_from_space;
  double det = m(0, 0) * (m(1, 1) * m(2, 2) - m(1, 2) * m(2, 1)) -
               m(0, 1) * (m(1, 0) * m(2, 2) - m(1, 2) * m(2, 0)) +
               m(0, 2) * (m(1, 0) * m(2, 1) - m(1, 1) * m(2, 0));
  return std::cbrt(std::fabs(det));
}

// The space a pattern is evaluated in, seen from the world: the object's (space
// "object") and then the pattern's transforms, and the length in world units of
// one of its units. Identity when neither applies.
struct PatternFrame {
  ir::Transform space_from_world;
  bool identity = true;
  double unit = 1;
};
inline PatternFrame pattern_frame(const ir::Texture& t, const TexturePoint& tp) {
  PatternFrame f;
  bool moved = !t.world_from_pattern.is_identity();
  bool object = t.space == ir::PatternSpace::Object && tp.shape;
  if (object) {
    const ir::Shape& sh = *tp.shape;
    const ir::Transform& placed =
        sh.in_object() ? sh.object_space().world_from_object : sh.world_from_object();
    const ir::Motion& motion = sh.in_object() ? sh.object_space().motion : sh.motion();
    ir::Transform world_from_object = motion.empty() ? placed : motion.at(double(tp.time)) * placed;
    // A CSG leaf that moves inside its object carries the object's space along
    // with it (the space is the object's where the leaf stands at shutter open).
    if (tp.leaf_motion) world_from_object = world_from_object * tp.leaf_motion->at(double(tp.time));
    f.space_from_world = world_from_object.inverse();
  }
  if (moved) f.space_from_world = t.world_from_pattern.inverse() * f.space_from_world;
  f.identity = !(object || moved);
  if (!f.identity) f.unit = unit_length(f.space_from_world.inv);
  return f;
}

// The world hit point moved inward by size / divisor of the pattern's unit
// (written so, a checker's S/100 rounds as it always did).
inline ir::Vec3 inward_point(const TexturePoint& tp, double size, double divisor, double unit) {
  const ir::Vec3 o = tp.origin;
  const Vec3f p = tp.p, n = tp.n_out;
  return {double(p.x) + o.x - n.x * size / divisor * unit,
          double(p.y) + o.y - n.y * size / divisor * unit,
          double(p.z) + o.z - n.z * size / divisor * unit};
}

// The point a pattern is evaluated at: the inward point in the pattern's space.
// Identity frames cost nothing and change no bit (a checker renders as it did
// before §15).
inline ir::Vec3 pattern_point(const ir::Texture& t, const TexturePoint& tp, double size,
                              double divisor) {
  // Without a frame, no frame is made: its two identity matrices were 2 % of the
  // glass bench (a checker floor).
  if (!(t.space == ir::PatternSpace::Object && tp.shape) && t.world_from_pattern.is_identity())
    return inward_point(tp, size, divisor, 1);
  PatternFrame f = pattern_frame(t, tp);
  ir::Vec3 w = inward_point(tp, size, divisor, f.unit);
  return f.identity ? w : f.space_from_world.point(w);
}

// §15 turbulence: the point displaced by T × a vector fbm before the pattern.
inline ir::Vec3 turbulent(const ir::Texture& t, ir::Vec3 q) {
  if (!(t.turbulence > 0)) return q;
  return q + pattern::vector_fbm(q, int(t.octaves)) * t.turbulence;
}

inline Color pattern_color(const ir::Constant& c, const ir::Texture&, const TexturePoint&) {
  return to_float(c.color.x, c.color.y, c.color.z);
}

// A checker's cell parity at a point of its space: 0 where i + j + k is even.
inline int checker_parity(const ir::Checker& c, ir::Vec3 w) {
  double s = c.size;
  // i + j + k is even exactly when the three parities cancel.
  return floor_parity(w.x / s) ^ floor_parity(w.y / s) ^ floor_parity(w.z / s);
}

// §8 checker: p (world space) moved inward by S/100 along the outward normal, cell
// floor(p / S), even i + j + k takes color1 (or the colour map's colour at 0).
inline Color pattern_color(const ir::Checker& c, const ir::Texture& t, const TexturePoint& tp) {
  int odd = checker_parity(c, turbulent(t, pattern_point(t, tp, c.size, 100)));
  const ir::Vec3 k = !t.color_map.empty() ? pattern::map_color(t.color_map, odd)
                     : odd == 0           ? c.color1
                                          : c.color2;
  return to_float(k.x, k.y, k.z);
}

// §15 `pattern { function f }`: f at the point (and the normal, taken into the
// pattern's space as normals are, when f reads it); clamped to [0, 1], 0 and
// counted where it is not finite.
inline double function_value(const ir::FunctionPattern& f, const PatternFrame& frame, ir::Vec3 q,
                             const TexturePoint& tp) {
  ir::Vec3 n{tp.n_out.x, tp.n_out.y, tp.n_out.z};
  // A background has no normal: n is 0 there, and stays 0 through the pattern's
  // transforms (normalised, it was NaN: a rotated sky of f(p, n) went black).
  if (f.program.reads_normal && !frame.identity && (n.x != 0 || n.y != 0 || n.z != 0)) {
    const ir::Mat4& m = frame.space_from_world.inv;  // world_from_space: transposed for normals
    n = ir::normalize(ir::Vec3{m(0, 0) * n.x + m(1, 0) * n.y + m(2, 0) * n.z,
                               m(0, 1) * n.x + m(1, 1) * n.y + m(2, 1) * n.z,
                               m(0, 2) * n.x + m(1, 2) * n.y + m(2, 2) * n.z});
  }
  bool finite = true;
  double v = pattern::run_program(f.program, q, n, finite);
  if (!finite && tp.nonfinite) ++*tp.nonfinite;
  return pattern::pattern_value(v, finite);
}

// A pattern's value at a point q of its own space (before turbulence), one overload
// per kind: what a colour map colours and a bump differentiates. A checker's is 0
// in even cells and 1 in odd ones, a constant's 0, an image's its luminance.
// `frame` and `tp` serve shading functions (their normal, the --stats count) and
// images (the texture system).
inline double kind_value(const ir::Constant&, const ir::Texture&, ir::Vec3, const PatternFrame&,
                         const TexturePoint&) {
  return 0.0;
}
inline double kind_value(const ir::Checker& c, const ir::Texture& t, ir::Vec3 q,
                         const PatternFrame&, const TexturePoint&) {
  return double(checker_parity(c, turbulent(t, q)));
}
inline double kind_value(const ir::FunctionPattern& f, const ir::Texture& t, ir::Vec3 q,
                         const PatternFrame& frame, const TexturePoint& tp) {
  return function_value(f, frame, turbulent(t, q), tp);
}
// §17 "uv": the surface's (u, v) at world point w, as the point (u, v, 0) through
// the pattern's transforms and turbulence.
inline ImageUV surface_coords(const ir::Texture& t, const SurfaceFrame& s, ir::Vec3 w) {
  ImageUV uv = surface_uv(s, w);
  ir::Vec3 q{uv.u, uv.v, 0};
  if (!t.world_from_pattern.is_identity()) q = t.world_from_pattern.inverse().point(q);
  q = turbulent(t, q);
  return {q.x, q.y};
}
inline bool maps_surface(const ir::ImageTexture& im, const TexturePoint& tp) {
  return im.mapping == ir::ImageMapping::Uv && tp.surface;
}

inline double kind_value(const ir::ImageTexture& im, const ir::Texture& t, ir::Vec3 q,
                         const PatternFrame& frame, const TexturePoint& tp) {
  if (!tp.images) return 0.0;
  ImageUV uv;
  if (!maps_surface(im, tp))
    uv = image_uv(im.mapping, turbulent(t, q));
  else  // q back to the world: "uv" takes the pattern's transforms in (u, v)
    uv = surface_coords(t, *tp.surface,
                        frame.identity ? q : frame.space_from_world.inverse().point(q));
  Color c = tp.images->lookup(im.image, uv.u, uv.v, 0, 0, 0, 0, im.repeat, im.mapping);
  return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z;
}
// A value pattern whose arithmetic overflows at a point (its own coordinates past
// ~1e154, where a length or a dot product is infinite) is 0 there: §15's
// patterns map to [0, 1], and a NaN would drop the whole sample.
template <class K>
double kind_value(const K& kind, const ir::Texture& t, ir::Vec3 q, const PatternFrame&,
                  const TexturePoint&) {
  const double v = pattern::value(kind, turbulent(t, q), int(t.octaves));
  return std::isfinite(v) ? v : 0.0;
}

inline double value_at(const ir::Texture& t, ir::Vec3 q, const PatternFrame& frame,
                       const TexturePoint& tp) {
  return std::visit([&](const auto& kind) { return kind_value(kind, t, q, frame, tp); }, t.pattern);
}

// §15's value patterns and shading functions: the value at the hit's pattern
// point, through the colour map.
template <class K>
double pattern_value(const K& kind, const ir::Texture& t, const TexturePoint& tp) {
  PatternFrame f = pattern_frame(t, tp);
  ir::Vec3 w = inward_point(tp, 1, 1e4, f.unit);
  return kind_value(kind, t, f.identity ? w : f.space_from_world.point(w), f, tp);
}
template <class K>
Color pattern_color(const K& kind, const ir::Texture& t, const TexturePoint& tp) {
  ir::Vec3 k = pattern::map_color(t.color_map, pattern_value(kind, t, tp));
  return to_float(k.x, k.y, k.z);
}

// §17 image: the colour at (u, v) of the mapping at the pattern point (the colour
// map is not used). The filter's footprint: two vectors of the footprint's width
// across the ray, carried onto the surface along the ray (the pixel's ray
// differentials at the hit, for a pinhole camera; the carried length is capped at
// 50 widths at grazing angles, where OIIO's anisotropy limit of 32 blurs anyway),
// taken into the pattern's space and through the mapping by differences.
inline Color pattern_color(const ir::ImageTexture& im, const ir::Texture& t,
                           const TexturePoint& tp) {
  if (!tp.images) return Color(0.0f);
  PatternFrame f = pattern_frame(t, tp);
  auto to_space = [&](ir::Vec3 x) { return f.identity ? x : f.space_from_world.point(x); };
  ir::Vec3 w = inward_point(tp, 1, 1e4, f.unit);
  auto coords = [&](ir::Vec3 x) {
    return maps_surface(im, tp) ? surface_coords(t, *tp.surface, x)
                                : image_uv(im.mapping, turbulent(t, to_space(x)));
  };
  ImageUV uv = coords(w);
  float d[4] = {0, 0, 0, 0};
  if (tp.footprint > 0) {
    ir::Vec3 dir{tp.dir.x, tp.dir.y, tp.dir.z};
    ir::Vec3 n{tp.n_out.x, tp.n_out.y, tp.n_out.z};
    ir::Vec3 a = ir::normalize(std::fabs(dir.x) < 0.9 ? ir::cross(dir, ir::Vec3{1, 0, 0})
                                                      : ir::cross(dir, ir::Vec3{0, 1, 0}));
    ir::Vec3 b = ir::cross(dir, a);
    double cos = ir::dot(dir, n);
    for (int k = 0; k < 2; ++k) {
      ir::Vec3 dw = (k == 0 ? a : b) * double(tp.footprint);
      if (cos != 0) {  // along the ray onto the tangent plane
        double c = std::fabs(cos) < 0.02 ? std::copysign(0.02, cos) : cos;
        dw = dw - dir * (ir::dot(dw, n) / c);
      }
      ImageUV uv2 = coords(w + dw);
      double du = uv2.u - uv.u;
      if (wraps_around(im.mapping)) du -= std::round(du);
      d[2 * k] = float(du);
      d[2 * k + 1] = float(uv2.v - uv.v);
    }
  }
  return tp.images->lookup(im.image, uv.u, uv.v, d[0], d[1], d[2], d[3], im.repeat, im.mapping);
}

inline Color texture_color(const ir::Texture& t, const TexturePoint& tp) {
  return std::visit([&](const auto& pattern) { return pattern_color(pattern, t, tp); }, t.pattern);
}

}  // namespace snell::rt
