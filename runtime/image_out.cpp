// write_image() without linking OpenImageIO: the writer (image_io.cpp, OIIO and
// OCIO) is a module, dlopen'ed once on first use. Linking OIIO directly made every
// start of `snell` bind ~260 shared libraries (0.3 s of a `snell check`); now only
// a command that writes an image pays it, and `snell render` pays it just before
// the render (preload_image_writer), so a missing module fails before the work.
//
// Where the module is looked for: the build tree's copy (tests and programs run in
// place), then the installed one. Both paths are fixed when Snell is configured.
#include <dlfcn.h>
#include <fmt/format.h>

#include <filesystem>
#include <mutex>
#include <string>

#include "runtime/image_format.hpp"
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
  static Writer w;
  static std::once_flag once;
  std::call_once(once, [] {
    std::string tried;
    for (const char* path : {SNELL_IMAGE_IO_BUILD_MODULE, SNELL_IMAGE_IO_INSTALL_MODULE}) {
      std::error_code ec;
      if (!std::filesystem::exists(path, ec)) {
        tried += fmt::format("{}{} (missing)", tried.empty() ? "" : ", ", path);
        continue;
      }
      // RTLD_NOW: a broken module fails here, not in the middle of a write.
      // Never unloaded: OIIO keeps threads and static state.
      void* h = dlopen(path, RTLD_NOW | RTLD_LOCAL);
      if (!h) {
        tried += fmt::format("{}{}", tried.empty() ? "" : ", ", dlerror());
        continue;
      }
      if (auto* f = reinterpret_cast<WriteFn>(dlsym(h, "snell_write_image_v1"))) {
        w.write = f;
        return;
      }
      tried += fmt::format("{}{}: no snell_write_image_v1", tried.empty() ? "" : ", ", path);
    }
    w.error = fmt::format("cannot load the image writer module (tried {})", tried);
  });
  return w;
}

}  // namespace

std::string preload_image_writer() {
  return writer().error;
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

}  // namespace snell::rt
