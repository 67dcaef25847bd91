// Image encoding: the only translation unit that includes OpenImageIO's writers.
// It is built into a module (libsnell_image_io.so) that image_out.cpp loads on
// first use: OpenImageIO pulls in ~260 shared libraries whose symbol binding
// costs ~0.3 s at start-up, which `snell check`, scene errors and tests that
// never write an image should not pay.
// EXR: linear float32 RGB radiance with metadata. PNG/JPEG/TIFF: 8-bit codes made
// through an OCIO display transform (color.cpp), clamped to [0, 1] and rounded.
// Every file is encoded whole into memory (OIIO's IOVecOutput proxy) and nothing
// touches the disk here: image_out.cpp then writes the bytes with every step
// checked (atomic_file.cpp). So a full disk can never reach a codec: libjpeg's
// default error handler ends the process, libpng's writer reported success on
// a short write.
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <memory>

#include "runtime/color.hpp"
#include "runtime/image_format.hpp"
#include "runtime/render.hpp"

namespace snell::rt {

namespace {

// Rows converted to display codes at a time: the PNG/JPEG/TIFF path holds one
// strip of float and 8-bit pixels besides the film, never a copy of the image
// (a 16384² film is 3.2 GB; a float copy of it was another 3.2 GB).
constexpr std::uint32_t kStripRows = 64;

}  // namespace

std::string encode_image_oiio(const std::string& path, const Image& image, const OutputInfo& info,
                              const DisplayView& display, std::vector<unsigned char>& bytes) {
  if (!is_supported_image_extension(path))
    return fmt::format("{}: unsupported image format (use .exr, .png, .jpg, .tif)", path);
  if (image.width == 0 || image.height == 0) return fmt::format("{}: empty image", path);
  std::string ext = lower_extension(path);
  bool exr = ext == ".exr";

  OIIO::ImageSpec spec;
  std::unique_ptr<ColorTransform> to_display;
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
    std::string err;
    to_display = ColorTransform::to_display(display, err);
    if (!to_display) return fmt::format("cannot write {}: {}", path, err);
    spec = OIIO::ImageSpec(int(image.width), int(image.height), 3, OIIO::TypeDesc::UINT8);
    // Tagged sRGB only when that is the display; another display's codes are not.
    const std::string& view = to_display->name();
    if (view.find("sRGB") != std::string::npos) spec.attribute("oiio:ColorSpace", "sRGB");
    spec.attribute("snell:display", view);
    if (ext == ".jpg" || ext == ".jpeg") spec.attribute("CompressionQuality", 95);
    // OIIO 2.4's TIFF writer, writing through a proxy, re-reads what it wrote to
    // add an Exif directory (oiio:ColorSpace goes there) and cannot: the file came
    // out without its image directory (OIIO PR #4300). No Exif directory, then;
    // the colour space and Snell's attributes stay in the main directory's tags.
    if (ext == ".tif" || ext == ".tiff") spec.attribute("tiff:write_exif", 0);
  }
  spec.attribute("Software", "snell 0.1");
  spec.attribute("snell:scene", info.scene_path);
  spec.attribute("snell:samples", int(info.samples));
  spec.attribute("snell:seed", fmt::format("{}", info.seed));
  spec.attribute("snell:render_seconds", float(info.render_seconds));
  for (const auto& [key, value] : info.attributes) spec.attribute(key, value);

  auto fail = [&](const std::string& why) { return fmt::format("cannot write {}: {}", path, why); };
  bytes.clear();
  OIIO::Filesystem::IOVecOutput memory(bytes);
  auto out = OIIO::ImageOutput::create(path);
  if (!out) return fail(OIIO::geterror());
  if (!out->supports("ioproxy")) return fail("this OpenImageIO cannot encode it in memory");
  out->set_ioproxy(&memory);
  if (!out->open(path, spec)) return fail(out->geterror());
  bool ok = true;
  if (exr) {
    ok = out->write_image(OIIO::TypeDesc::FLOAT, image.rgb.data());
  } else {
    const std::size_t row = std::size_t(image.width) * 3;
    std::vector<float> strip(row * kStripRows);
    std::vector<unsigned char> codes(row * kStripRows);
    for (std::uint32_t y0 = 0; ok && y0 < image.height; y0 += kStripRows) {
      std::uint32_t n = std::min(kStripRows, image.height - y0);
      std::copy_n(image.rgb.begin() + std::ptrdiff_t(y0 * row), n * row, strip.begin());
      to_display->apply(strip.data(), std::size_t(n) * image.width);
      for (std::size_t i = 0; i < n * row; ++i) codes[i] = quantize8(strip[i]);
      ok = out->write_scanlines(spec.y + int(y0), spec.y + int(y0 + n), 0, OIIO::TypeDesc::UINT8,
                                codes.data());
    }
  }
  if (!ok) {
    std::string e = out->geterror();
    out->close();
    return fail(e);
  }
  if (!out->close()) return fail(out->geterror());
  // Any message left pending after a successful close is dropped, not shown.
  (void)out->geterror();
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

// The module's entry points (image_out.cpp resolves them by name). The caller is
// the same build of Snell, so C++ types cross safely; the version in the name
// guards against a stale module from another build layout.
extern "C" __attribute__((visibility("default"))) void snell_encode_image_v2(
    const std::string& path, const snell::rt::Image& image, const snell::rt::OutputInfo& info,
    const snell::rt::DisplayView& display, std::vector<unsigned char>& bytes, std::string& error) {
  try {
    error = snell::rt::encode_image_oiio(path, image, info, display, bytes);
  } catch (const std::exception& e) {
    error = fmt::format("cannot write {}: {}", path, e.what());
  }
}

// The display transform made once: what a PNG write would report about the OCIO
// config, display and view, before any render.
extern "C" __attribute__((visibility("default"))) void snell_check_display_v2(
    const snell::rt::DisplayView& display, std::string& error) {
  try {
    error.clear();
    (void)snell::rt::ColorTransform::to_display(display, error);
  } catch (const std::exception& e) {
    error = e.what();
  }
}
