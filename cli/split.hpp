// §18 split renders: one render spread over many processes as pieces — a crop
// (--crop X0,Y0,X1,Y1: a window of the full image) and/or a sample range
// (--sample-range A..B: samples A <= s < B of every pixel) — each an EXR whose
// metadata says what it holds, and `snell merge`, which checks the pieces belong
// together and cover the image once, then assembles them (cli/merge.cpp).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "cli/animation.hpp"
#include "runtime/ir/ir.hpp"
#include "runtime/render.hpp"

namespace snell::cli {

using Window = rt::RenderOptions::Window;

// Reads "X0,Y0,X1,Y1" for an image of width × height: X0 < X1 <= width, Y0 < Y1 <=
// height; false with `error` set (a usage error) otherwise.
bool parse_crop(std::string_view text, std::uint32_t width, std::uint32_t height, Window& out,
                std::string& error);
std::string to_string(const Window& w);    // "X0,Y0,X1,Y1", what parse_crop reads
std::string to_string(const IntRange& r);  // "A..B"

// The metadata a piece carries (EXR string attributes; every render writes them).
namespace attr {
inline constexpr const char* kSceneHash = "snell:scene_hash";  // hash of the IR without settings
inline constexpr const char* kSettings = "snell:settings";     // the IR's settings, as text
inline constexpr const char* kFrame = "snell:frame";           // the predeclared frame and clock
inline constexpr const char* kClock = "snell:clock";
inline constexpr const char* kCrop = "snell:crop";                 // X0,Y0,X1,Y1 of the full image
inline constexpr const char* kSampleRange = "snell:sample_range";  // A..B of the full spp
inline constexpr const char* kPieceSamples = "snell:piece_samples";  // B - A: samples it holds
}  // namespace attr

// 16 hex digits: a 64-bit FNV-1a hash of the compiled scene (ir::to_string without
// its settings line, plus every mesh's vertices and indices, which the dump only
// counts). Two processes that compile the same scene with the same clock get the
// same hash; settings are compared on their own (settings_text) so that merge can
// say which of the two differs.
std::string scene_hash(const ir::Scene& scene);
std::string settings_text(const ir::Settings& settings);

struct PieceInfo {
  Window crop;
  IntRange samples;
  std::int64_t frame = 0;
  double clock = 0;
};
std::vector<std::pair<std::string, std::string>> piece_attributes(const ir::Scene& scene,
                                                                  const PieceInfo& piece);

// One piece read back.
struct Piece {
  std::string path;
  rt::ImageFile file;
};

// Checks the pieces and assembles them into `out` (the whole image) and
// `attributes` (the merged image's metadata: the whole crop and sample range).
// A pixel held by one piece with every sample is copied bit for bit; otherwise
// its pieces (crops may share pixels when their sample ranges are disjoint) are
// averaged weighted by their sample counts (in double, one rounding to float at
// the end). Returns an error message naming the pieces at fault (the
// merge then writes nothing): not a Snell piece, different scenes, settings or
// frames, overlapping pixels or samples, or pixels or samples not covered.
std::string merge_pieces(const std::vector<Piece>& pieces, rt::Image& out,
                         std::vector<std::pair<std::string, std::string>>& attributes);

}  // namespace snell::cli
