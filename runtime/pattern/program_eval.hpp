// The interpreter of shading programs (§15 `pattern { function f }`,
// runtime/ir/program.hpp): one pass over the code with a switch per instruction,
// on a register file on the stack. Thread-safe (no state), never allocates.
#pragma once

#include "runtime/ir/math.hpp"
#include "runtime/ir/program.hpp"

namespace snell::pattern {

// The function's value at point `p` with normal `n`: the raw number, unclamped.
// `finite` is false when it is NaN or infinite; the caller then uses 0 (and counts
// it for --stats) and clamps finite values to [0, 1]. `prog` must pass ir::check.
double run_program(const ir::Program& prog, ir::Vec3 p, ir::Vec3 n, bool& finite);

// The caller's side of that: the value clamped to [0, 1], 0 when non-finite.
inline double pattern_value(double raw, bool finite) {
  return finite ? std::fmin(std::fmax(raw, 0.0), 1.0) : 0.0;
}

}  // namespace snell::pattern
