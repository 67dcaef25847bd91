#include "runtime/pattern/patterns.hpp"

namespace snell::pattern {

// Ten points spread through the cube around the origin and frequencies between 0.5
// and 1.5: a fixed table, so ripples and waves are the same on every machine.
const WaveSource* wave_sources() {
  static constexpr WaveSource kTable[kWaves] = {
      {{0.31, -0.12, 0.44}, 1.00},  {{-0.42, 0.27, -0.08}, 0.73}, {{0.05, 0.48, -0.36}, 1.21},
      {{-0.19, -0.41, 0.22}, 0.58}, {{0.47, 0.09, -0.29}, 1.37},  {{-0.33, -0.05, 0.39}, 0.91},
      {{0.14, -0.37, -0.47}, 1.12}, {{-0.48, 0.43, 0.11}, 0.66},  {{0.26, 0.18, 0.03}, 1.45},
      {{-0.07, -0.24, -0.18}, 0.84}};
  return kTable;
}

}  // namespace snell::pattern
