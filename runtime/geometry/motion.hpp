// Motion (§8) as the geometry sees it: an object's camera-relative transform at a
// shutter fraction, and how finely a moving triangle shape must be stepped.
#pragma once

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
  return std::fmin(1.0, std::fmax(0.0, double(time)));
}

// Time steps for a moving triangle shape: Embree interpolates vertices linearly
// between steps, exact for pure translation (2 steps). Rotation and scale bend the
// paths, so segments are doubled until every checked vertex's mid-segment position
// is within 1e-4 of the shape's size of the linear interpolation, at most 128
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
        pad = std::fmax(pad, ir::length(w - prev[c])), prev[c] = w;
      ++c;
    });
  }
  for (int k = 0; k < 3; ++k) box.lo[k] -= pad, box.hi[k] += pad;
}

// The number of equal segments of the shutter (a power of 2, at most 128, Embree's
// limit being 129 time steps) over which Embree's linear interpolation of `verts`
// placed by s's motion stays within `tolerance` × the shape's size of the exact
// path. A moving mesh takes 1e-4: its hits are o + t·d on what Embree traces. A
// moving instance takes 1e-6: its hits are resolved with the exact placement at the
// ray's time, and where the two differ a ray that grazes a CSG rim was shaded as
// the wrong surface (a spinning wheel's rims speckled at 1e-4).
unsigned motion_segments(const ir::Shape& s, const std::vector<ir::Vec3>& verts, ir::Vec3 origin,
                         double tolerance = 1e-4);

}  // namespace snell::rt::geom
