// snell merge: checks that the pieces of a split render (cli/split.hpp) belong to
// one render and cover its pixels and samples exactly once, then assembles them.
// Every check runs before any pixel is written, and the caller writes nothing on
// an error, so a failed farm task (a missing or partial piece) fails the merge
// with its name instead of giving a plausible wrong image.
#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cstring>
#include <map>

#include "cli/split.hpp"

namespace snell::cli {

namespace {

// What one piece says it holds, read from its metadata and checked against its
// data window.
struct Header {
  const Piece* piece;
  Window crop;
  IntRange samples;
};

const std::string& need(const Piece& p, const char* name, std::string& error) {
  static const std::string kEmpty;
  const std::string* v = p.file.attribute(name);
  if (!v && error.empty())
    error =
        fmt::format("{} is not a piece of a Snell render: it has no {} attribute", p.path, name);
  return v ? *v : kEmpty;
}

bool read_header(const Piece& p, std::uint32_t& spp, Header& h, std::string& error) {
  const rt::Image& im = p.file.image;
  std::string why;
  const std::string& crop = need(p, attr::kCrop, error);
  const std::string& range = need(p, attr::kSampleRange, error);
  const std::string& samples = need(p, "snell:samples", error);
  for (const char* a : {attr::kSceneHash, attr::kSettings, attr::kFrame, attr::kClock})
    need(p, a, error);
  if (!error.empty()) return false;
  auto bad = [&](const std::string& what) {
    error = fmt::format("{}: {}", p.path, what);
    return false;
  };
  unsigned long n = 0;
  auto [end, ec] = std::from_chars(samples.data(), samples.data() + samples.size(), n);
  if (ec != std::errc() || end != samples.data() + samples.size() || n == 0 || n > (1u << 20))
    return bad(fmt::format("snell:samples '{}' is not a sample count", samples));
  spp = std::uint32_t(n);
  if (!parse_crop(crop, im.display_width(), im.display_height(), h.crop, why))
    return bad(fmt::format("its crop '{}' does not fit its {}x{} display window", crop,
                           im.display_width(), im.display_height()));
  if (h.crop.x0 != im.x0 || h.crop.y0 != im.y0 || h.crop.x1 - h.crop.x0 != im.width ||
      h.crop.y1 - h.crop.y0 != im.height)
    return bad(fmt::format("its crop {} is not its data window", crop));
  if (!parse_range(range, "snell:sample_range", spp, h.samples, why))
    return bad(fmt::format("its sample range '{}' is not a range of 0..{}", range, spp));
  h.piece = &p;
  return true;
}

bool overlap(const Window& a, const Window& b) {
  return a.x0 < b.x1 && b.x0 < a.x1 && a.y0 < b.y1 && b.y0 < a.y1;
}

}  // namespace

std::string merge_pieces(const std::vector<Piece>& pieces, rt::Image& out,
                         std::vector<std::pair<std::string, std::string>>& attributes) {
  if (pieces.empty()) return "no pieces to merge";
  std::vector<Header> headers(pieces.size());
  std::uint32_t spp = 0;
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    std::string error;
    std::uint32_t n = 0;
    if (!read_header(pieces[i], n, headers[i], error)) return error;
    if (i == 0) spp = n;
  }
  // One render: the same scene (and clock), settings and display window.
  const Piece& first = pieces[0];
  for (const Piece& p : pieces) {
    auto differs = [&](const char* name, const char* what) -> std::string {
      const std::string &a = *first.file.attribute(name), &b = *p.file.attribute(name);
      if (a == b) return {};
      return fmt::format("{} and {} are pieces of {} ({} vs {}): they cannot be merged", first.path,
                         p.path, what, a, b);
    };
    for (auto [name, what] :
         {std::pair{attr::kSceneHash, "different scenes (scene hash)"},
          std::pair{attr::kSettings, "renders with different settings"},
          std::pair{attr::kFrame, "different frames"}, std::pair{attr::kClock, "different clocks"}})
      if (std::string e = differs(name, what); !e.empty()) return e;
    if (p.file.image.display_width() != first.file.image.display_width() ||
        p.file.image.display_height() != first.file.image.display_height())
      return fmt::format("{} and {} have different display windows", first.path, p.path);
  }
  const std::uint32_t W = first.file.image.display_width(), H = first.file.image.display_height();

  // Pieces with one crop share its pixels and split its samples; different crops
  // must not share a pixel.
  std::map<std::string, std::vector<const Header*>> groups;
  for (const Header& h : headers) groups[to_string(h.crop)].push_back(&h);
  std::vector<const std::vector<const Header*>*> list;
  for (auto& [key, g] : groups) list.push_back(&g);
  for (std::size_t i = 0; i < list.size(); ++i)
    for (std::size_t j = i + 1; j < list.size(); ++j) {
      const Header &a = *(*list[i])[0], &b = *(*list[j])[0];
      if (overlap(a.crop, b.crop))
        return fmt::format("{} (crop {}) and {} (crop {}) overlap", a.piece->path,
                           to_string(a.crop), b.piece->path, to_string(b.crop));
    }
  std::uint64_t area = 0;
  for (auto& [key, g] : groups) {
    std::sort(g.begin(), g.end(),
              [](const Header* a, const Header* b) { return a->samples.begin < b->samples.begin; });
    std::int64_t next = 0;
    const Header* prev = nullptr;
    for (const Header* h : g) {
      if (h->samples.begin < next)
        return fmt::format(
            "{} and {} both hold samples {} of crop {}", prev->piece->path, h->piece->path,
            to_string(IntRange{h->samples.begin, std::min(next, h->samples.end)}), key);
      if (h->samples.begin > next)
        return fmt::format("no piece holds samples {} of crop {} (of 0..{})",
                           to_string(IntRange{next, h->samples.begin}), key, spp);
      next = h->samples.end;
      prev = h;
    }
    if (next < spp)
      return fmt::format("no piece holds samples {} of crop {} (of 0..{})",
                         to_string(IntRange{next, spp}), key, spp);
    const Window& c = g[0]->crop;
    area += std::uint64_t(c.x1 - c.x0) * (c.y1 - c.y0);
  }
  if (area != std::uint64_t(W) * H) {
    // Disjoint crops of less area than the image: name a pixel none holds.
    std::vector<std::uint8_t> covered(std::size_t(W) * H, 0);
    for (auto& [key, g] : groups)
      for (std::uint32_t y = g[0]->crop.y0; y < g[0]->crop.y1; ++y)
        for (std::uint32_t x = g[0]->crop.x0; x < g[0]->crop.x1; ++x) covered[y * W + x] = 1;
    std::size_t hole = std::find(covered.begin(), covered.end(), 0) - covered.begin();
    return fmt::format(
        "the pieces do not cover the {}x{} image: {} of its {} pixels are missing, the first at "
        "{},{}",
        W, H, std::uint64_t(W) * H - area, std::uint64_t(W) * H, hole % W, hole / W);
  }

  out = rt::Image{};
  out.width = W;
  out.height = H;
  out.rgb.assign(std::size_t(W) * H * 3, 0.0f);
  std::vector<double> acc;
  for (auto& [key, g] : groups) {
    const Window& c = g[0]->crop;
    std::uint32_t cw = c.x1 - c.x0;
    if (g.size() == 1) {  // the whole sample range: the piece's floats, bit for bit
      const rt::Image& im = g[0]->piece->file.image;
      for (std::uint32_t y = 0; y < im.height; ++y)
        std::memcpy(out.at(c.x0, c.y0 + y), im.at(0, y), sizeof(float) * 3 * cw);
      continue;
    }
    // A pixel of the one-run render is sum / spp over its samples in double; a
    // piece holds sum_i / n_i rounded to float, so n_i · value_i gives back sum_i
    // to within float rounding (docs/distributed.md: within 1e-6, not bit for bit).
    acc.assign(std::size_t(cw) * (c.y1 - c.y0) * 3, 0.0);
    for (const Header* h : g) {
      const rt::Image& im = h->piece->file.image;
      double n = double(h->samples.size());
      for (std::size_t i = 0; i < acc.size(); ++i) acc[i] += n * double(im.rgb[i]);
    }
    for (std::uint32_t y = 0; y < c.y1 - c.y0; ++y)
      for (std::uint32_t x = 0; x < cw; ++x)
        for (int k = 0; k < 3; ++k)
          out.at(c.x0 + x, c.y0 + y)[k] = float(acc[(std::size_t(y) * cw + x) * 3 + k] / spp);
  }
  attributes.clear();
  for (const char* a : {attr::kSceneHash, attr::kSettings, attr::kFrame, attr::kClock})
    attributes.emplace_back(a, *first.file.attribute(a));
  attributes.emplace_back(attr::kCrop, to_string(Window{0, 0, W, H}));
  attributes.emplace_back(attr::kSampleRange, to_string(IntRange{0, spp}));
  attributes.emplace_back(attr::kPieceSamples, fmt::format("{}", spp));
  return {};
}

}  // namespace snell::cli
