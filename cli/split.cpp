#include "cli/split.hpp"

#include <fmt/format.h>

#include <charconv>

#include "runtime/ir/ir.hpp"

namespace snell::cli {

bool parse_crop(std::string_view text, std::uint32_t width, std::uint32_t height, Window& out,
                std::string& error) {
  std::uint32_t v[4] = {0, 0, 0, 0};
  const char* p = text.data();
  const char* end = text.data() + text.size();
  bool ok = true;
  for (int i = 0; i < 4 && ok; ++i) {
    auto [next, ec] = std::from_chars(p, end, v[i]);
    ok = ec == std::errc() && (i < 3 ? next < end && *next == ',' : next == end);
    p = next + 1;
  }
  if (!ok) {
    error = fmt::format("--crop takes X0,Y0,X1,Y1 (pixels, e.g. 0,0,320,240), got '{}'", text);
    return false;
  }
  Window w{v[0], v[1], v[2], v[3]};
  if (w.x0 >= w.x1 || w.y0 >= w.y1 || w.x1 > width || w.y1 > height) {
    error = fmt::format(
        "--crop {}: the window X0 <= x < X1, Y0 <= y < Y1 must be non-empty and lie in the "
        "{}x{} image",
        text, width, height);
    return false;
  }
  out = w;
  return true;
}

std::string to_string(const Window& w) {
  return fmt::format("{},{},{},{}", w.x0, w.y0, w.x1, w.y1);
}

std::string to_string(const IntRange& r) {
  return fmt::format("{}..{}", r.begin, r.end);
}

namespace {

struct Fnv1a {
  std::uint64_t h = 0xcbf29ce484222325ull;
  void add(const void* data, std::size_t n) {
    const auto* b = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 0x100000001b3ull;
  }
};

}  // namespace

std::string scene_hash(const ir::Scene& scene) {
  std::string dump = ir::to_string(scene);
  // The first line is the settings (ir/dump.cpp): compared on their own.
  std::size_t nl = dump.find('\n');
  Fnv1a f;
  if (nl != std::string::npos) f.add(dump.data() + nl + 1, dump.size() - nl - 1);
  for (const ir::MeshData& m : scene.meshes) {
    f.add(m.positions.data(), m.positions.size() * sizeof(m.positions[0]));
    f.add(m.indices.data(), m.indices.size() * sizeof(m.indices[0]));
    f.add(m.normals.data(), m.normals.size() * sizeof(m.normals[0]));
    f.add(m.normal_indices.data(), m.normal_indices.size() * sizeof(m.normal_indices[0]));
  }
  return fmt::format("{:016x}", f.h);
}

std::string settings_text(const ir::Settings& settings) {
  return ir::to_string(settings);
}

std::vector<std::pair<std::string, std::string>> piece_attributes(const ir::Scene& scene,
                                                                  const PieceInfo& piece) {
  return {
      {attr::kSceneHash, scene_hash(scene)},
      {attr::kSettings, settings_text(scene.settings)},
      {attr::kFrame, fmt::format("{}", piece.frame)},
      {attr::kClock, fmt::format("{}", piece.clock)},
      {attr::kCrop, to_string(piece.crop)},
      {attr::kSampleRange, to_string(piece.samples)},
      {attr::kPieceSamples, fmt::format("{}", piece.samples.size())},
  };
}

}  // namespace snell::cli
