// A packet's shadow rays against one static plane at once (the planes are tested
// before the BVH query of an area light's 16-ray shadow packet, embree_scene.cpp),
// and a packet's camera rays after their BVH query,
// in the widest double SIMD the CPU has, chosen once at start-up. The same IEEE
// operations in the same order as the one-ray test (PlaneSet::hit_plane; for
// shadow rays with tnear 0, tmax kAreaShadowEnd and no tie), lane by lane, with no FMA contraction
// (the file is compiled with -ffp-contract=off), so every lane's answer is the one-ray test's:
// tests/runtime/test_plane_lanes.cpp checks each path the CPU offers against it. The one-ray test
// was a fifth of a thin-lens render over a floor.
//
// - avx512: AVX-512 F + VL, eight doubles at a time.
// - avx2: AVX2 (x86-64-v3), four doubles at a time.
// - none: the caller tests lane by lane (SNELL_SIMD=generic forces it).
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "runtime/geometry/ray.hpp"
#include "runtime/ir/math.hpp"

namespace snell::rt::geom {

// The lanes of `live` (bit i: lane i) whose segment the plane dot(n, x) = d
// (camera-relative, n unit) crosses: what PlaneSet::occluded says of each ray.
using PlaneLanesFn = std::uint32_t (*)(ir::Vec3 n, double d, const ShadowLanes16& rays,
                                       std::uint32_t live);

// The best path for this CPU, or null (test lane by lane).
PlaneLanesFn plane_lanes();
// Every path this build and CPU have, best first, by name (tests).
std::vector<std::pair<std::string, PlaneLanesFn>> plane_lanes_paths();

// A packet of 16 rays (SoA, camera-relative float, tnear per lane; Embree's
// RTCRay16 layout) for the nearest-hit query.
struct PlaneRayLanes {
  const float *ox, *oy, *oz, *dx, *dy, *dz, *tnear;
};
// The lanes of `live` whose ray hits the static plane dot(n, x) = d before
// tmax[i] (or within tie[i], a distance along the normal, beyond it): for those
// lanes tmax[i] becomes the hit's t and tie[i] 0. One step of
// PlaneSet::intersect's loop over its planes, lane by lane.
using PlaneHitLanesFn = std::uint32_t (*)(ir::Vec3 n, double d, const PlaneRayLanes& rays,
                                          std::uint32_t live, double* tmax, double* tie);
PlaneHitLanesFn plane_hit_lanes();
std::vector<std::pair<std::string, PlaneHitLanesFn>> plane_hit_lanes_paths();

}  // namespace snell::rt::geom
