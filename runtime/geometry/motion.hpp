// Motion (§8) as the geometry sees it: an object's camera-relative transform at a
// shutter fraction, and how finely a moving triangle shape must be stepped.
#pragma once

#include <vector>

#include "runtime/ir/ir.hpp"

namespace snell::rt::geom {

// The object's transform at shutter fraction u, camera-relative.
ir::Transform rel_at(const ir::Shape& s, ir::Vec3 origin, double u);

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
unsigned motion_segments(const ir::Shape& s, const std::vector<ir::Vec3>& verts, ir::Vec3 origin);

}  // namespace snell::rt::geom
