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
// - Colour: OIIO 2.4 applies no colour transform at lookup, so 8- and 16-bit files
//   (taken as sRGB-encoded unless their oiio:ColorSpace says linear) are decoded
//   once to linear half floats and made into a tiled, MIP-mapped .tx in the
//   user's temporary folder, named by the source's path, size and time; filtering
//   then averages linear radiance, as it must (a black-and-white checker far away
//   is 0.5, not sRGB's 0.21). Float files are read as they are (linear). Limit: the
//   decode reads an 8-bit image whole once.
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imagecache.h>
#include <OpenImageIO/imageio.h>
#include <OpenImageIO/texture.h>
#include <fmt/format.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

// The sRGB decoding function (IEC 61966-2-1).
float srgb_to_linear(float c) {
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

bool linear_by_metadata(const OIIO::ImageSpec& spec) {
  std::string cs = spec.get_string_attribute("oiio:ColorSpace");
  for (char& c : cs) c = char(std::tolower(static_cast<unsigned char>(c)));
  return cs.find("linear") != std::string::npos || cs == "scene_linear";
}

// The linear .tx made from an sRGB-encoded file, made once (reused while the
// source's size and time are unchanged). Empty, with `error`, on failure.
std::string linear_texture(const std::string& path, std::string& error) {
  std::error_code ec;
  auto size = fs::file_size(path, ec);
  auto time = fs::last_write_time(path, ec).time_since_epoch().count();
  std::size_t key = std::hash<std::string>{}(fmt::format("{}|{}|{}", path, size, time));
  fs::path dir = fs::temp_directory_path(ec) / fmt::format("snell-textures-{}", ::getuid());
  fs::create_directories(dir, ec);
  fs::path out = dir / fmt::format("{:016x}.tx", key);
  if (fs::exists(out, ec)) return out.string();
  OIIO::ImageBuf src(path);
  if (!src.read(0, 0, true, OIIO::TypeDesc::FLOAT)) {
    error = src.geterror();
    return {};
  }
  OIIO::ImageSpec spec = src.spec();
  spec.set_format(OIIO::TypeDesc::FLOAT);
  std::vector<float> px(std::size_t(spec.width) * spec.height * spec.nchannels);
  src.get_pixels(src.roi(), OIIO::TypeDesc::FLOAT, px.data());
  int colour = std::min(spec.nchannels, 3);  // alpha stays as it is
  if (spec.alpha_channel >= 0 && spec.alpha_channel < 3) colour = spec.alpha_channel;
  for (std::size_t i = 0; i < px.size(); i += std::size_t(spec.nchannels))
    for (int c = 0; c < colour; ++c)
      px[i + std::size_t(c)] = srgb_to_linear(px[i + std::size_t(c)]);
  OIIO::ImageBuf lin(spec, px.data());
  OIIO::ImageSpec config;
  config.set_format(OIIO::TypeDesc::HALF);
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
  return out.string();
}

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
  ts->attribute("gray_to_rgb", 1);  // a grey image gives grey, not red
  return ts;
}

extern "C" __attribute__((visibility("default"))) void snell_texture_destroy_v1(void* ts) {
  auto* t = static_cast<OIIO::TextureSystem*>(ts);
  OIIO::ImageCache* cache = t->imagecache();
  OIIO::TextureSystem::destroy(t);
  OIIO::ImageCache::destroy(cache, /*teardown=*/true);
}

// Opens `path` (decoding it to linear first when it is sRGB-encoded) and returns
// its handle, or null with `error`.
extern "C" __attribute__((visibility("default"))) void* snell_texture_open_v1(
    void* tsp, const std::string& path, std::string& error) {
  try {
    auto* ts = static_cast<OIIO::TextureSystem*>(tsp);
    auto in = OIIO::ImageInput::open(path);
    if (!in) {
      error = OIIO::geterror();
      return nullptr;
    }
    const OIIO::ImageSpec& spec = in->spec();
    std::string file = path;
    if (!spec.format.is_floating_point() && !linear_by_metadata(spec)) {
      in.reset();
      file = linear_texture(path, error);
      if (file.empty()) return nullptr;
    }
    in.reset();
    OIIO::TextureSystem::TextureHandle* h = ts->get_texture_handle(OIIO::ustring(file));
    int res[2] = {0, 0};
    if (!h || !ts->get_texture_info(h, nullptr, 0, OIIO::ustring("resolution"),
                                    OIIO::TypeDesc(OIIO::TypeDesc::INT, 2), res)) {
      error = ts->geterror();
      if (error.empty()) error = "not an image the texture system can read";
      return nullptr;
    }
    return h;
  } catch (const std::exception& e) {
    error = e.what();
    return nullptr;
  }
}

// A filtered lookup at (s, t) (OIIO's: t = 0 is the top row) with the footprint's
// derivatives; black outside [0, 1]² unless `repeat`.
extern "C" __attribute__((visibility("default"))) void snell_texture_lookup_v1(
    void* tsp, void* handle, int repeat, const float* st_derivs, float* rgb) {
  auto* ts = static_cast<OIIO::TextureSystem*>(tsp);
  OIIO::TextureOpt opt;
  opt.swrap = opt.twrap = repeat ? OIIO::TextureOpt::WrapPeriodic : OIIO::TextureOpt::WrapBlack;
  // Bilinear within a MIP level: exact at texel centres (OIIO's default bicubic
  // is a B-spline, which blurs a texel into its neighbours when magnifying).
  opt.interpmode = OIIO::TextureOpt::InterpBilinear;
  const float* d = st_derivs;
  if (!ts->texture(static_cast<OIIO::TextureSystem::TextureHandle*>(handle), nullptr, opt, d[0],
                   d[1], d[2], d[3], d[4], d[5], 3, rgb))
    rgb[0] = rgb[1] = rgb[2] = 0;
}

extern "C" __attribute__((visibility("default"))) void snell_texture_stats_v1(void* tsp,
                                                                              std::string& out) {
  out = static_cast<OIIO::TextureSystem*>(tsp)->getstats(1, true);
}
