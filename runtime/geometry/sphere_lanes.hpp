// A packet's rays against one static sphere at once (the user-geometry callback of
// a 16-ray packet, embree_scene.cpp), in the widest double SIMD the CPU has, chosen
// once at start-up. The same IEEE operations in the same order as the one-ray test
// (sphere.hpp: sphere_roots, hit_similar_sphere), lane by lane, with no FMA
// contraction (the file is compiled with -ffp-contract=off), so every lane's t and
// normal are the one-ray test's bit for bit: tests/runtime/test_sphere_lanes.cpp
// checks each path the CPU offers against the one-ray test.
//
// - avx512: AVX-512 F + VL, eight doubles at a time.
// - avx2: AVX2 (x86-64-v3), four doubles at a time.
// - none: the caller tests lane by lane (SNELL_SIMD=generic forces it).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "runtime/ir/math.hpp"

namespace snell::rt::geom {

// An SoA packet of n rays (Embree's RTCRayN layout, camera-relative float).
struct RayLanes {
  const float *ox, *oy, *oz, *dx, *dy, *dz, *tnear, *tfar;
  const int* valid;  // non-zero: the lane takes part
  std::uint32_t n;   // a multiple of 8
};
// What a lane's hit is: t and the outward normal (not unit: hit_similar_sphere),
// meaningful only for hit lanes (the paths store whole groups of eight lanes).
struct HitLanes {
  float t[16], nx[16], ny[16], nz[16];
};
// The lanes (bit i: lane i) that hit the sphere (centre c, radius r, both
// camera-relative) within (tnear, tfar), their hits in `out` unless it is null (an
// occlusion query needs only the lanes); `undecided`: lanes the vector path leaves
// to the one-ray test (the degenerate q == 0 of sphere_roots), never in the result.
using SphereLanesFn = std::uint32_t (*)(ir::Vec3 c, double r, const RayLanes& rays, HitLanes* out,
                                        std::uint32_t& undecided);

// The best path for this CPU, or null (test lane by lane).
SphereLanesFn sphere_lanes();
// Every path this build and CPU have, best first, by name (tests).
std::vector<std::pair<std::string, SphereLanesFn>> sphere_lanes_paths();

}  // namespace snell::rt::geom
