// write_image() and read_image() without linking OpenImageIO: the writer (image_io.cpp, OIIO and
// OCIO) is in the image module (image_module.cpp), loaded on first use; `snell
// render` loads it just before the render (preload_image_writer), so a missing
// module fails before the work.
#include <fmt/format.h>

#include <string>

#include "runtime/image_format.hpp"
#include "runtime/image_module.hpp"
#include "runtime/render.hpp"

namespace snell::rt {

namespace {

using WriteFn = void (*)(const std::string&, const Image&, const OutputInfo&, const std::string&,
                         std::string&);

struct Writer {
  WriteFn write = nullptr;
  std::string error;  // why the module could not be loaded
};

const Writer& writer() {
  static const Writer w = [] {
    Writer r;
    r.write = reinterpret_cast<WriteFn>(image_module_symbol("snell_write_image_v1", r.error));
    return r;
  }();
  return w;
}

}  // namespace

std::string preload_image_writer() {
  return writer().error;
}

std::string check_display_transform(const std::string& ocio_config) {
  using CheckFn = void (*)(const std::string&, std::string&);
  std::string error;
  static const CheckFn check =
      reinterpret_cast<CheckFn>(image_module_symbol("snell_check_display_v1", error));
  if (!check) return error.empty() ? "no display transform in the image module" : error;
  check(ocio_config, error);
  return error;
}

std::string write_image(const std::string& path, const Image& image, const OutputInfo& info,
                        const std::string& ocio_config) {
  if (!is_supported_image_extension(path))
    return fmt::format("{}: unsupported image format (use .exr, .png, .jpg, .tif)", path);
  if (image.width == 0 || image.height == 0) return fmt::format("{}: empty image", path);
  const Writer& w = writer();
  if (!w.write) return fmt::format("cannot write {}: {}", path, w.error);
  std::string error;
  w.write(path, image, info, ocio_config, error);
  return error;
}

std::string read_image(const std::string& path, ImageFile& out) {
  using ReadFn = void (*)(const std::string&, ImageFile&, std::string&);
  std::string error;
  static const ReadFn read =
      reinterpret_cast<ReadFn>(image_module_symbol("snell_read_image_v1", error));
  if (!read) return fmt::format("cannot read {}: {}", path, error.empty() ? "no reader" : error);
  read(path, out, error);
  return error;
}

}  // namespace snell::rt
