// What a render will take in memory, estimated before it starts (issue #18), so
// a scene that asks for more than the machine has fails at once with a clear
// error instead of being killed (or swapping the machine to a halt) later.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "runtime/ir/ir.hpp"

namespace snell::rt {

struct MemoryEstimate {
  std::uint64_t film = 0;      // the float RGB image
  std::uint64_t geometry = 0;  // Embree's BVH and Snell's per-object render data
  std::uint64_t textures = 0;  // the texture cache's bound, when the scene has images
  std::uint64_t encode = 0;    // the largest output encoded in memory (its raw size)
  std::uint64_t total() const { return film + geometry + textures + encode; }
  // "5.1 GB (film 3.2 GB, geometry 1.1 GB, textures 256 MB, encoding 805 MB)"
  std::string to_string() const;
};

// The memory a render of `scene` at `width`×`height` (a crop's size) writing
// `outputs` needs beyond the compiled scene itself. The per-object and
// per-triangle costs are measured upper bounds (bench/ has the figures), not
// exact: the estimate is for refusing what cannot fit, not for accounting.
MemoryEstimate estimate_memory(const ir::Scene& scene, std::uint64_t width, std::uint64_t height,
                               const std::vector<std::string>& outputs);

// The machine's physical memory in bytes (0 when unknown).
std::uint64_t physical_memory();

// "3.2 GB", "805 MB", "12 KB": decimal units, three significant digits.
std::string format_bytes(std::uint64_t bytes);

// Reads "8G", "512M", "2.5GB", "1000000" (bytes) into `bytes`; false when it is
// not a size.
bool parse_bytes(const std::string& text, std::uint64_t& bytes);

}  // namespace snell::rt
