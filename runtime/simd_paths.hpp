// How the packet kernels pick their SIMD path (geometry/sphere_lanes,
// shading/area_lanes, ray_packet, sampler_lanes): the AVX-512 function where the
// build and the CPU have it, then the portable one where there is one (none: the
// caller goes lane by lane), best first, chosen once at start-up. SNELL_SIMD=generic
// in the environment keeps only the portable path (A/B measurements, and the tests
// of both paths, which compare every path a CPU has with the one-lane form).
#pragma once

#include <cstdlib>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

namespace snell::rt {

template <class Fn>
using SimdPaths = std::vector<std::pair<std::string, Fn>>;

inline bool simd_forced_generic() {
  const char* force = std::getenv("SNELL_SIMD");
  return force && std::strcmp(force, "generic") == 0;
}

// `avx512` (null where the build has none) when `avx512_ok`, then `generic` (null:
// none).
template <class Fn>
SimdPaths<Fn> simd_paths(bool avx512_ok, Fn avx512, Fn generic) {
  SimdPaths<Fn> p;
  if (avx512 && avx512_ok && !simd_forced_generic()) p.emplace_back("avx512", avx512);
  if (generic) p.emplace_back("generic", generic);
  return p;
}
// The best path, or null when there is none.
template <class Fn>
Fn best_path(const SimdPaths<Fn>& paths) {
  return paths.empty() ? nullptr : paths.front().second;
}
template <class Fn>
std::vector<std::string> path_names(const SimdPaths<Fn>& paths) {
  std::vector<std::string> names;
  for (const auto& p : paths) names.push_back(p.first);
  return names;
}
// The path called `name`, or null.
template <class Fn>
Fn path_named(const SimdPaths<Fn>& paths, const std::string& name) {
  for (const auto& p : paths)
    if (p.first == name) return p.second;
  return nullptr;
}

}  // namespace snell::rt
