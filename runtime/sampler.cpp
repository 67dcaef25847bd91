#include "runtime/sampler.hpp"

#include <fmt/format.h>

#include <cmath>

namespace snell::rt {

SamplerSpec::SamplerSpec(ir::SamplerKind kind_, std::uint64_t seed_, std::uint32_t spp)
    : kind(kind_), seed(seed_), spp_(spp) {
  n = spp == 0 ? 1 : spp;
  m = static_cast<std::uint32_t>(std::sqrt(double(n)));
  if (m == 0) m = 1;
  k = (n + m - 1) / m;
  cells = m * k;
  cells_mask = permute_mask(cells);
  n_mask = permute_mask(n);
  div_cells = Divisor32(cells);
  div_k = Divisor32(k);
  div_m = Divisor32(m);
  div_n = Divisor32(n);
}

std::uint32_t permute(std::uint32_t i, std::uint32_t n, std::uint32_t key) {
  return permute(i, Divisor32(n), permute_mask(n), key);
}

std::string to_string(Sample2 s) {
  return fmt::format("({}, {})", s.u, s.v);
}

std::string to_string(const SamplerSpec& s) {
  return fmt::format("sampler {{ kind {} seed {} spp {} }}", ir::to_string(s.kind), s.seed,
                     s.spp());
}

}  // namespace snell::rt
