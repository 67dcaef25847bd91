// A packet's shading points against one cell of an area light at once (the direct
// light of a packet's lit nodes, integrators/whitted_light.hpp), in the widest
// float SIMD the CPU has, chosen once at start-up. The same IEEE operations in the
// same order as AreaLightF::sample_li_area (lights.hpp), lane by lane, with no FMA
// contraction (the file is compiled with -ffp-contract=off), so every lane's shadow
// ray, geometry factor and `to` are the one-lane sample's bit for bit:
// tests/runtime/test_area_lanes.cpp checks each path the CPU offers against it.
//
// - avx512: AVX-512 F, sixteen floats at a time.
// - avx2: AVX2 (x86-64-v3), eight floats at a time.
// - none: the caller samples lane by lane (SNELL_SIMD=generic forces it).
// Solid-angle sampling (light_sampling "solid_angle" / "adaptive") has no vector
// path: such lights go lane by lane.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace snell::rt {

struct AreaLightF;

// Up to 16 shading points in SoA: the point p, the shadow rays' origin o, the
// normal on the lit side nf, and the time.
struct PointLanes {
  alignas(64) float px[16], py[16], pz[16];
  alignas(64) float ox[16], oy[16], oz[16];
  alignas(64) float nx[16], ny[16], nz[16];
  alignas(64) float time[16];
};
// Each lit lane's shadow ray (origin o as given, direction dx/dy/dz to the offset
// light sample, tmax 1, tnear 0, the point's time), its geometry factor g and `to`
// (the sample minus p), written only for lit lanes.
struct ShadowLanes {
  alignas(64) float dx[16], dy[16], dz[16];
  alignas(64) float g[16];
  alignas(64) float tx[16], ty[16], tz[16];
};
// One light cell: the light (area sampling), the cell (iu, iv), the scene's
// offset scale.
struct AreaCell {
  const AreaLightF* light;
  std::uint32_t iu, iv;
  float scale;
};

// The lanes (bit i: lane i of `lanes`, bit set) whose sample at jitter (ju[i], jv[i])
// sees the light's lit face from above the point's surface: sample_li_area's true.
using AreaLanesFn = std::uint32_t (*)(const AreaCell& cell, const PointLanes& p, const float* ju,
                                      const float* jv, std::uint32_t lanes, ShadowLanes& out);

// The best path for this CPU, or null (sample lane by lane).
AreaLanesFn area_lanes();
// Every path this build and CPU have, best first, by name (tests).
std::vector<std::pair<std::string, AreaLanesFn>> area_lanes_paths();

}  // namespace snell::rt
