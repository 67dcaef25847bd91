// Samplers: every value is a pure function of (seed, pixel, sample index, dimension)
// plus the pixel's sample count, so the image does not depend on threads or tile
// order. Values lie in [0, 1) and are never exactly 1: they are built from 24-bit
// integers (k · 2^-24), which float represents exactly.
//
// - independent: a hash of all inputs.
// - stratified: per dimension pair, a jittered m×k grid (m = floor(sqrt(spp)),
//   k = ceil(spp / m)); the pixel's samples take distinct cells through a hashed
//   permutation (Kensler 2013), different per dimension pair, so pairs decorrelate.
//   When m·k > spp the unused cells are random, so each sample is still uniform.
// - sobol: the first two Sobol' dimensions, Owen-scrambled with a hash seeded by
//   (seed, pixel, dimension) and with a shuffled index (Burley 2020, "Practical
//   Hash-based Owen Scrambling"). Best with power-of-two sample counts.
//
// Dimensions are requested in pairs (`sample2`) or alone (`sample1`). A 1-D request
// is stratified on its own axis: the stratified sampler uses spp strata (not the
// columns of the 2-D grid) and sobol uses its first, (0,1)-sequence dimension.
//
// Allocation (the same for every sampler kind and every kernel, so specialising on
// ir::Features never changes which numbers a decision gets, docs/effects.md):
//   0 pixel (2-D), 1 lens (2-D), 2 time (1-D), then per ray-tree node dimensions
//   hashed from the node's path key: glossy jitter, and each area-light grid cell.
#pragma once

#include <cstdint>
#include <string>

#include "runtime/ir/ir.hpp"

namespace snell::rt {

struct Sample2 {
  float u = 0, v = 0;
};

// Fixed dimensions of a camera sample; the ray tree draws further dimensions from
// hashed per-node keys (integrator.cpp).
enum : std::uint32_t {
  kDimPixel = 0,  // film position inside the pixel
  kDimLens = 1,   // lens position (depth of field)
  kDimTime = 2,   // shutter fraction (motion blur), 1-D
  kDimFirstFree = 3,
};

struct SamplerSpec {
  ir::SamplerKind kind = ir::SamplerKind::Stratified;
  std::uint64_t seed = 0;
  std::uint32_t spp = 1;
};

// Helpers, exposed for the integrator and tests. Inline: every sample hashes.
inline std::uint64_t hash64(std::uint64_t x) {  // splitmix64 finaliser
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}
inline std::uint64_t hash_combine(std::uint64_t a, std::uint64_t b) {
  return hash64(a ^ (hash64(b) + 0x9e3779b97f4a7c15ull + (a << 6) + (a >> 2)));
}

// The pixel's part of every sample's key; the render loop computes it once per
// pixel and passes it to the keyed overloads below.
inline std::uint64_t pixel_hash(const SamplerSpec& spec, std::uint32_t px, std::uint32_t py) {
  return hash_combine(spec.seed, (std::uint64_t(py) << 32) | px);
}

Sample2 sample2(const SamplerSpec& spec, std::uint64_t pixel, std::uint32_t index,
                std::uint32_t dim);
float sample1(const SamplerSpec& spec, std::uint64_t pixel, std::uint32_t index, std::uint32_t dim);
inline Sample2 sample2(const SamplerSpec& spec, std::uint32_t px, std::uint32_t py,
                       std::uint32_t index, std::uint32_t dim) {
  return sample2(spec, pixel_hash(spec, px, py), index, dim);
}
inline float sample1(const SamplerSpec& spec, std::uint32_t px, std::uint32_t py,
                     std::uint32_t index, std::uint32_t dim) {
  return sample1(spec, pixel_hash(spec, px, py), index, dim);
}

// 24-bit float in [0, 1) from the top bits of a 32-bit integer.
inline float to_unit_float(std::uint32_t bits) {
  return static_cast<float>(bits >> 8) * (1.0f / 16777216.0f);
}
// Kensler's hashed permutation of [0, n).
std::uint32_t permute(std::uint32_t i, std::uint32_t n, std::uint32_t key);

std::string to_string(const SamplerSpec& s);
std::string to_string(Sample2 s);

}  // namespace snell::rt
