// snell merge: checks that the pieces of a split render (cli/split.hpp) belong to
// one render and cover its pixels and samples exactly once, then assembles them.
// Every check runs before any pixel is written, and the caller writes nothing on
// an error, so a failed farm task (a missing or partial piece) fails the merge
// with its name instead of giving a plausible wrong image.
#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cstring>
#include <vector>

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

// The pixels two windows share; false when they share none.
bool intersect(const Window& a, const Window& b, Window& both) {
  both = Window{std::max(a.x0, b.x0), std::max(a.y0, b.y0), std::min(a.x1, b.x1),
                std::min(a.y1, b.y1)};
  return both.x0 < both.x1 && both.y0 < both.y1;
}

// The image cut along every crop's edges: each cell lies wholly inside or wholly
// outside each crop, so one list of pieces holds for all its pixels: coverage is
// checked once a cell rather than once a pixel, and a pixel's sum visits only the
// pieces that hold it, however crops and sample ranges are mixed.
struct Grid {
  std::vector<std::uint32_t> xs, ys;              // cell edges, 0 .. W and 0 .. H
  std::vector<std::vector<const Header*>> cells;  // row-major; pieces by first sample

  Grid(const std::vector<Header>& headers, std::uint32_t W, std::uint32_t H) {
    xs = {0, W};
    ys = {0, H};
    for (const Header& h : headers) {
      xs.insert(xs.end(), {h.crop.x0, h.crop.x1});
      ys.insert(ys.end(), {h.crop.y0, h.crop.y1});
    }
    for (auto* v : {&xs, &ys}) {
      std::sort(v->begin(), v->end());
      v->erase(std::unique(v->begin(), v->end()), v->end());
    }
    cells.resize((xs.size() - 1) * (ys.size() - 1));
    std::vector<const Header*> order;
    for (const Header& h : headers) order.push_back(&h);
    // Sorted by first sample, a cell's list walks its samples in order, and the
    // sums below do not depend on the order the pieces were named in.
    std::stable_sort(order.begin(), order.end(), [](const Header* a, const Header* b) {
      return a->samples.begin < b->samples.begin;
    });
    auto index = [](const std::vector<std::uint32_t>& v, std::uint32_t e) {
      return std::size_t(std::lower_bound(v.begin(), v.end(), e) - v.begin());
    };
    for (const Header* h : order)
      for (std::size_t cy = index(ys, h->crop.y0); cy < index(ys, h->crop.y1); ++cy)
        for (std::size_t cx = index(xs, h->crop.x0); cx < index(xs, h->crop.x1); ++cx)
          cells[cy * (xs.size() - 1) + cx].push_back(h);
  }
  Window window(std::size_t cell) const {
    std::size_t cx = cell % (xs.size() - 1), cy = cell / (xs.size() - 1);
    return Window{xs[cx], ys[cy], xs[cx + 1], ys[cy + 1]};
  }
};

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

  // Each piece holds the (pixel, sample) pairs of its crop times its sample range;
  // two pieces overlap only when both their crops and their ranges meet. Crops may
  // share pixels when they split the samples differently (a full-image pass plus
  // a pass split in tiles).
  for (std::size_t i = 0; i < headers.size(); ++i)
    for (std::size_t j = i + 1; j < headers.size(); ++j) {
      const Header &a = headers[i], &b = headers[j];
      Window pixels;
      IntRange samples{std::max(a.samples.begin, b.samples.begin),
                       std::min(a.samples.end, b.samples.end)};
      if (samples.begin >= samples.end || !intersect(a.crop, b.crop, pixels)) continue;
      if (a.crop.x0 == b.crop.x0 && a.crop.y0 == b.crop.y0 && a.crop.x1 == b.crop.x1 &&
          a.crop.y1 == b.crop.y1)
        return fmt::format("{} and {} both hold samples {} of crop {}", a.piece->path,
                           b.piece->path, to_string(samples), to_string(a.crop));
      return fmt::format("{} (crop {}) and {} (crop {}) overlap: both hold samples {} of pixels {}",
                         a.piece->path, to_string(a.crop), b.piece->path, to_string(b.crop),
                         to_string(samples), to_string(pixels));
    }

  // Disjoint now, so a cell is covered exactly when its ranges leave no gap.
  const Grid grid(headers, W, H);
  std::uint64_t missing = 0;
  std::size_t first_hole = grid.cells.size();
  for (std::size_t cell = 0; cell < grid.cells.size(); ++cell) {
    const Window c = grid.window(cell);
    const std::vector<const Header*>& g = grid.cells[cell];
    if (g.empty()) {
      missing += std::uint64_t(c.x1 - c.x0) * (c.y1 - c.y0);
      first_hole = std::min(first_hole, cell);
      continue;
    }
    std::int64_t next = 0, gap_end = spp;
    for (const Header* h : g) {
      if (h->samples.begin > next) {
        gap_end = h->samples.begin;
        break;
      }
      next = h->samples.end;
    }
    if (next < spp)
      return fmt::format("no piece holds samples {} of pixels {} (of 0..{})",
                         to_string(IntRange{next, gap_end}), to_string(c), spp);
  }
  if (missing) {
    // Cells are row-major with rows of equal y0, so the first empty cell's corner
    // is the first pixel missing in reading order.
    const Window hole = grid.window(first_hole);
    return fmt::format(
        "the pieces do not cover the {}x{} image: {} of its {} pixels are missing, the first at "
        "{},{}",
        W, H, missing, std::uint64_t(W) * H, hole.x0, hole.y0);
  }

  out = rt::Image{};
  out.width = W;
  out.height = H;
  out.rgb.assign(std::size_t(W) * H * 3, 0.0f);
  std::vector<double> acc;
  for (std::size_t cell = 0; cell < grid.cells.size(); ++cell) {
    const Window c = grid.window(cell);
    const std::vector<const Header*>& g = grid.cells[cell];
    const std::uint32_t cw = c.x1 - c.x0, ch = c.y1 - c.y0;
    // A pixel of piece h at full-image x, y.
    auto at = [](const Header* h, std::uint32_t x, std::uint32_t y) {
      return h->piece->file.image.at(x - h->crop.x0, y - h->crop.y0);
    };
    if (g.size() == 1) {  // the whole sample range: the piece's floats, bit for bit
      for (std::uint32_t y = c.y0; y < c.y1; ++y)
        std::memcpy(out.at(c.x0, y), at(g[0], c.x0, y), sizeof(float) * 3 * cw);
      continue;
    }
    // A pixel of the one-run render is sum / spp over its samples in double; a
    // piece holds sum_i / n_i rounded to float, so n_i · value_i gives back sum_i
    // to within float rounding (docs/distributed.md: within 1e-6, not bit for bit).
    acc.assign(std::size_t(cw) * ch * 3, 0.0);
    for (const Header* h : g) {
      double n = double(h->samples.size());
      for (std::uint32_t y = 0; y < ch; ++y) {
        const float* row = at(h, c.x0, c.y0 + y);
        for (std::size_t k = 0; k < std::size_t(cw) * 3; ++k)
          acc[std::size_t(y) * cw * 3 + k] += n * double(row[k]);
      }
    }
    for (std::uint32_t y = 0; y < ch; ++y) {
      float* row = out.at(c.x0, c.y0 + y);
      for (std::size_t k = 0; k < std::size_t(cw) * 3; ++k)
        row[k] = float(acc[std::size_t(y) * cw * 3 + k] / spp);
    }
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
