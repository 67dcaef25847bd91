// Image output: the only translation unit that includes OpenImageIO. It is built
// into a module (libsnell_image_io.so) that image_out.cpp loads on first use:
// OpenImageIO pulls in ~260 shared libraries whose symbol binding costs ~0.3 s
// at start-up, which `snell check`, scene errors and tests that never write an
// image should not pay.
// EXR: linear float32 RGB radiance with metadata. PNG/JPEG/TIFF: 8-bit sRGB made
// through the OCIO display transform (color.cpp), clamped to [0, 1] and rounded.
// Every file is written to a temporary name beside the target and renamed into
// place, so an existing file is never left half-written; on failure the temporary
// is removed and the target is untouched.
#include <OpenImageIO/imageio.h>
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cstdio>
#include <filesystem>

#include "runtime/color.hpp"
#include "runtime/image_format.hpp"
#include "runtime/render.hpp"

namespace snell::rt {

namespace {

// A hidden sibling of the target that keeps its extension (OIIO picks the format
// from it) and is unique per process and call.
std::string temp_name(const std::string& path) {
  static std::atomic<unsigned> counter{0};
  std::filesystem::path p(path);
  std::string name = fmt::format(".{}.snell-tmp-{}-{}{}", p.stem().string(), ::getpid(), counter++,
                                 p.extension().string());
  return (p.parent_path() / name).string();
}

}  // namespace

std::string write_image_oiio(const std::string& path, const Image& image, const OutputInfo& info,
                             const std::string& ocio_config) {
  if (!is_supported_image_extension(path))
    return fmt::format("{}: unsupported image format (use .exr, .png, .jpg, .tif)", path);
  if (image.width == 0 || image.height == 0) return fmt::format("{}: empty image", path);
  std::string ext = lower_extension(path);
  bool exr = ext == ".exr";

  OIIO::ImageSpec spec;
  std::vector<unsigned char> bytes;
  if (exr) {
    spec = OIIO::ImageSpec(int(image.width), int(image.height), 3, OIIO::TypeDesc::FLOAT);
    // §18: a crop is its data window at its place in the full display window.
    spec.x = int(image.x0);
    spec.y = int(image.y0);
    spec.full_x = spec.full_y = 0;
    spec.full_width = int(image.display_width());
    spec.full_height = int(image.display_height());
    spec.attribute("compression", "zip");
    spec.attribute("oiio:ColorSpace", "Linear Rec.709 (sRGB)");
  } else {
    std::vector<float> disp = image.rgb;
    std::string err = apply_display_transform(ocio_config, disp.data(), disp.size() / 3);
    if (!err.empty()) return fmt::format("{}: {}", path, err);
    bytes.resize(disp.size());
    for (std::size_t i = 0; i < disp.size(); ++i) bytes[i] = quantize8(disp[i]);
    spec = OIIO::ImageSpec(int(image.width), int(image.height), 3, OIIO::TypeDesc::UINT8);
    spec.attribute("oiio:ColorSpace", "sRGB");
    if (ext == ".jpg" || ext == ".jpeg") spec.attribute("CompressionQuality", 95);
  }
  spec.attribute("Software", "snell 0.1");
  spec.attribute("snell:scene", info.scene_path);
  spec.attribute("snell:samples", int(info.samples));
  spec.attribute("snell:seed", fmt::format("{}", info.seed));
  spec.attribute("snell:render_seconds", float(info.render_seconds));
  for (const auto& [key, value] : info.attributes) spec.attribute(key, value);

  std::string tmp = temp_name(path);
  auto fail = [&](const std::string& why) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    return fmt::format("cannot write {}: {}", path, why);
  };
  auto out = OIIO::ImageOutput::create(tmp);
  if (!out) return fail(OIIO::geterror());
  if (!out->open(tmp, spec)) return fail(out->geterror());
  bool ok = exr ? out->write_image(OIIO::TypeDesc::FLOAT, image.rgb.data())
                : out->write_image(OIIO::TypeDesc::UINT8, bytes.data());
  if (!ok) {
    std::string e = out->geterror();
    out->close();
    return fail(e);
  }
  if (!out->close()) return fail(out->geterror());
  out.reset();
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) return fail(ec.message());
  return {};
}

std::string read_image_oiio(const std::string& path, ImageFile& file) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) return fmt::format("cannot read {}: {}", path, OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.nchannels < 3)
    return fmt::format("cannot read {}: it has {} channel(s), not RGB", path, spec.nchannels);
  if (spec.x < 0 || spec.y < 0 || spec.full_x != 0 || spec.full_y != 0 || spec.width <= 0 ||
      spec.height <= 0)
    return fmt::format("cannot read {}: its data window does not lie in a display window at 0, 0",
                       path);
  Image& im = file.image;
  im.width = std::uint32_t(spec.width);
  im.height = std::uint32_t(spec.height);
  im.x0 = std::uint32_t(spec.x);
  im.y0 = std::uint32_t(spec.y);
  im.full_width = std::uint32_t(std::max(spec.full_width, 0));
  im.full_height = std::uint32_t(std::max(spec.full_height, 0));
  im.rgb.resize(std::size_t(im.width) * im.height * 3);
  // The first three channels, as float: an EXR written by Snell is float already,
  // so its bits come back unchanged.
  if (!in->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, im.rgb.data()))
    return fmt::format("cannot read {}: {}", path, in->geterror());
  file.attributes.clear();
  for (const OIIO::ParamValue& p : spec.extra_attribs)
    file.attributes.emplace_back(p.name().string(), p.get_string());
  return {};
}

}  // namespace snell::rt

extern "C" __attribute__((visibility("default"))) void snell_read_image_v1(
    const std::string& path, snell::rt::ImageFile& file, std::string& error) {
  try {
    error = snell::rt::read_image_oiio(path, file);
  } catch (const std::exception& e) {
    error = fmt::format("cannot read {}: {}", path, e.what());
  }
}

// The module's entry point (image_out.cpp resolves it by name). The caller is the
// same build of Snell, so C++ types cross safely; the version in the name guards
// against a stale module from another build layout.
extern "C" __attribute__((visibility("default"))) void snell_write_image_v1(
    const std::string& path, const snell::rt::Image& image, const snell::rt::OutputInfo& info,
    const std::string& ocio_config, std::string& error) {
  try {
    error = snell::rt::write_image_oiio(path, image, info, ocio_config);
  } catch (const std::exception& e) {
    error = fmt::format("cannot write {}: {}", path, e.what());
  }
}

// The display transform made once on one black pixel: what a PNG write would
// report about the OCIO config, before any render.
extern "C" __attribute__((visibility("default"))) void snell_check_display_v1(
    const std::string& ocio_config, std::string& error) {
  try {
    float rgb[3] = {0, 0, 0};
    error = snell::rt::apply_display_transform(ocio_config, rgb, 1);
  } catch (const std::exception& e) {
    error = e.what();
  }
}
