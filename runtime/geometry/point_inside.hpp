// Whether a world point lies inside a top-level shape of the scene: a solid
// primitive, a closed mesh, a CSG object (by its tree: merge and union are the
// same solid, a difference its first child less the others) or an instance
// (inside any part of its value). The camera's checks and its starting §14
// interior both ask it. Limits: shapes are tested where they rest (the shutter-
// open placement); open shapes, discs, triangles and open meshes have no inside.
#pragma once

#include "runtime/ir/ir.hpp"

namespace snell::rt::geom {

enum class InsideRule {
  // As an object a user sees: a top-level plane is a floor, nothing is inside
  // it, and a shape that moves has no one inside to test (the camera warning).
  Object,
  // As a medium: a top-level plane is the half-space below it (the sea), and a
  // moving shape is tested at shutter open (a camera ray's starting interior).
  Medium,
};

bool point_inside(const ir::Scene& scene, const ir::Shape& shape, ir::Vec3 world_point,
                  InsideRule rule);
// Whether the world point lies inside one part of an instance (§14: each part of
// an instance is a solid of its own).
bool point_inside_part(const ir::Scene& scene, const ir::Shape& instance, const ir::Shape& part,
                       ir::Vec3 world_point, InsideRule rule);

}  // namespace snell::rt::geom
