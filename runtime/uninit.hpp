// Uninit<T, n>: an array of n trivially destructible T made without running T's
// default member initialisers, for hot-path scratch whose every element is
// assigned before it is read (a default-made array of rays, hits or colours was a
// memset per packet or per call).
#pragma once

#include <cstdint>
#include <type_traits>

namespace snell::rt {

template <class T, std::uint32_t n>
union Uninit {
  static_assert(std::is_trivially_destructible_v<T>);
  Uninit() {}
  T v[n];
};

}  // namespace snell::rt
