// §18 animation on the command line: `--frames A..B` renders frames A <= frame < B,
// each compiled afresh with the predeclared `frame` and `clock = (frame - A) / (B -
// A)`; every output name gets the frame number. Pure functions, so tests pin them.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace snell::cli {

// A half-open range of integers, `A..B` on the command line (--frames,
// --sample-range).
struct IntRange {
  std::int64_t begin = 0, end = 0;
  std::int64_t size() const { return end - begin; }
};

// Reads "A..B" (integers, 0 <= A < B <= max) for `option`; false with `error` set
// (a usage error: exit 2) otherwise.
bool parse_range(std::string_view text, std::string_view option, std::int64_t max, IntRange& out,
                 std::string& error);

// The clock of `frame` in `frames`: (frame - A) / (B - A), in [0, 1).
double frame_clock(const IntRange& frames, std::int64_t frame);

// The minimum width of the frame number added when an output name has no `#` run.
inline constexpr int kFrameDigits = 4;

// The output name of `frame`: the last run of '#' in the file name (not its folder)
// becomes the frame number zero-padded to the run's length (`out_####.png` ->
// `out_0007.png`); a name without one gets `_NNNN` before its extension
// (`out.png` -> `out_0007.png`). A number wider than the padding is written whole.
std::string frame_output_name(const std::string& path, std::int64_t frame);

}  // namespace snell::cli
