// How the packet kernels pick their SIMD path (geometry/sphere_lanes,
// geometry/plane_lanes, shading/area_lanes, ray_packet, sampler_lanes): the
// AVX-512 function where the build and the CPU have it, then the AVX2 one (with
// FMA: x86-64-v3, every x86 CPU since about 2015 and the AVX-512-less ones of
// today), then the portable one where there is one (none: the caller goes lane by
// lane), best first, chosen once at start-up. SNELL_SIMD in the environment caps the
// choice: `generic` keeps only the portable path, `avx2` drops AVX-512 (A/B
// measurements, and the tests of every path, which compare each path a CPU has with
// the one-lane form).
#pragma once

#include <cstdlib>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

namespace snell::rt {

template <class Fn>
using SimdPaths = std::vector<std::pair<std::string, Fn>>;

// The widest tier SNELL_SIMD allows: 2 (avx512, also when unset or unknown), 1
// (avx2) or 0 (generic).
inline int simd_cap() {
  const char* cap = std::getenv("SNELL_SIMD");
  if (cap && std::strcmp(cap, "generic") == 0) return 0;
  if (cap && std::strcmp(cap, "avx2") == 0) return 1;
  return 2;
}
// Whether the CPU has AVX2 and FMA (the `avx2` paths' target).
inline bool cpu_has_avx2() {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#else
  return false;
#endif
}

// `avx512` (null where the build has none) when `avx512_ok`, `avx2` likewise,
// then `generic` (null: none).
template <class Fn>
SimdPaths<Fn> simd_paths(bool avx512_ok, Fn avx512, bool avx2_ok, Fn avx2, Fn generic) {
  SimdPaths<Fn> p;
  const int cap = simd_cap();
  if (avx512 && avx512_ok && cap >= 2) p.emplace_back("avx512", avx512);
  if (avx2 && avx2_ok && cap >= 1) p.emplace_back("avx2", avx2);
  if (generic) p.emplace_back("generic", generic);
  return p;
}
template <class Fn>
SimdPaths<Fn> simd_paths(bool avx512_ok, Fn avx512, Fn generic) {
  return simd_paths<Fn>(avx512_ok, avx512, false, nullptr, generic);
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
