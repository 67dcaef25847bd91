// The per-ISA kernels of sampler_lanes.cpp that live in files of their own
// (sampler_lanes_avx2.cpp), and what they share with it. Internal to the sampler.
#pragma once

#include <cstdint>

#include "runtime/sampler.hpp"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define SNELL_HAVE_AVX2_PATH 1
#else
#define SNELL_HAVE_AVX2_PATH 0
#endif

namespace snell::rt::lanes {

// The scalar draws, lane by lane (the generic path; the SIMD paths' fallback past
// the grid).
void stratified_lanes_scalar(const SamplerSpec& spec, const StrataLanes* const* k,
                             std::uint32_t count, std::uint32_t n, std::uint32_t index,
                             float* const* u, float* const* v);

#if SNELL_HAVE_AVX2_PATH
void cell_keys_lanes_avx2(const std::uint64_t* node_keys, std::uint64_t cell,
                          const std::uint64_t* pixels, const std::uint64_t* indices,
                          std::uint64_t* out);
void sobol2_lanes_avx2(const SobolLanes& k, std::uint32_t n, std::uint32_t index, float* u,
                       float* v);
void stratified_lanes_avx2(const SamplerSpec& spec, const StrataLanes* const* k,
                           std::uint32_t count, std::uint32_t n, std::uint32_t index,
                           float* const* u, float* const* v);
#endif

}  // namespace snell::rt::lanes
