// §17's texture system: OpenImageIO's TextureSystem behind a small C interface
// (runtime/shading/image_texture.cpp resolves these functions by name), built into
// the image module so that scenes without images never load OIIO.
//
// - One TextureSystem per render (not OIIO's process-wide shared one, so each
//   render's statistics and cache bound are its own), shared by every render
//   thread; each lookup passes a TextureHandle, and OIIO keeps the per-thread
//   state itself.
// - The cache is bounded (max_memory_MB) and untiled files are read in 64² tiles
//   (autotile) and MIP-mapped in the cache (automip), so a huge image is not held
//   whole in memory.
// - Colour: OIIO 2.4 applies no colour transform at lookup, so a file that is not
//   linear already is decoded once to linear and made into a tiled, MIP-mapped
//   .tx in the texture cache folder (texture_cache.hpp), named by the source's
//   path, size, time, bytes and the decoding; filtering then averages linear radiance, as it must
//   (a black-and-white checker far away is 0.5, not sRGB's 0.21). The file's own colour space (its
//   oiio:ColorSpace) decides, as source_colour() says: none on 8- and 16-bit files is sRGB and none
//   on float files linear; a name the OCIO config (--ocio-config, else $OCIO, else Snell's) knows
//   is converted from that space to the config's scene_linear role; of the rest, OIIO's own names
//   ("sRGB", any "linear" one, "GammaG" for a PNG gAMA chunk) mean what they say,
//   "Rec709" (OIIO's tag for any PPM) is read as an untagged file of its format,
//   and anything else is an error. Primaries: a file with `chromaticities` (an
//   OpenEXR attribute) other than Rec.709/D65 is converted to Rec.709 by a matrix
//   (runtime/primaries.hpp) after that decoding, unless its colour space came from
//   the OCIO config by name (the config's transform already says everything);
//   a one- or two-channel image keeps its values. Limit: the decode reads the
//   image whole once.
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imagecache.h>
#include <OpenImageIO/imageio.h>
#include <OpenImageIO/texture.h>
#include <fmt/format.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <filesystem>
#include <functional>
#include <mutex>
#include <new>
#include <string>
#include <vector>

#include "runtime/color.hpp"
#include "runtime/primaries.hpp"
#include "runtime/texture_cache.hpp"

namespace {

namespace fs = std::filesystem;
using snell::rt::texture_cache_dir;
using snell::rt::texture_cache_max_bytes;
using snell::rt::texture_cache_prune;
using snell::rt::texture_cache_touch;

// The sRGB decoding function (IEC 61966-2-1).
float srgb_to_linear(float c) {
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

std::string lower(std::string s) {
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// How a file's values become linear radiance.
struct SourceColour {
  enum Kind { Linear, Srgb, Gamma, Ocio } kind = Linear;
  float gamma = 1;                                  // Gamma: linear = value^gamma
  std::unique_ptr<snell::rt::ColorTransform> ocio;  // Ocio: to scene_linear
  bool convert_primaries = false;                   // then rec709 = primaries · decoded RGB
  snell::rt::Mat3f primaries{};
  std::string key;  // names the decoding in the .tx's name
  bool is_identity() const { return kind == Linear && !convert_primaries; }
};

// The decoding of a file with `spec`, or false with `error` (a colour space the
// OCIO config lacks).
bool source_colour(const OIIO::ImageSpec& spec, const std::string& ocio_config, SourceColour& out,
                   std::string& error) {
  const std::string name = spec.get_string_attribute("oiio:ColorSpace");
  const std::string cs = lower(name);
  const float gamma = spec.get_float_attribute("oiio:Gamma", 0);
  std::string why;
  // OpenImageIO's own names for what an 8-bit file's header says of its coding:
  // "sRGB", "Rec709" (every PPM), "Linear" and "GammaG" (a PNG gAMA chunk, which
  // oiiotool writes as 1.0 when it converts float values to an 8-bit PNG).
  const bool oiio_name = cs == "srgb" || cs == "rec709" || cs == "linear" ||
                         (cs.rfind("gamma", 0) == 0 && cs.size() > 5 &&
                          cs.find_first_not_of("0123456789.", 5) == std::string::npos);
  const bool eight_bit =
      spec.format.basetype == OIIO::TypeDesc::UINT8 || spec.format.basetype == OIIO::TypeDesc::INT8;
  if (cs.empty() || (eight_bit && oiio_name)) {
    // §17: "8-bit files are taken as sRGB-encoded and linearised", whatever such
    // a header says (a colour space named in the OCIO config still decides).
    out.kind = spec.format.is_floating_point() ? SourceColour::Linear : SourceColour::Srgb;
  } else if ((out.ocio = snell::rt::ColorTransform::to_scene_linear(ocio_config, name, why))) {
    // A name the config knows means what the config says.
    out.kind = out.ocio->is_identity() ? SourceColour::Linear : SourceColour::Ocio;
  } else if (cs.find("linear") != std::string::npos || cs == "scene_linear" || cs == "raw") {
    out.kind = SourceColour::Linear;  // OIIO's own names, which configs seldom list
  } else if (cs == "srgb") {
    out.kind = SourceColour::Srgb;
  } else if (cs == "rec709") {
    // OIIO's tag for every PPM/PGM (the format's convention, not the file's word),
    // which converting one with oiiotool carries into a PNG: §17's rule for a file
    // of that format, as for an untagged one (8-bit sRGB, float linear).
    out.kind = spec.format.is_floating_point() ? SourceColour::Linear : SourceColour::Srgb;
  } else if (cs.rfind("gamma", 0) == 0 && std::isfinite(gamma) && gamma > 0) {
    out.kind = SourceColour::Gamma;  // OIIO's "Gamma2.2" for a PNG gAMA chunk
    out.gamma = gamma;
  } else {
    error = "its colour space (oiio:ColorSpace) is '" + name + "', and the " + why +
            " (retag the file, or choose the config with --ocio-config or $OCIO)";
    return false;
  }
  switch (out.kind) {
    case SourceColour::Linear:
      break;
    case SourceColour::Srgb:
      out.key = "srgb";
      break;
    case SourceColour::Gamma:
      out.key = fmt::format("gamma{}", out.gamma);
      break;
    case SourceColour::Ocio:
      out.key = "ocio " + out.ocio->to_string();
      break;
  }
  snell::rt::Chromaticities xy;
  if (out.kind != SourceColour::Ocio &&
      spec.getattribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8), xy.data()) &&
      !snell::rt::is_rec709(xy)) {
    if (!snell::rt::rec709_from(xy, out.primaries, error)) return false;
    out.convert_primaries = true;
    out.key += " primaries " + snell::rt::to_string(xy);
  }
  return true;
}

// Bytes the address-space limit (RLIMIT_AS) leaves this process: the limit less
// what is mapped now (/proc/self/statm); infinite without a limit.
double address_space_left() {
  struct rlimit rl {};
  if (getrlimit(RLIMIT_AS, &rl) != 0 || rl.rlim_cur == RLIM_INFINITY) return INFINITY;
  double mapped = 0;
  if (std::FILE* f = std::fopen("/proc/self/statm", "r")) {
    unsigned long long pages = 0;
    if (std::fscanf(f, "%llu", &pages) == 1)
      mapped = double(pages) * double(sysconf(_SC_PAGE_SIZE));
    std::fclose(f);
  }
  return double(rl.rlim_cur) - mapped;
}

// The .tx's count of pixels whose NaN or infinite values were mended, in a TIFF
// tag the texture maker keeps (a name of Snell's own is dropped): "snell:mended=N".
constexpr const char* kMendedAttribute = "DocumentName";
constexpr const char* kMendedPrefix = "snell:mended=";

// The linear .tx made from a file that needs decoding (or mending), made once (reused while
// the source's size and time and the decoding are unchanged). Empty, with
// `error`, on failure.
std::string linear_texture(const std::string& path, const SourceColour& colour,
                           const OIIO::ImageSpec& file_spec, std::string& error) {
  // The decoding holds the image whole as floats about six times over (the read,
  // the decoded copy, the texture maker's copies and its MIP levels): an 8192 x
  // 8192 RGB PNG peaked at 4.85 GB, 72 bytes a pixel, where three copies had been
  // counted. A small file can claim a huge image (a 2.7 MB PNG of 30000 x 30000),
  // so the claim is checked first against half the machine's memory.
  const double bytes = double(file_spec.width) * double(file_spec.height) *
                       double(std::max(file_spec.depth, 1)) *
                       double(std::max(file_spec.nchannels, 1)) * sizeof(float) * 6;
  const double memory = double(sysconf(_SC_PHYS_PAGES)) * double(sysconf(_SC_PAGE_SIZE));
  if (memory > 0 && bytes > memory / 2) {
    error = fmt::format(
        "it is {}x{} pixels: decoding it to linear would take {:.1f} GB, more than half of this "
        "machine's {:.1f} GB (store it as a linear EXR, which is read in tiles as needed, or "
        "make it smaller)",
        file_spec.width, file_spec.height, bytes / 1e9, memory / 1e9);
    return {};
  }
  // The process's own address-space limit (ulimit -v, a batch system's): past it an
  // allocation inside OpenImageIO's texture maker aborted the process with no word.
  if (const double room = address_space_left(); bytes > room) {
    error = fmt::format(
        "it is {}x{} pixels: decoding it to linear would take {:.1f} GB, more than the {:.1f} GB "
        "this process's address-space limit (ulimit -v) leaves (store it as a linear EXR, "
        "which is read in tiles as needed, make it smaller, or raise the limit)",
        file_spec.width, file_spec.height, bytes / 1e9, std::max(room, 0.0) / 1e9);
    return {};
  }
  std::error_code ec;
  auto size = fs::file_size(path, ec);
  auto time = fs::last_write_time(path, ec).time_since_epoch().count();
  // The bytes themselves are in the key too: a file replaced by another of the same
  // size and time (cp -p, rsync -t, a fixed-size PPM) kept the old decoding. A
  // hash reads the file once, far cheaper than decoding it.
  std::uint64_t content = 1469598103934665603ull;  // FNV-1a 64
  {
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) {
      error = "cannot open it";
      return {};
    }
    std::vector<unsigned char> buf(1 << 16);
    for (std::size_t n; (n = std::fread(buf.data(), 1, buf.size(), f)) > 0;)
      for (std::size_t i = 0; i < n; ++i) content = (content ^ buf[i]) * 1099511628211ull;
    std::fclose(f);
  }
  // "straight": the texels' colours are read without alpha's premultiplication
  // (.tx files made before are not reused).
  std::size_t key = std::hash<std::string>{}(
      fmt::format("{}|{}|{}|{}|{:016x}|straight|mended", path, size, time, colour.key, content));
  const fs::path dir = texture_cache_dir(error);
  if (dir.empty()) return {};
  fs::path out = dir / fmt::format("{:016x}.tx", key);
  if (fs::exists(out, ec)) {
    texture_cache_touch(out);
    return out.string();
  }
  // Colours as the file holds them: OIIO would multiply them by an unassociated
  // alpha (PNG's, TIFF's) as it reads, and the decoding below is of the file's
  // codes, not of codes times alpha. (§17 images give colours; alpha is unused.)
  OIIO::ImageSpec hint;
  hint.attribute("oiio:UnassociatedAlpha", 1);
  // Read into our own buffer, not an ImageBuf's: OpenImageIO 2.4's ImageBuf::read
  // goes on into a null buffer when its allocation fails (SIGSEGV), where a
  // vector's failure is a bad_alloc the caller reports.
  auto in = OIIO::ImageInput::open(path, &hint);
  if (!in) {
    error = OIIO::geterror();
    return {};
  }
  OIIO::ImageSpec spec = in->spec();
  const bool was_float = spec.format.is_floating_point();
  spec.set_format(OIIO::TypeDesc::FLOAT);
  spec.erase_attribute("chromaticities");  // the .tx holds Rec.709 values
  std::vector<float> px(std::size_t(spec.width) * spec.height * std::max(spec.depth, 1) *
                        spec.nchannels);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, px.data())) {
    error = in->geterror();
    return {};
  }
  in.reset();
  int colours = std::min(spec.nchannels, 3);  // alpha stays as it is
  if (spec.alpha_channel >= 0 && spec.alpha_channel < 3) colours = spec.alpha_channel;
  const std::size_t nc = std::size_t(spec.nchannels), pixels = px.size() / nc;
  if (colour.kind == SourceColour::Ocio) {
    // OCIO takes packed RGB: grey is spread to three channels and back.
    std::vector<float> rgb(pixels * 3);
    for (std::size_t i = 0; i < pixels; ++i)
      for (int c = 0; c < 3; ++c)
        rgb[3 * i + c] = px[i * nc + std::size_t(std::min(c, colours - 1))];
    colour.ocio->apply(rgb.data(), pixels);
    for (std::size_t i = 0; i < pixels; ++i)
      for (int c = 0; c < colours; ++c) px[i * nc + std::size_t(c)] = rgb[3 * i + c];
  } else {
    for (std::size_t i = 0; i < pixels; ++i)
      for (int c = 0; c < colours; ++c) {
        float& v = px[i * nc + std::size_t(c)];
        if (colour.kind == SourceColour::Srgb)
          v = srgb_to_linear(v);
        else if (colour.kind == SourceColour::Gamma)
          v = std::pow(std::max(v, 0.0f), colour.gamma);
      }
  }
  if (colour.convert_primaries && colours == 3) {
    const auto& m = colour.primaries;
    for (std::size_t i = 0; i < pixels; ++i) {
      float* p = &px[i * nc];
      float r = p[0], g = p[1], b = p[2];
      for (int c = 0; c < 3; ++c) p[c] = m[3 * c] * r + m[3 * c + 1] * g + m[3 * c + 2] * b;
    }
  }
  OIIO::ImageBuf lin(spec, px.data());
  // NaN and infinite values (a float file's, or a decoding's) become the mean of
  // their finite neighbours, as maketx --fixnan box3 does: filtering spread one
  // NaN texel over every lookup near it, and each such sample was dropped. How
  // many were mended rides in the .tx, so a reused one says it too.
  int mended = 0;
  if (!OIIO::ImageBufAlgo::fixNonFinite(lin, lin, OIIO::ImageBufAlgo::NONFINITE_BOX3, &mended)) {
    error = lin.geterror();
    return {};
  }
  lin.specmod().attribute(kMendedAttribute, kMendedPrefix + std::to_string(mended));
  OIIO::ImageSpec config;
  // Half holds 8- and 16-bit codes decoded exactly enough; float sources stay float.
  config.set_format(was_float ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::HALF);
  config.attribute("oiio:ColorSpace", "Linear");
  // Written beside its final name and renamed, so a concurrent render never reads
  // half a file.
  fs::path tmp = dir / fmt::format(".{:016x}-{}.tx", key, ::getpid());
  if (!OIIO::ImageBufAlgo::make_texture(OIIO::ImageBufAlgo::MakeTxTexture, lin, tmp.string(),
                                        config)) {
    error = OIIO::geterror();
    fs::remove(tmp, ec);
    return {};
  }
  fs::rename(tmp, out, ec);
  if (ec) {
    error = ec.message();
    return {};
  }
  // An hour's grace: a render in another process that opened a file may reopen it.
  texture_cache_prune(dir, texture_cache_max_bytes(), std::chrono::hours(1), out);
  return out.string();
}

// What the module's opaque pointers are: the render's texture system, and per
// opened image its handle and the channels a lookup reads. A grey image, with or
// without alpha, is read as its one grey channel, copied to R, G and B (OIIO's
// gray_to_rgb promotes only one-channel files: grey + alpha came out as red =
// grey, green = alpha, blue = 0).
struct Opened {
  OIIO::TextureSystem::TextureHandle* handle = nullptr;
  int first = 0;      // the first colour channel
  bool grey = false;  // one colour channel
};
struct Textures {
  OIIO::TextureSystem* ts = nullptr;
  std::mutex mutex;           // opens may come from any thread
  std::deque<Opened> opened;  // stable addresses, freed with the system
};

}  // namespace

extern "C" __attribute__((visibility("default"))) void* snell_texture_create_v1(int max_memory_mb) {
  // The cache is ours, not the texture system's: OpenImageIO 2.4 leaks part of a
  // cache it creates itself (LeakSanitizer: 25 KB per render), and destroys one it
  // was given only when asked to.
  OIIO::ImageCache* cache = OIIO::ImageCache::create(/*shared=*/false);
  OIIO::TextureSystem* ts = OIIO::TextureSystem::create(/*shared=*/false, cache);
  ts->attribute("max_memory_MB", float(max_memory_mb));
  ts->attribute("autotile", 64);
  ts->attribute("automip", 1);
  ts->attribute("unassociatedalpha", 1);  // a texel's colour, not colour times alpha
  auto* t = new Textures;
  t->ts = ts;
  return t;
}

extern "C" __attribute__((visibility("default"))) void snell_texture_destroy_v1(void* tp) {
  auto* t = static_cast<Textures*>(tp);
  OIIO::ImageCache* cache = t->ts->imagecache();
  OIIO::TextureSystem::destroy(t->ts);
  OIIO::ImageCache::destroy(cache, /*teardown=*/true);
  delete t;
}

// Opens `path` (decoding it to linear first when it is not linear; colour spaces
// by name from the OCIO config `ocio_config`, as resolve_ocio_config takes it) and
// returns its handle, or null with `error`.
extern "C" __attribute__((visibility("default"))) void* snell_texture_open_v3(
    void* tp, const std::string& path, const std::string& ocio_config, std::string& error,
    std::string& note) {
  try {
    Textures& t = *static_cast<Textures*>(tp);
    OIIO::TextureSystem* ts = t.ts;
    auto in = OIIO::ImageInput::open(path);
    if (!in) {
      error = OIIO::geterror();
      return nullptr;
    }
    const OIIO::ImageSpec spec = in->spec();  // a copy: `in` closes before the decoding
    std::string file = path;
    SourceColour colour;
    if (!source_colour(spec, ocio_config, colour, error)) return nullptr;
    in.reset();
    if (!colour.is_identity()) {
      file = linear_texture(path, colour, spec, error);
      if (file.empty()) return nullptr;
    }
    OIIO::TextureSystem::TextureHandle* h = ts->get_texture_handle(OIIO::ustring(file));
    int res[2] = {0, 0};
    if (!h || !ts->get_texture_info(h, nullptr, 0, OIIO::ustring("resolution"),
                                    OIIO::TypeDesc(OIIO::TypeDesc::INT, 2), res)) {
      error = ts->geterror();
      if (error.empty()) error = "not an image the texture system can read";
      return nullptr;
    }
    // A file decoded to linear above was read whole; one the texture system reads
    // itself (a float EXR) is read once here, through its cache in bands of rows,
    // so a damaged one is refused now (§17: exit 3 at its `file`) rather than
    // rendering black where its lookups fail.
    std::size_t nonfinite = 0;
    if (file == path) {
      const int channels = spec.nchannels > 0 ? spec.nchannels : 1;
      const std::size_t row = std::size_t(std::max(res[0], 1)) * std::size_t(channels);
      const int rows = int(std::clamp<std::size_t>((std::size_t(4) << 20) / row, 1, 4096));
      std::vector<float> band(row * std::size_t(rows));
      OIIO::TextureOpt all;
      for (int y = 0; y < res[1]; y += rows) {
        if (!ts->get_texels(h, nullptr, all, 0, 0, res[0], y, std::min(y + rows, res[1]), 0, 1, 0,
                            channels, OIIO::TypeDesc::FLOAT, band.data())) {
          // The cache says it once per tile it could not read: the first will do.
          error = ts->geterror();
          if (std::size_t again = error.find("Failed", 1); again != std::string::npos)
            error.resize(again);
          if (error.empty()) error = "its pixels cannot be read";
          return nullptr;
        }
        const std::size_t n = row * std::size_t(std::min(rows, res[1] - y));
        for (std::size_t i = 0; i < n; ++i) nonfinite += !std::isfinite(band[i]);
      }
    }
    if (nonfinite > 0) {  // mended in a .tx of its own (linear_texture)
      file = linear_texture(path, colour, spec, error);
      if (file.empty()) return nullptr;
      h = ts->get_texture_handle(OIIO::ustring(file));
      if (!h) {
        error = ts->geterror();
        return nullptr;
      }
    }
    Opened o;
    o.handle = h;
    if (const OIIO::ImageSpec* tx = ts->imagespec(h, nullptr)) {
      const std::string tag = tx->get_string_attribute(kMendedAttribute);
      const int mended = tag.rfind(kMendedPrefix, 0) == 0
                             ? std::atoi(tag.c_str() + std::strlen(kMendedPrefix))
                             : 0;
      if (mended > 0)
        note = fmt::format(
            "{} pixel{} of it hold{} NaN or infinite values: each is read as the mean of its "
            "finite neighbours",
            mended, mended == 1 ? "" : "s", mended == 1 ? "s" : "");
      const int alpha = tx->alpha_channel;
      const int colours = tx->nchannels - (alpha >= 0 && alpha < tx->nchannels ? 1 : 0);
      o.grey = colours == 1;
      o.first = alpha == 0 ? 1 : 0;
    }
    std::lock_guard<std::mutex> lock(t.mutex);
    return &t.opened.emplace_back(o);
  } catch (const std::bad_alloc&) {
    error = "there is not memory enough to decode it to linear";
    return nullptr;
  } catch (const std::exception& e) {
    error = e.what();
    return nullptr;
  }
}

// A filtered lookup at (s, t) (OIIO's: t = 0 is the top row) with the footprint's
// derivatives; `wrap` bit 0: s is periodic, bit 1: t is, else the filter clamps at
// that edge (the caller gives black outside [0, 1]² where it should).
extern "C" __attribute__((visibility("default"))) void snell_texture_lookup_v2(
    void* tp, void* handle, int wrap, const float* st_derivs, float* rgb) {
  OIIO::TextureSystem* ts = static_cast<Textures*>(tp)->ts;
  const Opened& o = *static_cast<const Opened*>(handle);
  OIIO::TextureOpt opt;
  opt.firstchannel = o.first;
  opt.swrap = wrap & 1 ? OIIO::TextureOpt::WrapPeriodic : OIIO::TextureOpt::WrapClamp;
  opt.twrap = wrap & 2 ? OIIO::TextureOpt::WrapPeriodic : OIIO::TextureOpt::WrapClamp;
  // Bilinear within a MIP level: exact at texel centres (OIIO's default bicubic
  // is a B-spline, which blurs a texel into its neighbours when magnifying).
  opt.interpmode = OIIO::TextureOpt::InterpBilinear;
  const float* d = st_derivs;
  if (!ts->texture(o.handle, nullptr, opt, d[0], d[1], d[2], d[3], d[4], d[5], o.grey ? 1 : 3, rgb))
    rgb[0] = rgb[1] = rgb[2] = 0;
  else if (o.grey)
    rgb[1] = rgb[2] = rgb[0];
}

extern "C" __attribute__((visibility("default"))) void snell_texture_stats_v1(void* tp,
                                                                              std::string& out) {
  out = static_cast<Textures*>(tp)->ts->getstats(1, true);
}
