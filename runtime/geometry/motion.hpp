// Motion (§8) as the geometry sees it: an object's camera-relative transform at a
// shutter fraction, and how finely a moving triangle shape must be stepped.
#pragma once

#include <optional>
#include <vector>

#include "runtime/geometry/xform.hpp"
#include "runtime/ir/ir.hpp"

namespace snell::rt::geom {

// The object's transform at shutter fraction u, camera-relative.
ir::Transform rel_at(const ir::Shape& s, ir::Vec3 origin, double u);
// rel_at(s, origin, u).inv, the same bits, computing no forward matrix.
ir::Mat4 rel_from_object_inverse_at(const ir::Shape& s, ir::Vec3 origin, double u);

// Clamps a ray time to the shutter (robustness #32).
inline double shutter_fraction(float time) {
  return ir::min_num(1.0, ir::max_num(0.0, double(time)));
}

// Time steps for a moving triangle shape: Embree interpolates vertices linearly
// between steps, exact for pure translation (2 steps). Rotation and scale bend the
// paths, so segments are doubled until every checked vertex's positions a quarter,
// half and three quarters into each segment are within 1e-4 of the shape's size of
// the linear interpolation (from first_segments on), at most 128
// segments (129 steps, Embree's limit): a 90° turn takes 64 segments; a turn beyond
// ~230° keeps a chord error above 1e-4 (documented limit).
// The box of a moving shape: the union of its boxes at 65 times u in [0, 1], grown
// by the largest distance a corner moves between two neighbouring times (a corner's
// path between samples stays within that of the chord). `rel_at(u)`: the placement
// at u (ir::Mat4); `corners(f)`: f(point) for the points whose hull holds the shape.
template <class At, class Corners>
void swept_bounds(At&& rel_at_u, Corners&& corners, Box3& box) {
  constexpr int kSteps = 64;
  std::vector<Vec3> prev;
  double pad = 0;
  for (int i = 0; i <= kSteps; ++i) {
    ir::Mat4 rel = rel_at_u(double(i) / kSteps);
    std::size_t c = 0;
    corners([&](Vec3 q) {
      Vec3 w = xform_point(rel, q);
      box.grow(w);
      if (i == 0)
        prev.push_back(w);
      else
        pad = ir::max_num(pad, ir::length(w - prev[c])), prev[c] = w;
      ++c;
    });
  }
  for (int k = 0; k < 3; ++k) box.lo[k] -= pad, box.hi[k] += pad;
}

// The most a motion turns over the shutter, in degrees (the sum of its rotations).
double turn_degrees(const ir::Motion& m);
// The most turn the segments of moving triangles and instances follow: 128 segments
// of 90° each. A faster spin is traced wrong (scene_warnings says so).
inline constexpr double kMaxFollowedTurn = 128 * 90.0;

// The fewest segments a motion's turns allow: a power of 2 (at most 128) with each
// segment turning at most 90°. Sampled errors alone cannot see whole turns: a box
// spinning 720° stands in the same place at the open, middle and close of the
// shutter (it was traced standing still).
unsigned first_segments(const ir::Motion& m);

// The number of equal segments of the shutter (a power of 2, at most 128, Embree's
// limit being 129 time steps) over which Embree's linear interpolation of `verts`
// placed by s's motion stays within `tolerance` × the shape's size of the exact
// path. A moving mesh takes 1e-4: its hits are o + t·d on what Embree traces. A
// moving instance takes 1e-6: its hits are resolved with the exact placement at the
// ray's time, and where the two differ a ray that grazes a CSG rim was shaded as
// the wrong surface (a spinning wheel's rims speckled at 1e-4).
unsigned motion_segments(const ir::Shape& s, const std::vector<ir::Vec3>& verts, ir::Vec3 origin,
                         double tolerance = 1e-4);

// A placement as Embree's quaternion motion takes it: p' = T·R·(U·p + shift), U
// upper triangular (scale and skew), R the rotation of the unit quaternion q (r, i,
// j, k), T a translation. Embree interpolates U, shift and T linearly between time
// steps and q along the shorter arc (slerp), so a turn about a fixed axis through
// `centre` (the shift puts it at the origin of R) is followed exactly however far
// it turns, where interpolated matrices cut the arc's chord.
struct QuatPlacement {
  double u[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  Vec3 shift{0, 0, 0}, translation{0, 0, 0};
  double q[4] = {1, 0, 0, 0};
};
// m's linear part as R·U (Gram–Schmidt, R proper: a mirror goes into U's last
// diagonal entry), about `centre` (object space). Empty when m has no such form (a
// linear part that is singular or not finite).
std::optional<QuatPlacement> quat_placement(const ir::Mat4& m, Vec3 centre);
ir::Mat4 quat_matrix(const QuatPlacement& p);
// What Embree places between steps a and b at fraction f.
QuatPlacement quat_between(const QuatPlacement& a, const QuatPlacement& b, double f);

// The time steps of a moving instance in quaternion form, as few (a power of 2 up to
// 128 segments) as keep the interpolated placement of `corners` within `tolerance`
// × the shape's size of the exact one, checked at a quarter, half and three
// quarters of every segment, with every segment turning less than 90° (a half turn
// has no shorter arc). Empty when some placement has no quaternion form.
std::vector<QuatPlacement> quat_motion_steps(const ir::Shape& s, const std::vector<Vec3>& corners,
                                             Vec3 centre, Vec3 origin, double tolerance);

}  // namespace snell::rt::geom
