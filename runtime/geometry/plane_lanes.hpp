// A packet's shadow rays against one static plane at once (the planes are tested
// before the BVH query of an area light's 16-ray shadow packet, embree_scene.cpp),
// in the widest double SIMD the CPU has, chosen once at start-up. The same IEEE
// operations in the same order as the one-ray test (PlaneSet::hit_plane with tnear
// 0, tmax kAreaShadowEnd and no tie), lane by lane, with no FMA contraction (the
// file is compiled with -ffp-contract=off), so every lane's answer is the one-ray
// test's: tests/runtime/test_plane_lanes.cpp checks each path the CPU offers
// against it. The one-ray test was a fifth of a thin-lens render over a floor.
//
// - avx512: AVX-512 F + VL, eight doubles at a time.
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

}  // namespace snell::rt::geom
