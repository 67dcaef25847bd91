// write_image() and read_image() without linking OpenImageIO: the encoder and
// reader (image_io.cpp, OIIO and OCIO) are in the image module (image_module.cpp),
// loaded on first use; `snell render` has it loaded in a helper process beside
// the work (image_helper.hpp), or here before the render (preload_image_writer),
// so a missing module fails at the start, not after the render. The module
// only encodes into memory; the file itself is written here, all or nothing
// (atomic_file.cpp), so the signal handler and the fault tests see one writer.
#include <fmt/format.h>

#include <string>
#include <vector>

#include "runtime/atomic_file.hpp"
#include "runtime/image_format.hpp"
#include "runtime/image_helper.hpp"
#include "runtime/image_module.hpp"
#include "runtime/render.hpp"

namespace snell::rt {

namespace {

using EncodeFn = void (*)(const std::string&, const Image&, const OutputInfo&, const DisplayView&,
                          std::vector<unsigned char>&, std::string&);

struct Encoder {
  EncodeFn encode = nullptr;
  std::string error;  // why the module could not be loaded
};

const Encoder& encoder() {
  static const Encoder e = [] {
    Encoder r;
    r.encode = reinterpret_cast<EncodeFn>(image_module_symbol("snell_encode_image_v2", r.error));
    return r;
  }();
  return e;
}

}  // namespace

std::string preload_image_writer() {
  return encoder().error;
}

std::string check_display_transform(const DisplayView& display) {
  using CheckFn = void (*)(const DisplayView&, std::string&);
  std::string error;
  static const CheckFn check =
      reinterpret_cast<CheckFn>(image_module_symbol("snell_check_display_v2", error));
  if (!check) return error.empty() ? "no display transform in the image module" : error;
  check(display, error);
  return error;
}

namespace {
// A large image is encoded here: handing it to the helper or the resident server
// copies the film into the message and the encoded file out of the reply, while the
// other process holds both too (a 16384² PNG peaked at 9.5 GB here and 6.6 GB there,
// where the memory estimate, and the in-process writer, need 3.4 GB). At this size
// the image module's load (~0.25 s) is nothing beside the render.
bool hands_over(const Image& image) {
  constexpr std::size_t kHandOverBytes = std::size_t(64) << 20;
  return image_helper_running() && image.rgb.size() * sizeof(float) <= kHandOverBytes;
}
}  // namespace

std::string image_encoder_for(const Image& image) {
  return hands_over(image) ? image_writer_kind() : "this process";
}

std::string write_image(const std::string& path, const Image& image, const OutputInfo& info,
                        const DisplayView& display) {
  if (!is_supported_image_extension(path))
    return fmt::format("{}: unsupported image format (use .exr, .png, .jpg, .tif)", path);
  if (image.width == 0 || image.height == 0) return fmt::format("{}: empty image", path);
  std::vector<unsigned char> bytes;
  std::string error = hands_over(image) ? image_helper_encode(path, image, info, display, bytes)
                                        : encode_image_here(path, image, info, display, bytes);
  if (!error.empty()) return error;
  return write_file_atomically(path, bytes.data(), bytes.size());
}

std::string encode_image_here(const std::string& path, const Image& image, const OutputInfo& info,
                              const DisplayView& display, std::vector<unsigned char>& bytes) {
  const Encoder& e = encoder();
  if (!e.encode) return fmt::format("cannot write {}: {}", path, e.error);
  std::string error;
  e.encode(path, image, info, display, bytes, error);
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
