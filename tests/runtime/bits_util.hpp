// Bit-for-bit comparison of floats, for the tests that hold a SIMD path to its
// one-lane form (the same bits, NaNs and signed zeros included).
#pragma once

#include <cstring>

namespace snell::test {

inline bool same_bits(float a, float b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

}  // namespace snell::test
