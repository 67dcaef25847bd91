// A batch of rays into Embree's 16-wide packet layout (RTCRay16): the transposition
// of the span queries (embree_scene.cpp), in the widest SIMD the CPU has, chosen
// once at start-up. Every path writes the same floats (a copy, no arithmetic);
// tests/runtime/test_ray_packet.cpp checks each path.
//
// - avx512: AVX-512 F, gathers.
// - avx2: AVX2 (x86-64-v3), loads and an 8x8 transposition.
// - generic: field by field (SNELL_SIMD=generic forces it).
#pragma once

#include <embree3/rtcore.h>

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "runtime/geometry/ray.hpp"

namespace snell::rt {

// Lanes [0, n) take rays[0, n) (n in [1, 16]); lanes past n repeat rays[0] (Embree
// reads every lane's fields, valid or not). mask ~0, id 0, flags 0.
using StoreRays16Fn = void (*)(const Ray* rays, std::size_t n, RTCRay16& packet);

StoreRays16Fn store_rays16();
// Every path this build and CPU have, best first, by name (tests).
std::vector<std::pair<std::string, StoreRays16Fn>> store_rays16_paths();

}  // namespace snell::rt
