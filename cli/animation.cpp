#include "cli/animation.hpp"

#include <fmt/format.h>

#include <charconv>
#include <filesystem>

namespace snell::cli {

namespace {

bool parse_int(std::string_view s, std::int64_t& out) {
  if (s.empty()) return false;
  auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return ec == std::errc() && end == s.data() + s.size();
}

}  // namespace

bool parse_range(std::string_view text, std::string_view option, std::int64_t max, IntRange& out,
                 std::string& error) {
  std::size_t dots = text.find("..");
  IntRange r;
  if (dots == std::string_view::npos || !parse_int(text.substr(0, dots), r.begin) ||
      !parse_int(text.substr(dots + 2), r.end)) {
    error = fmt::format("{} takes A..B (integers, e.g. 0..24), got '{}'", option, text);
    return false;
  }
  if (r.begin < 0 || r.end > max) {
    error = fmt::format("{} {}: the range must lie in 0..{}", option, text, max);
    return false;
  }
  if (r.end <= r.begin) {
    error = fmt::format("{} {}: A..B means A <= n < B, so B must be greater than A", option, text);
    return false;
  }
  out = r;
  return true;
}

double frame_clock(const IntRange& frames, std::int64_t frame) {
  return double(frame - frames.begin) / double(frames.size());
}

std::string frame_output_name(const std::string& path, std::int64_t frame) {
  std::filesystem::path p(path);
  std::string name = p.filename().string();
  std::size_t last = name.rfind('#');
  std::string out;
  if (last != std::string::npos) {
    std::size_t first = last;
    while (first > 0 && name[first - 1] == '#') --first;
    int width = int(last - first + 1);
    out = name.substr(0, first) + fmt::format("{:0{}}", frame, width) + name.substr(last + 1);
  } else {
    std::string ext = p.extension().string();
    out = p.stem().string() + fmt::format("_{:0{}}", frame, kFrameDigits) + ext;
  }
  return (p.parent_path() / out).string();
}

}  // namespace snell::cli
